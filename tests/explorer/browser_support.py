"""What the browser tests share: the window size, the marks that skip them without chromium
or Playwright, a wait that says what it waited for, and the camera of a tab once still."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from explorer.capture import CHROMIUM, settled_pose

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


STILL = 1.5  # s without camera motion before a tab's camera is read


def settled_camera(view) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(position, look_at, up, vertical fov) of the one tab's camera, as its browser last
    reported it, once unchanged for `STILL` s (the framing of a new solution is animated)."""
    clients = list(view.camera.clients.values())
    assert len(clients) == 1
    return settled_pose(clients[0].camera, STILL, PATIENCE)


def slider_key(page, label: str, key: str, times: int = 1) -> None:
    """Focus a viser slider's thumb and press `key` (ArrowRight steps, Home goes to min)."""
    slider_id = page.locator("label", has_text=label).first.get_attribute("for")
    page.locator(f'[id="{slider_id}"]').get_by_role("slider").focus()
    for _ in range(times):
        page.keyboard.press(key)
