"""The newest-request-wins queue of one session: one waiting request at most, run on the
queue's own thread; a newer request cancels the running one (or, with `patience`, lets a young
one's solve finish so a slider drag shows its intermediate optima; a check is never waited
for) and replaces the waiting one."""

from __future__ import annotations

import threading
import time
import traceback
from collections.abc import Callable

from .requests import Request


class RequestQueue:
    """Runs `run(request)` for the newest request on one thread; never two at once."""

    def __init__(self, run: Callable[[Request], None], patience: float = 0.0) -> None:
        self.patience = patience
        self._run = run
        self._cond = threading.Condition()
        self._pending: Request | None = None
        self._running: Request | None = None
        self._newest = 0
        self._delivered = 0
        self._closed = False
        self._thread = threading.Thread(target=self._work, name="explorer-session", daemon=True)
        self._thread.start()

    def put(self, request: Request) -> None:
        """Queue `request`: it supersedes the waiting one and the running one."""
        with self._cond:
            running = self._running
            if running is not None:
                age = time.monotonic() - running.started
                if (age < self.patience and not running.answered.is_set()
                        and not running.compare and not request.compare):
                    running.superseded.set()
                    timer = threading.Timer(self.patience - age, self._give_up, (running,))
                    timer.daemon = True
                    timer.start()
                else:
                    running.cancel.set()
            if self._pending is not None:
                self._pending.cancel.set()
            self._pending = request
            self._newest = request.seq
            self._cond.notify_all()

    def _give_up(self, request: Request) -> None:
        """A superseded solve that is still running after `patience`: cancel it."""
        with self._cond:
            if self._running is request:
                request.cancel.set()

    @property
    def busy(self) -> bool:
        with self._cond:
            return self._pending is not None or self._running is not None

    def wait_idle(self, timeout: float | None = None) -> bool:
        """Block until the newest request has been delivered (result, check or error)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self._cond:
            while self._delivered < self._newest and not self._closed:
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(left)
            return True

    def close(self) -> None:
        """Stop the thread, cancelling the running and the waiting request."""
        with self._cond:
            self._closed = True
            for request in (self._running, self._pending):
                if request is not None:
                    request.cancel.set()
            self._cond.notify_all()

    def drop(self) -> None:
        """Cancel the running and the waiting request; nothing is owed to the caller."""
        with self._cond:
            for request in (self._running, self._pending):
                if request is not None:
                    request.cancel.set()
            self._pending = None
            self._delivered = self._newest
            self._cond.notify_all()

    def stale(self, request: Request) -> bool:
        """Superseded and cancelled, or the queue is closed: its answer is not wanted."""
        return request.cancel.is_set() or self._closed

    def _work(self) -> None:
        while True:
            with self._cond:
                while self._pending is None and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                request, self._pending = self._pending, None
                self._running = request
            try:
                self._run(request)
            except Exception:  # noqa: BLE001 - the session's thread must survive anything
                traceback.print_exc()
            finally:
                with self._cond:
                    self._running = None
                    if not self.stale(request):
                        self._delivered = max(self._delivered, request.seq)
                    self._cond.notify_all()
