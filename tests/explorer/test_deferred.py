"""The plots of an answer follow its picture (explorer/deferred.py): the newest action
runs a moment after the oldest waiting one, a steady stream still shows, and an action
shown at once drops the waiting one."""

from __future__ import annotations

import threading
import time

from explorer.deferred import Deferred


def _until(condition, timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.005)


def test_the_newest_action_runs_once_after_the_delay():
    ran: list[int] = []
    later = Deferred(0.2)
    started = time.monotonic()
    for i in range(5):
        later.post(lambda i=i: ran.append(i))
    assert ran == [] and later.waiting
    _until(lambda: ran)
    assert time.monotonic() - started >= 0.2
    _until(lambda: not later.waiting)
    assert ran == [4]  # only the newest of the burst
    later.close()


def test_a_steady_stream_shows_at_the_delays_pace():
    """A throttle, not a debounce: posts every 20 ms for 0.6 s still run about every 0.1 s
    (a drag's plots follow the hand instead of waiting for it to stop)."""
    ran: list[float] = []
    later = Deferred(0.1)
    stop = time.monotonic() + 0.6
    while time.monotonic() < stop:
        later.post(lambda: ran.append(time.monotonic()))
        time.sleep(0.02)
    _until(lambda: not later.waiting)
    assert len(ran) >= 3
    later.close()


def test_cancel_and_flush():
    ran: list[str] = []
    later = Deferred(10.0)
    later.post(lambda: ran.append("dropped"))
    later.cancel()
    later.post(lambda: ran.append("flushed"))
    later.flush()
    assert ran == ["flushed"] and not later.waiting
    done = threading.Event()
    later.close()
    later.post(done.set)  # a closed one never runs again
    assert not done.wait(0.2)
