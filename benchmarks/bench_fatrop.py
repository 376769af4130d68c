"""IPOPT against FATROP on the same stage-structured NLPs, side by side in one run (issue 17).

Run: python benchmarks/bench_fatrop.py [--case MISSION:METHOD ...] [--repeats 20] [--cold 5]
                                       [--step S]

For each case (a mission's method at its default node count) both back ends solve the same
requests in one process, interleaved (every round solves each back end once, in turn, so a
change of machine load hits both):
- "first": the first solve, which builds the NLP and the solver (once);
- "cold": solves from the method's initial guess on the built NLP (`--cold` rounds);
- "warm": re-solves after a step of +1 % and -1 % (alternating) of the mission's live
  parameter from the optimum at the defaults, warm-started from that optimum: what a slider
  move costs in the explorer (`--repeats` rounds). The reentry's entry speed steps -0.5 %
  instead: 1 % below the default neither back end finds a feasible trajectory. `--step S`
  makes the steps +S and -S (relative) for every case: a far jump of the slider.
Times are medians of the whole `Mission.solve` (verify=False: the explorer defers the
check) and, in "nlp", of the NLP solve inside it (the solver call with FATROP's mapping to
and from stage order). "it" are median iteration counts; "ratio" is a median time over
IPOPT's, cold and warm (below 1: FATROP faster). "dJ" is the relative difference of FATROP's
optimal cost at the defaults from IPOPT's. "off" counts the converged solves at two
off-default values of the live parameter (`OFF_DEFAULT`), each cold and warm from the
default optimum. A case whose mission does not offer FATROP (hovercraft: from the cold guess
it stops short of the optimum at some off-default thrusts where IPOPT converges) is
measured all the same, FATROP offered for the run only.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import solvers
from solvers.nlp.casadi_nlp import NLP

sys.path.insert(0, str(Path(__file__).parent))
from bench_missions import LIVE_PARAMETER  # noqa: E402

CASES = ("lunar-landing:hermite-simpson", "lunar-landing:multiple-shooting",
         "hovercraft:multiple-shooting", "apollo-reentry:hermite-simpson")
BACKENDS = ("ipopt", "fatrop")
# The two warm steps of the live parameter (bench_missions.LIVE_PARAMETER) from the default
# (factors) and two off-default values (factors) that the mission's prechecks accept.
STEPS = {"lunar-landing": (1.01, 0.99), "hovercraft": (1.01, 0.99),
         "apollo-reentry": (1.01, 0.995)}
OFF_DEFAULT = {"lunar-landing": (0.8, 1.25), "hovercraft": (0.9, 1.25),
               "apollo-reentry": (1.05, 1.09)}


class NLPClock:
    """Wall time spent in `NLP.solve` while `measuring()` is active."""

    def __init__(self) -> None:
        self.total = 0.0

    @contextmanager
    def measuring(self) -> Iterator[None]:
        original = NLP.solve

        def timed(nlp: NLP, *args: object, **kwargs: object) -> object:
            start = time.perf_counter()
            try:
                return original(nlp, *args, **kwargs)
            finally:
                self.total += time.perf_counter() - start

        NLP.solve = timed  # type: ignore[method-assign]
        try:
            yield
        finally:
            NLP.solve = original  # type: ignore[method-assign]


@contextmanager
def offering_fatrop(mission: solvers.Mission, method: str) -> Iterator[None]:
    """`method` of `mission` offers FATROP while measuring, whether or not it does."""
    mission.methods = tuple(  # an instance attribute over the class's tuple
        m.replace(backends=tuple(dict.fromkeys((*m.backends, "fatrop")))) if m.key == method
        else m for m in type(mission).methods)
    try:
        yield
    finally:
        del mission.methods


def _timed(clock: NLPClock, solve: Callable[[], solvers.Solution]
           ) -> tuple[solvers.Solution, float, float]:
    """(solution, wall s, NLP s) of one solve."""
    clock.total = 0.0
    start = time.perf_counter()
    with clock.measuring():
        sol = solve()
    return sol, time.perf_counter() - start, clock.total


def bench_case(case: str, repeats: int, cold_rounds: int, step: float | None = None
               ) -> list[str]:
    """The table rows of one case, one per back end (`step`: the warm steps' size instead
    of the mission's)."""
    mission_key, method = case.split(":")
    mission = solvers.get_mission(mission_key)
    key = LIVE_PARAMETER[mission_key]
    base = mission.defaults(method)[key]
    steps = STEPS[mission_key] if step is None else (1.0 + step, 1.0 - step)
    clock = NLPClock()

    def run(backend: str, factor: float = 1.0, warm: solvers.Solution | None = None
            ) -> tuple[solvers.Solution, float, float]:
        return _timed(clock, lambda: mission.solve({key: base * factor}, method=method,
                                                   backend=backend, warm=warm, verify=False))

    first = {b: run(b) for b in BACKENDS}
    optimum = {b: first[b][0] for b in BACKENDS}
    times = {b: {"cold": [], "warm": [], "nlp": [], "it_cold": [], "it_warm": []}
             for b in BACKENDS}
    ok = {b: optimum[b].status == "optimal" for b in BACKENDS}
    for b in BACKENDS:  # builds the warm-start solver, untimed
        run(b, steps[0], optimum[b])
    for _ in range(cold_rounds):
        for b in BACKENDS:
            sol, wall, _ = run(b)
            times[b]["cold"].append(wall)
            times[b]["it_cold"].append(sol.stats.get("iterations", 0))
            ok[b] &= sol.status == "optimal"
    for k in range(repeats):
        for b in BACKENDS:
            sol, wall, nlp = run(b, steps[k % 2], optimum[b])
            times[b]["warm"].append(wall)
            times[b]["nlp"].append(nlp)
            times[b]["it_warm"].append(sol.stats.get("iterations", 0))
            ok[b] &= sol.status == "optimal"
    off = {b: [run(b, f, w)[0].status == "optimal" for f in OFF_DEFAULT[mission_key]
               for w in (None, optimum[b])] for b in BACKENDS}
    med = {b: {k: statistics.median(v) for k, v in times[b].items()} for b in BACKENDS}
    j_ipopt = optimum["ipopt"].cost.value
    rows = []
    for b in BACKENDS:
        m = med[b]
        cold_ratio, ratio = (m[k] / med["ipopt"][k] for k in ("cold", "warm"))
        d_j = (optimum[b].cost.value - j_ipopt) / abs(j_ipopt)
        flag = "" if ok[b] else "  [not all optimal]"
        rows.append(
            f"{case:34s} {b:7s} {1e3 * first[b][1]:8.0f} {1e3 * m['cold']:8.1f} "
            f"{m['it_cold']:4.0f} {cold_ratio:6.2f} {1e3 * m['warm']:8.1f} "
            f"{1e3 * m['nlp']:8.1f} {m['it_warm']:4.0f} {ratio:6.2f} "
            f"{optimum[b].cost.value:14.8f} {d_j:9.1e} "
            f"{sum(off[b])}/{len(off[b])}{flag}")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", nargs="*", default=list(CASES),
                        help="MISSION:METHOD pairs (default: %(default)s)")
    parser.add_argument("--repeats", type=int, default=20, help="warm re-solves per back end")
    parser.add_argument("--cold", type=int, default=5, help="cold solves per back end")
    parser.add_argument("--step", type=float, help="relative size of the warm steps "
                        "(default: 0.01, the reentry's -0.005)")
    args = parser.parse_args()
    header = (f"{'case':34s} {'backend':7s} {'first ms':>8s} {'cold ms':>8s} {'it':>4s} "
              f"{'ratio':>6s} {'warm ms':>8s} {'nlp ms':>8s} {'it':>4s} {'ratio':>6s} "
              f"{'cost':>14s} {'dJ':>9s} off")
    print(header)
    print("-" * len(header))
    for case in args.case:
        mission_key, method = case.split(":")
        with offering_fatrop(solvers.get_mission(mission_key), method):
            try:
                rows = bench_case(case, args.repeats, args.cold, args.step)
            except ValueError as exc:  # a step outside the parameter's range
                rows = [f"{case:34s} skipped: {exc}"]
        print("\n".join(rows), flush=True)


if __name__ == "__main__":
    main()
