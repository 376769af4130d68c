"""Where the page spends one update: the JavaScript CPU profile (Chrome DevTools Protocol,
`Profiler` domain) of real chromium from a key press on a live slider until 0.5 s after the
new status, summed over `--repeats` updates and grouped by script and function (self time).
Issue 22 asks for this breakdown before optimising: it says whether plot redraws, React
re-renders or the 3D scene dominate.

    python benchmarks/profile_page.py [--case lunar-landing:hermite-simpson] [--repeats 5]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_browser import INSTRUMENT, show_case, slider_thumb  # noqa: E402
from bench_missions import LIVE_PARAMETER  # noqa: E402

SAMPLING_US = 200  # µs between profiler samples
TRACE_CATEGORIES = "devtools.timeline,disabled-by-default-devtools.timeline,v8.execute"


def bucket(url: str, function: str) -> str:
    """A readable group for a call frame: plotly, three.js / the scene, React, viser, GC…"""
    name = url.rsplit("/", 1)[-1].split("?")[0] or url
    if not url:
        return f"(native) {function or '(program)'}"
    return f"{name}: {function or '(anonymous)'}"


def self_times(profile: dict) -> dict[str, float]:
    """ms of self time per call frame group in one CPU profile."""
    nodes = {n["id"]: n for n in profile["nodes"]}
    out: dict[str, float] = defaultdict(float)
    for sample, delta in zip(profile["samples"], profile["timeDeltas"], strict=True):
        frame = nodes[sample]["callFrame"]
        out[bucket(frame["url"], frame["functionName"])] += delta / 1e3
    return out


def trace_update(page, cdp, press, wait) -> dict[str, float]:
    """One update under the DevTools timeline trace: ms per event name on the page's main
    thread (complete events; nested ones overlap their parents, e.g. FunctionCall in
    RunTask)."""
    events: list[dict] = []
    done: list[bool] = []
    cdp.on("Tracing.dataCollected", lambda e: events.extend(e["value"]))
    cdp.on("Tracing.tracingComplete", lambda e: done.append(True))
    cdp.send("Tracing.start", {"categories": TRACE_CATEGORIES, "transferMode": "ReportEvents"})
    press()
    wait()
    cdp.send("Tracing.end")
    while not done:
        page.wait_for_timeout(50)
    main = {(e["pid"], e["tid"]) for e in events
            if e.get("ph") == "M" and e.get("name") == "thread_name"
            and e.get("args", {}).get("name") == "CrRendererMain"}
    out: dict[str, float] = defaultdict(float)
    for e in events:
        if e.get("ph") == "X" and (e["pid"], e["tid"]) in main:
            out[e["name"]] += e.get("dur", 0) / 1e3
    return out


def script_of(group: str) -> str:
    return group.split(":", 1)[0]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", default="lunar-landing:hermite-simpson", help="MISSION:METHOD")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--top", type=int, default=20)
    args = parser.parse_args(argv)
    key, method = args.case.split(":")

    from explorer.app import ExplorerApp
    from explorer.capture import chromium, close_webgl_toast, free_port, open_tab
    from explorer.panels.status import fmt
    from explorer.panels.value_input import label_of

    app = ExplorerApp("127.0.0.1", free_port())
    app.service.wait_prebuilt()
    try:
        with chromium(1280, 800) as context:
            page, view = open_tab(app, context)
            close_webgl_toast(page)
            mission = show_case(page, view, key, method)
            page.evaluate(INSTRUMENT)
            param = next(p for p in mission.params if p.key == LIVE_PARAMETER[key])
            thumb = slider_thumb(page, label_of(param))
            cdp = context.new_cdp_session(page)
            cdp.send("Profiler.enable")
            cdp.send("Profiler.setSamplingInterval", {"interval": SAMPLING_US})
            total: dict[str, float] = defaultdict(float)
            wall = 0.0
            for k in range(args.repeats):
                before = view.session.latest
                thumb.focus()
                cdp.send("Profiler.start")
                t0 = time.perf_counter()
                page.keyboard.press("ArrowRight" if k % 2 == 0 else "ArrowLeft")
                deadline = time.monotonic() + 120.0
                while view.session.latest is before or view.session.busy:
                    assert time.monotonic() < deadline, "no new answer"
                    time.sleep(0.01)
                sol = view.session.latest
                text = fmt(sol.cost.value, sol.cost.unit) if sol.ok else sol.status
                page.wait_for_function(
                    "(text) => window.__bench.status.some(([t, c]) => c.includes(text))",
                    arg=text, timeout=120e3)
                time.sleep(0.5)
                profile = cdp.send("Profiler.stop")["profile"]
                wall += time.perf_counter() - t0
                for group, ms in self_times(profile).items():
                    total[group] += ms
                page.evaluate("() => { window.__bench.status = []; }")
                view.session.wait_idle(60.0)
            n = args.repeats
            # One more update under the timeline trace: layout, style, paint, compositing.
            before = view.session.latest
            thumb.focus()

            def wait() -> None:
                deadline = time.monotonic() + 120.0
                while view.session.latest is before or view.session.busy:
                    assert time.monotonic() < deadline, "no new answer"
                    time.sleep(0.01)
                time.sleep(1.0)

            trace = trace_update(page, cdp, lambda: page.keyboard.press("ArrowRight"), wait)
            # The same wall time with no input: what the page spends anyway (frames).
            cdp.send("Profiler.start")
            time.sleep(wall / n)
            idle = self_times(cdp.send("Profiler.stop")["profile"])
            idle_busy = sum(ms for g, ms in idle.items() if "(idle)" not in g)
            busy = sum(ms for g, ms in total.items() if "(idle)" not in g)
            print(f"{key} {method}: {n} updates, {1e3 * wall / n:.0f} ms of wall time each "
                  f"(key press to 0.5 s after the status), {busy / n:.0f} ms of it busy; "
                  f"the same time with no input: {idle_busy:.0f} ms busy")
            scripts: dict[str, float] = defaultdict(float)
            for group, ms in total.items():
                scripts[script_of(group)] += ms
            print("\nper script (ms per update):")
            for name, ms in sorted(scripts.items(), key=lambda kv: -kv[1])[:10]:
                print(f"  {ms / n:8.1f}  {name}")
            print(f"\ntop {args.top} functions by self time (ms per update):")
            for group, ms in sorted(total.items(), key=lambda kv: -kv[1])[:args.top]:
                print(f"  {ms / n:8.1f}  {group[:110]}")
            print("\none update under the timeline trace, main thread (ms; nested events "
                  "overlap):")
            for name, ms in sorted(trace.items(), key=lambda kv: -kv[1])[:args.top]:
                print(f"  {ms:8.1f}  {name}")
    finally:
        app.stop()


if __name__ == "__main__":
    main()
