"""Lunar landing: cold and warm solve times, iterations and error against paper 002.

Run: python benchmarks/bench_lunar_landing.py [--nodes 30 100]
"Cold" includes building the NLP (first call for that node count); "built" is a second cold
start on the built NLP; "warm" re-solves after a 1 % thrust change from the previous optimum.
The re-propagation check (solve_ivp, rtol 1e-10) is timed separately: the explorer defers it.
"""

from __future__ import annotations

import argparse
import time

import solvers

PUBLISHED_TF = 398.03868  # paper 002, table 1
PAPER_WALL_S = 0.641  # paper 002: 3643 integrations in 0.641 s on a 2008 workstation


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--nodes", type=int, nargs="*", default=[30, 100])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    mission = solvers.get_mission("lunar-landing")
    header = (f"{'method':18s} {'N':>4s} {'cold ms':>9s} {'built ms':>9s} {'warm ms':>9s} "
              f"{'it cold':>7s} {'it warm':>7s} {'tf err %':>9s} {'check ms':>9s}")
    print(header)
    print("-" * len(header))
    for method in mission.methods:
        for n in args.nodes:
            lo, _, hi = method.nodes
            if not lo <= n <= hi:
                continue
            cold, t_cold = _timed(lambda: mission.solve(method=method.key, nodes=n, verify=False))
            built, t_built = _timed(
                lambda: mission.solve(method=method.key, nodes=n, verify=False))
            warm_times, warm = [], cold
            for k in range(args.repeats):
                thrust = 2000.0 * (1.01 if k % 2 == 0 else 1.0)
                warm, t = _timed(lambda th=thrust, w=warm: mission.solve(
                    {"thrust": th}, method=method.key, nodes=n, warm=w, verify=False))
                warm_times.append(t)
            _, t_check = _timed(cold.run_check)
            err = 100 * (cold.quantities["tf"].value / PUBLISHED_TF - 1) if cold.ok else float("nan")
            print(f"{method.key:18s} {n:4d} {1e3 * t_cold:9.1f} {1e3 * t_built:9.1f} "
                  f"{1e3 * min(warm_times):9.1f} {int(cold.stats['iterations']):7d} "
                  f"{int(warm.stats['iterations']):7d} {err:9.5f} {1e3 * t_check:9.1f}"
                  + ("" if cold.ok and warm.ok else f"  ({cold.status}/{warm.status})"))
    print(f"\npaper 002's own figure: {PAPER_WALL_S} s for its method on a 2008 workstation")


if __name__ == "__main__":
    main()
