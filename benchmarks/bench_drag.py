"""Optima shown per second while a handle is dragged (issue 19), server side, per mission.

    python benchmarks/bench_drag.py [--mission KEY ...] [--seconds 5] [--rate 10]
                                    [--method lunar-landing:hermite-simpson]

Builds a real `View` on a viser server (server-side GUI and scene, no browser) solving on the
solve service's worker processes, as bench_live_latency.py does, then drags one handle of
each mission the way a hand does: `--rate` drag events a second for `--seconds` s through
the explorer's handle path (`Handles.drag`: clamping, `session.set_values`, newest request
wins), the handle sweeping steadily along its first free axis from half a gizmo arm before
where it started to half an arm beyond (no drag event repeats another's values, except
where the drag stops at a range's end: the distinct values per second are printed too). A
watcher notes every drawing of a solution whose bound values are those of a drag event: the
new optima shown per second, and the drag-to-drawn latency (from that event to the drawing)
p50/p95. The issue's target: at least 10 new optima a second (at `--rate` events a second
no more than `--rate` can show: raise it to see the ceiling).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import threading
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_live_latency import make_view  # noqa: E402

# The handle dragged in each mission.
HANDLE = {"lunar-landing": "ignition", "cw-rendezvous": "start", "hovercraft": "target",
          "bang-bang": "target"}
AMPLITUDE = 0.5  # of a gizmo arm, either side of the start


class _Watcher(threading.Thread):
    """Notes, for every new drawing, the bound values of the solution drawn and when."""

    def __init__(self, view, params: tuple[str, ...]) -> None:
        super().__init__(daemon=True)
        self.view, self.params = view, params
        self.drawings: list[tuple[tuple[float, ...], float]] = []
        self.stop = threading.Event()

    def run(self) -> None:
        seen = self.view.drawn
        while not self.stop.is_set():
            drawn = self.view.drawn
            if drawn != seen:
                seen, now = drawn, time.perf_counter()
                # What is on screen (the view's record; the session's latest may be newer).
                shown = self.view._shown
                if shown is not None and not shown[2]:  # a new optimum, not a dimmed one
                    values = shown[0].values
                    self.drawings.append((tuple(values[k] for k in self.params), now))
            time.sleep(0.0005)


def drag(view, key: str, seconds: float, rate: float
         ) -> tuple[float, float, list[float]]:
    """Drag handle `key` for `seconds` at `rate` events/s: (distinct values the drag set per
    second — fewer than the events where it stops at a range's end —, new optima shown per
    second, drag-to-drawn latencies in s)."""
    handles, session = view.handles, view.session
    drawn = handles.drawn[key]
    params = drawn.handle.params
    axis = drawn.handle.active_axes.index(True)
    start = np.array(drawn.gizmo.position, float)
    swing = AMPLITUDE * float(drawn.gizmo.scale)
    sent: dict[tuple[float, ...], float] = {}
    watcher = _Watcher(view, params)
    watcher.start()
    t0 = time.perf_counter()
    events = int(seconds * rate)
    for k in range(1, events + 1):
        while time.perf_counter() < t0 + k / rate:
            time.sleep(0.001)
        position = start.copy()
        position[axis] += swing * (2 * k / events - 1)  # one steady sweep: no value repeats
        handles.drag(key, tuple(position), phase="update" if k < events else "end")
        values = tuple(session.values[p] for p in params)
        sent[values] = time.perf_counter()
    elapsed = time.perf_counter() - t0
    watcher.stop.set()
    watcher.join()
    shown = [(values, at) for values, at in watcher.drawings if values in sent]
    latencies = [at - sent[values] for values, at in shown]
    return len(sent) / elapsed, len({values for values, _ in shown}) / elapsed, latencies


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q * (len(ordered) - 1))))]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", nargs="*", default=list(HANDLE))
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--rate", type=float, default=10.0, help="drag events per second")
    parser.add_argument("--method", action="append", default=[], metavar="MISSION:METHOD",
                        help="solve MISSION by METHOD (default: its first method)")
    args = parser.parse_args(argv)
    methods = dict(m.split(":", 1) for m in args.method)

    import viser

    from explorer.capture import free_port
    from explorer.runners import ServiceRunner
    from solvers import get_mission, list_missions
    from solvers.service import SolveService

    missions = list_missions()
    service = SolveService(prebuild=False)
    service.wait_ready()
    runner = ServiceRunner(service)
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    print(f"{'mission':16s} {'method':18s} {'nodes':>5s} {'events/s':>8s} {'values/s':>8s} "
          f"{'optima/s':>8s} {'p50 ms':>7s} {'p95 ms':>7s}")
    try:
        for key in args.mission:
            mission = get_mission(key)
            method = methods.get(key, mission.methods[0].key)
            view = make_view(server, missions, mission, method, runner)
            try:
                view.session.wait_idle(300.0)
                values, rate, latencies = drag(view, HANDLE[key], args.seconds, args.rate)
                p50 = statistics.median(latencies) if latencies else math.nan
                p95 = _percentile(latencies, 0.95) if latencies else math.nan
                print(f"{key:16s} {view.session.method:18s} {view.session.nodes:5d} "
                      f"{args.rate:8.1f} {values:8.1f} {rate:8.1f} {1e3 * p50:7.1f} "
                      f"{1e3 * p95:7.1f}",
                      flush=True)
            finally:
                view.close()
    finally:
        server.stop()
        service.close()


if __name__ == "__main__":
    main()
