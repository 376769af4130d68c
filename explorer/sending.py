"""Sending a part of an update before the rest: viser groups the messages of a short window
into one batch, and its page applies a batch that touches only the GUI at once but holds one
that touches the scene for the next 3D frame (with its text committed after that frame). The
status of a new answer sent on its own is therefore painted with the new scene, one software
frame sooner, instead of a frame after it."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

SEND_WAIT = 0.03  # s at most that a drawing waits for its words to leave


def sender(atomic: Callable[[], Any]) -> Callable[[bool], None]:
    """For a view's `atomic` (a client's, or the server's in shared mode), a function that
    sends what is queued now (viser would wait up to a window, 1/60 s) and, with `wait`,
    returns once it has left (or after `SEND_WAIT`); a no-op where viser's message buffer is
    not at hand (its internals are not an interface)."""
    owner = getattr(atomic, "__self__", None)
    connection = getattr(owner, "_websock_connection", None) or getattr(
        owner, "_websock_server", None)
    buffer = getattr(connection, "get_message_buffer", lambda: None)()
    if buffer is None or not hasattr(buffer, "generator_cursors"):
        return lambda wait=True: None

    def send(wait: bool = True) -> None:
        last = buffer.message_counter - 1
        buffer.flush()
        deadline = time.monotonic() + (SEND_WAIT if wait else 0.0)
        while time.monotonic() < deadline and any(
                cursor < last for cursor in list(buffer.generator_cursors.values())):
            time.sleep(0.001)

    return send
