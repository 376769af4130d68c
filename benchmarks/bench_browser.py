"""Input to new picture, measured in the page: real chromium (software WebGL), 1280x800.

For each case a slider thumb of the mission's live parameter is stepped with the keyboard
(as a person would) and the page's own clocks measure the time until the status element
shows the new optimum; the Long Tasks API sums the page's long tasks from the key press
until 0.5 s after the new status; viser's sender counts the messages and websocket bytes sent to
the page for the update. Median over `--repeats`.

    python benchmarks/bench_browser.py [--repeats 5] [--case lunar-landing:hermite-simpson]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402

CASES = (("lunar-landing", "hermite-simpson"), ("lunar-landing", "paper"),
         ("hovercraft", "multiple-shooting"), ("apollo-reentry", "hermite-simpson"),
         ("cw-rendezvous", "paper"), ("elliptic-transfer", "stm-law"),
         ("asteroid-rendezvous", "hermite-simpson"))

INSTRUMENT = """() => {
  window.__bench = {longtasks: [], status: []};
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__bench.longtasks.push([e.startTime, e.duration]);
  }).observe({type: 'longtask', buffered: true});
  let last = null;
  new MutationObserver(() => {
    const el = document.getElementById('explorer-status');
    const text = el ? el.textContent : null;
    if (text !== last) { last = text; window.__bench.status.push([performance.now(), text]); }
  }).observe(document.body, {subtree: true, childList: true, characterData: true});
}"""


class Frames:
    """viser messages and websocket bytes the server sends to the page (counted in viser's
    sender: the page receives them in a web worker, out of the DevTools page's sight)."""

    def __init__(self) -> None:
        from viser.infra import _infra, _messages

        self.count = self.bytes = 0
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
            return serialize(message, *a, **k)

        _infra._append_aligned_buffers = counted_append
        _messages.Message.as_serializable_dict = counted_serialize

    def take(self) -> tuple[int, int]:
        with self.lock:
            out, self.count, self.bytes = (self.count, self.bytes), 0, 0
        return out


def measure(page, view, key: str, label: str, repeats: int, frames: Frames) -> list[tuple]:
    from explorer.panels.status import fmt

    slider_id = page.locator("label", has_text=label).first.get_attribute("for")
    thumb = page.locator(f'[id="{slider_id}"]').get_by_role("slider")
    rows = []
    for k in range(repeats):
        before = view.session.latest
        page.evaluate("() => { window.__bench.status = []; window.__bench.longtasks = []; }")
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
        shown = None
        while shown is None and time.monotonic() < deadline:
            records = page.evaluate("() => window.__bench.status")
            shown = next((t for t, content in records if text in content), None)
            time.sleep(0.05)
        time.sleep(0.5)
        long_ms = page.evaluate(f"""() => window.__bench.longtasks
            .filter(([start, d]) => start >= {t0} && start <= {shown or t0} + 500)
            .reduce((s, [_, d]) => s + d, 0)""")
        count, size = frames.take()
        rows.append((shown - t0 if shown else float("nan"), long_ms, count, size, sol.status))
        view.session.wait_idle(60.0)
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--case", action="append", help="MISSION:METHOD (repeatable)")
    parser.add_argument("--gpu-process", action="store_true",
                        help="composite the (software) WebGL in the GPU process, as a browser "
                             "on a machine with a GPU does (no per-frame readback)")
    args = parser.parse_args(argv)
    cases = [tuple(c.split(":")) for c in args.case] if args.case else CASES

    from explorer.app import ExplorerApp
    from explorer.capture import chromium, close_webgl_toast, free_port, open_tab, settle
    from explorer.panels.value_input import label_of
    from solvers import get_mission

    app = ExplorerApp("127.0.0.1", free_port())
    app.service.wait_prebuilt()  # measure the classroom after start-up, not during it
    print(f"{'mission':20s} {'method':18s} {'input→status ms':>16s} {'long tasks ms':>14s} "
          f"{'messages':>9s} {'kB':>7s}", flush=True)
    try:
        with chromium(1280, 800, gpu_process=args.gpu_process) as context:
            frames = Frames()
            page, view = open_tab(app, context)
            close_webgl_toast(page)
            page.evaluate(INSTRUMENT)
            for key, method in cases:
                mission = get_mission(key)
                if view.session.mission is not mission:
                    view.session.select_mission(mission)
                    view.session.wait_idle(300.0)
                if view.session.method != method:
                    view.session.select_method(method)
                    view.session.wait_idle(300.0)
                settle(page, 60.0)
                param = next(p for p in mission.params if p.key == LIVE_PARAMETER[key])
                rows = measure(page, view, key, label_of(param), args.repeats, frames)
                lat = statistics.median(r[0] for r in rows)
                long_ms = statistics.median(r[1] for r in rows)
                msgs = statistics.median(r[2] for r in rows)
                kb = statistics.median(r[3] for r in rows) / 1e3
                print(f"{key:20s} {method:18s} {lat:16.0f} {long_ms:14.0f} {msgs:9.0f} "
                      f"{kb:7.0f}", flush=True)
    finally:
        app.stop()


if __name__ == "__main__":
    main()
