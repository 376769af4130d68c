"""One solve handed to the solve service (`pool.SolveService.submit`): the caller waits on
it for the answer and then for its re-propagation check, which may arrive later."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from ..request import SolveRequest
from ..solution import Solution

Progress = Callable[[int, str], None]


class Job:
    """One solve handed to the service: wait for `result()`, then (optionally) `check()`."""

    def __init__(self, job_id: int, request: SolveRequest, session: str,
                 progress: Progress | None, grace: float, cancel: Callable[[Job], None], *,
                 warm: Solution | None = None, verify: bool = True,
                 test_hook: str | None = None) -> None:
        """`grace`: s past the time limit before the service gives up on the worker;
        `cancel`: the service's way to stop this job; `verify`: run the re-propagation
        check after the answer; `test_hook`: "hang" / "crash" / "stop" (test hooks only)."""
        self.id, self.request, self._grace, self._cancel = job_id, request, grace, cancel
        self.warm, self.verify, self.test_hook = warm, verify, test_hook
        self.session, self.progress = session, progress
        self.solution: Solution | None = None
        self.error: str | None = None
        self.done = threading.Event()
        self.checked = threading.Event()
        self.worker: int | None = None
        self.started: float | None = None
        self.blank: Solution | None = None  # its answer if none comes (sent at begin)

    @property
    def deadline(self) -> float | None:
        limit = self.request.time_limit
        if self.started is None or limit is None:
            return None
        return self.started + limit + self._grace

    def result(self, timeout: float | None = None) -> Solution:
        """The answer (any status); `ValueError` for bad input, `TimeoutError` if none came
        within `timeout`."""
        if not self.done.wait(timeout):
            raise TimeoutError(f"no answer within {timeout:g} s")
        if self.error is not None:
            raise ValueError(self.error)
        assert self.solution is not None
        return self.solution

    def check(self, timeout: float | None = None) -> bool:
        """Wait until the re-propagation check has been filled into `result()`."""
        return self.checked.wait(timeout)

    def checked_result(self) -> Solution:
        """The answer with its check, waited for in short slices (Ctrl-C stays prompt). The
        check gets what the solve left of the time limit; one not back by the hard deadline
        (limit plus grace) is given up, and the answer says that its accuracy is unknown."""
        while not self.done.wait(0.1):
            pass
        sol = self.result()
        while not self.checked.wait(0.1):
            if self.deadline is not None and time.monotonic() > self.deadline:
                sol.check["error"] = float("nan")
                sol.message += (" (the re-propagation check did not finish within the time "
                                f"limit of {self.request.time_limit:g} s)")
                sol.judge()
                break
        return sol

    def cancel(self) -> None:
        self._cancel(self)

    def _finish(self, solution: Solution | None = None, error: str | None = None,
                checked: bool = True) -> None:
        self.solution, self.error = solution, error
        self.done.set()
        if checked:
            self.checked.set()
