"""The newest of a stream of actions, run a moment after the first of them: the plots of an
answer leave after its picture. viser's page applies a batch that touches only the GUI at
once, and a plotly redraw holds the page's main thread (100-150 ms for lunar landing's six
plots under software WebGL, measured in the page); sent with the scene, it ran before the
frame that shows the new path. Sent `delay` later, the picture comes first, and during a
drag (10 answers a second) the plots redraw at most once a `delay` with the newest answer
instead of falling behind the hand."""

from __future__ import annotations

import threading
import time
import traceback
from collections.abc import Callable

Action = Callable[[], None]


class Deferred:
    """Runs the newest `post`ed action `delay` s after the oldest still waiting (a throttle,
    not a debounce: a steady stream still shows), on a thread of its own."""

    def __init__(self, delay: float) -> None:
        self.delay = delay
        self._wake = threading.Condition()
        self._action: Action | None = None
        self._due = 0.0
        self._closed = False
        self._running = False
        self._thread: threading.Thread | None = None

    def post(self, action: Action) -> None:
        with self._wake:
            if self._action is None:
                self._due = time.monotonic() + self.delay
            self._action = action
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, daemon=True,
                                                name="deferred")
                self._thread.start()
            self._wake.notify()

    def cancel(self) -> None:
        """Drop the waiting action (something newer was shown at once)."""
        with self._wake:
            self._action = None

    def flush(self) -> None:
        """Run the waiting action now (tests, exports)."""
        with self._wake:
            action, self._action = self._action, None
        if action is not None:
            action()

    @property
    def waiting(self) -> bool:
        """An action waits or runs."""
        return self._action is not None or self._running

    def close(self) -> None:
        with self._wake:
            self._closed, self._action = True, None
            self._wake.notify()

    def _run(self) -> None:
        while True:
            with self._wake:
                while not self._closed and (self._action is None
                                            or time.monotonic() < self._due):
                    self._wake.wait(None if self._action is None
                                    else max(0.0, self._due - time.monotonic()))
                if self._closed:
                    return
                action, self._action, self._running = self._action, None, True
            try:
                action()
            except Exception:  # noqa: BLE001 - the thread serves every later action too
                traceback.print_exc()
            finally:
                self._running = False
