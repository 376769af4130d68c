"""Makes viser's message buffers safe to push into from any thread.

The explorer pushes scene and GUI updates from worker, relay and timer threads. viser 1.1's
`AsyncMessageBuffer.push` calls `asyncio.Event.set()` on the caller's thread before handing
the same call to the event loop; `set()` walks the event's waiters, which the loop thread
adds and removes, so now and then the pushing thread dies with "deque mutated during
iteration" (seen in our CI: a plot-marker thread and the classroom's relay thread died, the
room's students froze), and the event can be left set with its waiter never woken (that
client gets no more messages). Here the buffer's event hands a `set()` made off the loop to
the loop (`call_soon_threadsafe`), which viser does right after anyway; on the loop it sets
at once. viser reads the event nowhere else, so nothing waits on the direct call."""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import functools

from viser.infra import _async_message_buffer as buffers


class LoopSafeEvent(asyncio.Event):
    """An `asyncio.Event` whose `set()` from another thread runs on `loop`."""

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        super().__init__()
        self._owner = loop

    def set(self) -> None:
        try:
            on_loop = asyncio.get_running_loop() is self._owner
        except RuntimeError:  # no loop runs in this thread
            on_loop = False
        if on_loop:
            super().set()
            return
        with contextlib.suppress(RuntimeError):  # a closed loop has no consumer to wake
            self._owner.call_soon_threadsafe(super().set)


def make_pushes_thread_safe() -> None:
    """Give every message buffer viser creates from now on a `LoopSafeEvent` (idempotent;
    a viser without the field is left as it is)."""
    cls = buffers.AsyncMessageBuffer
    if getattr(cls, "_explorer_loop_safe", False) or "message_event" not in {
            f.name for f in dataclasses.fields(cls)}:
        return
    original = cls.__init__

    @functools.wraps(original)
    def init(self, *args, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003 - viser's own
        original(self, *args, **kwargs)
        self.message_event = LoopSafeEvent(self.event_loop)

    cls.__init__ = init
    cls._explorer_loop_safe = True
