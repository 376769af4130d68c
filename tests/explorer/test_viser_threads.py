"""viser's message buffers, pushed into from many threads (explorer/viser_threads.py): a
`set()` made off the event loop never walks the waiters the loop thread changes (the CI
runs of c152d8e and ca3464d lost a plot-marker thread and the classroom's relay thread to
"deque mutated during iteration"), and still wakes the waiting consumer."""

from __future__ import annotations

import asyncio
import collections
import threading

from explorer.viser_threads import LoopSafeEvent, make_pushes_thread_safe


class WatchedWaiters(collections.deque):
    """The event's waiters, recording every thread that walks them."""

    def __init__(self) -> None:
        super().__init__()
        self.walked_by: set[int] = set()

    def __iter__(self):
        self.walked_by.add(threading.get_ident())
        return super().__iter__()


def test_a_set_off_the_loop_is_run_on_the_loop_and_wakes_the_waiter() -> None:
    loop = asyncio.new_event_loop()
    waiting, done = threading.Event(), threading.Event()
    box: dict = {}

    async def consumer() -> None:
        event = box["event"] = LoopSafeEvent(loop)
        event._waiters = box["waiters"] = WatchedWaiters()
        box["loop_thread"] = threading.get_ident()
        loop.call_soon(waiting.set)
        await asyncio.wait_for(event.wait(), 30.0)
        done.set()

    thread = threading.Thread(target=loop.run_until_complete, args=(consumer(),))
    thread.start()
    try:
        assert waiting.wait(30.0)
        box["event"].set()  # from this (non-loop) thread, as a worker pushes
        assert done.wait(30.0), "the consumer was not woken"
        assert box["waiters"].walked_by == {box["loop_thread"]}
    finally:
        thread.join(30.0)
        loop.close()
    box["event"].set()  # after the loop closed: nothing to wake, no error


def test_the_explorers_viser_buffers_use_the_loop_safe_event() -> None:
    import viser

    make_pushes_thread_safe()
    make_pushes_thread_safe()  # idempotent
    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        buffer = server._websock_server._broadcast_buffer
        assert isinstance(buffer.message_event, LoopSafeEvent)
        server.scene.add_frame("/pushed/from/a/thread")  # a push still goes through
    finally:
        server.stop()
