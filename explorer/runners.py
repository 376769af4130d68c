"""Who runs a session's solves: on the solve service's worker processes (`ServiceRunner`, the
app), on a dask cluster (`ClusterRunner`, `--scheduler`: a lecture hall's exploring students
beyond one machine) or in this process (`LocalRunner`, for tests with missions of their own).
A runner blocks the session's own thread until the answer is there; the session's
`Request.cancel` event stops a solve early, wherever it runs."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Protocol

from solvers.cluster import check_on_worker, solve_on_worker
from solvers.mission import Mission
from solvers.request import SolveRequest
from solvers.service import Job, SolveService
from solvers.solution import Solution

Progress = Callable[[int, str], None]


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
    def start(self, mission: Mission, request: SolveRequest, *, warm: Solution | None,
              session: str, cancel: threading.Event, progress: Progress | None) -> Pending:
        """Start solving `request` on `mission`, warm from `warm` (None: cold) for
        `session`; `cancel` set from any thread stops it."""


class _LocalPending:
    def __init__(self, mission: Mission, request: SolveRequest, warm: Solution | None,
                 cancel: threading.Event, progress: Progress | None):
        self.mission, self.request, self.warm = mission, request, warm
        self.cancel_event, self.progress = cancel, progress
        self._solution: Solution | None = None

    def result(self) -> Solution:
        self._solution = self.request.run(self.mission, warm=self.warm, progress=self.progress,
                                          cancel=self.cancel_event, verify=False)
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

    def start(self, mission: Mission, request: SolveRequest, *, warm: Solution | None,
              session: str, cancel: threading.Event, progress: Progress | None) -> Pending:
        return _LocalPending(mission, request, warm, cancel, progress)


POLL_S = 0.02  # how often a waiting session looks at its cancel event


def _cancelled(mission: Mission, r: SolveRequest) -> Solution:
    """The answer a session gets for a solve it stopped waiting for."""
    return r.unanswered(mission, "cancelled", "cancelled by a newer request")


class _ServicePending:
    def __init__(self, job: Job, mission: Mission, cancel: threading.Event) -> None:
        self.job, self.mission, self.cancel_event = job, mission, cancel

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
            return _cancelled(self.mission, self.job.request)
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

    def start(self, mission: Mission, request: SolveRequest, *, warm: Solution | None,
              session: str, cancel: threading.Event, progress: Progress | None) -> Pending:
        job = self.service.submit(request, session=session, progress=progress,
                                  warm=None if request.cold else warm)
        return _ServicePending(job, mission, cancel)

    def forget(self, session: str) -> None:
        self.service.forget(session)


# A worker runs a waiting solve before a waiting check (as the solve service does): a check
# only refines what is already on screen.
SOLVE_PRIORITY, CHECK_PRIORITY = 10, 0


class _ClusterPending:
    """A solve on a dask cluster: the answer's future, then the deferred check run on the
    worker that holds the answer (its check closure stays there), added to this copy."""

    def __init__(self, client: Any, future: Any, mission: Mission, request: SolveRequest,
                 cancel: threading.Event) -> None:
        self.client, self.future, self.mission = client, future, mission
        self.request, self.cancel_event = request, cancel
        self._solution: Solution | None = None

    def _wait(self, future: Any) -> Any:
        """`future`'s result; None as soon as the request is cancelled (a remote
        exception, e.g. the `ValueError` of bad input, is raised here). It polls `done()`:
        `result(timeout=...)` of distributed 2026.8 may raise `UnboundLocalError` when its
        timeout expires, which a loaded room met on most solves."""
        while not future.done():
            if self.cancel_event.wait(POLL_S):
                future.cancel()
                return None
        return future.result()

    def result(self) -> Solution:
        sol = self._wait(self.future)
        if sol is None:
            return _cancelled(self.mission, self.request)
        self._solution = sol
        return sol

    def check(self) -> None:
        sol = self._solution
        if sol is None:
            return
        holders = self.client.who_has(self.future).get(self.future.key, ())
        checking = self.client.submit(check_on_worker, self.future, workers=list(holders),
                                      allow_other_workers=False, pure=False,
                                      priority=CHECK_PRIORITY)
        try:
            update = self._wait(checking)
        except Exception as exc:  # the check failed on the worker: said, not fatal
            sol.check["error"] = float("nan")
            sol.message += f" (re-propagation check failed: {exc})"
            sol.judge()
            return
        finally:
            self.future.release()
        if update is not None:
            update.apply(sol)

    def cancel(self) -> None:
        self.cancel_event.set()
        self.future.cancel()

    def discard(self) -> None:
        self.future.release()  # the worker frees the answer it kept for the check


class ClusterRunner:
    """Hands every solve to a dask.distributed cluster (`solvers.cluster`): where one
    machine cannot solve for a lecture hall. A worker cannot be interrupted: a cancelled
    solve runs on to its time limit there while the session goes on; following the
    teacher costs nothing (the room shares the teacher's answers)."""

    def __init__(self, client: Any, mission_files: tuple[str, ...] = ()) -> None:
        self.client, self.mission_files = client, tuple(mission_files)

    def start(self, mission: Mission, request: SolveRequest, *, warm: Solution | None,
              session: str, cancel: threading.Event, progress: Progress | None) -> Pending:
        if progress is not None:
            progress(0, "solving on the cluster")
        future = self.client.submit(solve_on_worker, request, None if request.cold else warm,
                                    self.mission_files, pure=False, priority=SOLVE_PRIORITY)
        return _ClusterPending(self.client, future, mission, request, cancel)

    def close(self) -> None:
        self.client.close()
