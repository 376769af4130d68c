"""Mesh refinement to an accuracy target: `Mission.solve(..., nodes="auto", tol=...)`.

Solve at a node count, re-propagate the control (the mission's check), and while the miss
exceeds a target (`Mission.accuracy_targets`) or the cost error estimate its target
(`solvers.cost_error`: a target of `Solution.targets` like the misses) solve again with more
nodes, warm-started from the previous answer, until every target is met, the method's
node cap is reached or a refinement no longer reduces the miss (`stalled`). Each step is
recorded in `Solution.mesh`: nodes, the headline miss, the worst miss relative to its
target, the largest interval error and the time the step took.

The choice: uniform refinement through the mission's own node count, not a non-uniform (h)
mesh. It is the one knob every method has, the paper's own methods included (integral
transformation segments, burn sub-intervals, LGL degree), the NLPs are built and cached per
node count, and a warm start re-interpolates across counts. The next count comes from the
observed convergence of the miss: with miss ~ N^-q, N_next = N (SAFETY r)^(1/q) where r is the
worst miss over its target and q is measured from the last two steps (the method's nominal
order before that: `transcription.convergence_order`), kept within [GROWTH_MIN N,
GROWTH_MAX N]. The interval errors (`Solution.interval_error`) show where a finer mesh would
be needed; an h-refinement that places nodes there would need every transcription to accept
a mesh instead of a count.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Mapping
from typing import TypedDict, Unpack

from .context import ProgressCallback
from .solution import Solution
from .solvable import SolvableMission
from .transcription import convergence_order

SAFETY = 2.0  # aim below the target by this factor
GROWTH_MIN, GROWTH_MAX = 1.25, 3.0
ORDER_MIN, ORDER_MAX = 1.0, 8.0
STALL = 0.7  # a step must cut the worst miss to this fraction of the one before


def next_nodes(steps: list[dict[str, float]], order: float, cap: int) -> int:
    """The node count predicted to meet the targets from the recorded steps."""
    n, ratio = steps[-1]["nodes"], steps[-1]["worst_ratio"]
    q = order
    if len(steps) > 1 and steps[-2]["worst_ratio"] > ratio > 0:
        q = math.log(steps[-2]["worst_ratio"] / ratio) / math.log(n / steps[-2]["nodes"])
        q = min(max(q, ORDER_MIN), ORDER_MAX)
    grow = (SAFETY * ratio) ** (1.0 / q) if math.isfinite(ratio) else GROWTH_MAX
    grow = min(max(grow, GROWTH_MIN), GROWTH_MAX)
    return int(min(cap, math.ceil(n * grow)))


def stalled(steps: list[dict[str, float]]) -> bool:
    """The last refinement did not reduce the worst miss by STALL: the error does not come
    from the mesh (e.g. a method's own solver tolerance, or a state constraint the control
    form cannot follow), so more nodes would not help."""
    return len(steps) > 1 and not steps[-1]["worst_ratio"] < STALL * steps[-2]["worst_ratio"]


def _step(sol: Solution, wall: float) -> dict[str, float]:
    """One refinement step's record."""
    ratios = [abs(v) / tol for v, tol in
              ((sol.check.get(k, math.inf), tol) for k, tol in sol.targets.items())]
    headline = next(iter(sol.targets), "")
    step = {"nodes": float(sol.nodes), "miss": float(sol.check.get(headline, math.nan)),
            "worst_ratio": max(ratios, default=math.nan), "solve_s": wall}
    if sol.interval_error is not None and len(sol.interval_error.t):
        step["max_interval_error"] = float(sol.interval_error.values.max())
    return step


class StepOptions(TypedDict, total=False):
    """What every refinement step passes on to `Mission.solve` unchanged."""

    tol: float | None
    backend: str | None
    progress: ProgressCallback | None
    cancel: threading.Event | None


def solve_auto(mission: SolvableMission, values: Mapping[str, float] | None, method: str | None,
               *, warm: Solution | None = None, cold: bool = False,
               time_limit: float | None = None, **step: Unpack[StepOptions]) -> Solution:
    """Refine until the re-propagated miss meets the targets (see the module docstring).
    The first step starts at the method's default node count (or at `warm`'s, when `warm` is
    a converged solution of the same method); every later step is warm-started from the
    step before, unless `cold` (every step from the initial guess, with no rescue).
    Returns the last converged step's solution with `mesh` filled in."""
    m = mission.method(method)
    mission.validate(values, m.key, None)
    mission.accuracy_targets(step.get("tol"))  # refuses a bad tol before any work
    usable = (warm is not None and warm.converged and warm.mission == mission.key
              and warm.method == m.key)
    n = warm.nodes if usable else m.nodes[1]
    cap = m.nodes[2]
    started = time.perf_counter()
    steps: list[dict[str, float]] = []
    best: Solution | None = None
    order = convergence_order(m.transcription)
    while True:
        remaining = None if time_limit is None else time_limit - (time.perf_counter() - started)
        if remaining is not None and remaining <= 0:
            break
        t0 = time.perf_counter()
        sol = mission.solve(values, m.key, n, warm=warm if usable else None, cold=cold,
                            time_limit=remaining, **step)
        steps.append(_step(sol, time.perf_counter() - t0))
        if not sol.converged:
            if best is None:
                best = sol
            break
        best = sol
        if not cold:
            warm, usable = sol, True
        if sol.status == "optimal" or n >= cap or stalled(steps):
            break
        n = next_nodes(steps, order, cap)
    best.mesh = steps
    best.stats["wall_s"] = time.perf_counter() - started  # the whole refinement
    best.message += _summary(best, steps, cap)
    return best


def _summary(sol: Solution, steps: list[dict[str, float]], cap: int) -> str:
    nodes = " → ".join(str(int(s["nodes"])) for s in steps)
    if sol.status == "optimal":
        return f" [auto nodes: {nodes}; every accuracy target met]"
    if not sol.converged or int(steps[-1]["nodes"]) != sol.nodes:
        return f" [auto nodes: {nodes}; refinement stopped: the last step did not converge]"
    if sol.nodes >= cap:
        return f" [auto nodes: {nodes}; stopped at the node cap {cap}]"
    if stalled(steps):
        return (f" [auto nodes: {nodes}; stopped: the last refinement did not reduce the miss, "
                "so its error does not come from the mesh]")
    return f" [auto nodes: {nodes}; stopped at the time limit]"
