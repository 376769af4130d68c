"""What the browser tests share: the window size, the marks that skip them without chromium
or Playwright, and a wait that says what it waited for."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest

from explorer.capture import CHROMIUM

WIDTH, HEIGHT = 1280, 800
BROWSER = [
    pytest.mark.browser,
    pytest.mark.skipif(not Path(CHROMIUM).exists(),
                       reason=f"{CHROMIUM} is missing (apt-get install chromium)"),
]


# How long a browser test waits for a condition (s, and ms for Playwright). Generous: a test
# waits for what it needs and no longer, so only a loaded machine (software WebGL on two busy
# cores) ever comes near it.
PATIENCE = 120.0
PATIENCE_MS = PATIENCE * 1e3


def until(condition: Callable[[], object], what: str, timeout: float = PATIENCE) -> object:
    """Poll `condition` until it is truthy (returned) or `timeout` s pass (a failure naming
    `what`)."""
    deadline = time.monotonic() + timeout
    while not (value := condition()):
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)
    return value
