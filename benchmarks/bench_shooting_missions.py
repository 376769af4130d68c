"""Paper 004's two examples (hovercraft, Apollo reentry): solve times and accuracy per method
and back end, against the maximum-principle references and the published numbers.

Run: python benchmarks/bench_shooting_missions.py [--repeats 5] [--fine]

"cold" is the first solve (includes building the NLP), "warm" the best of `repeats` re-solves
after a 1 % change of a live parameter (alternating), warm-started from the previous optimum —
what a slider move costs (target: under 100 ms at the default node count); the first warm
re-solve, which builds the warm-start solver, is not counted. Errors: the hovercraft's T
against the maximum-principle T (both of the paper's guesses T0 = 2 and 5), the reentry's
J and T against the indirect multiple-shooting solution; "paper" is the published value.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import solvers
from solvers.missions.apollo_reentry import indirect_solution
from solvers.missions.hovercraft.model import cold_guess, solve_min_time

LIVE = {"hovercraft": "accel", "apollo-reentry": "v0"}


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def _warm_ms(mission, method: str, backend: str, nodes: int, values: dict, base, repeats: int):
    key = LIVE[mission.key]
    x0 = mission.defaults(method)[key]
    sol, times = base, []
    for k in range(repeats + 1):
        vals = dict(values, **{key: x0 * (1.01 if k % 2 == 0 else 1.0)})
        sol, t = _timed(lambda v=vals, w=sol: mission.solve(
            v, method=method, backend=backend, nodes=nodes, warm=w, verify=False))
        if k:  # the first warm solve builds the warm-start solver
            times.append(t)
    return 1e3 * min(times), sol


def hovercraft(repeats: int, fine: bool) -> None:
    mission = solvers.get_mission("hovercraft")
    x0, xf = np.array([0.0, 0.0, 5.0, 0.0]), np.array([5.0, 5.0, 0.0, 5.0])
    ref, t_ref = _timed(lambda: solve_min_time(x0, xf, 3.0, cold_guess(x0, xf, 3.0)))
    print(f"hovercraft: maximum principle T* = {ref.T:.10f} s ({1e3 * t_ref:.1f} ms); "
          f"paper 2.464 (T0 = 2) is {100 * (2.464 / ref.T - 1):+.2f} %, "
          f"2.529 (T0 = 5) {100 * (2.529 / ref.T - 1):+.2f} %")
    print(f"{'method':18s} {'backend':7s} {'N':>4s} {'T0':>4s} {'cold ms':>8s} {'it':>4s} "
          f"{'warm ms':>8s} {'it w':>4s} {'T':>14s} {'T/T*-1':>10s}")
    for method in mission.methods:
        runs = [(b, method.nodes[1]) for b in method.backends]
        # CasADi's SQP (BFGS Hessian) takes tens of seconds at 40 nodes: fine meshes use IPOPT.
        runs += [("ipopt", 40)] if fine else []
        for backend, n in runs:
            for t0 in (2.0, 5.0):
                vals = {"T_guess": t0}
                cold, t_cold = _timed(lambda v=vals, b=backend, n=n, m=method.key:
                                      mission.solve(v, method=m, backend=b, nodes=n,
                                                    verify=False))
                warm_ms, warm = _warm_ms(mission, method.key, backend, n, vals, cold,
                                         repeats)
                flag = "" if cold.ok and warm.ok else f" [{cold.status}/{warm.status}]"
                print(f"{method.key:18s} {backend:7s} {n:4d} {t0:4.0f} {1e3 * t_cold:8.1f} "
                      f"{int(cold.stats['iterations']):4d} {warm_ms:8.1f} "
                      f"{int(warm.stats['iterations']):4d} {cold.cost.value:14.10f} "
                      f"{cold.cost.value / ref.T - 1:10.2e}{flag}", flush=True)


def reentry(repeats: int, fine: bool) -> None:
    mission = solvers.get_mission("apollo-reentry")
    seed = mission.solve(method="hermite-simpson", nodes=160, verify=False)
    ref, t_ref = _timed(lambda: indirect_solution(seed))
    print(f"\napollo-reentry: indirect multiple shooting J* = {ref.cost:.10e}, "
          f"T* = {ref.T:.7f} s ({1e3 * t_ref:.0f} ms, residual {ref.residual:.1e}); "
          f"paper J = 2.4967e-2 ({100 * (2.4967e-2 / ref.cost - 1):+.1f} %), "
          f"T = 226.3 s ({100 * (226.3 / ref.T - 1):+.2f} %)")
    print(f"{'method':18s} {'backend':7s} {'N':>4s} {'cold ms':>8s} {'it':>4s} {'warm ms':>8s} "
          f"{'it w':>4s} {'J':>14s} {'J/J*-1':>10s} {'T':>11s} {'T/T*-1':>10s}")
    fine_nodes = {"multiple-shooting": [10, 40], "hermite-simpson": [10, 160], "lgl": [60]}
    for method in mission.methods:
        nodes = [method.nodes[1]] + (fine_nodes[method.key] if fine else [])
        for backend in method.backends[:1]:
            for n in nodes:
                cold, t_cold = _timed(lambda b=backend, n=n, m=method.key: mission.solve(
                    method=m, backend=b, nodes=n, verify=False))
                warm_ms, warm = _warm_ms(mission, method.key, backend, n, {}, cold, repeats)
                T = cold.quantities["T"].value if "T" in cold.quantities else float("nan")
                flag = "" if cold.ok and warm.ok else f" [{cold.status}/{warm.status}]"
                print(f"{method.key:18s} {backend:7s} {n:4d} {1e3 * t_cold:8.1f} "
                      f"{int(cold.stats['iterations']):4d} {warm_ms:8.1f} "
                      f"{int(warm.stats['iterations']):4d} {cold.cost.value:14.8e} "
                      f"{cold.cost.value / ref.cost - 1:10.2e} {T:11.5f} "
                      f"{T / ref.T - 1:10.2e}{flag}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--fine", action="store_true",
                        help="add the paper's 10 nodes and fine meshes")
    args = parser.parse_args()
    hovercraft(args.repeats, args.fine)
    reentry(args.repeats, args.fine)


if __name__ == "__main__":
    main()
