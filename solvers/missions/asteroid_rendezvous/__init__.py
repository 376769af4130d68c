"""Mission `asteroid-rendezvous`: fuel-optimal low-thrust rendezvous with the near-Earth
asteroid 469219 Kamoʻoalewa (2016 HO3), paper 003 / SPEC M4.

Two stages as in the paper: a particle swarm searches one of three kinds of impulsive
transfer (`guess.py`), which seeds the general Hermite–Simpson transcription of the OCP in
`problem.py` (free launch date, free flight time, the launch v∞ as static variables). The
`impulsive` method shows the first stage alone; `launch_map.py` is paper 003's fig. 2 and its
CLI (`python -m solvers launch-map`).
"""

from __future__ import annotations

from ...context import SolveContext
from ...mission import Mission
from ...problem import Method
from ...solution import Solution
from . import problem, view
from .fixed_structure import BURN_COAST, solve_burn_coast
from .methods import IMPULSIVE, LOW_THRUST, solve_impulsive, solve_low_thrust


class AsteroidRendezvous(Mission, records=problem):
    key = "asteroid-rendezvous"
    title = "Low-thrust asteroid rendezvous"
    summary = ("Fuel-optimal electric-propulsion transfer from Earth to asteroid Kamoʻoalewa "
               "with free launch and arrival dates.")
    methods = (LOW_THRUST, BURN_COAST, IMPULSIVE)
    cost_label = "fuel"
    cost_unit = "kg"
    live_method = "burn-coast"  # a slider move: ~25 ms warm, against ~1 s for Hermite–Simpson
    cold_seconds = 10.0  # bench_missions: 11.1-11.8 s cold with the NLP build, 6.1-6.2 s built

    def help_tables(self) -> dict[str, str]:
        guesses = "\n".join(f"- {i}: {name}" for i, name in enumerate(problem.GUESS_OPTIONS))
        return {**super().help_tables(), "guesses": guesses}

    def solves_itself(self, method: Method) -> bool:
        """The Hermite–Simpson method starts from the swarm's guess (paper 003 §3.1)."""
        return True

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        if method.key == IMPULSIVE.key:
            return solve_impulsive(self.key, values, nodes, ctx)
        if method.key == BURN_COAST.key:
            return solve_burn_coast(self, values, nodes, backend, warm, ctx)
        return solve_low_thrust(self, values, nodes, backend, warm, ctx)

    _present = staticmethod(view.present)


MISSION = AsteroidRendezvous()
