"""Nothing runs unbounded and no bad option costs a user their work: the default time limit
(`Mission.solve`, the CLI), a check bounded by what its solve left of the limit, and output
paths and option values refused before any work starts (issue 16)."""

from __future__ import annotations

import inspect
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import solvers
from solvers import __main__ as cli
from solvers.context import DEFAULT_TIME_LIMIT, SolveContext
from solvers.mission import Mission
from solvers.missions.asteroid_rendezvous import launch_map
from solvers.solution import Quantity, Solution
from solvers.verify import CheckTimeLimit, integrate_piecewise, time_budget


def _cli(argv: list[str]) -> int:
    """Exit code of the CLI run in this process (a parser's exit is an exit code too)."""
    try:
        return cli.main(argv)
    except SystemExit as exc:
        return int(exc.code or 0)


@pytest.fixture
def no_work(monkeypatch):
    """Any solve, sweep or launch map started fails the test: refusals come first."""
    def started(*args, **kwargs):
        raise AssertionError("work started before the bad option was refused")

    monkeypatch.setattr(cli, "solve_isolated", started)
    monkeypatch.setattr(cli, "mission_grid", started)
    monkeypatch.setattr(launch_map, "compute_launch_map", started)


@pytest.mark.parametrize("argv, named", [
    (["solve", "hovercraft", "--csv", "/tmp"], "--csv /tmp"),
    (["solve", "hovercraft", "--csv", "/proc/version"], "--csv /proc/version"),
    (["solve", "hovercraft", "--csv", ""], "--csv ''"),
    (["solve", "hovercraft", "--csv", "/nonexistent/x.csv"], "--csv /nonexistent/x.csv"),
    (["sweep", "hovercraft", "--grid", "accel=3,4", "--out", "/tmp"], "--out /tmp"),
    (["sweep", "hovercraft", "--grid", "accel=3,4", "--workers", "0"], "--workers"),
    (["sweep", "hovercraft", "--grid", "accel=3,4", "--workers", "-3"], "--workers"),
    (["solve", "hovercraft", "--time-limit", "-5"], "--time-limit"),
    (["launch-map", "--out", "/nonexistent/a/b"], "--out /nonexistent/a/b"),
    (["launch-map", "--frobnicate", "--out", "/tmp"], "--frobnicate"),
])
def test_bad_output_paths_and_options_are_refused_in_one_line_before_any_work(
        argv, named, no_work, capsys):
    assert _cli(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and named in err and "Errno" not in err, err


def test_launch_map_creates_no_missing_folders(tmp_path, no_work, capsys):
    assert _cli(["launch-map", "--out", str(tmp_path / "a" / "b")]) == 2
    assert not (tmp_path / "a").exists()


def test_a_refused_output_file_is_not_left_behind(tmp_path, no_work):
    """The writability probe of a new file removes it again (here the solve is refused)."""
    target = tmp_path / "out.csv"
    assert _cli(["solve", "hovercraft", "--csv", str(target), "--time-limit", "-1"]) == 2
    assert not target.exists()
    cli._writable(str(target), "--csv")
    assert not target.exists()


@pytest.mark.parametrize("given, expected", [([], DEFAULT_TIME_LIMIT), (["--time-limit", "7"], 7.0),
                                             (["--time-limit", "0"], None)])
def test_solve_and_sweep_carry_the_default_time_limit_and_0_means_none(
        monkeypatch, given, expected):
    seen: dict[str, object] = {}

    def fake_solve(spec, files=()):
        seen["solve"] = spec.time_limit
        return solvers.get_mission("hovercraft").empty({}, solvers.get_mission(
            "hovercraft").method(None), 10, "ipopt", "failed", "not solved")

    def fake_grid(*args, **kwargs):
        seen["sweep"] = kwargs["time_limit"]
        return []

    monkeypatch.setattr(cli, "solve_isolated", fake_solve)
    monkeypatch.setattr(cli, "mission_grid", fake_grid)
    _cli(["solve", "hovercraft", *given])
    _cli(["sweep", "hovercraft", "--grid", "accel=3,4", *given])
    assert seen == {"solve": expected, "sweep": expected}
    assert f"default {DEFAULT_TIME_LIMIT:g}" in cli.TIME_LIMIT_HELP


def test_the_python_api_has_the_default_limit_and_0_means_none():
    assert inspect.signature(Mission.solve).parameters["time_limit"].default == \
        DEFAULT_TIME_LIMIT
    # 0 is "no limit", not "stop at once" (it was a time-limit status at the first iteration).
    assert solvers.get_mission("hovercraft").solve(time_limit=0, verify=False).ok


def _endless_check() -> dict[str, float]:
    """A check whose integration would take far longer than any budget: y' = -y for 1e12 s
    with steps no larger than round-off allows (stiff, many steps), in small pieces."""
    integrate_piecewise(lambda t, y: -1e6 * y, np.ones(1), np.linspace(0.0, 1e9, 10**6),
                        1e-12, 1e-14)
    return {"miss_m": 0.0}


def test_a_deferred_check_gets_what_the_solve_left_of_the_limit_and_stops_there():
    ctx = SolveContext(time_limit=0.5)
    sol = Solution(mission="m", method="x", nodes=2, status="optimal", message="converged",
                   cost=Quantity(1.0, "cost", ""), checker=_endless_check)
    ctx.bound_check(sol)
    time.sleep(0.2)  # a deferred check runs later: it still gets the 0.3 s left, no more
    started = time.monotonic()
    sol.run_check()
    assert time.monotonic() - started < 0.3 + 0.5
    assert sol.status == "inaccurate" and "time limit" in sol.message


def test_a_check_not_back_by_the_hard_deadline_is_given_up():
    """The CLI's last line of defence: a check still owed at the time limit plus the grace
    (e.g. stuck in a native call of the worker) is given up and the answer says so."""
    from solvers.request import SolveRequest
    from solvers.service import Job

    job = Job(1, SolveRequest("m", time_limit=0.2), "", None, grace=0.1,
              cancel=lambda job: None)
    job.started = time.monotonic()
    job._finish(Solution(mission="m", method="x", nodes=2, status="optimal",
                         message="converged", cost=Quantity(1.0, "cost", "")), checked=False)
    sol = job.checked_result()
    assert time.monotonic() - job.started < 0.3 + 0.5
    assert sol.status == "inaccurate" and "did not finish within the time limit" in sol.message


def test_a_budget_stops_an_integration():
    started = time.monotonic()
    with pytest.raises(CheckTimeLimit), time_budget(0.2):
        _endless_check()
    assert time.monotonic() - started < 0.2 + 0.5


@pytest.fixture(scope="module")
def reentry():
    """A reentry answer (the paper's case, multiple shooting) whose check has not run."""
    mission = solvers.get_mission("apollo-reentry")
    sol = mission.solve(method="multiple-shooting", verify=False, time_limit=0)
    assert sol.ok and sol.checker is not None
    return mission, sol


def test_the_reentry_reference_stops_at_its_budget(reentry):
    """The maximum-principle reference (scipy root over solve_ivp) is bounded too."""
    mission, sol = reentry
    started = time.monotonic()
    with time_budget(0.0), pytest.raises(CheckTimeLimit):
        mission.indirect_reference(sol, mission.parameter_vector(sol.values))
    assert time.monotonic() - started < 0.5


def test_a_reference_cut_by_the_limit_leaves_the_miss_and_says_so(reentry, monkeypatch):
    mission, sol = reentry

    def out_of_time(*args):
        raise CheckTimeLimit("the check stopped at the time limit")

    monkeypatch.setattr(type(mission), "indirect_reference", out_of_time)
    sol.run_check()
    assert abs(sol.check["altitude_miss_m"]) < mission.tolerances["altitude_miss_m"]
    assert "did not finish within its share of the time limit" in sol.message


def test_a_wandering_newton_iterate_of_the_reentry_reference_warns_nothing():
    """The reference's Newton iterates can leave every extremal far behind (costates of
    1e160 here): the segment's variational equations overflow, which is a failed segment,
    not a numpy warning on stderr (issue 16)."""
    from solvers.missions.apollo_reentry import model

    y0 = np.array([0.36, -0.14, 4 / 209.0, 1e160, 1e160, 1e160])  # S&B units
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        _, _, ok = model._segment(y0, 230.0, 0.0, 0.1)
    assert not ok


def test_a_reentry_check_prints_no_overflow_warning(tmp_path):
    """Issue 16: the Apollo checks printed numpy overflow warnings on stderr."""
    import subprocess
    import sys

    res = subprocess.run([sys.executable, "-m", "solvers", "solve", "apollo-reentry",
                          "--csv", str(Path(tmp_path) / "r.csv")],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "RuntimeWarning" not in res.stderr and "overflow" not in res.stderr
    assert (tmp_path / "r.csv").read_text().count("\n") > 10  # written after the solve


def test_a_rescue_stays_within_the_time_limit(monkeypatch):
    """A lunar request (bench_robustness.py seed 7, case 7: 368 N on 1459 kg) that multiple
    shooting cannot solve under the 300 km altitude box it had then (its optimum climbs to
    973 km): its rescue seeds only from back ends that stop at the time limit (a FATROP
    seed, which checks no limit mid-solve, ran 19 s past a 15 s limit)."""
    from solvers.missions.lunar_landing import problem as lunar_problem

    monkeypatch.setattr(lunar_problem, "ALTITUDE_MAX", 300e3)
    values = {"altitude0": 35285.9, "omega_source": 0.0, "omega0": 0.00127895,
              "apolune_altitude": 145171.5, "mass0": 1459.10, "thrust": 368.368,
              "exhaust_speed": 1170.0, "sigma0": 634.94, "psi_guess": -0.43688}
    started = time.monotonic()
    sol = solvers.get_mission("lunar-landing").solve(values, method="multiple-shooting",
                                                      time_limit=15.0)
    assert time.monotonic() - started < 15.0 + 4.0, sol.message
    assert sol.status in ("failed", "time-limit") and "fatrop" not in sol.message


def test_a_rescue_stage_that_used_up_its_share_ends_time_limit(monkeypatch):
    """A rescue is `failed` only when exhausted: when a stage ran out of its share of the
    limit (on a busy machine a seed may), the answer is `time-limit` and says a longer limit
    may find it (a fuzzed hovercraft case was `failed` under load, solved when quiet)."""
    from solvers import continuation

    mission = solvers.get_mission("hovercraft")
    method = mission.method(None)
    values = mission.validate(None, method.key)[0]
    request = continuation.Case(mission, values, method, 10, "ipopt")

    def busy(_request, stage: SolveContext, tried: list[str]) -> None:
        tried.append("a seed")
        while not stage.should_stop():  # works until its share is gone
            time.sleep(0.01)

    monkeypatch.setattr(continuation, "_starts", lambda *args: iter(()))
    monkeypatch.setattr(continuation, "_seeded", busy)
    monkeypatch.setattr(continuation, "_stand_in", lambda *args: None)
    monkeypatch.setattr(continuation, "_restarted", lambda *args: None)
    failed = mission.empty({}, method, 10, "ipopt", "failed", "not solved")
    sol = continuation.rescue(request, None, failed, SolveContext(time_limit=0.5))
    assert sol.status == "time-limit", sol.message
    assert "ran out of its share of the time limit of 0.5 s" in sol.message


def test_a_rescue_seeds_from_no_back_end_that_stops_only_between_long_iterations():
    """SQP stops only between iterations, and one QP of a large NLP ran 6 min past a 15 s
    limit (a rescue's SQP seed of a fuzzed 400-segment asteroid case): no rescue calls it.
    A hovercraft request of the slow fuzz (its LGL rescue tried an SQP seed before)."""
    values = {"steering": 1.0, "vx0": 1.1926, "y0": 1.1926, "alpha_guess": -1.0401,
              "yf": 1.5213, "vy0": 0.0, "x0": 1.1926, "vyf": 3.8565, "vxf": 1.1926,
              "T_guess": 3.5520, "accel": 7.8734, "xf": 1.5213}
    sol = solvers.get_mission("hovercraft").solve(values, method="lgl", time_limit=15.0)
    assert sol.status in ("failed", "time-limit") and "continuation" in sol.message
    assert "sqp" not in sol.message, sol.message


def test_a_rescue_walks_with_another_back_end_when_its_own_walk_stalls():
    """A hovercraft request of the slow fuzz (2026-12-07): multiple shooting with SQP walks
    from the defaults 34 % of the way and fails from every seed; IPOPT walks there in one
    step, and SQP converges from IPOPT's answer."""
    values = {"yf": 23.6417, "vx0": 12.5137, "y0": 24.3910, "vxf": 0.0, "steering": 1.0,
              "xf": 14.9005, "T_guess": 0.8937, "vy0": 0.0, "x0": 0.0, "accel": 8.9746,
              "vyf": 0.0278, "alpha_guess": -3.14159}
    sol = solvers.get_mission("hovercraft").solve(values, method="multiple-shooting",
                                                  time_limit=15.0)
    assert sol.converged and sol.backend == "sqp", sol.message
    assert "seeded by the ipopt back end, which reached this case by continuation" \
        in sol.message
