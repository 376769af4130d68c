"""Robustness within the documented ranges (issue 17): solve random requests with every method
of a mission and count each method's statuses and the cross-method contradictions.

Run: python benchmarks/bench_robustness.py [--mission KEY ...] [--cases 20] [--seed 0]
     [--nodes default|reduced] [--time-limit 15] [--cold] [--jsonl cases.jsonl]

Every mission and method parameter is drawn uniformly within its range (choices and integers
as whole numbers; the swarm's size kept at its default, as the default fuzz set does); a draw
that breaks a cross-parameter rule (`Mission.validate`) is redrawn. Each case is solved cold
by every method of the mission, at its default node count or half of it ("reduced", the
default fuzz set's); `--cold` solves from the initial guess only (no continuation, no seed:
what the code did before issue 17). A contradiction is a case that one method solves (optimal or
inaccurate) while another says `failed`; every `failed` and `infeasible` case is listed with
its message, and `--jsonl` keeps every solve for a closer look.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter

import numpy as np

import solvers
from solvers.mission import Mission
from solvers.solution import STATUSES

MISSIONS = ("lunar-landing", "cw-rendezvous", "elliptic-transfer", "hovercraft",
            "apollo-reentry", "bang-bang", "asteroid-rendezvous")
# Kept at their defaults: a 1000-generation swarm is a valid request but costs a minute.
FIXED = {"pso_particles", "pso_generations"}


def draw(mission: Mission, rng: np.random.Generator) -> dict[str, float]:
    """One request: every parameter of every method uniform in its range, valid together."""
    params = {p.key: p for m in mission.methods for p in mission.all_params(m.key)}
    while True:
        values = {}
        for key, p in params.items():
            if key in FIXED:
                continue
            if p.options or p.integer:
                values[key] = float(rng.integers(int(p.min), int(p.max) + 1))
            else:
                values[key] = float(rng.uniform(p.min, p.max))
        try:
            mission.validate(values, mission.methods[0].key)
        except ValueError:
            continue
        return values


def solve_case(mission: Mission, values: dict[str, float], reduced: bool,
               time_limit: float, cold: bool) -> list[dict[str, object]]:
    """Every method's answer to one request: status, message, cost and wall time."""
    rows = []
    for method in mission.methods:
        lo, default, _ = method.nodes
        nodes = max(lo, default // 2) if reduced else default
        start = time.perf_counter()
        sol = mission.solve(values, method=method.key, nodes=nodes, time_limit=time_limit,
                            cold=cold)
        rows.append({"mission": mission.key, "method": method.key, "nodes": nodes,
                     "status": sol.status, "message": sol.message,
                     "cost": float(sol.cost.value), "wall_s": time.perf_counter() - start,
                     "values": values})
    return rows


def contradiction(rows: list[dict[str, object]]) -> bool:
    """One method converged while another says `failed`."""
    statuses = {r["status"] for r in rows}
    return "failed" in statuses and bool(statuses & {"optimal", "inaccurate"})


def report(key: str, cases: list[list[dict[str, object]]]) -> None:
    """The status counts per method, then every failed case and contradiction."""
    counts: dict[str, Counter[str]] = {}
    for rows in cases:
        for r in rows:
            counts.setdefault(str(r["method"]), Counter())[str(r["status"])] += 1
    shown = [s for s in STATUSES if any(c[s] for c in counts.values())]
    print(f"\n{key}: {len(cases)} cases")
    print(f"  {'method':20s}" + "".join(f"{s:>16s}" for s in shown))
    for method, c in counts.items():
        print(f"  {method:20s}" + "".join(f"{c[s]:16d}" for s in shown))
    contra = [rows for rows in cases if contradiction(rows)]
    print(f"  contradictions (converged vs failed): {len(contra)}")
    for i, rows in enumerate(cases):
        odd = [r for r in rows if r["status"] not in ("optimal", "inaccurate")]
        if not odd:
            continue
        flag = "CONTRADICTION " if contradiction(rows) else ""
        print(f"  case {i} {flag}{json.dumps(rows[0]['values'])}")
        for r in rows:
            print(f"    {r['method']:18s} {r['status']:12s} {r['wall_s']:6.1f} s  "
                  f"{str(r['message'])[:220]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", nargs="*", default=list(MISSIONS))
    parser.add_argument("--cases", type=int, default=20, help="requests per mission")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--nodes", choices=("default", "reduced"), default="default")
    parser.add_argument("--time-limit", type=float, default=15.0, help="s per solve")
    parser.add_argument("--cold", action="store_true",
                        help="from the initial guess only, no rescue (the code before issue 17)")
    parser.add_argument("--jsonl", help="append every solve to this file (one JSON a line)")
    args = parser.parse_args()
    for key in args.mission:
        mission = solvers.get_mission(key)
        rng = np.random.default_rng([args.seed, sum(map(ord, key))])
        started, cases = time.perf_counter(), []
        for _ in range(args.cases):
            rows = solve_case(mission, draw(mission, rng), args.nodes == "reduced",
                              args.time_limit, args.cold)
            cases.append(rows)
            if args.jsonl:
                with open(args.jsonl, "a", encoding="utf-8") as out:
                    out.writelines(json.dumps(r) + "\n" for r in rows)
        report(key, cases)
        print(f"  {time.perf_counter() - started:.0f} s", flush=True)


if __name__ == "__main__":
    main()
