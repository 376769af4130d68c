"""Who runs a session's solves: on the solve service's worker processes (`ServiceRunner`, the
app) or in this process (`LocalRunner`, for tests with missions of their own). A runner blocks the
session's own thread until the answer is there; the session's `Request.cancel` event stops a
solve early, wherever it runs."""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Protocol

from solvers.mission import Mission
from solvers.multistart import multistart
from solvers.service import Job, SolveService, SolveSpec
from solvers.solution import Solution

Progress = Callable[[int, str], None]


@dataclass(frozen=True)
class Solve:
    """One solve of a request (a session's request, or one method of a comparison)."""

    mission: Mission
    method: str
    nodes: int | str  # a count, or "auto": refine until the accuracy targets are met
    backend: str | None
    values: Mapping[str, float]
    warm: Solution | None
    time_limit: float | None
    session: str = ""
    cold: bool = False  # from the initial guess (and every refinement step too)
    starts: int = 1  # several cold starts, keep the best


class Pending(Protocol):
    """A solve under way."""

    def result(self) -> Solution:
        """Block until the solve has answered (any status); raises `ValueError` for bad
        input."""

    def check(self) -> None:
        """Block until the solution's deferred re-propagation check has been filled in."""

    def cancel(self) -> None:
        """Stop the solve (and its check) early."""

    def discard(self) -> None:
        """The answer is in and no check will be asked for: release what is kept for it."""


class Runner(Protocol):
    def start(self, solve: Solve, cancel: threading.Event, progress: Progress | None
              ) -> Pending:
        """Start a solve; `cancel` set from any thread stops it."""


class _LocalPending:
    def __init__(self, solve: Solve, cancel: threading.Event, progress: Progress | None):
        self.solve, self.cancel_event, self.progress = solve, cancel, progress
        self._solution: Solution | None = None

    def result(self) -> Solution:
        s = self.solve
        if s.starts > 1:
            self._solution = multistart(s.mission, dict(s.values), s.method, s.nodes,
                                        starts=s.starts, backend=s.backend)
            return self._solution
        self._solution = s.mission.solve(
            dict(s.values), s.method, s.nodes, backend=s.backend, warm=s.warm, cold=s.cold,
            progress=self.progress, cancel=self.cancel_event, time_limit=s.time_limit,
            verify=False)
        return self._solution

    def check(self) -> None:
        if self._solution is not None:
            self._solution.run_check()

    def cancel(self) -> None:
        self.cancel_event.set()

    def discard(self) -> None:
        self._solution = None


class LocalRunner:
    """Solves in the calling thread of this process (no isolation: tests, scripts)."""

    def start(self, solve: Solve, cancel: threading.Event, progress: Progress | None
              ) -> Pending:
        return _LocalPending(solve, cancel, progress)


POLL_S = 0.02  # how often a waiting session looks at its cancel event


class _ServicePending:
    def __init__(self, job: Job, solve: Solve, cancel: threading.Event) -> None:
        self.job, self.solve, self.cancel_event = job, solve, cancel

    def _wait(self, event: threading.Event) -> bool:
        """Wait for `event`; False as soon as the request is cancelled (the job is told to
        stop and finishes in the background)."""
        while not event.wait(POLL_S):
            if self.cancel_event.is_set():
                self.job.cancel()
                return False
        return True

    def result(self) -> Solution:
        if not self._wait(self.job.done):
            s = self.solve
            nodes = s.nodes if isinstance(s.nodes, int) else s.mission.method(s.method).nodes[1]
            return s.mission.empty(dict(s.values), s.mission.method(s.method), nodes,
                                   s.backend or "", "cancelled", "cancelled by a newer request")
        return self.job.result()

    def check(self) -> None:
        self._wait(self.job.checked)

    def cancel(self) -> None:
        self.cancel_event.set()
        self.job.cancel()

    def discard(self) -> None:
        if not self.job.checked.is_set():
            self.job.cancel()


class ServiceRunner:
    """Hands every solve to the solve service (worker processes), tagged with the session
    so it sticks to one worker while it can."""

    def __init__(self, service: SolveService) -> None:
        self.service = service

    def start(self, solve: Solve, cancel: threading.Event, progress: Progress | None
              ) -> Pending:
        spec = SolveSpec(solve.mission.key, solve.method, solve.nodes, solve.backend,
                         dict(solve.values), None if solve.cold else solve.warm,
                         solve.time_limit, starts=solve.starts, cold=solve.cold)
        job = self.service.submit(spec, session=solve.session, progress=progress)
        return _ServicePending(job, solve, cancel)

    def forget(self, session: str) -> None:
        self.service.forget(session)
