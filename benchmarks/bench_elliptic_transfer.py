"""Cold and warm solve times of mission `elliptic-transfer`, per method and LGL degree.

Cold: caches cleared (LGL matrices, STMs, KKT solve, the NLP build). Warm: the same
geometry re-solved after a slider move on the chaser's initial state (what the explorer
does); the deferred re-propagation check is timed separately. Target (issue): warm re-solve
under 50 ms for the closed-form laws at the default N = 64.

    python benchmarks/bench_elliptic_transfer.py [--nodes 16 64 128] [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

from solvers.missions.elliptic_transfer import laws, methods, model
from solvers.registry import get_mission


def _clear_caches() -> None:
    laws.plan.cache_clear()
    methods.lgl_nlp.cache_clear()
    model._gramian.cache_clear()


def bench(method: str, nodes: int, repeat: int) -> dict[str, float]:
    mission = get_mission("elliptic-transfer")
    _clear_caches()
    t0 = time.perf_counter()
    sol = mission.solve(method=method, nodes=nodes, verify=False)
    cold = time.perf_counter() - t0
    warm_times = []
    for k in range(repeat):
        t0 = time.perf_counter()
        sol = mission.solve({"x0": 10000.0 + 100.0 * (k + 1)}, method=method, nodes=nodes,
                            warm=sol, verify=False)
        warm_times.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    sol.run_check()
    check = time.perf_counter() - t0
    return {"cold": cold, "warm": statistics.median(warm_times), "check": check,
            "J": sol.cost.value, "status_ok": float(sol.ok)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--nodes", type=int, nargs="+", default=[16, 64, 128])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"{'method':10s} {'N':>4s} {'cold [ms]':>10s} {'warm [ms]':>10s} "
          f"{'check [ms]':>11s} {'J [m^2/s^3]':>14s}")
    for method in ("stm-law", "seq-law", "lgl-nlp"):
        for n in args.nodes:
            r = bench(method, n, args.repeat)
            flag = "" if r["status_ok"] else "  (not optimal)"
            print(f"{method:10s} {n:4d} {1e3 * r['cold']:10.1f} {1e3 * r['warm']:10.1f} "
                  f"{1e3 * r['check']:11.0f} {r['J']:14.8e}{flag}")


if __name__ == "__main__":
    main()
