"""Mission `cw-rendezvous`: finite-thrust, minimum-burn-time rendezvous in a circular orbit
(paper 000, SPEC M1), Clohessy–Wiltshire relative motion, fixed total time.

Three methods: the paper's burn/coast arc transcription (`methods.py`: HS collocation on
burns, the CW state transition matrix on coasts; IPOPT or the paper's exterior penalty
method), and the general Hermite–Simpson and multiple-shooting transcriptions of the
free-structure OCP in `problem.py` (an L1 cost whose bang–bang structure emerges by itself).
"""

from __future__ import annotations

import numpy as np

from ...context import SolveContext
from ...methods import HERMITE_SIMPSON, MULTIPLE_SHOOTING
from ...mission import Mission
from ...ocp import OCP, OCPResult
from ...problem import Method
from ...solution import Quantity, Series, Solution
from . import problem, view
from .methods import PAPER_METHOD, control_burn_time, solve_paper
from .primer import switching


class CWRendezvous(Mission, records=problem):
    key = "cw-rendezvous"
    title = "Finite-thrust rendezvous (CW)"
    summary = "Minimum burn time rendezvous with a target in a circular orbit, fixed time."
    methods = (
        PAPER_METHOD,
        HERMITE_SIMPSON.replace(
            label="Free structure: Hermite–Simpson, L1 cost",
            summary="Hermite–Simpson over the whole transfer with |a u| <= s <= a and cost "
                    "∫ s/a dt: the burn/coast structure is not imposed but emerges "
                    "(bang–bang).",
            nodes=(10, 60, 400)),
        MULTIPLE_SHOOTING.replace(
            label="Direct multiple shooting (free structure, L1 cost)",
            summary="The free-structure problem by direct multiple shooting (RK4 per "
                    "interval).",
            nodes=(10, 60, 400)),
    )
    cost_label = "burn time"
    cost_unit = "s"

    def ocp(self, method: Method, values: dict[str, float]) -> OCP:
        return problem.free_ocp()

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        """Arcs from the throttle s, the acceleration (a_x, a_y, a_z) as the control."""
        accel = sol.values["accel"]
        sol.arcs = problem.arcs_from_throttle(res.t_nodes,
                                              res.U[:, 3] > problem.THROTTLE_ON * accel)
        sol.message = problem.explain(res.status, res.message, sol.values, "free-structure")
        burn = control_burn_time(res.controls, res.t_nodes, accel)  # the cost of what is drawn
        sol.cost = Quantity(burn, sol.cost.label, sol.cost.unit)
        sol.quantities = problem.quantities(burn, accel, sol.arcs, surrogate=float(res.cost))
        sol.control_names, sol.control_units = problem.CONTROLS, problem.CONTROL_UNITS
        sol.node_u, sol.u = res.U[:, :3], res.U_dense[:, :3]
        if sol.costates is not None:
            sol.switching = Series(sol.costates.t, switching(
                np.asarray(sol.costates.values), accel)[:, None], ("S",), ("",))

    def indirect_reference(self, sol: Solution, p: np.ndarray) -> None:
        """The primer-vector extremal (`primer.solve_primer`) started from the initial
        costate that fits the estimate: its trajectory, costates and switching function,
        burn time and the costate agreement."""
        if sol.costates is not None:
            problem.store_primer(sol, p)

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str]:
        """Local error in position (the headline: the arrival distance), m."""
        return np.linalg.norm(dx[:, :3], axis=1), "m"

    def check_direct(self, _ocp: OCP, p: np.ndarray, res: OCPResult) -> dict[str, float]:
        """The method's control re-propagated in the CW model (the miss) and, beside it, in
        full two-body gravity (the linearisation's error)."""
        return problem.check(p, res.t_nodes, lambda t, x: res.control(t, x)[:3])

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        p = problem.parameter_vector(values)
        problem.precheck(p)
        return solve_paper(values, p, nodes, backend, warm, ctx)

    _present = staticmethod(view.present)


MISSION = CWRendezvous()
