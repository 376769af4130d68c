"""A classroom on one server: N sessions, each a real `View` on one viser server (server side
only, no browser), spread over the five small missions, each moving its live parameter once
every `--period` seconds for `--duration` seconds; optionally more sessions re-solving the
asteroid mission back to back. Prints p50/p95/max slider-to-drawn latency per mission, how
many requests missed their time limit, and the resident memory of the server and the solve
workers.

    python benchmarks/bench_classroom.py [--sessions 30] [--asteroid 2] [--duration 60]
                                         [--period 3] [--workers N]
    python benchmarks/bench_classroom.py --presenter [--sessions 30] [--explore 10] ...

`--presenter` measures the classroom mode instead (`explorer.room`): one teacher view moving
the lunar landing's thrust every `--period` s, `--sessions` followers (server-side
`RoomView`s) of which `--explore` have branched off and move their own thrust; it prints the
teacher's move-to-drawn latency, the delay from the teacher's picture to each follower's
(p50/p95/max), the explorers' latency, the server's CPU use and memory.

The same script runs on the code before the solve service (no `explorer.view`: every solve
in the server process), which is how the README's before/after table was made.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import threading
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402

SMALL = ("lunar-landing", "cw-rendezvous", "elliptic-transfer", "hovercraft", "apollo-reentry")


def peak_mb() -> float:
    """This process's peak resident memory."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def resident_mb(pid: int | str = "self") -> float:
    try:
        with open(f"/proc/{pid}/statm") as f:
            return int(f.read().split()[1]) * 4096 / 2**20
    except OSError:
        return 0.0


class Clock:
    """Times each request from the slider move to its drawn answer (a SessionListener after
    the view, so the view has drawn when it is called)."""

    def __init__(self) -> None:
        self.moved: dict[int, float] = {}
        self.latencies: list[float] = []
        self.statuses: list[str] = []
        self.done = threading.Event()
        self.move_started = 0.0

    def on_submit(self, request) -> None:
        self.moved[request.seq] = self.move_started

    def _ignore(self, *args) -> None:
        """Listeners hear every event (the code before the service calls each one)."""

    on_config = on_view = on_progress = on_check = on_error = on_compare = _ignore

    def on_result(self, request, solution) -> None:
        started = self.moved.pop(request.seq, None)
        if started is not None:
            self.latencies.append(time.perf_counter() - started)
            self.statuses.append(solution.status)
        self.done.set()


def make_view(server, missions, mission, runner, index: int):
    """A view on the server's GUI and scene (each in its own branch of the scene)."""
    try:
        from explorer.view import View
    except ImportError:  # the code before the solve service: one scene for all views
        from explorer.app import View
        return View(server.gui, server.scene, server.atomic, missions, mission)
    return View(server.gui, server.scene, server.atomic, missions, mission, runner=runner,
                scene_root=f"/session{index}")


def drive(view, clock: Clock, key: str | None, moves: int, period: float, offset: float,
          stop: threading.Event, rng: random.Random) -> None:
    """Every `period` s from `offset` s in: move `key` up by 1 % and back, or (`key` None)
    pick a new node count in the method's range (every count a new NLP to build)."""
    session = view.session
    base = session.values[key] if key else 0.0
    t0 = time.perf_counter() + offset
    for k in range(moves):
        wait = t0 + k * period - time.perf_counter()
        if stop.wait(max(wait, 0.0)):
            return
        clock.done.clear()
        clock.move_started = time.perf_counter()
        if key is None:
            lo, _, hi = session.mission.method(session.method).nodes
            session.set_nodes(rng.randint(lo, min(hi, 4 * session.nodes)))
        else:
            session.set_value(key, base * (1.01 if k % 2 == 0 else 1.0))


def hammer(view, clock: Clock, stop: threading.Event) -> None:
    """Re-solve the asteroid back to back (thrust up by 1 % and back)."""
    session = view.session
    base, k = session.values["thrust"], 0
    while not stop.is_set():
        clock.done.clear()
        clock.move_started = time.perf_counter()
        session.set_value("thrust", base * (1.01 if k % 2 == 0 else 1.0))
        k += 1
        clock.done.wait(120.0)


class Drawn:
    """Stamps when a view has drawn a solution (a listener after the view)."""

    def __init__(self) -> None:
        self.at: dict[int, float] = {}  # id(solution) -> time drawn

    def on_result(self, request, solution) -> None:
        self.at[id(solution)] = time.perf_counter()


def percentiles(xs: list[float]) -> str:
    if not xs:
        return f"{'-':>8s} {'-':>8s} {'-':>8s}"
    xs = sorted(xs)
    p95 = xs[min(len(xs) - 1, int(0.95 * len(xs)))]
    return f"{1e3 * statistics.median(xs):8.0f} {1e3 * p95:8.0f} {1e3 * xs[-1]:8.0f}"


def presenter(args, server, missions, runner, service) -> None:
    """The classroom mode: one teacher, followers sharing its solves, some explorers."""
    from explorer.room import Room
    from explorer.room_view import RoomView
    from explorer.view import View
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    teacher = View(server.gui, server.scene, server.atomic, missions, mission, runner=runner,
                   scene_root="/teacher")
    teacher.session.wait_idle(600.0)
    room = Room(teacher.session)  # the room follows the teacher's session (no tab)
    followers = []
    wall0 = time.perf_counter()
    for i in range(args.sessions):
        view = RoomView(server.gui, server.scene, server.atomic, missions, mission, None, None,
                        5.0, runner, room=room, member_id=i, room_url="",
                        claim=lambda v, k: None, scene_root=f"/student{i}")
        followers.append(view)
    for view in followers:
        until_drawn = time.monotonic() + 120.0
        while view.drawn == 0 and time.monotonic() < until_drawn:
            time.sleep(0.05)
    print(f"{len(followers)} followers drawn in {time.perf_counter() - wall0:.1f} s", flush=True)
    explorers = followers[:args.explore]
    for view in explorers:
        view.room_session.branch()
    teacher_clock, stamps = Clock(), []
    teacher.session.listeners.append(teacher_clock)
    teacher_drawn = Drawn()
    teacher.session.listeners.append(teacher_drawn)
    for view in followers[args.explore:]:
        stamps.append(Drawn())
        view.session.listeners.append(stamps[-1])
    clocks, stop, rng = [], threading.Event(), random.Random(args.seed)
    moves = int(args.duration / args.period)
    threads = [threading.Thread(target=drive, daemon=True, args=(
        teacher, teacher_clock, "thrust", moves, args.period, 0.0, stop, rng))]
    for view in explorers:
        clock = Clock()
        view.session.listeners.append(clock)
        clocks.append(clock)
        threads.append(threading.Thread(target=drive, daemon=True, args=(
            view, clock, "thrust", moves, args.period, rng.uniform(0.0, args.period), stop,
            random.Random(rng.random()))))
    cpu0, wall0 = time.process_time(), time.perf_counter()
    for t in threads:
        t.start()
    time.sleep(args.duration + args.period)
    stop.set()
    teacher.session.wait_idle(60.0)
    time.sleep(2.0)  # the last relays
    cpu = (time.process_time() - cpu0) / (time.perf_counter() - wall0)
    delays, missed = [], 0
    for sol_id, t_teacher in teacher_drawn.at.items():
        for stamp in stamps:
            if sol_id in stamp.at:
                delays.append(stamp.at[sol_id] - t_teacher)
            else:
                missed += 1
    print(f"{'':34s} {'n':>5s} {'p50 ms':>8s} {'p95 ms':>8s} {'max ms':>8s}")
    print(f"{'teacher move -> teacher drawn':34s} {len(teacher_clock.latencies):5d} "
          f"{percentiles(teacher_clock.latencies)}")
    print(f"{'teacher drawn -> follower drawn':34s} {len(delays):5d} {percentiles(delays)}"
          f"  ({missed} pictures skipped)")
    lat = [x for c in clocks for x in c.latencies]
    print(f"{'explorer move -> drawn':34s} {len(lat):5d} {percentiles(lat)}")
    memory = (f"server CPU {100 * cpu:.0f} % of a core, {resident_mb():.0f} MB "
              f"(peak {peak_mb():.0f})")
    if service is not None:
        workers = [resident_mb(pid) for pid in service.pids()]
        memory += f", workers {' + '.join(f'{w:.0f}' for w in workers)} MB"
    print(memory, flush=True)
    for view in [teacher, *followers]:
        view.close()
    room.close()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sessions", type=int, default=30)
    parser.add_argument("--asteroid", type=int, default=0, help="extra asteroid sessions")
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--period", type=float, default=3.0)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--node-moves", action="store_true",
                        help="move node counts (a new NLP each) instead of a parameter")
    parser.add_argument("--presenter", action="store_true",
                        help="the classroom mode: one teacher, --sessions followers")
    parser.add_argument("--explore", type=int, default=0,
                        help="with --presenter: followers that explore on their own")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT|local",
                        help="solve on this dask cluster instead of the solve service "
                             "('local': a LocalCluster of --workers processes here)")
    args = parser.parse_args(argv)

    import viser

    from explorer.capture import free_port
    from solvers import get_mission, list_missions

    runner, service, cluster = None, None, None
    if args.scheduler:
        from dask.distributed import LocalCluster

        from explorer.runners import ClusterRunner
        from solvers.cluster import connect

        if args.scheduler == "local":
            cluster = LocalCluster(n_workers=args.workers or 2, threads_per_worker=1,
                                   processes=True, dashboard_address=None)
        runner = ClusterRunner(connect(cluster.scheduler_address if cluster else args.scheduler))
    try:
        from explorer.runners import ServiceRunner
        from solvers.service import SolveService

        if runner is None:
            service = SolveService(args.workers, first_mission=SMALL[0])
            service.wait_prebuilt()
            runner = ServiceRunner(service)
    except ImportError:
        pass
    missions = list_missions()
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    if args.presenter:
        presenter(args, server, missions, runner, service)
        server.stop()
        if service is not None:
            service.close()
        if args.scheduler:
            runner.close()
        if cluster is not None:
            cluster.close()
        return
    views, clocks = [], defaultdict(list)
    started = time.perf_counter()
    for i in range(args.sessions):
        mission = get_mission(SMALL[i % len(SMALL)])
        views.append((mission.key, make_view(server, missions, mission, runner, i)))
    for i in range(args.asteroid):
        views.append(("asteroid-rendezvous", make_view(
            server, missions, get_mission("asteroid-rendezvous"), runner, args.sessions + i)))
    for _, view in views:  # every tab's first answer
        view.session.wait_idle(600.0)
    print(f"{len(views)} sessions answered their first request in "
          f"{time.perf_counter() - started:.1f} s", flush=True)
    rng = random.Random(args.seed)
    stop = threading.Event()
    moves = int(args.duration / args.period)
    threads = []
    for key, view in views:
        clock = Clock()
        view.session.listeners.append(clock)
        clocks[key].append(clock)
        if key == "asteroid-rendezvous":
            target, fn_args = hammer, (view, clock, stop)
        else:
            target = drive
            fn_args = (view, clock, None if args.node_moves else LIVE_PARAMETER[key], moves,
                       args.period, rng.uniform(0.0, args.period), stop,
                       random.Random(rng.random()))
        threads.append(threading.Thread(target=target, args=fn_args, daemon=True))
    for t in threads:
        t.start()
    time.sleep(args.duration + args.period)
    stop.set()
    for _, view in views:
        view.session.wait_idle(60.0)
    print(f"{'mission':22s} {'moves':>5s} {'p50 ms':>8s} {'p95 ms':>8s} {'max ms':>8s} "
          f"{'time-limit':>10s} {'not optimal':>11s}")
    for key in [*SMALL, "asteroid-rendezvous"]:
        lat = sorted(x for c in clocks.get(key, []) for x in c.latencies)
        stat = [s for c in clocks.get(key, []) for s in c.statuses]
        if not lat:
            continue
        p95 = lat[min(len(lat) - 1, int(0.95 * len(lat)))]
        print(f"{key:22s} {len(lat):5d} {1e3 * statistics.median(lat):8.0f} {1e3 * p95:8.0f} "
              f"{1e3 * lat[-1]:8.0f} {stat.count('time-limit'):10d} "
              f"{sum(s != 'optimal' for s in stat):11d}")
    small = sorted(x for k in SMALL for c in clocks.get(k, []) for x in c.latencies)
    p95 = small[min(len(small) - 1, int(0.95 * len(small)))]
    print(f"{'small missions':22s} {len(small):5d} {1e3 * statistics.median(small):8.0f} "
          f"{1e3 * p95:8.0f} {1e3 * small[-1]:8.0f}")
    memory = f"server {resident_mb():.0f} MB (peak {peak_mb():.0f})"
    if service is not None:
        workers = [resident_mb(pid) for pid in service.pids()]
        memory += (f", workers {' + '.join(f'{w:.0f}' for w in workers)} MB, total "
                   f"{resident_mb() + sum(workers):.0f} MB, worker restarts {service.restarts}")
    print(memory, flush=True)
    for _, view in views:
        view.close()
    server.stop()
    if service is not None:
        service.close()


if __name__ == "__main__":
    main()
