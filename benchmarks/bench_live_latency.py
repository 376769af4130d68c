"""Slider-to-picture latency of the live explorer: how long after a slider move the new
optimum is drawn (trajectory, nodes, arrows and plots sent), per mission and method.

    python benchmarks/bench_live_latency.py [--mission KEY ...] [--moves 20]

Builds a real `View` on a viser server (server-side GUI and scene, no browser), solving on
the solve service's worker processes (in-process on the code before the service), moves each
mission's live parameter by ±1 % `--moves` times, and measures from `set_value` until the
view has drawn the new solution (the deferred re-propagation check runs after that and is
not counted). "Live" for the small missions means under 100 ms.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402


def make_view(server, missions, mission, method: str, runner):
    """A view on the server's GUI and scene, solving on the service when there is one."""
    try:
        from explorer.view import View
    except ImportError:  # the code before the solve service: solves in this process
        from explorer.app import View
        return View(server.gui, server.scene, server.atomic, missions, mission, method)
    return View(server.gui, server.scene, server.atomic, missions, mission, method,
                runner=runner)


def measure(server, missions, mission, method: str, moves: int, runner) -> list[float]:
    view = make_view(server, missions, mission, method, runner)
    session = view.session
    try:
        session.wait_idle(300.0)
        key = LIVE_PARAMETER[mission.key]
        base = session.values[key]
        times = []
        for k in range(moves):
            drawn = view.drawn
            start = time.perf_counter()
            session.set_value(key, base * (1.01 if k % 2 == 0 else 1.0))
            while view.drawn == drawn:
                if time.perf_counter() - start > 60.0:
                    raise TimeoutError(f"{mission.key}/{method}: nothing drawn in 60 s")
                time.sleep(0.0005)
            times.append(time.perf_counter() - start)
            session.wait_idle(120.0)  # let the check finish before the next move
        return times
    finally:
        view.close()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", nargs="*")
    parser.add_argument("--moves", type=int, default=20)
    args = parser.parse_args(argv)

    import viser

    from explorer.capture import free_port
    from solvers import get_mission, list_missions

    missions = list_missions()
    chosen = [get_mission(k) for k in args.mission] if args.mission else missions
    runner, service = None, None
    try:
        from explorer.runners import ServiceRunner
        from solvers.service import SolveService

        service = SolveService(prebuild=False)
        service.wait_ready()
        runner = ServiceRunner(service)
    except ImportError:
        pass
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    print(f"{'mission':20s} {'method':18s} {'median ms':>9s} {'p90 ms':>7s} {'max ms':>7s}")
    try:
        for mission in chosen:
            if mission.key not in LIVE_PARAMETER:
                continue
            for method in mission.methods:
                times = sorted(measure(server, missions, mission, method.key, args.moves,
                                       runner))
                p90 = times[int(0.9 * (len(times) - 1))]
                print(f"{mission.key:20s} {method.key:18s} "
                      f"{1e3 * statistics.median(times):9.1f} {1e3 * p90:7.1f} "
                      f"{1e3 * times[-1]:7.1f}", flush=True)
    finally:
        server.stop()
        if service is not None:
            service.close()


if __name__ == "__main__":
    main()
