"""Mission `powered-descent`: Mars pinpoint landing, minimum fuel with free final time
(Açıkmeşe & Ploen 2007; Blackmore, Açıkmeşe & Scharf 2010).

Three kinds of method solve it: `lossless`, the papers' convex relaxation, an SOCP compiled
once and re-solved (`lossless.py`, `methods.py`); `scvx`, successive convexification of the
nonconvex original (`solvers/transcription/scvx.py`, general); and the NLP methods on the
nonconvex original (`problem.ocp`).
"""

from __future__ import annotations

import numpy as np

from ...context import SolveContext
from ...methods import HERMITE_SIMPSON, SCVX
from ...mission import Mission
from ...ocp import OCP, OCPResult
from ...problem import Method
from ...solution import Solution
from . import problem, view
from .methods import LOSSLESS, certify_infeasible, record_direct, solve_method
from .model import parameter_vector


class PoweredDescent(Mission, records=problem):
    key = "powered-descent"
    title = "Mars powered descent (convex guidance)"
    summary = "Minimum-fuel pinpoint landing on Mars with a nonconvex thrust bound."
    methods = (LOSSLESS, SCVX.replace(nodes=(10, 30, 120)),
               HERMITE_SIMPSON.replace(nodes=(10, 40, 200)))
    cost_label = "fuel"
    cost_unit = "kg"

    def check_values(self, values: dict[str, float]) -> None:
        problem.check_values(values)

    def parameter_vector(self, values: dict[str, float]) -> np.ndarray:
        return parameter_vector(values)

    def precheck(self, values: dict[str, float], p: np.ndarray) -> None:
        problem.precheck(p)

    def ocp(self, method: Method, values: dict[str, float]) -> OCP:
        return problem.ocp()

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        record_direct(sol, res, p)

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        return problem.touchdown_miss(x_final)

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str]:
        """Local error in position (the headline: the touchdown distance), m."""
        return np.linalg.norm(dx[:, :3], axis=1), "m"

    def check_atol(self, ocp: OCP) -> np.ndarray:
        return np.array([1e-6] * 3 + [1e-8] * 3 + [1e-12])

    def solve_direct(self, values: dict[str, float], method: Method, nodes: int, backend: str,
                     warm: Solution | None, ctx: SolveContext) -> Solution:
        """A general method; when it fails, the convex relaxation (exact here) decides
        whether the request is impossible and names the bound (`certify_infeasible`)."""
        sol = super().solve_direct(values, method, nodes, backend, warm, ctx)
        if sol.status in ("failed", "iteration-limit"):
            reason = certify_infeasible(parameter_vector(values), ctx)
            if reason:
                return self.empty(values, method, nodes, backend, "infeasible", reason)
        return sol

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        p = parameter_vector(values)
        problem.precheck(p)
        return solve_method(values, p, nodes, warm, ctx)

    _present = staticmethod(view.present)


MISSION = PoweredDescent()
