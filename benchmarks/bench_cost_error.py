"""The cost error estimate of issue 17, per mission and method at the default node count:
cost, estimated cost error (`Solution.cost.error_estimate`), true error against the
mission's published or analytic optimum where it records one, status, and the times of the
solve, of the whole deferred check and of the estimate within it, and of a warm re-solve
after a 1 % step of the mission's live parameter (`bench_missions.LIVE_PARAMETER`),
warm-started from the answer before it (median of 4 steps, up and back twice as in
bench_missions, unchecked: what a slider move waits for).

    python benchmarks/bench_cost_error.py [--missions KEY ...]

Prints one markdown table.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import solvers
from solvers.mission import Mission
from solvers.solution import Solution

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402


def optimum(mission: Mission, sol: Solution) -> float:
    """The tightest published value at the defaults that is the solution's cost (NaN: none)."""
    best = math.nan, math.inf
    for pub in mission.published:
        if (pub.checked and pub.holds and pub.relation == "equal" and pub.case is None
                and pub.name in (*sol.quantities, "cost")
                and sol.value(pub.name) == sol.cost.value and pub.rtol < best[1]):
            best = pub.value, pub.rtol
    return best[0]


def row(mission: Mission, method: str) -> str:
    t0 = time.perf_counter()
    sol = mission.solve(method=method, verify=False)
    t1 = time.perf_counter()
    sol.run_check()
    t2 = time.perf_counter()
    est = sol.cost.error_estimate
    est = math.nan if est is None else est
    true = abs(sol.cost.value - optimum(mission, sol))
    key = LIVE_PARAMETER[mission.key]
    base, warm, previous = mission.defaults(method)[key], [], sol
    for factor in (1.01, 1.0, 1.01, 1.0):
        t = time.perf_counter()
        previous = mission.solve({key: base * factor}, method=method, warm=previous,
                                 verify=False)
        warm.append(time.perf_counter() - t)
    return (f"| {mission.key} | {method} | {sol.nodes} | {sol.cost.value:.9g} {sol.cost.unit} "
            f"| {est:.2e} | {est / abs(sol.cost.value):.1e} | {true:.2e} | {sol.status} | "
            f"{t1 - t0:.2f} | {t2 - t1:.2f} | {sol.stats.get('cost_error_s', math.nan):.2f} | "
            f"{1e3 * statistics.median(warm):.0f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--missions", nargs="*", default=None)
    args = parser.parse_args()
    keys = args.missions or [m.key for m in solvers.list_missions()]
    print("| mission | method | nodes | cost | estimate | relative | true error | status | "
          "solve s | check s | estimate s | warm ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key in keys:
        mission = solvers.get_mission(key)
        for method in mission.methods:
            print(row(mission, method.key), flush=True)


if __name__ == "__main__":
    main()
