"""Solve-time and accuracy table for every mission and method, measured side by side.

Run: python benchmarks/bench_missions.py [--mission KEY ...] [--nodes N ...] [--repeats 5]

Columns: "cold" includes building the NLP (first call for that node count); "built" is a
second cold start on the built NLP; "warm" is the best of `repeats` re-solves after a 1 %
change of the mission's live parameter (alternating), warm-started from the previous optimum
— what a slider move costs in the explorer. The re-propagation check (solve_ivp, rtol 1e-10)
is timed separately because the explorer defers it. "err" compares each quantity that has a
published value (the papers, as each mission's published records cite them) with it, in percent.
"""

from __future__ import annotations

import argparse
import time

import solvers

# The parameter a user is most likely to drag, perturbed by 1 % for the warm re-solve.
LIVE_PARAMETER = {
    "lunar-landing": "thrust",
    "cw-rendezvous": "accel",
    "elliptic-transfer": "x0",
    "hovercraft": "accel",
    "apollo-reentry": "v0",
    "asteroid-rendezvous": "thrust",
    "bang-bang": "accel",
    "powered-descent": "altitude0",
}


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def _published_error(mission, sol) -> str:
    errors = []
    for pub in mission.published:
        q = sol.quantities.get(pub.name)
        if q is not None and pub.value:
            errors.append(f"{pub.name} {100 * (q.value / pub.value - 1):+.5f}%")
    return ", ".join(dict.fromkeys(errors)) or "-"


def bench(mission, method, nodes: int, repeats: int) -> str:
    key = LIVE_PARAMETER.get(mission.key)
    defaults = mission.defaults(method.key)
    base = defaults.get(key)
    run = lambda vals, warm=None: mission.solve(  # noqa: E731
        vals, method=method.key, nodes=nodes, warm=warm, verify=False)
    cold, t_cold = _timed(lambda: run({}))
    _, t_built = _timed(lambda: run({}))
    warm, warm_times = cold, []
    for k in range(repeats if base is not None else 0):
        vals = {key: base * (1.01 if k % 2 == 0 else 1.0)}
        warm, t = _timed(lambda v=vals, w=warm: run(v, w))
        warm_times.append(t)
    _, t_check = _timed(cold.run_check)
    warm_ms = f"{1e3 * min(warm_times):9.1f}" if warm_times else f"{'-':>9s}"
    flag = "" if cold.ok and warm.ok else f"  [{cold.status}/{warm.status}]"
    return (f"{mission.key:20s} {method.key:18s} {nodes:5d} {1e3 * t_cold:9.1f} "
            f"{1e3 * t_built:9.1f} {warm_ms} {int(cold.stats.get('iterations', 0)):6d} "
            f"{int(warm.stats.get('iterations', 0)):6d} {1e3 * t_check:8.1f}  "
            f"{_published_error(mission, cold)}{flag}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--mission", nargs="*", help="mission keys (default: all)")
    parser.add_argument("--nodes", type=int, nargs="*", help="node counts (default: each "
                        "method's default)")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    missions = [solvers.get_mission(k) for k in args.mission] if args.mission else \
        solvers.list_missions()
    header = (f"{'mission':20s} {'method':18s} {'N':>5s} {'cold ms':>9s} {'built ms':>9s} "
              f"{'warm ms':>9s} {'it':>6s} {'it w':>6s} {'check ms':>8s}  published error")
    print(header)
    print("-" * len(header))
    for mission in missions:
        for method in mission.methods:
            lo, default, hi = method.nodes
            for n in args.nodes or [default]:
                if lo <= n <= hi:
                    print(bench(mission, method, n, args.repeats), flush=True)


if __name__ == "__main__":
    main()
