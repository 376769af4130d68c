"""Mission `lunar-landing`: minimum-fuel powered descent from perilune (paper 002, SPEC M3).

Three methods solve the same problem: the paper's integral transformation with an Adams
predictor-corrector and the generalised multiplier method (`methods.py`), and the general
Hermite–Simpson and multiple-shooting transcriptions of the OCP in `problem.py`.
"""

from __future__ import annotations

import numpy as np

from ...context import SolveContext
from ...methods import HERMITE_SIMPSON, MULTIPLE_SHOOTING
from ...mission import Mission
from ...ocp import OCP, OCPResult
from ...problem import Method
from ...solution import Solution
from . import problem, view
from .methods import PAPER_METHOD, landing_quantities, solve_paper
from .pmp import reference_extremal


class LunarLanding(Mission, records=problem):
    key = "lunar-landing"
    title = "Lunar soft landing"
    summary = "Minimum-fuel powered descent from a 100 × 15 km orbit to a soft touchdown."
    methods = (PAPER_METHOD,
               HERMITE_SIMPSON.replace(nodes=(5, 30, 200), backends=("ipopt", "sqp", "fatrop")),
               MULTIPLE_SHOOTING.replace(nodes=(5, 30, 200),
                                         backends=("ipopt", "sqp", "fatrop")))
    # A slider move re-solves in 7 ms by Hermite–Simpson, 57 ms by the paper's method (both
    # `optimal` at their defaults, bench_missions 2026-12-07): the explorer opens with it.
    live_method = "hermite-simpson"
    cost_label = "fuel"
    cost_unit = "kg"

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        sol.quantities = landing_quantities(p, res.t_nodes, res.X)

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        return problem.touchdown_miss(x_final)

    def indirect_reference(self, sol: Solution, p: np.ndarray) -> None:
        """Paper 002's Pontryagin reference (`pmp.solve_extremal`) started from the costate
        estimate (or from the last extremal of the same request when the method has no
        costates): the extremal, its tf and the costate agreement."""
        reference_extremal(sol, p)

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str]:
        """Local error in radius (the headline: the touchdown altitude), m."""
        return np.abs(dx[:, 0]), "m"

    def check_atol(self, ocp: OCP) -> np.ndarray:
        return np.array([1e-6, 1e-9, 1e-12, 1e-14, 1e-9])

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        p = problem.parameter_vector(values)
        problem.precheck(p)
        return solve_paper(values, p, nodes, warm, ctx)

    _present = staticmethod(view.present)


MISSION = LunarLanding()
