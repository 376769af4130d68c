"""Necessary conditions named before solving (issue 16): a case just past a mission's bound is
refused at once as `infeasible`, naming the bound with its numbers; a case just inside it is
not refused. Each threshold is computed here from the physics (not copied from our output);
the derivations are in each mission's `precheck`."""

from __future__ import annotations

import math
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

import solvers
from solvers.context import Infeasible
from solvers.missions.apollo_reentry import model as apollo_model
from solvers.missions.apollo_reentry import reach as apollo_reach
from solvers.missions.elliptic_transfer.problem import MIN_PERIGEE_ALTITUDE, R_EARTH
from solvers.missions.hovercraft import problem as hover_problem
from solvers.missions.lunar_landing import problem as lunar_problem
from solvers.missions.lunar_landing.model import MU_MOON, R_MOON

HOVER = solvers.get_mission("hovercraft")
LUNAR = solvers.get_mission("lunar-landing")
APOLLO = solvers.get_mission("apollo-reentry")
ELLIPTIC = solvers.get_mission("elliptic-transfer")
DEG = math.pi / 180


def _refused(mission: solvers.Mission, values: dict[str, float], method: str | None = None
             ) -> str | None:
    """The precheck's message for `values` (validated as a solve would), None if accepted."""
    vals, _, _ = mission.validate(values, method)
    try:
        mission.precheck(vals, mission.parameter_vector(vals))
    except Infeasible as exc:
        return str(exc)
    return None


# ---- hovercraft: vx >= 0, so braking along x needs (vx0² - vxf²) / (2 A/m) of room ----------
@pytest.mark.parametrize("method", ["multiple-shooting", "hermite-simpson", "lgl"])
def test_hovercraft_braking_distance_is_named_by_every_method(method):
    """The issue's case: braking from 5 m/s at 3 m/s² needs 25/6 = 4.17 m; 3.5 m remain."""
    start = time.perf_counter()
    sol = HOVER.solve({"x0": 1.5}, method=method)
    assert time.perf_counter() - start < 1.0
    assert sol.status == "infeasible"
    assert "4.17 m" in sol.message and "3.5 m" in sol.message and "vx ≥ 0" in sol.message


def test_hovercraft_braking_distance_just_inside_and_past():
    need = 5.0**2 / (2 * 3.0)  # m, from vx0 = 5 m/s to rest at A/m = 3 m/s²
    past = {"x0": 5.0 - 0.98 * need}
    inside = {"x0": 5.0 - 1.02 * need}
    assert HOVER.solve(past, method="multiple-shooting").status == "infeasible"
    hover_problem.precheck(hover_problem.parameter_vector(HOVER.validate(inside)[0]))
    assert HOVER.solve(inside, method="multiple-shooting").converged  # 1 cm of margin
    behind = HOVER.solve({"x0": 2.0, "xf": 1.0}, method="multiple-shooting")
    assert behind.status == "infeasible" and "behind" in behind.message


def test_cli_names_the_hovercraft_bound_promptly():
    """Issue 16: this command printed nothing for 120 s; vx0 = 5 m/s at 3.3 m/s² needs
    25/6.6 = 3.79 m."""
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "solvers", "solve", "hovercraft", "--method",
                          "multiple-shooting", "--nodes", "25", "--set", "x0=1.5", "--set",
                          "accel=3.3"], capture_output=True, text=True, timeout=120)
    assert time.perf_counter() - start < 60.0  # the interpreter's start-up, no solve
    assert "infeasible" in out.stdout and "3.79 m" in out.stdout and "3.5 m" in out.stdout


# ---- lunar landing: the energy to shed, and the range angle to brake in --------------------
def _lunar_range_angle(values: dict[str, float]) -> float:
    """The least range angle before the angular momentum h = r²ω can reach zero, integrated
    numerically: θ̇ >= h/r_max², h(t) >= h0 - r_max c ln(m0/m(t)), m(t) = m0 - F t/c."""
    r0 = R_MOON + values["altitude0"]
    h0, c, m0, thrust = r0**2 * values["omega0"], values["exhaust_speed"], values["mass0"], \
        values["thrust"]
    r_max = R_MOON + lunar_problem.ALTITUDE_MAX
    t_star = (m0 - m0 * math.exp(-h0 / (r_max * c))) * c / thrust

    def h_low(t: float) -> float:
        return h0 - r_max * c * math.log(m0 / (m0 - thrust * t / c))

    return quad(h_low, 0.0, t_star)[0] / r_max**2


def test_lunar_thrust_too_weak_for_the_range_angle_bound():
    """The bound with the radius at the box's top throughout (the test's own quadrature above,
    a weaker special case of `braking_range_angle`) refuses below its critical thrust, so the
    mission's bound must too; it never refuses a thrust Hermite–Simpson lands with (200 N
    at the defaults: the optimum climbs to several hundred km first)."""
    defaults = LUNAR.defaults("hermite-simpson")
    # θ_min is proportional to 1/F: the thrust at which it equals θ_max = 3 rad.
    f_crit = defaults["thrust"] * _lunar_range_angle(defaults) / lunar_problem.THETA_MAX
    assert 10.0 / 0.98 < f_crit < 200.0
    message = _refused(LUNAR, {"thrust": 0.98 * f_crit})
    assert message is not None and "too weak" in message and "θ ≤ 3 rad" in message
    sol = LUNAR.solve({"thrust": 200.0}, method="hermite-simpson")
    assert sol.status in ("optimal", "inaccurate"), sol.message
    assert float(np.max(sol.x[:, 0])) - R_MOON > 300e3  # above the old box: it was needed
    # F/m0 below lunar gravity is not a bound: the mass falls as the engine burns.
    assert _refused(LUNAR, {"thrust": 900.0}) is None


def test_lunar_thrust_too_weak_to_stop_the_fall():
    """A slow start (ω0 well below the circular rate) with F/m0 below lunar gravity: the
    lander falls. The bound (`fall_surface_speed`) refuses just below the thrust where it
    stops proving the fall, and just above it Hermite–Simpson lands: the proof is sharp and
    never refuses a request a method solves."""
    case = {"altitude0": 20e3, "omega0": 4.2e-4, "mass0": 5000.0, "exhaust_speed": 4000.0}
    lo, hi = 1000.0, 20000.0  # N: refused at lo, accepted at hi
    assert _refused(LUNAR, {**case, "thrust": lo}) and not _refused(LUNAR, {**case, "thrust": hi})
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _refused(LUNAR, {**case, "thrust": mid}) else (lo, mid)
    message = _refused(LUNAR, {**case, "thrust": 0.98 * hi})
    assert message is not None and "stop the fall" in message and "|ψ| ≤ 90°" in message
    sol = LUNAR.solve({**case, "thrust": 1.02 * hi}, method="hermite-simpson")
    assert sol.status in ("optimal", "inaccurate"), sol.message
    assert sol.check["altitude_m"] == pytest.approx(0.0, abs=1.0)


def test_lunar_propellant_that_cannot_shed_the_orbital_energy():
    case = {"altitude0": 100e3, "omega0": 1.4e-3, "mass0": 50.0, "thrust": 2000.0}
    r0 = R_MOON + case["altitude0"]
    # √(2 e0): the speed that cancels the orbital speed and the height above the surface.
    dv = math.sqrt((r0 * case["omega0"]) ** 2 + 2 * MU_MOON * (1 / R_MOON - 1 / r0))
    c_crit = dv / math.log(case["mass0"] / lunar_problem.M_MIN)
    sol = LUNAR.solve({**case, "exhaust_speed": 0.98 * c_crit}, method="hermite-simpson")
    assert sol.status == "infeasible" and "propellant" in sol.message
    assert f"{dv:.4g} m/s" in sol.message
    # Just above it the energy bound lets it pass (the descent bound refuses it: at this
    # exhaust speed the 50 kg lander burns out within 17 s, 100 km up).
    above = _refused(LUNAR, {**case, "exhaust_speed": 1.02 * c_crit}) or ""
    assert "orbital energy" not in above and "descends at most" in above


# A slow-fuzz request (2026-12-07) whose three methods failed or ran out of time: 17.6 kN on
# 92 kg at c = 671 m/s burns out within 3.5 s, 94 km up.
BURNS_OUT = {"altitude0": 93989.5548, "omega_source": 0.0, "omega0": 0.0006,
             "mass0": 91.9773, "thrust": 17575.5708, "exhaust_speed": 670.6244}


@pytest.mark.parametrize("method", ["paper", "hermite-simpson", "multiple-shooting"])
def test_lunar_lander_that_burns_out_before_it_gets_down_is_refused(method):
    sol = LUNAR.solve(BURNS_OUT, method=method)
    assert sol.status == "infeasible", sol.message
    assert "descends at most" in sol.message and "±2000 m/s" in sol.message
    assert "within 3.47 s" in sol.message  # (m0 - 1 kg) c / F


@pytest.mark.parametrize("case", [{}, {"thrust": 12000.0, "mass0": 400.0},
                                  {"omega0": 3e-4, "thrust": 4000.0, "altitude0": 40e3}])
def test_lunar_descent_bound_holds_along_solved_trajectories(case):
    """Each inequality of `descent_reach` holds on a solved landing: the fall speed -ṙ is at
    most g_R t + c ln(m0/m(t)) (falling) and s (T - t) + c ln(m(t)/m(T)) (braking, with the
    trajectory's own T and final mass), and the bound allows the altitude it descended."""
    sol = LUNAR.solve(case, method="hermite-simpson")
    assert sol.converged, sol.message
    values = sol.values
    p = lunar_problem.parameter_vector(values)
    assert lunar_problem.descent_reach(p) >= values["altitude0"]
    t, (_, v, _, _, m) = sol.t, sol.x.T
    c, m0, T = values["exhaust_speed"], values["mass0"], sol.t[-1]
    h0 = p[0] ** 2 * p[1]
    radii = np.linspace(R_MOON, R_MOON + lunar_problem.ALTITUDE_MAX, 20001)
    support = np.max(h0**2 / radii**3 - MU_MOON / radii**2)
    tol = 0.5  # m/s: the interpolated dense path
    assert np.all(-v <= MU_MOON / R_MOON**2 * t + c * np.log(m0 / m) + tol)
    assert np.all(-v <= support * (T - t) + c * np.log(m / m[-1]) + tol)
    assert np.max(np.abs(v)) <= lunar_problem.RADIAL_SPEED_MAX + tol


# ---- Apollo reentry: drag only dissipates; the climb and descent rates are bounded ---------
def test_apollo_energy_cannot_rise():
    v0, h0, hf = 8000.0, 4.0 * apollo_model.LENGTH_UNIT, 2.5 * apollo_model.LENGTH_UNIT
    mu = apollo_model.G * apollo_model.LENGTH_UNIT * apollo_model.R_EARTH**2
    re = apollo_model.R_EARTH
    reachable = math.sqrt(v0**2 + 2 * mu * (1 / (re + hf) - 1 / (re + h0)))
    # A shallow entry: at the default −8.1° a capsule that may lose almost no energy cannot
    # pull up before the ground either (the pull-up bound refuses it too).
    base = {"v0": v0, "h0": h0, "hf": hf, "gamma0": -1 * DEG}
    message = _refused(APOLLO, {**base, "vf": 1.001 * reachable})
    assert message is not None and "drag only removes energy" in message
    assert _refused(APOLLO, {**base, "vf": 0.999 * reachable}) is None


def test_apollo_descent_within_the_flight_path_and_time_bounds():
    values = APOLLO.defaults()
    drop = values["h0"] - values["hf"]
    base = {"gamma0": -1 * DEG, "gamma_min": -1 * DEG, "T_min": 50.0}
    t_crit = drop / (values["v_max"] * math.sin(1 * DEG))
    message = _refused(APOLLO, {**base, "T_max": 0.98 * t_crit})
    assert message is not None and "cannot descend" in message and "gamma_min" in message
    assert _refused(APOLLO, {**base, "T_max": 1.02 * t_crit}) is None
    sol = APOLLO.solve({**base, "T_max": 0.98 * t_crit}, method="hermite-simpson")
    assert sol.status == "infeasible"


def test_apollo_climb_within_the_flight_path_bound():
    base = {"h0": 60e3, "hf": 170e3, "gamma0": -1 * DEG, "gammaf": 0.0}
    values = APOLLO.defaults()
    g_crit = math.asin((170e3 - 60e3) / (values["T_max"] * values["v_max"]))
    message = _refused(APOLLO, {**base, "gamma_max": 0.98 * g_crit})
    assert message is not None and "cannot climb" in message
    assert _refused(APOLLO, {**base, "gamma_max": 1.02 * g_crit}) is None



# A request drawn by `benchmarks/bench_robustness.py --mission apollo-reentry --seed 7` (case 4)
# that all three methods failed on, 3–11 s each, before the dense-air bound: it ends at 38 km
# still at 9.2 km/s after at least 185 s, descending no steeper than 4°.
LOW_FAST_END = {"v0": 10913.99, "gamma0": -0.0529, "h0": 146446.0, "vf": 9195.85,
                "gammaf": -0.0545, "hf": 38351.8, "u_max": 0.3092, "T_min": 185.03,
                "T_max": 500.15, "v_min": 2237.46, "v_max": 17997.64, "gamma_min": -0.0695,
                "gamma_max": 0.2307, "h_max": 181476.8}


@pytest.mark.parametrize("method", ["multiple-shooting", "hermite-simpson", "lgl"])
def test_apollo_low_fast_end_is_refused_by_the_dense_air_bound(method):
    sol = APOLLO.solve(LOW_FAST_END, method=method)
    assert sol.status == "infeasible"
    assert "drag takes at least" in sol.message and "T_min" in sol.message


@pytest.mark.parametrize("change", [{}, {"vf": 8000.0}, {"hf": 70e3}, {"gamma0": -0.1}])
def test_apollo_dense_air_bound_never_refuses_a_solved_trajectory(change):
    """The bound is a necessary condition: a trajectory the solver found (and re-propagated)
    satisfies it even when T_min is raised to that trajectory's own duration."""
    sol = APOLLO.solve({**APOLLO.defaults(), **change}, method="hermite-simpson")
    assert sol.status in ("optimal", "inaccurate")
    duration = float(sol.t[-1] - sol.t[0])
    values = {**sol.values, "T_min": 0.999 * duration,
              "T_max": max(sol.values["T_max"], 1.01 * duration)}
    assert _refused(APOLLO, values) is None

# A request drawn by `benchmarks/bench_robustness.py --mission apollo-reentry --seed 7` (case 0)
# that all three methods failed on before the pull-up bound: from 125 km diving at 9.3°, with
# |u| <= 19°, it must still fly 558 s and end at 46.5 km at 8.98 km/s.
STEEP_DIVE = {"v0": 9230.33, "gamma0": -0.1621, "h0": 125263.1, "vf": 8978.28, "gammaf": 0.0144,
              "hf": 46549.5, "u_max": 0.3331, "T_min": 558.31, "T_max": 776.55,
              "v_min": 3870.17, "v_max": 17949.37, "gamma_min": -0.2671, "gamma_max": 0.2309,
              "h_max": 381067.4}


@pytest.mark.parametrize("method", ["multiple-shooting", "hermite-simpson", "lgl"])
def test_apollo_steep_dive_is_refused_by_the_pull_up_bound(method):
    sol = APOLLO.solve(STEEP_DIVE, method=method)
    assert sol.status == "infeasible"
    assert "dives too steeply at its start" in sol.message and "u_max" in sol.message


def _pull_up_lowest(values: dict[str, float]) -> float:
    """The pull-up bound's lowest altitude at the start, computed here with scipy's scalar
    optimisers (the derivation is in `reach.pull_up_floor`): the air's radial impulse
    I = m (E0 - Ef) / v_lo, the largest upward pull c of gravity and the path's turning, and
    the vertex of h0 + (ṙ0 + I) t + c t²/2 within T_min."""
    mu = apollo_model.G * apollo_model.LENGTH_UNIT * apollo_model.R_EARTH**2
    re = apollo_model.R_EARTH

    def energy(v: float, h: float) -> float:
        return v * v / 2 - mu / (re + h)

    e0, ef = energy(values["v0"], values["h0"]), energy(values["vf"], values["hf"])
    c1, c2, c3 = apollo_model.C1, apollo_model.C2, apollo_model.C3
    k = -minimize_scalar(lambda u: -c3 * math.sin(u) / (c1 - c2 * math.cos(u)),
                         bounds=(0.0, values["u_max"]), method="bounded").fun
    m = -minimize_scalar(lambda g: -(k * math.cos(g) + abs(math.sin(g))),
                         bounds=(values["gamma_min"], values["gamma_max"]),
                         method="bounded").fun
    v_lo = max(values["v_min"], math.sqrt(2 * (ef + mu / (re + values["h_max"]))))
    impulse = m * (e0 - ef) / v_lo

    def pull(r: float) -> float:
        return (min(values["v_max"] ** 2, 2 * (e0 + mu / r)) - mu / r) / r

    c = -minimize_scalar(lambda r: -pull(r), bounds=(re, re + values["h_max"]),
                         method="bounded").fun
    rate = values["v0"] * math.sin(values["gamma0"]) + impulse
    t = min(values["T_min"], max(0.0, -rate / c))
    return values["h0"] + rate * t + c * t * t / 2


def test_apollo_pull_up_bound_is_sharp_in_the_entry_angle():
    """Just past the steepest start the bound allows, refused; just inside, not."""
    base = {**STEEP_DIVE, "gamma_min": -0.4, "gamma0": -0.1}
    steepest = brentq(lambda g: _pull_up_lowest({**base, "gamma0": g}), -0.4, -0.05)
    past = _refused(APOLLO, {**base, "gamma0": 1.02 * steepest})
    assert past is not None and "dives too steeply" in past
    assert _refused(APOLLO, {**base, "gamma0": 0.98 * steepest}) is None


@pytest.mark.parametrize("change", [{}, {"gamma0": -8.2 * DEG}, {"u_max": 60 * DEG},
                                    {"gammaf": 2 * DEG}])
def test_apollo_pull_up_bound_never_refuses_a_solved_trajectory(change):
    """A necessary condition: a trajectory the solver found satisfies it even with every
    bound the proof uses shrunk to that trajectory's own range (T_min to its duration, u_max
    to its largest |u|, v_min, the flight-path angles and h_max to its extremes)."""
    sol = APOLLO.solve({**APOLLO.defaults(), **change}, method="hermite-simpson", nodes=80)
    assert sol.status in ("optimal", "inaccurate"), sol.message
    speed, gamma, height = sol.x[:, 0], sol.x[:, 1], sol.x[:, 2]  # SI: m/s, rad, m
    tight = {**sol.values, "T_min": 0.999 * float(sol.t[-1] - sol.t[0]),
             "u_max": 1.001 * float(np.max(np.abs(sol.u))),
             "v_min": 0.999 * float(np.min(speed)), "gamma_min": float(np.min(gamma)) - 1e-4,
             "gamma_max": float(np.max(gamma)) + 1e-4, "h_max": 1.001 * float(np.max(height))}
    assert apollo_reach.pull_up_floor(tight).lowest >= 0  # (v_min may leave its GUI range)

# ---- elliptic transfer: the target's perigee above 100 km ----------------------------------
def test_elliptic_perigee_just_inside_and_past():
    e_crit = 1 - (R_EARTH + MIN_PERIGEE_ALTITUDE) / ELLIPTIC.defaults()["a"]
    past = ELLIPTIC.solve({"e": 1.01 * e_crit})
    assert past.status == "infeasible" and "perigee" in past.message
    assert ELLIPTIC.solve({"e": 0.99 * e_crit}).converged

