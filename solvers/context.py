"""What a running solve may consult and how it stops: progress reporting, cancellation and a
deadline (`SolveContext`), and the three ways a solve ends early (`Infeasible`, `Cancelled`,
`TimeLimit`). Kept apart from `mission.py` so that the NLP back-ends and transcriptions,
which `Mission` calls, need not import `Mission` back (the knot of issue 18)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from .verify import time_budget

if TYPE_CHECKING:
    from .solution import Solution

ProgressCallback = Callable[[int, str], None]
# s: the time limit of a solve when the caller names none (`Mission.solve`, the CLI); a
# limit of None or 0 means none.
DEFAULT_TIME_LIMIT = 120.0


class Infeasible(Exception):
    """The request has no solution (a named physical or model bound); the message says why."""


class Cancelled(Exception):
    """A newer request or the user stopped the solve."""


class TimeLimit(Exception):
    """The solve ran past its time limit."""


@dataclass
class SolveContext:
    """What a running solve may consult: progress reporting, cancellation and a deadline."""

    progress: ProgressCallback | None = None
    cancel: threading.Event | None = None
    time_limit: float | None = None
    started: float = field(default_factory=time.perf_counter)
    iterations: int = 0

    def report(self, iteration: int, message: str = "") -> None:
        """Record progress; raise `Cancelled`/`TimeLimit` when the solve must stop."""
        self.iterations = iteration
        if self.progress is not None:
            self.progress(iteration, message)
        self.checkpoint()

    def checkpoint(self) -> None:
        if self.cancel is not None and self.cancel.is_set():
            raise Cancelled("cancelled by a newer request")
        if self.time_limit is not None and self.elapsed() > self.time_limit:
            raise TimeLimit(f"stopped at the time limit of {self.time_limit:g} s")

    def should_stop(self) -> bool:
        try:
            self.checkpoint()
        except (Cancelled, TimeLimit):
            return True
        return False

    def remaining(self) -> float | None:
        return None if self.time_limit is None else max(self.time_limit - self.elapsed(), 1e-3)

    def bound_check(self, sol: Solution) -> None:
        """Give the solution's deferred check what is left of the time limit: run whenever
        it is, it stops (`verify.CheckTimeLimit`, reported in its message) once that budget
        is spent, so solve plus check stay within the limit."""
        budget, checker = self.remaining(), sol.checker
        if budget is None or checker is None:
            return
        def budgeted() -> dict[str, float]:
            with time_budget(budget):
                return checker()

        sol.checker = budgeted

    def elapsed(self) -> float:
        return time.perf_counter() - self.started
