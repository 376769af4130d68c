"""The cost error estimate of an answer: how far its cost is from the true optimum.

The method's own error control: the same request is solved again on a finer mesh (1.5
times the nodes, or fewer at the node cap: `reference_nodes`), warm-started from the
answer, and the two costs are Richardson-extrapolated with the method's order of
convergence (`transcription.convergence_order`): with J_N - J* ~ C N^-q, the error of J_N is
|J_N - J_M| / |1 - (N/M)^q| (`richardson`). It runs in the deferred check, after the
re-propagation, within what is left of the check's time budget. An answer is "optimal" only
when the estimate is within the cost target (`COST_RTOL` of |J|, or the mission's tighter
`cost_rtol`): the estimate is stored in `Solution.check` with its target in
`Solution.targets`, so `Solution.judge` and the refinement treat it like a miss.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from .solution import Label, Solution
from .solvable import SolvableMission
from .transcription import convergence_order
from .verify import checkpoint, remaining_budget, stop_requested

if TYPE_CHECKING:
    from .problem import Method

KEY = "cost_error_estimate"
COST_RTOL = 1e-4  # default cost target, relative to |J|
# Added to the estimate (relative to |J|): what the NLP's own convergence leaves (IPOPT's
# tol is 1e-10 on the scaled problem; Bryson–Denham, whose arc ends fall on the nodes, is
# 5e-9 off), which a finer mesh returning the same cost does not remove.
FLOOR_RTOL = 1e-8
GROWTH = 1.5  # node count of the second solve over the answer's (see `reference_nodes`)


def richardson(cost: float, other: float, nodes: int, other_nodes: int, order: float) -> float:
    """The error of `cost` (at `nodes`) from a second solve at `other_nodes`. From a coarser
    solve the order is taken as 1: a nominal order the problem does not reach (bang-bang
    arcs converge at order 1 to 2) would shrink the estimate below the error; from a finer
    one the nominal order errs on the safe side (a lower true order q gives an error at most
    (1 - r^order) / (1 - r^q) times the estimate, r = nodes / other_nodes: 2.4 for
    r = 2/3, order 4 and q = 1)."""
    ratio = nodes / other_nodes
    factor = abs(1.0 - ratio ** (order if ratio < 1 else 1.0))
    return abs(cost - other) / factor + FLOOR_RTOL * abs(cost)


def reference_nodes(method: Method, nodes: int) -> int | None:
    """The node count of the second solve: 1.5 times as many, else (near the cap) the cap
    or two thirds. Not twice as many: where a switch falls in the mesh the error need not
    shrink smoothly with the node count (bang-bang Hermite–Simpson: an odd count puts the
    switch on a midpoint, 4 times closer than an even one), and N and 2N can then agree by
    accident far from the optimum."""
    lo, _, hi = method.nodes
    finer = math.ceil(GROWTH * nodes)
    if finer <= hi:
        return finer
    if hi >= 1.25 * nodes:
        return hi
    coarser = math.floor(nodes / GROWTH)
    return coarser if lo <= coarser < nodes else None


def order(method: Method) -> float:
    """The method's order of convergence of the cost in its node count."""
    return convergence_order(method.transcription)


def estimate(mission: SolvableMission, sol: Solution, method: Method) -> tuple[float, str]:
    """(estimate, note): the absolute cost error of `sol` in its cost's unit, or NaN and
    why there is none."""
    other = reference_nodes(method, sol.nodes)
    if other is None:
        return math.nan, "it has no second node count to compare with"
    cancel = threading.Event()

    def watch(_iteration: int, _message: str) -> None:
        if stop_requested():
            cancel.set()

    finer = mission.solve(sol.values, method.key, other, backend=sol.backend or None,
                          warm=sol, progress=watch, cancel=cancel,
                          time_limit=remaining_budget(), verify=False)
    checkpoint()  # interrupted: the check runs again later
    if not finer.converged:
        return math.nan, f"the solve with {other} {method.nodes_label} ended {finer.status}"
    sol.stats["cost_reference_nodes"] = float(other)
    return richardson(sol.cost.value, finer.cost.value, sol.nodes, other, order(method)), ""


def with_estimate(mission: SolvableMission, sol: Solution, method: Method,
                  checker: Callable[[], dict[str, float]]) -> Callable[[], dict[str, float]]:
    """`checker` followed by the cost error estimate (see the module docstring)."""

    def checked() -> dict[str, float]:
        check = checker()
        if not math.isfinite(sol.cost.value):
            return check
        started = time.perf_counter()
        try:
            value, note = estimate(mission, sol, method)
        except Exception as exc:  # noqa: BLE001 - a failed estimate is reported, not fatal
            value, note = math.nan, f"it failed: {exc}"
        sol.cost.error_estimate = value
        sol.stats["cost_error_s"] = time.perf_counter() - started
        if not math.isfinite(value):
            sol.message += f" (no cost error estimate: {note})"
            if reference_nodes(method, sol.nodes) is None:
                return check
        # An estimate that was tried and did not come (its second solve failed or ran out
        # of time) stays in the check as NaN: the answer's cost error is unknown, and
        # `Solution.judge` does not call it optimal.
        rtol = min(COST_RTOL, mission.cost_rtol)
        sol.targets[KEY] = rtol * abs(sol.cost.value)
        sol.labels[KEY] = Label("estimated cost error", sol.cost.unit)
        return {**check, KEY: value}

    return checked


def attach(mission: SolvableMission, sol: Solution, method: Method) -> None:
    """Make `sol`'s deferred check estimate its cost error too (a converged answer only)."""
    if sol.status == "optimal" and sol.checker is not None:
        sol.checker = with_estimate(mission, sol, method, sol.checker)
