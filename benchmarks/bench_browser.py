"""Input to new picture, measured in the page: real chromium (software WebGL), 1280x800.

For each case a slider thumb of the mission's live parameter is stepped with the keyboard
(as a person would) and the page's own clocks measure the time until the status element
shows the new optimum, and until the new picture is on its way to the screen: the later of
the frame that paints the new text and the first frame that draws the changed scene (it
uploads the new geometry). The Long Tasks API sums the page's long tasks from the key press
until 0.5 s after the new status; viser's sender counts the messages and websocket bytes
sent to the page for the update. Median over `--repeats`. The floor is measured first in
the same browser: a bare viser page whose slider writes a markdown line (with the
explorer's guard that keeps arrow keys on a focused slider, which in a bare page also turn
the camera); each case's ratio to it is printed, and to a scene floor, the same page also
moving a path over a lit sphere. `--by-type` also lists, per case, what the messages of one
update were: type, the scene node or GUI element, the properties they set. `--trace`
records one more update per case with Chromium's tracing (DevTools protocol) and prints
where the page's threads spent it: each thread's busy time and its largest kinds of task.

    python benchmarks/bench_browser.py [--repeats 7] [--case lunar-landing:hermite-simpson]
                                       [--by-type] [--trace] [--second-tab]

`--second-tab` measures every case again with a second explorer tab (its own session) open
in the same browser, and prints the ratio of the two key → status times.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402

# Each mission's live method (what the explorer opens with), and beside it the paper's
# method where that is another.
CASES = (("lunar-landing", "hermite-simpson"), ("lunar-landing", "paper"),
         ("hovercraft", "hermite-simpson"), ("hovercraft", "multiple-shooting"),
         ("apollo-reentry", "hermite-simpson"), ("apollo-reentry", "multiple-shooting"),
         ("cw-rendezvous", "paper"), ("elliptic-transfer", "stm-law"),
         ("bang-bang", "hermite-simpson"), ("asteroid-rendezvous", "burn-coast"),
         ("asteroid-rendezvous", "hermite-simpson"))

# The end of the first frame after a change of the page's text: the frame's callbacks run,
# then its paint and commit (for a 3D canvas in software, the wait for its pixels); a task
# queued from the callbacks runs after all of that, as the frame goes to the screen.
PAINTED = """const painted = (record) => {
    requestAnimationFrame(() => setTimeout(() => record.push(performance.now()), 0));
    return record;
  };"""

# The frames that draw a changed scene: the first to upload geometry (a new path's points)
# after a key press is the one that shows the new answer in 3D; its end is the picture's.
UPLOADS = """window.__uploads = [];
  for (const C of [WebGLRenderingContext, WebGL2RenderingContext]) {
    for (const name of ['bufferData', 'bufferSubData']) {
      const original = C.prototype[name];
      C.prototype[name] = function (...args) {
        const last = window.__uploads[window.__uploads.length - 1];
        if (!last || last.length > 1) window.__uploads.push(painted([performance.now()]));
        return original.apply(this, args);
      };
    }
  }"""

INSTRUMENT = """() => {
  window.__bench = {longtasks: [], status: []};
  """ + PAINTED + UPLOADS + """
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__bench.longtasks.push([e.startTime, e.duration]);
  }).observe({type: 'longtask', buffered: true});
  let last = null;
  new MutationObserver(() => {
    const el = document.getElementById('explorer-status');
    const text = el ? el.textContent : null;
    if (text !== last) {
      last = text;
      window.__bench.status.push(painted([performance.now(), text]));
    }
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}"""


class Frames:
    """viser messages and websocket bytes the server sends to the page (counted in viser's
    sender: the page receives them in a web worker, out of the DevTools page's sight)."""

    def __init__(self) -> None:
        from viser.infra import _infra, _messages

        self.count = self.bytes = 0
        self.kinds: Counter[tuple[str, str, str]] = Counter()  # (type, target, properties)
        self.lock = threading.Lock()
        append, serialize = _infra._append_aligned_buffers, _messages.Message.as_serializable_dict

        def counted_append(parts, buffers, offset):
            out = append(parts, buffers, offset)
            with self.lock:
                self.bytes += sum(len(p) for p in parts)
            return out

        def counted_serialize(message, *a, **k):
            with self.lock:
                self.count += 1
                self.kinds[kind_of(message)] += 1
            return serialize(message, *a, **k)

        _infra._append_aligned_buffers = counted_append
        _messages.Message.as_serializable_dict = counted_serialize

    def take(self) -> tuple[int, int]:
        with self.lock:
            out, self.count, self.bytes = (self.count, self.bytes), 0, 0
        return out


def slider_thumb(page, label: str):
    """The thumb of the slider labelled `label` (focused, it takes the arrow keys)."""
    slider_id = page.locator("label", has_text=label).first.get_attribute("for")
    return page.locator(f'[id="{slider_id}"]').get_by_role("slider")


def kind_of(message) -> tuple[str, str, str]:
    """A message's type, the scene node or GUI element it is for, the properties it sets."""
    target = getattr(message, "name", None) or str(getattr(message, "uuid", ""))[:8]
    updates = getattr(message, "updates", None)
    return (type(message).__name__.removesuffix("Message"), str(target),
            ",".join(sorted(updates)) if isinstance(updates, dict) else "")


def print_kinds(kinds: Counter, updates: int) -> None:
    """The messages of the case's updates, most frequent first, per update."""
    for (kind, target, props), n in kinds.most_common():
        print(f"    {n / updates:5.1f}  {kind:28s} {target:36s} {props}", flush=True)


TRACE_CATEGORIES = "devtools.timeline,disabled-by-default-devtools.timeline,toplevel,gpu,v8"


def trace_update(context, page, view, label: str) -> dict[str, tuple[float, Counter]]:
    """One more slider step under Chromium's tracing, until the new answer is drawn and
    0.5 s after: per thread, its busy time (ms, top-level tasks) and the durations of the
    events directly inside those tasks by name."""
    events: list[dict] = []
    cdp = context.new_cdp_session(page)
    cdp.on("Tracing.dataCollected", lambda e: events.extend(e["value"]))
    done = threading.Event()
    cdp.on("Tracing.tracingComplete", lambda _e: done.set())
    thumb = slider_thumb(page, label)
    before = view.session.latest
    cdp.send("Tracing.start", {"categories": TRACE_CATEGORIES, "transferMode": "ReportEvents"})
    thumb.focus()
    page.keyboard.press("ArrowRight")
    deadline = time.monotonic() + 120.0
    while view.session.latest is before or view.session.busy:
        if time.monotonic() > deadline:
            raise TimeoutError("no new answer under tracing")
        page.wait_for_timeout(10)
    page.wait_for_timeout(500)
    cdp.send("Tracing.end")
    while not done.is_set() and time.monotonic() < deadline:
        page.wait_for_timeout(50)
    cdp.detach()
    return thread_breakdown(events)


def thread_breakdown(events: list[dict]) -> dict[str, tuple[float, Counter]]:
    """Per named thread: the summed duration of its top-level tasks (ms) and the self time
    of each kind of event within them (its duration less that of the events inside it),
    keyed by (name, how many)."""
    names = {(e["pid"], e["tid"]): e["args"]["name"] for e in events
             if e.get("ph") == "M" and e.get("name") == "thread_name"}
    by_thread: dict[tuple, list[dict]] = {}
    for e in events:
        if e.get("ph") == "X" and "dur" in e:
            by_thread.setdefault((e["pid"], e["tid"]), []).append(e)
    out: dict[str, tuple[float, Counter]] = {}
    for key, items in by_thread.items():
        items.sort(key=lambda e: (e["ts"], -e["dur"]))
        busy, own, count = 0.0, Counter(), Counter()
        stack: list[list] = []  # [end, name, self time]
        for e in items + [{"ts": float("inf"), "dur": 0.0, "name": ""}]:
            while stack and e["ts"] >= stack[-1][0]:
                _, name, self_ms = stack.pop()
                own[name] += self_ms
                count[name] += 1
            if e["ts"] == float("inf"):
                break
            ms = e["dur"] / 1e3
            if stack:
                stack[-1][2] -= ms
            else:
                busy += ms
            stack.append([e["ts"] + e["dur"], e["name"], ms])
        name = names.get(key, str(key))
        total, counter = out.get(name, (0.0, Counter()))
        out[name] = (total + busy, counter + Counter({(n, count[n]): ms for n, ms in own.items()}))
    return out


def print_breakdown(breakdown: dict[str, tuple[float, Counter]]) -> None:
    for thread, (busy, inner) in sorted(breakdown.items(), key=lambda kv: -kv[1][0])[:5]:
        parts = ", ".join(f"{n} {ms:.0f} ({k})" for (n, k), ms in inner.most_common(6))
        print(f"    {thread:24s} busy {busy:6.0f} ms: {parts}", flush=True)


def measure(page, view, key: str, label: str, repeats: int, frames: Frames) -> list[tuple]:
    from explorer.panels.status import fmt

    thumb = slider_thumb(page, label)
    rows = []
    for k in range(repeats):
        before = view.session.latest
        page.evaluate("() => { window.__bench.status = []; window.__bench.longtasks = [];"
                      " window.__uploads = []; }")
        frames.take()
        thumb.focus()
        t0 = page.evaluate("() => performance.now()")
        page.keyboard.press("ArrowRight" if k % 2 == 0 else "ArrowLeft")
        deadline = time.monotonic() + 120.0
        while not (view.session.latest is not before and view.session.latest is not None
                   and not view.session.busy):
            if time.monotonic() > deadline:
                raise TimeoutError(f"{key}: no new answer")
            time.sleep(0.01)
        sol = view.session.latest
        text = fmt(sol.cost.value, sol.cost.unit) if sol.ok else sol.status
        shown = painted = None
        while painted is None and time.monotonic() < deadline:
            records = page.evaluate("() => window.__bench.status")
            record = next((r for r in records if text in r[1]), None)
            if record is not None:
                shown, painted = record[0], (record[2] if len(record) > 2 else None)
            time.sleep(0.05)
        picture = _picture(page, painted, deadline)
        time.sleep(0.5)
        long_ms = page.evaluate(f"""() => window.__bench.longtasks
            .filter(([start, d]) => start >= {t0} && start <= {shown or t0} + 500)
            .reduce((s, [_, d]) => s + d, 0)""")
        count, size = frames.take()
        rows.append((shown - t0 if shown else float("nan"), long_ms, count, size, sol.status,
                     picture - t0 if picture else float("nan")))
        view.session.wait_idle(60.0)
    return rows


def _picture(page, painted: float | None, deadline: float) -> float | None:
    """When the new picture is on its way to the screen: the later of the frame that
    painted the new text and the first frame that drew the changed scene (None: neither)."""
    if painted is None:
        return None
    while time.monotonic() < deadline:
        drawn = page.evaluate("() => (window.__uploads[0] || [])[1] || null")
        if drawn is not None:
            return max(painted, drawn)
        time.sleep(0.02)
    return None


def show_case(page, view, key: str, method: str):
    """Put the tab on `key` solved by `method` and wait until its picture has settled; the
    mission."""
    from explorer.capture import settle
    from solvers import get_mission

    mission = get_mission(key)
    if view.session.mission is not mission:
        view.session.select_mission(mission)
        view.session.wait_idle(300.0)
    if view.session.method != method:
        view.session.select_method(method)
        view.session.wait_idle(300.0)
    settle(page, 60.0)
    return mission


FLOOR_OBSERVER = """() => {
  window.__floor = [];
  window.__floorLong = [];
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__floorLong.push([e.startTime, e.duration]);
  }).observe({type: 'longtask', buffered: true});
  """ + PAINTED + UPLOADS + r"""
  new MutationObserver(() => {
    const el = [...document.querySelectorAll('p')].find((p) => /^floor \d+$/.test(p.textContent));
    if (el) window.__floor.push(painted([performance.now(), el.textContent]));
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}"""


def measure_floor(context, repeats: int, scene: bool = False
                  ) -> list[tuple[float, float, float]]:
    """The floor: a bare `viser.ViserServer` with one slider whose `on_update` writes a
    markdown line, in the same browser; key press -> (new text, new picture, long tasks) in ms,
    as `measure` times ours.
    With `scene`, the scene floor: the slider also moves a 1200-point path drawn over a lit
    sphere that fills most of the view (a body as the lunar landing's Moon is drawn, the
    same subdivisions): viser's page then renders what any 3D update costs (its render
    settle window of continuous frames after each change, each frame in software WebGL)."""
    import viser

    from explorer.capture import close_webgl_toast, free_port, settle
    from explorer.help import CAMERA_KEYS, KEEP_KEYS_ON_CONTROLS

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        slider = server.gui.add_slider("floor value", min=0, max=100, step=1, initial_value=50)
        text = server.gui.add_markdown("floor 50")
        path = add_scene_floor(server) if scene else None

        @slider.on_update
        def _(_event) -> None:
            if path is not None:
                path.points = floor_path(slider.value)
            text.content = f"floor {slider.value:g}"

        page = context.new_page()
        page.goto(f"http://127.0.0.1:{server.get_port()}")
        page.get_by_text("floor 50").wait_for(timeout=120e3)
        close_webgl_toast(page)
        if scene:
            settle(page, 60.0)  # the first frame (shaders) before the first key press
        # The explorer's guard that keeps arrow keys on a focused slider: in a bare viser
        # page they also turn the camera, and the floor would pay for those frames.
        page.evaluate("() => {" + KEEP_KEYS_ON_CONTROLS.replace(
            "CAMERA_KEYS", json.dumps(CAMERA_KEYS)) + "}")
        page.evaluate(FLOOR_OBSERVER)
        thumb = slider_thumb(page, "floor value")
        times = []
        for k in range(repeats):
            page.evaluate("() => { window.__floor = []; window.__uploads = []; }")
            value = 51 if k % 2 == 0 else 50
            thumb.focus()
            t0 = page.evaluate("() => performance.now()")
            page.keyboard.press("ArrowRight" if k % 2 == 0 else "ArrowLeft")
            page.wait_for_function(
                f"() => window.__floor.some(([t, c, p]) => c === 'floor {value}' && p)",
                timeout=60e3)
            shown, _, painted = page.evaluate(
                f"() => window.__floor.find(([t, c]) => c === 'floor {value}')")
            picture = _picture(page, painted, time.monotonic() + 60.0) if scene else painted
            time.sleep(0.5)
            long_ms = page.evaluate(f"""() => window.__floorLong
                .filter(([start, d]) => start >= {t0} && start <= {shown} + 500)
                .reduce((s, [_, d]) => s + d, 0)""")
            times.append((shown - t0, picture - t0, long_ms))
        page.close()
        return times
    finally:
        server.stop()


def add_scene_floor(server):
    """The scene floor's content: a lit sphere that fills most of the view and a path above
    it (`floor_path(50)`); returns the path's handle, whose points the floor moves."""
    server.scene.configure_environment_map(None)
    server.scene.configure_default_lights(cast_shadow=False)
    server.initial_camera.position = (0.0, -2.4, 0.8)
    server.initial_camera.look_at = (0.0, 0.0, 0.0)
    server.scene.add_icosphere("/body", 1.0, (150, 150, 150), subdivisions=20,
                               cast_shadow=False, receive_shadow=False)
    return server.scene.add_line_segments("/path", floor_path(50.0), (255, 160, 0),
                                          thickness=4.0, thickness_units="screen")


def floor_path(value: float) -> np.ndarray:
    """The scene floor's path: a 1200-sample arc above the sphere, bent by the slider."""
    s = np.linspace(0.0, 1.0, 1201)
    pts = np.column_stack([np.cos(2.5 * s) * (1.1 + 0.002 * value * s),
                           np.sin(2.5 * s) * (1.1 + 0.002 * value * s), 0.3 * s])
    return np.stack([pts[:-1], pts[1:]], axis=1).astype(np.float32)


def measure_cases(page, view, cases, args, frames: Frames,
                  floors: tuple[float, float, float]
                  ) -> dict[tuple[str, str], tuple[float, float]]:
    """Measure and print every case in the tab; each case's median key → status and key →
    picture ms."""
    from explorer.panels.value_input import label_of

    floor, scene_picture, scene_floor = floors
    print(f"{'mission':20s} {'method':18s} {'input→status ms':>16s} {'× floor':>8s} "
          f"{'× scene':>8s} {'picture ms':>11s} {'× scene':>8s} {'long tasks ms':>14s} "
          f"{'messages':>9s} {'kB':>7s}", flush=True)
    latencies = {}
    for key, method in cases:
        mission = show_case(page, view, key, method)
        param = next(p for p in mission.params if p.key == LIVE_PARAMETER[key])
        frames.take()
        frames.kinds.clear()
        rows = measure(page, view, key, label_of(param), args.repeats, frames)
        lat, long_ms, msgs, size, paint = (
            statistics.median(r[i] for r in rows) for i in (0, 1, 2, 3, 5))
        latencies[(key, method)] = (lat, paint)
        print(f"{key:20s} {method:18s} {lat:16.0f} {lat / floor:8.1f} "
              f"{lat / scene_floor:8.1f} {paint:11.0f} {paint / scene_picture:8.2f} "
              f"{long_ms:14.0f} {msgs:9.0f} {size / 1e3:7.0f}", flush=True)
        if args.by_type:
            print_kinds(frames.kinds, args.repeats)
        if args.trace:
            view.session.wait_idle(60.0)
            print_breakdown(trace_update(page.context, page, view, label_of(param)))
    return latencies


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--case", action="append", help="MISSION:METHOD (repeatable)")
    parser.add_argument("--trace", action="store_true",
                        help="trace one more update per case and print the threads' time")
    parser.add_argument("--by-type", action="store_true",
                        help="list each case's messages per update by type and target")
    parser.add_argument("--second-tab", action="store_true",
                        help="measure every case again with a second explorer tab open")
    parser.add_argument("--gpu-process", action="store_true",
                        help="composite the (software) WebGL in the GPU process, as a browser "
                             "on a machine with a GPU does (no per-frame readback)")
    args = parser.parse_args(argv)
    cases = [tuple(c.split(":")) for c in args.case] if args.case else CASES

    from explorer.app import ExplorerApp
    from explorer.capture import chromium, close_webgl_toast, free_port, open_tab, settle

    app = ExplorerApp("127.0.0.1", free_port())
    app.service.wait_prebuilt()  # measure the classroom after start-up, not during it
    try:
        with chromium(1280, 800, gpu_process=args.gpu_process) as context:
            floor_runs = measure_floor(context, args.repeats)
            floor, floor_paint = (statistics.median(f[i] for f in floor_runs) for i in (0, 1))
            print(f"floor (bare viser page, slider -> markdown): {floor:.0f} ms, picture "
                  f"{floor_paint:.0f} ms, long tasks "
                  f"{statistics.median(f[2] for f in floor_runs):.0f} ms", flush=True)
            scenes = measure_floor(context, args.repeats, scene=True)
            scene_floor, scene_picture = (statistics.median(f[i] for f in scenes)
                                          for i in (0, 1))
            print(f"scene floor (the same, moving a path over a lit sphere): "
                  f"{scene_floor:.0f} ms, picture {scene_picture:.0f} ms, long tasks "
                  f"{statistics.median(f[2] for f in scenes):.0f} ms", flush=True)
            frames = Frames()
            page, view = open_tab(app, context)
            close_webgl_toast(page)
            page.evaluate(INSTRUMENT)
            floors = (floor, scene_picture, scene_floor)
            alone = measure_cases(page, view, cases, args, frames, floors)
            if args.second_tab:
                other, _ = open_tab(app, context)  # its own session, on the default mission
                close_webgl_toast(other)
                settle(other, 60.0)  # its first frames (shaders) before the first key press
                # Back to the measured tab, as a person switches tabs: a tab in the
                # background gets no animation frames and timers at most once a second.
                page.bring_to_front()
                settle(page, 60.0)
                print("\nwith a second tab open in the same browser (its own session):")
                together = measure_cases(page, view, cases, args, frames, floors)
                print(f"{'mission':20s} {'method':18s} {'status ms: 1 tab':>17s} {'2 tabs':>7s} "
                      f"{'×':>5s} {'picture ms: 1 tab':>18s} {'2 tabs':>7s} {'×':>5s}")
                for case in cases:
                    (one, one_pic), (two, two_pic) = alone[case], together[case]
                    print(f"{case[0]:20s} {case[1]:18s} {one:17.0f} {two:7.0f} {two / one:5.2f} "
                          f"{one_pic:18.0f} {two_pic:7.0f} {two_pic / one_pic:5.2f}")
    finally:
        app.stop()


if __name__ == "__main__":
    main()
