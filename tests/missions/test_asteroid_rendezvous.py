"""Mission `asteroid-rendezvous` against paper 003 (SPEC M4): launch map, impulsive guesses,
low-thrust solution, sweeps and the launch-map CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest
from mission_checks import pickled

import solvers
from solvers import sweep
from solvers.dynamics.ephemeris import KAMOOALEWA_B, VU, iso_from_mjd, mjd_from_iso
from solvers.missions.asteroid_rendezvous import fixed_structure
from solvers.missions.asteroid_rendezvous.guess import KINDS, THREE, Window, pso_search
from solvers.missions.asteroid_rendezvous.launch_map import (
    compute_launch_map,
    launch_c3_rows,
    main,
    seed_values,
    windows,
)
from solvers.missions.asteroid_rendezvous.view import body_tracks

MISSION = solvers.get_mission("asteroid-rendezvous")
# Paper 003 §4: the optimised transfers launch on 2022-05-28 and 2022-11-29.
PAPER_LAUNCHES = (mjd_from_iso("2022-05-28"), mjd_from_iso("2022-11-29"))
MJD_2022 = mjd_from_iso("2022-01-01")


def _near_paper_launch(mjd: float, days: float) -> bool:
    return min(abs(mjd - p) for p in PAPER_LAUNCHES) <= days


@pytest.fixture(scope="module")
def launch_map():
    return compute_launch_map(workers=1)


@pytest.fixture(scope="module")
def fast_solution(solved):
    return solved("asteroid-rendezvous", "hermite-simpson", 40, {})


def _published(name: str):
    return next(p for p in MISSION.published if p.name == name)


def test_three_impulse_swarm_finds_the_papers_two_launch_dates():
    """Paper 003 §4: launch windows 2022-05-28 and 2022-11-29; the three-impulse fitness has
    one minimum in each half of 2022 (searched separately, so the seed cannot pick)."""
    for (start, end), expected in zip((("2022-01-01", "2022-09-01"), ("2022-09-01", "2023-03-01")),
                                      PAPER_LAUNCHES, strict=True):
        window = Window(mjd_from_iso(start), mjd_from_iso(end), 700.0, 20e6, KAMOOALEWA_B)
        transfer = pso_search(THREE, window, particles=60, generations=120, seed=0)
        assert abs(transfer.launch_mjd - expected) <= 3.0, iso_from_mjd(transfer.launch_mjd)
        assert transfer.c3 <= 20e6 * (1 + 1e-9)


def test_launch_map_has_four_windows_a_year(launch_map):
    """Paper 003 fig. 2: four launch-C3 troughs a year, short transfers of 50–200 d and long
    ones of 380–550 d, alternating."""
    assert launch_map.c3.shape == (730, 130)
    found = windows(launch_map, c3_max=20.0)
    per_year = _published("windows_per_year").value
    for year in ("2022", "2023"):
        assert sum(iso_from_mjd(w.first_mjd).startswith(year) for w in found) >= per_year
    short = [w for w in found if 50.0 <= w.best_tof <= 200.0]
    long_ = [w for w in found if w.tof_min >= 370.0 and w.tof_max <= 560.0]
    assert len(short) >= 4 and len(long_) >= 4


def test_launch_map_windows_open_and_close_at_the_papers_dates(launch_map):
    """The paper's launch dates are the node crossings, where windows of the map begin."""
    firsts = np.array([w.first_mjd for w in windows(launch_map)])
    for date in PAPER_LAUNCHES:
        assert np.min(np.abs(firsts - date)) <= 2.0


def test_sweep_processes_match_the_in_process_grid():
    launch = MJD_2022 + np.arange(0.0, 60.0, 3.0)
    tofs = np.linspace(50.0, 600.0, 12)
    serial = launch_c3_rows(launch, tofs, KAMOOALEWA_B)
    parallel = sweep.grid_rows(launch_c3_rows, launch, tofs, KAMOOALEWA_B, workers=2, chunks=3)
    assert np.array_equal(np.isnan(serial), np.isnan(parallel))
    assert np.allclose(serial, parallel, equal_nan=True)


def test_the_same_sweep_runs_on_a_dask_cluster():
    distributed = pytest.importorskip("dask.distributed")
    launch = MJD_2022 + np.arange(0.0, 30.0, 3.0)
    tofs = np.linspace(50.0, 600.0, 8)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        remote = sweep.grid_rows(launch_c3_rows, launch, tofs, KAMOOALEWA_B,
                                 scheduler=cluster.scheduler_address, chunks=3)
    assert np.allclose(remote, launch_c3_rows(launch, tofs, KAMOOALEWA_B), equal_nan=True)


def test_a_scheduler_address_without_dask_says_how_to_get_it():
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        with pytest.raises(RuntimeError, match="dask"):
            sweep.grid_rows(launch_c3_rows, np.array([MJD_2022]), np.array([100.0]),
                            KAMOOALEWA_B, scheduler="tcp://127.0.0.1:1")
    else:
        pytest.skip("dask is installed")


def test_mission_grid_and_monte_carlo_solve_every_value_set():
    fixed = {"pso_particles": 20, "pso_generations": 20}
    grid = sweep.mission_grid("asteroid-rendezvous", {"guess_kind": [0, 1]}, fixed,
                              method="impulsive", nodes=20, workers=2)
    assert [g["values"]["guess_kind"] for g in grid] == [0.0, 1.0]
    assert all(g["status"] == "optimal" for g in grid)
    runs = sweep.monte_carlo("asteroid-rendezvous",
                             lambda rng: {"pso_seed": float(rng.integers(0, 100))}, runs=2,
                             fixed=fixed, method="impulsive", nodes=20, workers=2)
    assert len(runs) == 2 and all(r["cost"]["value"] > 0 for r in runs)


def test_a_map_cell_seeds_the_solve(launch_map):
    """Choosing a cell (launch date, flight time) of the map seeds the transfer there."""
    best = min(windows(launch_map), key=lambda w: w.best_c3)
    values = seed_values(best.best_mjd, best.best_tof)
    sol = MISSION.solve(values, method="impulsive")
    assert sol.status == "optimal"
    assert sol.quantities["launch_date"].value == pytest.approx(best.best_mjd - MJD_2022)
    assert sol.quantities["flight_time"].value == pytest.approx(best.best_tof)
    assert sol.quantities["launch_c3"].value == pytest.approx(best.best_c3, rel=1e-6)


def test_launch_map_cli_writes_the_data_files(tmp_path):
    assert main(["--out", str(tmp_path), "--start", "2022-01-01", "--end", "2022-02-01",
                 "--tof", "50", "500", "10", "--workers", "1", "--no-png"]) == 0
    data = np.load(tmp_path / "launch_c3.npz")
    assert data["c3_km2_s2"].shape == (31, 10)
    lines = (tmp_path / "launch_c3.csv").read_text().splitlines()
    assert lines[2].startswith("2022-01-01,59580.0,") and len(lines) == 2 + 31


def test_low_thrust_fast_case_reproduces_the_papers_shape(fast_solution):
    """Paper 003 §4 and fig. 3 (40 segments instead of 150 to stay fast): launch on one of the
    paper's dates, bang–bang thrust with two main burns, |U| <= Fmax at every node."""
    sol = fast_solution
    # 40 segments converge but miss the arrival by thousands of km on re-propagation: the
    # status says so (issue 12) instead of "optimal".
    assert sol.status == "inaccurate", sol.message
    assert "arrival_position_miss_m" in sol.message and "nodes='auto'" in sol.message
    launch = MJD_2022 + sol.quantities["launch_date"].value
    assert _near_paper_launch(launch, 3.0), iso_from_mjd(launch)
    assert sol.quantities["flight_time"].value <= 700.0 + 1e-6
    assert sol.quantities["burn_arcs"].value == 2
    throttle = np.linalg.norm(sol.node_u, axis=1) / 0.12
    assert throttle.max() <= 1.0 + 1e-6
    assert np.mean((throttle < 0.05) | (throttle > 0.95)) >= 0.9  # bang–bang
    # The departure uses the launcher's v∞ within the C3 bound.
    assert sol.quantities["launch_c3"].value <= 20.0 + 1e-6
    assert sol.cost.value == pytest.approx(1500.0 - sol.quantities["final_mass"].value)


def test_low_thrust_repropagation_misses_little(fast_solution):
    check = fast_solution.check
    # 40 segments of ~10 d: Hermite–Simpson is 4th order, the miss shrinks fast with N
    # (under 1 km at the default 400 segments, next test).
    assert check["arrival_position_miss_m"] < 3e7
    assert check["arrival_velocity_miss_m_s"] < 5.0
    assert abs(check["final_mass_difference_kg"]) < 1e-6


def test_the_live_default_is_optimal_within_the_one_kilometre_target(solved):
    """The default 400-segment mesh meets the mission's own targets (1 km, 1 cm/s, cost
    error within 1e-4 of the fuel) on the paper 003 case; 150 segments missed by 30 km."""
    sol = solved("asteroid-rendezvous", "hermite-simpson", None, {})
    assert sol.nodes == 400
    assert sol.status == "optimal", sol.message
    assert sol.check["arrival_position_miss_m"] < 1e3
    assert sol.cost.error_estimate <= 1e-4 * sol.cost.value


@pytest.fixture(scope="module")
def burn_coast(solved):
    return solved("asteroid-rendezvous", "burn-coast", None, {})


def test_the_burn_coast_method_refines_the_hermite_simpson_optimum(solved, burn_coast):
    """The live method keeps the Hermite–Simpson optimum's structure (coast, burn, coast,
    burn: paper 003 fig. 3) with free switch times. Its fuel lies within three times
    Hermite–Simpson's own cost error estimate of that answer (the estimate's honesty: the
    burn/coast answer has no idle mass flow on its coasts and no throttle smeared over a
    switch, and its own estimate is a thousand times smaller), and its re-propagated
    arrival is far inside the 1 km target (400 Hermite–Simpson segments: 0.6 km)."""
    hs = solved("asteroid-rendezvous", "hermite-simpson", None, {})
    sol = burn_coast
    assert sol.status == "optimal", sol.message
    assert [kind for *_, kind in sol.arcs] == ["coast", "burn", "coast", "burn"]
    assert abs(sol.cost.value - hs.cost.value) <= 3 * hs.cost.error_estimate
    assert sol.cost.error_estimate < 1e-3 * hs.cost.error_estimate
    assert sol.check["arrival_position_miss_m"] < 100.0
    assert sol.check["final_mass_difference_kg"] == pytest.approx(0.0, abs=1e-6)


def test_a_slider_move_re_solves_the_fixed_structure_in_a_few_newton_steps(burn_coast,
                                                                            monkeypatch):
    """No thrust bound is active in the fixed-structure NLP, so a 1 % thrust step is a
    few Newton steps from the last answer (the 400-segment Hermite–Simpson NLP took 73-251
    IPOPT iterations for the same steps; a cold start from it, 6), without a structure
    solve; and the NLP's optimum does not depend on the path: back at the defaults the
    first answer returns."""
    found = []
    real = fixed_structure.solve_low_thrust
    monkeypatch.setattr(fixed_structure, "solve_low_thrust",
                        lambda *args: found.append(args[2]) or real(*args))
    thrust = MISSION.defaults("burn-coast")["thrust"]
    up = MISSION.solve({"thrust": 1.01 * thrust}, method="burn-coast", warm=burn_coast,
                       verify=False)
    back = MISSION.solve({}, method="burn-coast", warm=up, verify=False)
    assert up.status == back.status == "optimal", (up.message, back.message)
    assert max(up.stats["iterations"], back.stats["iterations"]) <= 4 and found == []
    assert up.cost.value < burn_coast.cost.value  # more thrust, less propellant
    assert back.cost.value == pytest.approx(burn_coast.cost.value, abs=1e-6)


def test_a_phase_that_vanishes_sends_the_solve_back_for_the_structure(burn_coast,
                                                                      monkeypatch):
    """A warm answer in which a phase shrinks below its share of the flight is not kept:
    the Hermite–Simpson solve finds the structure again (every phase counts as vanished
    here)."""
    found = []
    real = fixed_structure.solve_low_thrust
    monkeypatch.setattr(fixed_structure, "solve_low_thrust",
                        lambda *args: found.append(args[2]) or real(*args))
    monkeypatch.setattr(fixed_structure, "MIN_SHARE", 0.9)
    thrust = MISSION.defaults("burn-coast")["thrust"]
    sol = MISSION.solve({"thrust": 1.01 * thrust}, method="burn-coast", warm=burn_coast,
                        verify=False)
    assert found == [400] and sol.status == "optimal", sol.message


def test_warm_restart_after_a_small_thrust_change(fast_solution):
    warm = MISSION.solve({"thrust": 0.1212}, nodes=40, warm=fast_solution, verify=False)
    assert warm.status == "optimal"
    assert warm.stats["iterations"] < fast_solution.stats["iterations"]
    # More thrust never needs more propellant for the same transfer.
    assert warm.cost.value <= fast_solution.cost.value + 1e-6


def test_other_segment_counts_and_other_guesses_restart_correctly(fast_solution):
    finer = MISSION.solve(nodes=60, warm=fast_solution, verify=False)
    assert finer.status == "optimal"
    assert finer.cost.value == pytest.approx(fast_solution.cost.value, rel=0.01)
    # A new guess kind must not be replaced by the previous optimum.
    other = MISSION.solve({"guess_kind": 0}, nodes=40, warm=fast_solution, verify=False)
    assert other.quantities["impulsive_dv"].value != fast_solution.quantities["impulsive_dv"].value


def test_solution_carries_what_the_explorer_draws(fast_solution):
    sol = fast_solution
    pres = MISSION.present(sol)
    n = sol.nodes + 1
    assert sol.node_x.shape == (n, 7) and sol.node_u.shape == (n, 3)
    assert pres.path.shape == (len(sol.t), 3) and pres.thrust.shape == (n, 3)
    assert pres.display_unit == "AU" and pres.display_scale == pytest.approx(1 / 1.495978707e11)
    assert pres.time_unit == "d" and pres.time_scale == pytest.approx(1 / 86400)
    tracks = body_tracks(sol)
    assert all(p.shape == (len(sol.t), 3) for p in tracks.values())
    # The spacecraft leaves Earth and meets the asteroid: both tracks touch the path's ends.
    assert np.linalg.norm(tracks["Earth"][0] - pres.path[0]) < 1e3
    assert np.linalg.norm(tracks["Kamoʻoalewa"][-1] - pres.path[-1]) < 1.0
    # Earth and the asteroid move with the spacecraft in the animation.
    moving = {b.name: b.track for b in pres.bodies if b.track is not None}
    assert len(moving) == 2 and all(t.shape == (len(sol.t), 3) for t in moving.values())
    # The path is coloured by thrust magnitude: coasts (0 mN) stand apart from burns.
    assert pres.color_by.values.shape == (len(sol.t),)
    assert pres.color_by.values.min() < 0.1 and pres.color_by.values.max() > 119.0
    launch_label = f"launch {iso_from_mjd(MJD_2022 + sol.quantities['launch_date'].value)}"
    arrival_label = f"arrival {iso_from_mjd(MJD_2022 + sol.quantities['arrival_date'].value)}"
    # Both dates are named, at Earth and at the asteroid; a year's flight ends within a
    # label's length of its start (a quasi-satellite), so one label names both there and
    # the arrival keeps its point (two labels at one spot covered each other).
    gap = np.linalg.norm(tracks["Kamoʻoalewa"][-1] - tracks["Earth"][0])
    labels = [(m.name, m.point) for m in pres.markers]
    assert gap < 0.5 * 1.495978707e11
    assert labels[:2] == [(f"{launch_label} · {arrival_label}", True), ("", True)]
    # The transfer starts at Earth (within epv00's spline error) and ends at the asteroid.
    earth = np.array(pres.bodies[1].center)
    assert np.linalg.norm(pres.path[0] - earth) < 1e3
    titles = {p.title for p in pres.plots}
    assert {"thrust magnitude", "thrust ecliptic longitude", "thrust ecliptic latitude",
            "semi-major axis", "eccentricity", "inclination", "mass"} <= titles
    kinds = {kind for _, _, kind in sol.arcs}
    assert kinds == {"burn", "coast"}
    # Paper 003 fig. 2 beside the plots, with this solution's date pair marked.
    (grid,) = pres.maps
    assert grid.z.shape == (len(grid.x), len(grid.y))
    assert grid.marker == pytest.approx((sol.quantities["launch_date"].value,
                                         sol.quantities["flight_time"].value))
    assert pres.iterates and pres.iterates[0][1].shape == (n, 3)
    json.loads(sol.to_json(dense=True))


@pytest.mark.parametrize("method", [m.key for m in MISSION.methods])
def test_every_method_pickles_and_presents(solved, method):
    sol = solved("asteroid-rendezvous", method, 40 if method == "hermite-simpson" else None, {})
    assert sol.converged, sol.message
    copy = pickled(sol)
    assert copy.check == sol.check
    pres = MISSION.present(copy)  # the mission has no view options
    assert pres.path.shape == (len(sol.t), 3) and pres.maps
    assert pres.nodes.shape == (len(sol.node_t), 3)


def test_the_low_thrust_nlp_is_the_general_hermite_simpson_transcription(fast_solution):
    """Paper 003's NLP is the OCP solved by the general transcription: free launch date and
    launch v∞ (static variables), warm start typed and re-interpolable."""
    warm = fast_solution.warm
    assert warm.kind == "hermite-simpson" and warm.n_intervals == 40 and warm.has_duals
    assert len(warm.statics) == 3
    vinf = np.linalg.norm(warm.statics) * VU
    assert vinf**2 / 1e6 == pytest.approx(fast_solution.quantities["launch_c3"].value, rel=1e-4)
    assert MISSION.method("hermite-simpson").transcription == "hermite-simpson"


def test_impulsive_method_arcs_hit_the_asteroid():
    sol = MISSION.solve(method="impulsive")
    assert sol.status == "optimal"
    assert sol.check["arrival_position_miss_m"] < 1e3
    assert sol.check["arrival_velocity_miss_m_s"] < 1e-3
    sizes = np.linalg.norm(sol.node_u, axis=1)
    assert sol.cost.value == pytest.approx(sizes[1:].sum())
    assert sizes[0] ** 2 <= 20e6 * (1 + 1e-9)


def test_no_launch_energy_is_reported_unsolved_with_the_reason():
    """Paper eq. 13 read literally (departure at Earth's velocity): 120 mN cannot make the
    ~4 km/s plane change plus the phasing within 700 d. No bound proves it (the engine's
    Δv budget, 5.2 km/s, exceeds the plane change), so it is not called infeasible: the
    solver found no feasible trajectory, and the message says why that is expected. The
    rescue (continuation, seeds, other guesses) is cut by a 30 s limit: `time-limit`, with the
    same reason (with the default 120 s it ran 94 s on a quiet machine, a stage using up its
    share of the limit: `time-limit` too)."""
    sol = MISSION.solve({"c3_max": 0.0}, nodes=20, verify=False, time_limit=30.0)
    assert sol.status == "time-limit", sol.message
    assert "no feasible trajectory" in sol.message and "plane change" in sol.message


def test_bad_window_is_rejected():
    with pytest.raises(ValueError, match="closes"):
        MISSION.solve({"launch_start": 100.0, "launch_end": 50.0})


def test_impulsive_dv_spread_differs_from_the_paper():
    """Paper 003 §4: the three impulsive guesses differ by up to 58 % in Δv; ours by 71 %
    (the record says it does not hold)."""
    dvs = [MISSION.solve({"guess_kind": k}, method="impulsive", verify=False).cost.value
           for k in range(len(KINDS))]
    spread = 100 * (max(dvs) / min(dvs) - 1)
    pub = _published("impulsive_dv_spread")
    assert not pub.holds and not pub.agrees(spread), spread
    assert spread == pytest.approx(71.0, abs=1.0)


@pytest.mark.slow
@pytest.mark.parametrize("kind", [0, 1, 2])
def test_paper_case_each_guess_kind(kind):
    """Paper 003 §4 at 150 segments: each guess kind converges to a bang–bang transfer with two
    main burns launched on one of the paper's dates."""
    sol = MISSION.solve({"guess_kind": kind})
    # The 700 d multi-revolution transfer (kind 2) misses by about 1,200 km at 150 segments:
    # converged, and "inaccurate" by the mission's 100 km target (issue 12).
    assert sol.converged, sol.message
    launch = MJD_2022 + sol.quantities["launch_date"].value
    assert _near_paper_launch(launch, 3.0), iso_from_mjd(launch)
    assert sol.quantities["burn_arcs"].value == 2
    assert sol.check["arrival_position_miss_m"] < 2e6
    assert sol.check["arrival_velocity_miss_m_s"] < 0.5


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="the three-impulse and multi-revolution guesses run to "
                   "the 700 d limit and save ~23 % fuel: the paper's < 6 % spread does not "
                   "reproduce")
def test_optimised_fuels_within_six_percent():
    """Paper 003 §4: the three optimised fuels differ by under 6 %, each NLP seeded by its
    impulsive guess itself as in the paper (no coarse pre-solve)."""
    fuels = [MISSION.solve({"guess_kind": k, "presolve_segments": 0}, verify=False).cost.value
             for k in range(3)]
    assert max(fuels) / min(fuels) - 1 < 0.06


@pytest.mark.slow
def test_launch_map_png(tmp_path):
    pytest.importorskip("kaleido")
    assert main(["--out", str(tmp_path), "--workers", "2"]) == 0
    assert (tmp_path / "launch_c3.png").stat().st_size > 10_000


def test_a_guess_kind_with_no_arc_in_the_window_is_not_called_infeasible():
    """A request of the slow fuzz: a multi-revolution guess with flights of at most 228 d
    has no arc at all (one revolution takes about a year), which says nothing of the
    problem. Before, both methods called it `infeasible` ("the particle swarm found no
    feasible impulsive transfer in the window": no bound, no proof); now the rescue tries
    other guesses (here a three-impulse transfer converges)."""
    mission = solvers.get_mission("asteroid-rendezvous")
    values = {"pso_generations": 20, "launch_end": 992.68, "elements": 1, "pso_seed": 130,
              "pso_particles": 40, "c3_max": 64.67e6, "launch_start": -656.01,
              "max_flight_time": 227.89, "mass0": 4047.4, "isp": 2160.2, "thrust": 0.4725,
              "guess_kind": KINDS.index("two-impulse multi-revolution")}
    sol = mission.solve(values, method="impulsive", time_limit=30)
    # The rescue may find a transfer from another guess kind; the first guess's failure is
    # said either way, with what to change.
    assert sol.status != "infeasible", sol.message
    assert "choose another guess kind" in sol.message and "227.89 d" in sol.message
