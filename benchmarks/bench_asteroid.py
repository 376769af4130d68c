"""Asteroid rendezvous (paper 003): launch map, PSO guesses, low-thrust solves, against the
issue's speed targets and the paper's results.

Run: python benchmarks/bench_asteroid.py [--nodes 150] [--workers 2]
Targets: launch map (730 x 130 Lambert grid) < 5 s with local processes; one PSO guess < 2 s;
150-segment low-thrust solve < 3 s cold, < 1 s warm after a small thrust change.
"Cold" is the first solve in a fresh process: PSO, Earth spline, both NLP builds (30-segment
pre-solve and N-segment) and the solves. "Warm" re-solves from the previous optimum after a
1 % thrust change; the first warm solve also builds IPOPT's warm-start instance.
"""

from __future__ import annotations

import argparse
import time

import solvers
from solvers.dynamics.ephemeris import KAMOOALEWA_B, MJD_2022, iso_from_mjd, mjd_from_iso
from solvers.missions.asteroid_rendezvous.guess import KINDS, Window, pso_search
from solvers.missions.asteroid_rendezvous.launch_map import compute_launch_map, windows

TARGETS = {"map": 5.0, "pso": 2.0, "cold": 3.0, "warm": 1.0}


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def _verdict(seconds: float, key: str) -> str:
    verdict = "ok" if seconds < TARGETS[key] else "MISSED"
    return f"{seconds:7.2f} s  (target < {TARGETS[key]:g} s: {verdict})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--nodes", type=int, default=150)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    mission = solvers.get_mission("asteroid-rendezvous")

    print("== low-thrust solve (paper 003 case, three-impulse guess)")
    cold, t_cold = _timed(lambda: mission.solve(nodes=args.nodes, verify=False))
    print(f"cold, fresh process      {_verdict(t_cold, 'cold')}  {cold.stats['iterations']:.0f} it")
    warm = cold
    for k, factor in enumerate((1.01, 1.0, 1.01)):
        warm, t = _timed(lambda f=factor, w=warm: mission.solve(
            {"thrust": 0.12 * f}, nodes=args.nodes, warm=w, verify=False))
        label = "warm (builds warm IPOPT)" if k == 0 else "warm"
        print(f"{label:24s} {_verdict(t, 'warm')}  {warm.stats['iterations']:.0f} it, "
              f"fuel {warm.cost.value:.3f} kg")
    _, t_check = _timed(cold.run_check)
    print(f"re-propagation check     {t_check:7.2f} s")

    print("\n== launch map (paper 003 fig. 2)")
    for revs in (0, 1):
        m, t = _timed(lambda r=revs: compute_launch_map(workers=args.workers, max_revs=r))
        print(f"{m.c3.shape[0]} x {m.c3.shape[1]}, revolutions 0..{revs}, processes "
              f"{_verdict(t, 'map')}")
    m1, t1 = _timed(lambda: compute_launch_map(workers=1))
    print(f"same, in this process    {t1:7.2f} s")
    found = windows(m1)
    print(f"{len(found)} windows with C3 <= 20 km²/s² over 2022-2023:")
    for w in found:
        print(f"  {iso_from_mjd(w.first_mjd)} .. {iso_from_mjd(w.last_mjd)}  flight "
              f"{w.tof_min:3.0f}-{w.tof_max:3.0f} d  best {iso_from_mjd(w.best_mjd)} "
              f"{w.best_tof:3.0f} d C3 {w.best_c3:.2f}")

    print("\n== PSO guesses (100 particles x 200 generations, seed 0)")
    window = Window(mjd_from_iso("2022-01-01"), mjd_from_iso("2024-01-01"), 700.0, 20e6,
                    KAMOOALEWA_B)
    for kind, name in enumerate(KINDS):
        tr, t = _timed(lambda k=kind: pso_search(k, window, 100, 200, 0))
        print(f"{name:30s} {_verdict(t, 'pso')}  launch {iso_from_mjd(tr.launch_mjd)}, "
              f"{tr.flight_days:.0f} d, Δv {tr.total_dv:.0f} m/s")

    print(f"\n== per guess kind, {args.nodes} segments (NLP already built; 'direct': the "
          "impulsive guess seeds the N-segment NLP itself, no 30-segment pre-solve)")
    header = (f"{'guess':30s} {'guess launch':>12s} {'Δv m/s':>7s} {'launch':>10s} "
              f"{'tof d':>6s} {'fuel kg':>8s} {'m_f kg':>8s} {'burns':>5s} {'miss km':>8s} "
              f"{'miss m/s':>8s} {'solve s':>7s}")
    print(header)
    print("-" * len(header))
    rows = [(k, name, 30) for k, name in enumerate(KINDS)]
    rows += [(k, f"{name[:21]}, direct", 0) for k, name in enumerate(KINDS)]
    for kind, name, presolve in rows:
        sol, t = _timed(lambda k=kind, p=presolve: mission.solve(
            {"guess_kind": k, "presolve_segments": p}, nodes=args.nodes, verify=False))
        sol.run_check()
        q = sol.quantities
        print(f"{name:30s} {iso_from_mjd(MJD_2022 + q['guess_launch'].value):>12s} "
              f"{q['impulsive_dv'].value:7.0f} "
              f"{iso_from_mjd(MJD_2022 + q['launch_date'].value):>10s} "
              f"{q['flight_time'].value:6.1f} {sol.cost.value:8.3f} "
              f"{q['final_mass'].value:8.2f} {q['burn_arcs'].value:5.0f} "
              f"{sol.check['arrival_position_miss_m'] / 1e3:8.1f} "
              f"{sol.check['arrival_velocity_miss_m_s']:8.4f} {t:7.2f}  {sol.status}, "
              f"{sol.stats['iterations']:.0f} it")


if __name__ == "__main__":
    main()
