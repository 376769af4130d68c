"""Accuracy read-outs of issue 12, per mission and method: at the default node count and
with `nodes="auto"` (to the mission's targets, and to a target 100x tighter): the largest
interval error, the re-propagated headline miss, nodes, solve and check times; and what the
deferred check costs with and without the interval errors and the indirect reference.

    python benchmarks/bench_accuracy.py [--tight-factor 100] [--missions KEY ...]

Prints a markdown table per mission.
"""

from __future__ import annotations

import argparse
import time

import solvers
from solvers.solution import Solution


def _row(label: str, sol: Solution, wall: float) -> str:
    headline = next(iter(sol.targets), "")
    err = sol.interval_error.values.max() if sol.interval_error is not None else float("nan")
    miss = sol.check.get(headline, float("nan"))
    steps = " → ".join(str(int(s["nodes"])) for s in sol.mesh) or str(sol.nodes)
    return (f"| {label} | {sol.method} | {steps} | {sol.status} | {err:.2e} | {miss:.3e} | "
            f"{sol.targets.get(headline, float('nan')):g} | {wall:.2f} |")


def bench(key: str, tight: float) -> list[str]:
    mission = solvers.get_mission(key)
    headline = next(iter(mission.tolerances))
    lines = [f"### {key} (headline miss: {headline})", "",
             "| nodes | method | mesh | status | max interval error | miss | target | "
             "time s |", "|---|---|---|---|---|---|---|---|"]
    for method in mission.methods:
        t0 = time.perf_counter()
        sol = mission.solve(method=method.key, verify=False)
        t1 = time.perf_counter()
        sol.run_check()
        t2 = time.perf_counter()
        lines.append(_row("default", sol, t2 - t0) + f" solve {t1 - t0:.2f} + check "
                     f"{t2 - t1:.2f}")
        for label, tol in (("auto", None),
                           ("auto, tight", mission.tolerances[headline] / tight)):
            t0 = time.perf_counter()
            auto = mission.solve(method=method.key, nodes="auto", tol=tol)
            lines.append(_row(label, auto, time.perf_counter() - t0))
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--tight-factor", type=float, default=100.0)
    parser.add_argument("--missions", nargs="*", default=[m.key for m in solvers.list_missions()])
    args = parser.parse_args()
    for key in args.missions:
        print("\n".join(bench(key, args.tight_factor)), "\n", flush=True)


if __name__ == "__main__":
    main()
