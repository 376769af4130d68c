"""Memory of one explorer session over many consecutive re-solves (issue #5: bounded).

    python benchmarks/bench_explorer_memory.py [--mission lunar-landing] [--method KEY]
                                               [--solves 200] [--every 25]

Builds a real `View` on a viser server (server-side GUI and scene, exactly what a shared
session uses; no browser needed), moves one slider `--solves` times, waits for each solve
and its re-propagation check, and prints the process RSS, the scene nodes the view holds,
and the messages viser keeps to replay to a browser that connects later. Bounded means the
last three columns stop growing after the first few solves.
"""

from __future__ import annotations

import argparse
import gc
import time
from pathlib import Path


def rss_mb() -> float:
    """Resident set size of this process (Linux /proc)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", default="lunar-landing")
    parser.add_argument("--method", default="hermite-simpson")
    parser.add_argument("--key", default="thrust", help="the parameter the 'slider' moves")
    parser.add_argument("--solves", type=int, default=200)
    parser.add_argument("--every", type=int, default=25)
    args = parser.parse_args(argv)

    import viser

    from explorer.capture import free_port
    from explorer.runners import ServiceRunner
    from explorer.view import View
    from solvers import get_mission, list_missions
    from solvers.service import SolveService

    mission = get_mission(args.mission)
    service = SolveService(1, prebuild=False)
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    view = View(server.gui, server.scene, server.atomic, list_missions(), mission, args.method,
                runner=ServiceRunner(service))
    session = view.session
    session.wait_idle(120.0)
    param = next(p for p in mission.all_params(session.method) if p.key == args.key)
    lo, hi = param.default, min(param.max, 1.5 * param.default)
    buffer = server._websock_server._broadcast_buffer
    print(f"{args.mission}/{session.method}: moving '{args.key}' between {lo:g} and {hi:g}")
    print(f"{'solves':>6} {'RSS MB':>8} {'scene nodes':>11} {'replay msgs':>11} "
          f"{'ms/solve':>8} {'status':>8}")
    t0 = time.perf_counter()
    for k in range(args.solves + 1):
        if k:
            session.set_value(args.key, lo + (hi - lo) * (k % 20) / 19)
            session.wait_idle(120.0)
        if k % args.every == 0:
            gc.collect()
            elapsed = (time.perf_counter() - t0) / max(k, 1)
            worker = service.resident().get("worker 0", 0.0)
            print(f"{k:6d} {rss_mb():8.1f} {view.scene.node_count:11d} "
                  f"{len(buffer.message_from_id):11d} {1e3 * elapsed:8.0f} "
                  f"{session.latest.status:>8}  worker {worker:.0f} MB", flush=True)
    view.close()
    server.stop()
    service.close()


if __name__ == "__main__":
    main()
