"""Local error on the path: every interval integrated on its own from its node state with
the method's own control, against the next node state.

For interval k, y_k(t_k+1) is the solution of x' = f(x, u(t), p) from x(t_k) = X_k, with u
exactly as the method defines it between nodes, by DOP853 (rtol 1e-10), and the local error
is e_k = y_k(t_k+1) - X_k+1: the collocation defect (or shooting error) that the NLP's own
equations cannot see. Unlike the terminal miss it says where the mesh is too coarse. All
intervals are integrated at once as one stacked system on s in [0, 1] (t = t_k + s h_k), so
the cost is one integration, not one per interval.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp

from . import state_box
from .solution import Series, Solution
from .solvable import SolvableMission
from .verify import RTOL, CheckTimeLimit, bounded, remaining_budget, time_budget

if TYPE_CHECKING:
    from .ocp import OCP, OCPResult

# s: the most the maximum-principle reference may take of a check's budget (see `checked`).
REFERENCE_S = 20.0
# Points inside each interval (besides its end) where the state box is checked.
BOX_SAMPLES = 7
# Control of all intervals at once: times (K,) -> controls (K, nu).
Controls = Callable[[np.ndarray], np.ndarray]


def local_paths(f: ca.Function, p: np.ndarray, t_nodes: np.ndarray, X: np.ndarray,
                controls: Controls, atol: np.ndarray, samples: int = 0
                ) -> tuple[np.ndarray, np.ndarray]:
    """Every interval's path from its node state under the method's control: (t, Y) with
    Y[j, k] the state of interval k at its fraction s_j of the way (s = (j+1)/(samples+1),
    the last row the interval's end), t[j, k] its time."""
    K, nx = len(t_nodes) - 1, X.shape[1]
    t0, h = t_nodes[:-1], np.diff(t_nodes)
    fmap = f.map(K)
    P = np.tile(np.asarray(p, float)[:, None], (1, K))

    def rhs(s: float, y: np.ndarray) -> np.ndarray:
        U = controls(t0 + s * h)
        dx = np.asarray(fmap(y.reshape(K, nx).T, U.T, P)).T
        return (dx * h[:, None]).ravel()

    s_eval = np.linspace(0.0, 1.0, samples + 2)[1:]
    sol = solve_ivp(bounded(rhs), (0.0, 1.0), X[:-1].ravel(), method="DOP853", rtol=RTOL,
                    atol=np.tile(np.asarray(atol, float) * np.ones(nx), K), t_eval=s_eval)
    if not sol.success:
        raise RuntimeError(f"interval integration failed: {sol.message}")
    return t0 + np.outer(s_eval, h), sol.y.T.reshape(len(s_eval), K, nx)


def local_errors(f: ca.Function, p: np.ndarray, t_nodes: np.ndarray, X: np.ndarray,
                 controls: Controls, atol: np.ndarray) -> np.ndarray:
    """(K, nx) errors e_k of the K = len(t_nodes) - 1 intervals (the states' units)."""
    return local_paths(f, p, t_nodes, X, controls, atol)[1][-1] - X[1:]


def box_check(sol: Solution, problem: OCP, p: np.ndarray, res: OCPResult,
              atol: np.ndarray | float) -> tuple[np.ndarray, dict[str, float]]:
    """The interval errors (K, nx) and the state-box check of the paths between nodes
    (`state_box.check`, BOX_SAMPLES points inside each interval besides its end)."""
    t, Y = local_paths(problem.functions().f, p, res.t_nodes, res.X, res.controls,
                       np.asarray(atol, float), BOX_SAMPLES)
    b = problem.bounds(p)
    nx = res.X.shape[1]
    units = problem.state_units or ("",) * nx
    box = state_box.check(sol, t.ravel(), Y.reshape(-1, nx), b.x_lb, b.x_ub, problem.x_scale,
                          problem.states, units)
    return Y[-1] - res.X[1:], box


def error_series(t_nodes: np.ndarray, norms: np.ndarray, name: str, unit: str) -> Series:
    """Interval errors at the interval midpoints."""
    mid = (t_nodes[:-1] + t_nodes[1:]) / 2
    return Series(mid, np.asarray(norms, float)[:, None], (name,), (unit,))


def record(sol: Solution, series: Series) -> None:
    """Store the interval errors and name the worst interval in the statistics."""
    sol.interval_error = series
    values = np.asarray(series.values)[:, 0]
    k = int(np.argmax(values))
    sol.stats["worst_interval"] = float(k)
    sol.stats["worst_interval_t"] = float(series.t[k])
    sol.stats["worst_interval_error"] = float(values[k])


def checked(mission: SolvableMission, sol: Solution, problem: OCP, p: np.ndarray, res: OCPResult
            ) -> dict[str, float]:
    """The deferred check of a general method: the re-propagated miss
    (`Mission.check_direct`), the local error of every interval in the headline's unit
    (`Mission.interval_error_norm`), the state box between nodes (`box_check`) and the
    indirect reference
    (`Mission.indirect_reference`)."""
    miss = mission.check_direct(problem, p, res)
    errors, box = box_check(sol, problem, p, res, mission.check_atol(problem))
    miss.update(box)
    norm = mission.interval_error_norm(errors)
    if norm is not None:
        record(sol, error_series(sol.node_t, norm[0], "error", norm[1]))
    try:
        # At most half of what is left and REFERENCE_S: the cost error estimate that
        # follows decides the status, the reference only informs (an Apollo case's indirect
        # shooting ran past 30 s and left the estimate no time).
        left = remaining_budget()
        with time_budget(None if left is None else min(left / 2, REFERENCE_S)):
            mission.indirect_reference(sol, p)
    except CheckTimeLimit:  # the miss stands; only the reference is missing
        sol.message += (" (the maximum-principle reference did not finish within its share "
                        "of the time limit)")
    return miss


def record_defects(mission: SolvableMission, sol: Solution, t: np.ndarray,
                   rows: np.ndarray) -> None:
    """A failed answer's dynamics constraints as `interval_error` ("defect"): where it
    fails, in the headline miss's unit; t in the OCP's time unit."""
    norm = mission.interval_error_norm(rows)
    if norm is not None:
        record(sol, Series(t, norm[0][:, None], ("defect",), (norm[1],)))
