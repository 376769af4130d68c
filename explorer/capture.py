"""Headless screenshots of the explorer: the app in-process on a free port, Debian chromium
driven by Playwright (software WebGL), a PNG once the solved scene has settled.

    python -m explorer.capture --mission lunar-landing --out shot.png [--width 1280 --height 800]
    python -m explorer.capture --all --out DIR
"""

from __future__ import annotations

import argparse
import contextlib
import json
import shutil
import socket
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from playwright.sync_api import BrowserContext, Page, sync_playwright

from .app import ExplorerApp
from .session import DEFAULT_TIME_LIMIT
from .view import View

CAPTURE_TIME_LIMIT = 120.0  # s: a screenshot waits for the solution, however slow
CHROMIUM = "/usr/bin/chromium"
LAUNCH_ARGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]
# WebGL still in software (SwiftShader), but run and composited in the GPU process as a
# machine with a GPU does: without it every 3D frame is read back into the page's main
# thread (about 100 ms per frame at 1280x800 here), a cost no real browser pays.
GPU_PROCESS_ARGS = [a for a in LAUNCH_ARGS if a != "--disable-gpu"] + [
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"]


def settled_pose(camera: Any, still: float = 1.5, patience: float = 120.0
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(position, look_at, up, vertical fov) of a client's camera (`viser.CameraHandle`) as
    its browser last reported it, once unchanged for `still` s (a new framing animates)."""

    def pose() -> tuple:
        return (tuple(np.round(camera.position, 9)), tuple(np.round(camera.look_at, 9)),
                tuple(camera.up_direction), float(camera.fov))

    last, since = pose(), time.monotonic()
    deadline = since + patience
    while time.monotonic() - since < still:
        if time.monotonic() > deadline:
            raise TimeoutError("the camera did not settle")
        time.sleep(0.05)
        now = pose()
        if now != last:
            last, since = now, time.monotonic()
    position, look_at, up, fov = last
    return np.array(position), np.array(look_at), np.array(up), fov


def projector(page: Page, position: np.ndarray, look_at: np.ndarray, up: np.ndarray,
              fov: float) -> Callable[[np.ndarray], tuple[float, float]]:
    """A function from a world point to page pixels for a camera pose (three.js
    perspective: vertical `fov`, the canvas's aspect): where a mouse grabs a gizmo."""
    box = page.locator("canvas").first.bounding_box()
    assert box is not None, "the page has no canvas"
    back = np.asarray(position, float) - np.asarray(look_at, float)
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    true_up = np.cross(back, right)
    tan = np.tan(fov / 2)
    aspect = box["width"] / box["height"]

    def project(point: np.ndarray) -> tuple[float, float]:
        d = np.asarray(point, float) - position
        depth = -float(d @ back)
        x, y = float(d @ right) / depth / (tan * aspect), float(d @ true_up) / depth / tan
        return (box["x"] + (x + 1) / 2 * box["width"], box["y"] + (1 - y) / 2 * box["height"])

    return project


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Browser:
    """A running app with one chromium page connected to it."""

    app: ExplorerApp
    page: Page
    view: View
    first_frame_s: float


@contextlib.contextmanager
def chromium(width: int = 1280, height: int = 800, gpu_process: bool = False
             ) -> Iterator[BrowserContext]:
    """A headless Debian chromium context (fresh profile, removed afterwards); with
    `gpu_process`, software WebGL composited in the GPU process (`GPU_PROCESS_ARGS`)."""
    if not Path(CHROMIUM).exists():
        raise FileNotFoundError(f"{CHROMIUM} not found (apt-get install chromium)")
    profile = tempfile.mkdtemp(prefix="explorer-chromium-")
    try:
        with sync_playwright() as pw:
            context = pw.chromium.launch_persistent_context(
                profile, executable_path=CHROMIUM, headless=True,
                args=GPU_PROCESS_ARGS if gpu_process else LAUNCH_ARGS,
                viewport={"width": width, "height": height})
            try:
                yield context
            finally:
                context.close()
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def open_tab(app: ExplorerApp, context: BrowserContext, timeout: float = 120.0,
             page: Page | None = None) -> tuple[Page, View]:
    """Open the app in a new tab (or `page`); returns it with the view it connected to
    (in shared mode, the shared view) once that view has answered its first request."""
    with app._lock:
        before = set(app.views)
    page = page or context.new_page()
    page.goto(app.url)
    deadline = time.monotonic() + timeout
    while True:
        with app._lock:
            new = [cid for cid in app.views if cid not in before]
        if new:
            view = app.views[new[0]]
            break
        if time.monotonic() > deadline:
            raise TimeoutError(f"the tab did not connect within {timeout:g} s")
        time.sleep(0.05)
    wait_solved(view, timeout)
    return page, view


@contextlib.contextmanager
def open_browser(mission: str | None = None, method: str | None = None,
                 nodes: int | None = None, width: int = 1280, height: int = 800,
                 timeout: float = 120.0, render: bool = True,
                 shared: bool = False, time_limit: float | None = DEFAULT_TIME_LIMIT,
                 mission_files: tuple[str, ...] = ()) -> Iterator[Browser]:
    """Start the app and chromium, wait for the first solve and (with `render`) for its
    settled 3D frame; GUI-only tests skip that wait for the software WebGL start-up."""
    started = time.perf_counter()
    app = ExplorerApp("127.0.0.1", free_port(), mission, method, nodes, shared=shared,
                      time_limit=time_limit, mission_files=mission_files)
    try:
        with chromium(width, height) as context:
            page, view = open_tab(app, context, timeout, page=context.pages[0] if
                                  context.pages else None)
            if render:
                close_webgl_toast(page)
                settle(page, timeout)
            yield Browser(app, page, view, time.perf_counter() - started)
    finally:
        app.stop()


def wait_solved(view: View, timeout: float) -> None:
    """Wait until the session has answered its newest request and something was drawn."""
    deadline = time.monotonic() + timeout
    if not view.session.wait_idle(timeout):
        raise TimeoutError(f"the solve did not finish within {timeout:g} s")
    while view.drawn == 0 and view.session.last_good is not None:
        if time.monotonic() > deadline:
            raise TimeoutError("the solution was not drawn")
        time.sleep(0.05)


def close_webgl_toast(page: Page, timeout: float = 15.0) -> None:
    """Dismiss the "Software WebGL rendering detected" notification if it shows up."""
    toast = page.locator(".mantine-Notification-root", has_text="Software WebGL")
    with contextlib.suppress(Exception):
        toast.first.wait_for(timeout=1e3 * timeout)
        toast.first.get_by_role("button").click()
        toast.first.wait_for(state="detached", timeout=5e3)


def settle(page: Page, timeout: float, interval: float = 0.5) -> bytes:
    """Screenshot until two consecutive frames are identical (the client draws on demand)."""
    deadline = time.monotonic() + timeout
    previous = page.screenshot()
    while time.monotonic() < deadline:
        time.sleep(interval)
        shot = page.screenshot()
        if shot == previous:
            return shot
        previous = shot
    return previous


def capture(out: Path, mission: str | None = None, method: str | None = None,
            nodes: int | None = None, width: int = 1280, height: int = 800,
            mission_files: tuple[str, ...] = ()) -> dict:
    """Write one PNG of the solved mission; returns timings (s), status and drawn colours."""
    with open_browser(mission, method, nodes, width, height,
                      time_limit=CAPTURE_TIME_LIMIT, mission_files=mission_files) as b:
        t0 = time.perf_counter()
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(b.page.screenshot())
        return {"first_frame_s": b.first_frame_s, "screenshot_s": time.perf_counter() - t0,
                **_shot_record(b.view)}


def _shot_record(view) -> dict:
    """Status of the drawn solution and the sRGB colours its trajectory was drawn in (so a
    test can find them in the picture)."""
    latest, g = view.session.latest, view.geometry
    colors = np.unique(g.segment_colors[:, 0], axis=0) if g is not None else []
    return {"status": latest.status if latest else "none",
            "colors": [list(map(int, c)) for c in colors]}


def capture_all(out_dir: Path, width: int = 1280, height: int = 800,
                mission_files: tuple[str, ...] = ()) -> list[Path]:
    """One PNG per mission (default preset; the built-in ones and those of `mission_files`),
    switching missions in one browser session; DIR/shots.json records each one's status
    and the sRGB colours its trajectory was drawn in (so a test can find them in the
    picture)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    written, manifest = [], {}
    with open_browser(width=width, height=height, time_limit=CAPTURE_TIME_LIMIT,
                      mission_files=mission_files) as b:
        for mission in b.app.missions:
            if b.view.session.mission is not mission:
                b.view.session.select_mission(mission)
                wait_solved(b.view, 120.0)
                settle(b.page, 60.0)
            path = out_dir / f"{mission.key}.png"
            path.write_bytes(b.page.screenshot())
            written.append(path)
            manifest[mission.key] = _shot_record(b.view)
    (out_dir / "shots.json").write_text(json.dumps(manifest, indent=1))
    return written


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m explorer.capture", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission")
    parser.add_argument("--method")
    parser.add_argument("--nodes", type=int)
    parser.add_argument("--all", action="store_true", help="one PNG per mission into --out DIR")
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=800)
    parser.add_argument("--mission-file", action="append", default=[], metavar="F",
                        help="a mission file (or folder) to add, as for python -m explorer")
    args = parser.parse_args(argv)
    if args.all:
        for path in capture_all(args.out, args.width, args.height,
                                tuple(args.mission_file)):
            print(path)
        return
    timings = capture(args.out, args.mission, args.method, args.nodes, args.width, args.height,
                      tuple(args.mission_file))
    print(f"{args.out}: status {timings['status']}, first frame {timings['first_frame_s']:.1f} s, "
          f"screenshot {timings['screenshot_s']:.2f} s")


if __name__ == "__main__":
    main()
