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
from ...solution import Iterate, Solution, WarmStart
from ...transcription import Transcription
from . import problem, view
from .methods import LOSSLESS, certify_infeasible, record_direct, solve_method
from .model import P_RHO1, P_RHO2, parameter_vector
from .switch_mesh import SHORT, switch_mesh, switch_times

ROUNDS = 3  # re-solves with the mesh moved onto the last answer's switches
# The general methods take the switch mesh per solve, and keep |T| >= ρ1 at the midpoints
# where Simpson's rule samples the mass flow (`HermiteSimpson`).
ON_MESH = (("variable_mesh", 1), ("midpoint_path", 1))


class PoweredDescent(Mission, records=problem):
    key = "powered-descent"
    title = "Mars powered descent (convex guidance)"
    summary = "Minimum-fuel pinpoint landing on Mars with a nonconvex thrust bound."
    methods = (LOSSLESS, SCVX.replace(nodes=(10, 40, 120), options=ON_MESH),
               HERMITE_SIMPSON.replace(nodes=(10, 40, 200), options=ON_MESH))
    cost_label = "fuel"
    cost_unit = "kg"

    def parameter_vector(self, values: dict[str, float]) -> np.ndarray:
        return parameter_vector(values)

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

    def solve_transcription(self, transcription: Transcription, p: np.ndarray,
                            warm: WarmStart | None, ctx: SolveContext) -> OCPResult:
        """Nodes where the thrust switches, as the lossless method places them
        (`switch_mesh`): on equal steps a switch between ρ1 and ρ2 is a ramp over its
        interval whose fuel error depends on where in it the switch falls (SCvx at 30
        intervals: ± 0.066 kg, 45: ± 0.117, 60: ± 0.018). Solved first on a warm start's
        mesh when it has this many intervals (a slider move: one solve, or two when the
        switches moved), on the warm start's switches otherwise (another node count: the
        cost error estimate's second solve), on equal steps cold; then again on the
        answer's switch mesh until the mesh no longer moves. The iterates of every solve
        make one replay (`_joined`)."""
        n = transcription.N
        tau = None
        if warm is not None:
            tau = warm.tau if warm.n_intervals == n else _switch_mesh(
                n, warm.tau * warm.T, warm.U, warm.T, p)
        res = transcription.solve(p, warm, ctx, tau=tau)
        iterations, history = res.iterations, res.history
        for _ in range(ROUNDS):
            if res.status != "optimal":
                break
            mesh = _switch_mesh(n, res.t_nodes, res.U, res.T, p)
            if mesh is None or np.allclose(mesh, res.t_nodes / res.T, rtol=0.0,
                                           atol=SHORT / (2 * n)):
                break
            res = transcription.solve(p, res.warm, ctx, tau=mesh)
            history = _joined(history, res.history, iterations)
            iterations += res.iterations
        res.iterations, res.history = iterations, history
        return res

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        p = parameter_vector(values)
        problem.precheck(p)
        return solve_method(values, p, nodes, warm, ctx)

    _present = staticmethod(view.present)


def _joined(history: list[Iterate], later: list[Iterate], offset: int) -> list[Iterate]:
    """The iterates of a cold solve and of its re-solves on the switch mesh as one replay,
    numbered on: a re-solve's first (the last answer on the new mesh) only when it moved no
    further."""
    return history + [Iterate(offset + it.iteration, it.t, it.x) for it in later[1:] or later]


def _switch_mesh(n: int, t_nodes: np.ndarray, U: np.ndarray, T: float, p: np.ndarray
                 ) -> np.ndarray | None:
    """The mesh of n intervals with a short one at each thrust switch of an answer (node
    times, thrust vectors in N, final time); None when its switches leave no room."""
    switches = switch_times(t_nodes, np.linalg.norm(U, axis=1), p[P_RHO1], p[P_RHO2])
    return switch_mesh(n, [s / T for s in switches])


MISSION = PoweredDescent()
