"""Convex guidance side by side, in one run.

Run: python benchmarks/bench_convex.py [--skip-others]

1. Mars powered descent: `lossless` (SOCP, CVXPY + Clarabel), `scvx` and `hermite-simpson`
   (IPOPT) on the nonconvex original, at their default node counts: fuel, flight time, solver
   iterations (SOCP solves for lossless), cold time (first solve, building included) and warm
   time (a 1 % change of the start's downrange speed, warm-started from the optimum).
2. SCvx against IPOPT on the same Hermite–Simpson NLP of other missions (lunar landing,
   hovercraft, CW rendezvous, and the gallery's keep-out rendezvous, whose clearance path
   constraint is active on an arc): cost, iterations, cold and warm time.

Times are wall-clock on this machine with the re-propagation check deferred (as the explorer
does); run it on an idle machine for numbers worth comparing.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import solvers
from solvers.context import SolveContext
from solvers.methods import SCVX
from solvers.mission import Mission
from solvers.problem import Method
from solvers.registry import load_mission_files
from solvers.solution import Solution

LIVE = {"powered-descent": "vx0", "lunar-landing": "thrust", "hovercraft": "accel",
        "cw-rendezvous": "accel", "keep-out-rendezvous": "keep_out"}
KEEP_OUT = Path(__file__).parents[1] / "examples" / "keep_out_rendezvous.py"


def _timed(fn, *args, **kwargs) -> tuple[Solution, float]:
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def _nudged(mission: Mission, values: dict[str, float]) -> dict[str, float]:
    key = LIVE[mission.key]
    return {**values, key: values[key] * 1.01}


def _row(label: str, cold: Solution, t_cold: float, warm: Solution, t_warm: float) -> str:
    tf = cold.quantities.get("tf") or cold.quantities.get("T")
    tf_text = f"{tf.value:10.4f}" if tf is not None else " " * 10
    return (f"| {label:<34} | {cold.cost.value:12.6f} | {tf_text} | "
            f"{int(cold.stats.get('iterations', 0)):5d} | {1e3 * t_cold:9.0f} | "
            f"{int(warm.stats.get('iterations', 0)):5d} | {1e3 * t_warm:9.0f} | "
            f"{cold.status}/{warm.status} |")


def descent_table() -> list[str]:
    mission = solvers.get_mission("powered-descent")
    rows = []
    for method in mission.methods:
        values = mission.defaults(method.key)
        cold, t_cold = _timed(mission.solve, values, method.key, verify=False)
        warm, t_warm = _timed(mission.solve, _nudged(mission, values), method.key, warm=cold,
                              verify=False)
        rows.append(_row(f"powered-descent {method.key} N={cold.nodes}", cold, t_cold, warm,
                         t_warm))
    return rows


def _general(mission: Mission, method: Method, values: dict[str, float], nodes: int,
             backend: str, warm: Solution | None) -> Solution:
    """A general method the mission does not list (SCvx), through the mission's own path."""
    ctx = SolveContext()
    if mission.solves_itself(method):
        return mission._solve(values, method, nodes, backend, warm, ctx)
    return mission.solve_direct(values, method, nodes, backend, warm, ctx)


def scvx_table(keys: tuple[str, ...] = ("lunar-landing", "hovercraft", "cw-rendezvous",
                                         "keep-out-rendezvous")) -> list[str]:
    errors = load_mission_files([str(KEEP_OUT)])
    if errors:
        raise SystemExit(f"{KEEP_OUT}: {errors}")
    rows = []
    for key in keys:
        mission = solvers.get_mission(key)
        hs = mission.method("hermite-simpson")
        values, _, nodes = mission.validate({}, hs.key, None)
        for method, backend in ((hs, "ipopt"), (SCVX.replace(nodes=hs.nodes), "scvx")):
            cold, t_cold = _timed(_general, mission, method, values, nodes, backend, None)
            warm, t_warm = _timed(_general, mission, method, _nudged(mission, values), nodes,
                                  backend, cold)
            rows.append(_row(f"{key} {method.key} ({backend}) N={nodes}", cold, t_cold, warm,
                             t_warm))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-others", action="store_true",
                        help="only the powered-descent methods")
    args = parser.parse_args()
    print("| case | cost | tf | it cold | cold ms | it warm | warm ms | status |")
    print("|---|---|---|---|---|---|---|---|")
    for row in descent_table() + ([] if args.skip_others else scvx_table()):
        print(row, flush=True)


if __name__ == "__main__":
    main()
