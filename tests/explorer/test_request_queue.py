"""The newest-request-wins queue (explorer/request_queue.py): with `patience`, a newer
request lets a young running solve finish (a drag shows its intermediate optima), but never
waits for the check of an answer already out (a drag showed 2.6 optima a second instead of
9.8 while each waited for the last answer's re-propagation)."""

from __future__ import annotations

import threading

from explorer.request_queue import RequestQueue
from explorer.requests import Request
from solvers.request import SolveRequest


def _request(seq: int) -> Request:
    return Request(seq, None, SolveRequest("test"))  # type: ignore[arg-type]


def _queue_running(answered: bool) -> tuple[RequestQueue, Request, threading.Event]:
    """A queue whose first request is running: solving, or with its answer out and its
    check under way (it blocks until cancelled)."""
    started, release = threading.Event(), threading.Event()

    def run(request: Request) -> None:
        if request.seq == 1:
            if answered:
                request.answered.set()
            started.set()
            request.cancel.wait(30.0)
        release.set()

    queue = RequestQueue(run, patience=60.0)
    first = _request(1)
    queue.put(first)
    assert started.wait(30.0)
    return queue, first, release


def test_a_young_solve_is_let_finish():
    queue, first, _ = _queue_running(answered=False)
    queue.put(_request(2))
    assert first.superseded.is_set() and not first.cancel.is_set()
    queue.close()


def test_a_running_check_is_cancelled_at_once():
    queue, first, release = _queue_running(answered=True)
    queue.put(_request(2))
    assert first.cancel.is_set()  # set by put itself: no waiting for the check
    assert release.wait(30.0) and queue.wait_idle(30.0)
    queue.close()
