"""CasADi NLP back ends (IPOPT, SQP, FATROP) behind one call, built once and re-solved warm.

An `NLP` is built from symbolic (x, f, g, p) once per (mission, method, node count) and then
solved many times with new numeric parameters, bounds and starting points. An iteration
callback reports progress, records a few iterate snapshots and stops the solver when the
request is cancelled or past its time limit (FATROP calls none: `fatrop`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ..context import Cancelled, SolveContext, TimeLimit
from .backends import backend as registered_backend
from .cache import BUILD_LOCK, built_once
from .exterior_penalty import penalty_functions, solve_exterior_penalty
from .fatrop import Stages, return_status

__all__ = ["NLP", "NLPResult", "built_once", "status_of"]

SNAPSHOT_ITERATIONS = frozenset({0, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89})
# Solver verdicts that stop short of a proof: at a point that satisfies the constraints to
# FEASIBLE (scaled) they are re-checked by a warm re-solve, never reported as infeasible.
STALLED = frozenset({"Infeasible_Problem_Detected", "Restoration_Failed",
                     "Error_In_Step_Computation", "Search_Direction_Becomes_Too_Small",
                     "Invalid_Number_Detected", "Feasible_Point_Found"})
FEASIBLE = 1e-8

_IPOPT_COMMON = {
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "print_time": False,
    "ipopt.tol": 1e-10,
    "ipopt.constr_viol_tol": 1e-9,
    "ipopt.max_iter": 3000,
}
_IPOPT_WARM = {
    "ipopt.warm_start_init_point": "yes",
    "ipopt.warm_start_bound_push": 1e-9,
    "ipopt.warm_start_bound_frac": 1e-9,
    "ipopt.warm_start_slack_bound_push": 1e-9,
    "ipopt.warm_start_slack_bound_frac": 1e-9,
    "ipopt.warm_start_mult_bound_push": 1e-9,
    "ipopt.mu_init": 1e-7,
}
_SQP = {
    "print_time": False,
    "print_header": False,
    "print_iteration": False,
    "print_status": False,
    "qpsol": "qrqp",
    # A time limit is checked between SQP iterations, so one QP must stay short: a qrqp
    # iteration costs ~35 ms on lunar landing's 30-interval multiple-shooting NLP, and its
    # default of 1000 held one SQP iteration 35 s past a 4 s limit off the defaults. The
    # missions' SQP solves take the same steps with 100 (costs and iteration counts equal).
    "qpsol_options": {"print_iter": False, "print_header": False, "print_info": False,
                      "error_on_fail": False, "max_iter": 100},
    # The exact Hessian with CasADi's convexification stalls on these problems; a BFGS
    # Hessian converges (slower than IPOPT: a teaching point, not the default).
    "hessian_approximation": "limited-memory",
    "lbfgs_memory": 30,
    "max_iter": 500,
    "tol_pr": 1e-9,
    "tol_du": 1e-7,
    "error_on_fail": False,
}


@dataclass
class NLPResult:
    """Primal/dual solution of one NLP solve, with the back end's own verdict."""

    x: np.ndarray
    f: float
    g: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    iterations: int
    return_status: str
    success: bool
    max_violation: float
    history: list[tuple[int, np.ndarray]] = field(default_factory=list)
    # The first verdict when a stalled solve at a feasible point was re-solved from it.
    rechecked: str = ""


class _IterationHook(ca.Callback):
    """CasADi iteration callback forwarding each iterate to the active solve's handler."""

    def __init__(self, name: str, nx: int, ng: int, np_: int) -> None:
        ca.Callback.__init__(self)
        self._sizes = {"x": nx, "lam_x": nx, "g": ng, "lam_g": ng, "lam_p": np_, "f": 1}
        self.handler: Callable[[int, np.ndarray], bool] | None = None
        self.count = 0
        self.construct(name, {})

    def get_n_in(self) -> int:
        return ca.nlpsol_n_out()

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return ca.nlpsol_out(i)

    def get_name_out(self, i: int) -> str:
        return "ret"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        n = self._sizes.get(ca.nlpsol_out(i), 0)
        return ca.Sparsity.dense(n, 1) if n else ca.Sparsity(0, 0)

    def eval(self, arg: list) -> list:
        stop = False
        if self.handler is not None:
            stop = self.handler(self.count, np.asarray(arg[0]).ravel())
        self.count += 1
        return [1 if stop else 0]


class NLP:
    """A parametric NLP  min f(x, p)  s.t.  lbg <= g(x, p) <= ubg,  lbx <= x <= ubx."""

    def __init__(
        self,
        x: ca.SX | ca.MX,
        f: ca.SX | ca.MX,
        g: ca.SX | ca.MX,
        p: ca.SX | ca.MX,
        backend: str = "ipopt",
        name: str = "nlp",
        ipopt_options: dict | None = None,
        stages: Stages | None = None,
    ) -> None:
        """`ipopt_options` are added to (and override) the common IPOPT settings, e.g.
        {"ipopt.mu_strategy": "adaptive"} for a problem that needs it. `stages`: the same
        problem in stage order, which the "fatrop" back end solves (and needs)."""
        with BUILD_LOCK:
            self._build(x, f, g, p, backend, name, ipopt_options, stages)

    def _build(self, x, f, g, p, backend: str, name: str, ipopt_options: dict | None,
               stages: Stages | None) -> None:
        if registered_backend(backend).kind != "nlp":
            raise ValueError(f"back end '{backend}' does not solve a general NLP")
        if backend == "fatrop" and stages is None:
            raise ValueError("back end 'fatrop' needs the NLP in stage order (variables stage "
                             "by stage, gap constraints tying each stage to the next); this "
                             "method builds none")
        self.backend = backend
        self.n_x = int(x.numel())
        self.n_g = int(g.numel())
        self.n_p = int(p.numel())
        self._problem = {"x": x, "f": f, "g": g, "p": p}
        self._ipopt_options = dict(ipopt_options or {})
        self._name = name
        self._stages = stages
        # The original constraints at a staged solution's point (FATROP solves a copy).
        self._g_of = ca.Function(f"{name}_g", [x, p], [g]) if stages is not None else None
        self._hook = _IterationHook(f"{name}_hook", self.n_x, self.n_g, self.n_p)
        self._solvers: dict[bool, ca.Function] = {}
        self._penalty_parts: ca.Function | None = None
        # CasADi builds are not thread-safe and IPOPT's MUMPS keeps global state: in one
        # process, one build or solve at a time. The solve service runs one solve per worker
        # process, so this lock is never contended there.
        self._lock = BUILD_LOCK

    def _solver(self, warm: bool) -> ca.Function:
        key = warm and self.backend in ("ipopt", "fatrop")
        if key not in self._solvers:
            if self.backend == "fatrop":
                self._solvers[key] = self._stages.solver(self._name, self._problem["p"], key)
            elif self.backend == "ipopt":
                opts = {**_IPOPT_COMMON, **self._ipopt_options, **(_IPOPT_WARM if key else {})}
                opts["iteration_callback"] = self._hook
                self._solvers[key] = ca.nlpsol(self._name, "ipopt", self._problem, opts)
            else:
                opts = dict(_SQP, iteration_callback=self._hook)
                self._solvers[key] = ca.nlpsol(self._name, "sqpmethod", self._problem, opts)
        return self._solvers[key]

    def solve(
        self,
        x0: np.ndarray,
        p: np.ndarray,
        lbx: np.ndarray,
        ubx: np.ndarray,
        lbg: np.ndarray,
        ubg: np.ndarray,
        lam_x0: np.ndarray | None = None,
        lam_g0: np.ndarray | None = None,
        ctx: SolveContext | None = None,
    ) -> NLPResult:
        """Solve once; raises `Cancelled`/`TimeLimit` when the context asks to stop."""
        stop_reason: list[Exception] = []

        def on_iteration(k: int, x: np.ndarray) -> bool:
            if ctx is None:
                return False
            try:
                ctx.report(k, f"iteration {k}")
            except (Cancelled, TimeLimit) as exc:
                stop_reason.append(exc)
                return True
            return False

        if self.backend == "penalty-bfgs":
            return self._solve_penalty(x0, p, lbx, ubx, lbg, ubg, ctx)
        res = self._solve_once(x0, p, lbx, ubx, lbg, ubg, lam_x0, lam_g0, on_iteration,
                               stop_reason)
        first = res
        for duals in (True, False):
            if res.success or res.return_status not in STALLED or res.max_violation > FEASIBLE:
                break
            # A solver verdict at a point that satisfies the constraints proves nothing:
            # re-check the point by a warm re-solve from it (it is often optimal), with its
            # multipliers, then without them (a stall's multipliers may be what stalls: a
            # CW free-structure case stalled again with them and converged without, 0.8 s).
            again = self._solve_once(res.x, p, lbx, ubx, lbg, ubg,
                                     res.lam_x if duals else None,
                                     res.lam_g if duals else None, on_iteration, stop_reason)
            again.iterations += res.iterations
            again.history = res.history + again.history
            again.rechecked = first.return_status
            res = again
        return res

    def _solve_once(self, x0, p, lbx, ubx, lbg, ubg, lam_x0, lam_g0, on_iteration,
                    stop_reason: list[Exception]) -> NLPResult:
        warm = lam_x0 is not None and lam_g0 is not None
        history: list[tuple[int, np.ndarray]] = []

        def hook(k: int, x: np.ndarray) -> bool:
            if k in SNAPSHOT_ITERATIONS:
                history.append((k, x.copy()))
            return on_iteration(k, x)

        args = {"x0": x0, "p": p, "lbx": lbx, "ubx": ubx, "lbg": lbg, "ubg": ubg}
        staged = self.backend == "fatrop"
        if staged:  # FATROP calls back no iterate: a stop is checked before and after it
            hook(0, np.asarray(x0, float))
            if stop_reason:
                raise stop_reason[0]
            args = self._stages.arguments(x0, p, lbx, ubx, lbg, ubg)
        elif warm:
            args.update(lam_x0=lam_x0, lam_g0=lam_g0)
        out, stats = self._call(warm, args, hook)
        if staged:
            out = self._stages.original(out, self._g_of, p)
            stats["return_status"] = return_status(stats)
            on_iteration(int(stats.get("iter_count", 0)), out["x"])
        if stop_reason:
            raise stop_reason[0]
        x = np.asarray(out["x"]).ravel()
        g = np.asarray(out["g"]).ravel()
        violation = max(
            float(np.max(np.maximum(lbg - g, 0.0), initial=0.0)),
            float(np.max(np.maximum(g - ubg, 0.0), initial=0.0)),
        )
        return NLPResult(
            x=x,
            f=float(out["f"]),
            g=g,
            lam_x=np.asarray(out["lam_x"]).ravel(),
            lam_g=np.asarray(out["lam_g"]).ravel(),
            iterations=int(stats.get("iter_count", len(history))),
            return_status=str(stats.get("return_status", "")),
            success=bool(stats.get("success", False)),
            max_violation=violation,
            history=history,
        )

    def _call(self, warm: bool, args: dict, hook: Callable[[int, np.ndarray], bool]
              ) -> tuple[dict, dict]:
        """One call of the built solver (outputs, statistics), its iterations to `hook`."""
        with self._lock:
            solver = self._solver(warm)
            self._hook.handler = hook
            self._hook.count = 0
            try:
                out = solver(**args)
            finally:
                self._hook.handler = None
            return out, solver.stats()

    def _solve_penalty(self, x0, p, lbx, ubx, lbg, ubg, ctx) -> NLPResult:
        """The exterior penalty method (paper 000, eq. 12) on the same NLP."""
        with BUILD_LOCK:
            if self._penalty_parts is None:
                pr = self._problem
                self._penalty_parts = penalty_functions(pr["x"], pr["f"], pr["g"], pr["p"])
            parts = self._penalty_parts
        z, f, g, iterations, converged, history = solve_exterior_penalty(
            parts, np.asarray(x0, float), np.asarray(p, float), np.asarray(lbx, float),
            np.asarray(ubx, float), np.asarray(lbg, float), np.asarray(ubg, float), ctx,
        )
        violation = max(
            float(np.max(np.maximum(lbg - g, 0.0), initial=0.0)),
            float(np.max(np.maximum(g - ubg, 0.0), initial=0.0)),
        )
        return NLPResult(
            x=z, f=f, g=g, lam_x=np.zeros_like(z), lam_g=np.zeros_like(g),
            iterations=iterations,
            return_status="Solve_Succeeded" if converged else "Penalty_Not_Converged",
            success=converged, max_violation=violation, history=history,
        )


def status_of(result: NLPResult) -> tuple[str, str]:
    """Map a back end's return status to the Solution vocabulary and a human message.

    A solver never proves a request impossible here: "infeasible" is only for a named
    physical bound (`Mission.precheck`). A local infeasibility is "failed" with the
    violation it stopped at; a stalled solve at a feasible point (re-solved once from it by
    `NLP.solve`) says that the solver did not converge from this guess."""
    rs = result.return_status
    again = f" (re-solved from a feasible point after {result.rechecked})" \
        if result.rechecked else ""
    if result.success or rs in ("Solve_Succeeded", "Solved_To_Acceptable_Level"):
        return "optimal", f"converged in {result.iterations} iterations{again}"
    if "Maximum_Iter" in rs:
        return "iteration-limit", f"stopped at the iteration limit ({result.iterations})"
    if result.max_violation <= FEASIBLE and rs != "Penalty_Not_Converged":
        return "failed", (
            f"the solver did not converge from this guess: it stopped ({rs}) at a point that "
            f"satisfies the constraints (violation {result.max_violation:.2g}) without "
            "proving it optimal; try another guess, more iterations or a warm start")
    if "Infeasib" in rs or rs in ("Restoration_Failed",):
        return "failed", (
            f"the solver found no feasible trajectory from this guess ({rs}, constraint "
            f"violation {result.max_violation:.2g}): the request may be impossible, or the "
            "guess too poor (no physical bound proves it impossible)")
    if rs == "Penalty_Not_Converged":
        return "iteration-limit", (
            f"the exterior penalty method stopped at its largest penalty factor with constraint "
            f"violation {result.max_violation:.2g}"
        )
    if "Time" in rs:
        return "time-limit", "stopped at the time limit"
    return "failed", f"the NLP solver stopped without converging ({rs or 'unknown status'})"
