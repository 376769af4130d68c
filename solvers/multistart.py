"""Answers that do not depend on history, or say so: a few cold solves from different
guesses; the best is kept and the number of distinct optima met is reported.

The guesses vary the method's guess parameters (`Param.guess`: e.g. the hovercraft's T and
α guesses, the lunar paper method's ψ guess and σ): start 0 uses the request's own values,
the others a Halton sequence over the parameters' ranges (deterministic, so a multi-start is
itself reproducible). Every start is cold (`warm=None`). A method without guess parameters
has one cold start only, and says so. Two converged answers are the same optimum when their
costs agree to `SAME_OPTIMUM` (relative).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Mapping
from typing import TYPE_CHECKING

from .problem import Param
from .solution import Solution

if TYPE_CHECKING:
    from .context import ProgressCallback
    from .solvable import SolvableMission

SAME_OPTIMUM = 1e-5
PRIMES = (2, 3, 5, 7, 11, 13)


def halton(index: int, base: int) -> float:
    """The `index`-th element (from 1) of the van der Corput sequence in `base`."""
    out, f = 0.0, 1.0
    while index > 0:
        f /= base
        out += f * (index % base)
        index //= base
    return out


def guess_values(params: tuple[Param, ...], values: Mapping[str, float], starts: int
                 ) -> list[dict[str, float]]:
    """`starts` value sets: the request's own, then Halton points over the guess
    parameters' ranges (choices and integers rounded)."""
    guesses = [p for p in params if p.guess][: len(PRIMES)]
    out = [dict(values)]
    for i in range(1, starts):
        point = dict(values)
        for param, base in zip(guesses, PRIMES, strict=False):
            v = param.min + halton(i, base) * (param.max - param.min)
            point[param.key] = float(round(v)) if (param.integer or param.options) else v
        out.append(point)
    return out


def distinct_optima(costs: list[float]) -> list[float]:
    """The distinct values among converged costs (agreeing to SAME_OPTIMUM are one)."""
    found: list[float] = []
    for c in sorted(costs):
        if not found or abs(c - found[-1]) > SAME_OPTIMUM * max(abs(c), abs(found[-1]), 1e-12):
            found.append(c)
    return found


def multistart(
    mission: SolvableMission,
    values: Mapping[str, float] | None,
    method: str | None,
    nodes: int | str | None = None,
    *,
    starts: int = 4,
    tol: float | None = None,
    backend: str | None = None,
    progress: ProgressCallback | None = None,
    cancel: threading.Event | None = None,
    time_limit: float | None = None,
) -> Solution:
    """Solve from `starts` cold guesses and keep the best converged answer (optimal before
    inaccurate, then the least cost). Its `stats` gain `starts`, `converged_starts` and
    `distinct_optima`, its message the costs found; `Solution.starts` lists every start."""
    vals, m, _ = mission.validate(values, method, None if nodes == "auto" else nodes)
    params = mission.all_params(m.key)
    points = guess_values(params, vals, starts if any(p.guess for p in params) else 1)
    started = time.perf_counter()
    solutions: list[Solution] = []
    for point in points:
        remaining = None if time_limit is None else time_limit - (time.perf_counter() - started)
        if remaining is not None and remaining <= 0:
            break
        solutions.append(mission.solve(point, m.key, nodes, tol=tol, backend=backend,
                                       progress=progress, cancel=cancel, time_limit=remaining))
        if solutions[-1].status == "cancelled":
            break
    done = [s for s in solutions if s.converged]
    best = min(done, key=lambda s: (s.status != "optimal", s.cost.value)) if done else \
        solutions[0]
    optima = distinct_optima([s.cost.value for s in done if math.isfinite(s.cost.value)])
    best.stats.update(starts=float(len(solutions)), converged_starts=float(len(done)),
                      distinct_optima=float(len(optima)),
                      wall_s=time.perf_counter() - started)  # every start
    best.starts = [_start(s, params) for s in solutions]
    best.message += _summary(best, len(solutions), len(done), optima, len(points) == 1)
    return best


def _start(sol: Solution, params: tuple[Param, ...]) -> dict[str, float]:
    row = {"cost": float(sol.cost.value), "converged": float(sol.converged)}
    row.update({p.key: sol.values[p.key] for p in params if p.guess and p.key in sol.values})
    return row


def _summary(best: Solution, n: int, converged: int, optima: list[float], single: bool
             ) -> str:
    if single:
        return " [multi-start: this method has no guess parameters, one cold start]"
    costs = ", ".join(f"{c:.6g}" for c in optima)
    return (f" [multi-start: {n} cold starts, {converged} converged, {len(optima)} distinct "
            f"optim{'um' if len(optima) == 1 else 'a'} ({costs} {best.cost.unit}); the best "
            "is shown]")
