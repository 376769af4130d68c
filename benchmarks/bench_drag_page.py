"""Optima shown per second *in the page* while a handle is dragged with the mouse (issues 19
and 22), beside the floor: a bare viser page whose dragged transform control writes a text on
every update, in the same browser and the same run.

    python benchmarks/bench_drag_page.py [--mission KEY ...] [--seconds 5] [--rate 10]

Debian chromium (software WebGL, 1280×800) on the explorer in-process with its solve service.
Per mission the mouse grabs the handle's gizmo arrow where the settled camera projects it,
holds it and moves along the arrow at `--rate` moves a second for `--seconds` s (one steady
sweep of one gizmo arm), then lets go. In the page a MutationObserver notes every new cost in
the status line (`#explorer-status`): the new optima the page showed per second, from the
first move until the page caught up (a page behind the hand shows the gesture's optima
long after it stopped: the lag column), and the drag events the server heard. The floor:
the same gesture on a bare `viser.ViserServer` whose transform control's `on_update` writes
"floor N" (N counting its events): the new texts it showed per second; and the scene floor,
the same page also moving a path over a lit sphere on every event (what a new 3D picture
costs this browser, as in `bench_browser.py`).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_browser import add_scene_floor, floor_path  # noqa: E402
from bench_drag import HANDLE  # noqa: E402

ARM = 0.6  # where along the gizmo arrow (fraction of its length) the mouse grabs it
SHOWN = """(selector) => {
  window.__shown = [];
  const note = () => {
    const text = selector();
    const last = window.__shown[window.__shown.length - 1];
    if (text && (!last || last[1] !== text)) window.__shown.push([performance.now(), text]);
  };
  new MutationObserver(note).observe(document.body,
                                     {subtree: true, childList: true, characterData: true});
}"""
# What counts as a new picture: the cost in the status (the bold item after the status word;
# a "solving…" line above the previous result is skipped), or the floor's text.
COST = ("() => { const s = document.querySelector('#explorer-status'); if (!s) return '';"
        " let b = [...s.querySelectorAll('strong')].map((e) => e.textContent);"
        " if (b.length && b[0].startsWith('solving')) b = b.slice(1);"
        " return b.length > 1 ? b[1] : ''; }")
FLOOR = ("() => { const p = [...document.querySelectorAll('p')].find("
         "(e) => /^floor \\d+$/.test(e.textContent)); return p ? p.textContent : ''; }")


def watch(page, selector: str) -> None:
    page.evaluate(f"() => ({SHOWN})({selector})")


def gesture(page, project, grab: np.ndarray, direction: np.ndarray, length: float,
            seconds: float, rate: float) -> tuple[float, float]:
    """Hold the mouse on `grab` and move it `length` along `direction` (world units) at
    `rate` moves a second for `seconds`; the page clock at the first and the last move."""
    x0, y0 = project(grab)
    x1, y1 = project(grab + length * direction)
    page.mouse.move(x0, y0)
    page.mouse.down()
    moves = int(seconds * rate)
    start = time.perf_counter()
    first = last = 0.0
    for k in range(1, moves + 1):
        while time.perf_counter() < start + k / rate:
            time.sleep(0.001)
        page.mouse.move(x0 + (x1 - x0) * k / moves, y0 + (y1 - y0) * k / moves)
        if k == 1:
            first = page.evaluate("() => performance.now()")
    last = page.evaluate("() => performance.now()")
    page.mouse.up()
    return first, last


def shown_rate(page, first: float, last: float, settle_s: float = 3.0) -> tuple[float, float]:
    """(new pictures per second the page showed from the first move until it caught up,
    s from the last move to the last picture). A page whose main thread is behind shows the
    gesture's pictures long after the hand stopped: the rate counts them all, over the time
    they took, and the lag says how far behind it was. Caught up: no new picture for
    `settle_s` s."""
    def times() -> list[float]:
        return [t for t, _ in page.evaluate("() => window.__shown") if t >= first]

    seen, since = len(times()), time.monotonic()
    while time.monotonic() - since < settle_s:
        time.sleep(0.2)
        if len(now := times()) != seen:
            seen, since = len(now), time.monotonic()
    shown = times()
    if not shown:
        return 0.0, float("nan")
    span = max(shown[-1], last) - first
    return len(shown) / (span / 1e3), (shown[-1] - last) / 1e3


def floor_rate(context, seconds: float, rate: float, scene: bool = False) -> float:
    """New texts a second on a bare viser page whose dragged transform writes one; with
    `scene`, each drag event also moves a path over a lit sphere (`bench_browser`'s scene
    floor): what any new 3D picture costs this browser."""
    import viser

    from explorer.capture import close_webgl_toast, free_port, projector, settle, settled_pose

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        path = add_scene_floor(server) if scene else None
        server.initial_camera.position = (0.0, -3.0, 1.0)
        server.initial_camera.look_at = (0.0, 0.0, 0.0)
        gizmo = server.scene.add_transform_controls(
            "/floor", scale=1.0, active_axes=(True, False, False), disable_rotations=True,
            depth_test=False)
        text = server.gui.add_markdown("floor 0")
        events = [0]

        @gizmo.on_update
        def _(_event) -> None:
            events[0] += 1
            if path is not None:
                path.points = floor_path(50.0 + events[0] % 50)
            text.content = f"floor {events[0]}"

        page = context.new_page()
        page.goto(f"http://127.0.0.1:{server.get_port()}")
        page.get_by_text("floor 0").wait_for(timeout=120e3)
        close_webgl_toast(page)
        settle(page, 60.0)
        client = next(iter(server.get_clients().values()))
        project = projector(page, *settled_pose(client.camera))
        watch(page, FLOOR)
        first, last = gesture(page, project, np.array([ARM, 0.0, 0.0]), np.eye(3)[0], 1.0,
                              seconds, rate)
        shown, _ = shown_rate(page, first, last)
        page.close()
        return shown
    finally:
        server.stop()


def explorer_rate(page, view, key: str, seconds: float, rate: float
                  ) -> tuple[float, float, float]:
    """(optima shown per second in the page, its lag behind the hand in s, drag events the
    server heard per second of the gesture) for a gesture on mission `key`'s handle."""
    from explorer.capture import projector, settle, settled_pose
    from solvers import get_mission

    view.session.select_mission(get_mission(key))
    view.session.wait_idle(300.0)
    settle(page, 60.0)
    drawn = view.handles.drawn[HANDLE[key]]
    axis = drawn.handle.active_axes.index(True)
    direction = np.eye(3)[axis]
    camera = next(iter(view.camera.clients.values())).camera
    project = projector(page, *settled_pose(camera))
    grab = np.asarray(drawn.gizmo.position, float) + ARM * drawn.gizmo.scale * direction
    watch(page, COST)
    moves = view.handles.moves
    first, last = gesture(page, project, grab, direction, float(drawn.gizmo.scale), seconds,
                          rate)
    shown, lag = shown_rate(page, first, last)
    heard = (view.handles.moves - moves) / seconds
    view.session.wait_idle(120.0)
    return shown, lag, heard


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", nargs="*", default=list(HANDLE))
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--rate", type=float, default=10.0, help="mouse moves per second")
    args = parser.parse_args(argv)

    from explorer.app import ExplorerApp
    from explorer.capture import chromium, close_webgl_toast, free_port, open_tab

    with chromium() as context:
        floor = floor_rate(context, args.seconds, args.rate)
        print(f"floor (bare viser page, dragged transform -> text): {floor:.1f} texts/s at "
              f"{args.rate:g} moves/s", flush=True)
        scene = floor_rate(context, args.seconds, args.rate, scene=True)
        print(f"scene floor (the same, each event also moving a path over a lit sphere): "
              f"{scene:.1f} texts/s", flush=True)
        app = ExplorerApp("127.0.0.1", free_port(), args.mission[0])
        app.service.wait_prebuilt()  # the room after start-up, not during its NLP builds
        try:
            page, view = open_tab(app, context, 300.0)
            close_webgl_toast(page)
            print(f"{'mission':16s} {'method':18s} {'heard/s':>8s} {'shown/s':>8s} "
                  f"{'÷ floor':>8s} {'÷ scene':>8s} {'lag s':>6s}")
            for key in args.mission:
                shown, lag, heard = explorer_rate(page, view, key, args.seconds, args.rate)
                print(f"{key:16s} {view.session.method:18s} {heard:8.1f} {shown:8.1f} "
                      f"{shown / floor:8.2f} {shown / scene:8.2f} {lag:6.1f}", flush=True)
        finally:
            app.stop()


if __name__ == "__main__":
    main()
