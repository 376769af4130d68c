"""Lunar soft landing as a problem (paper 002, SPEC M3): parameters, the OCP the general
methods solve, published numbers and presets."""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ...context import Infeasible
from ...handles import Axis, Handle
from ...ocp import OCP, Bounds, Guess
from ...problem import Consistency, Param, Preset, Published
from ...solution import Label
from .model import MU_MOON, R_MOON, STATE_UNITS, STATES, descent_rhs, perilune_rate

DEG = np.pi / 180
PAPER = "Zhao & Gu 2008, Science & Technology Review 26(20) (paper 002)"
# Parameter vector of the OCP: initial radius, initial angular rate, initial mass, thrust,
# exhaust speed.
P_R0, P_W0, P_M0, P_F, P_C = range(5)
# The OCP's state bounds that `precheck` derives its necessary conditions from: altitude
# (m), range angle θ (rad) and mass (kg).
# The altitude bound is a box for the NLP, not part of the problem: it lies above the highest
# apolune a request may start on (2000 km), since a weak engine's optimum may climb first (a
# 368 N, 1459 kg lander from 35 km rises to 973 km; under a 300 km bound it was unsolvable).
ALTITUDE_MAX, THETA_MAX, M_MIN = 2500e3, 3.0, 1.0
RADIAL_SPEED_MAX = 2e3  # m/s, the box of the radial speed
REACH_STEPS = 2000  # time steps of the descent bound (`descent_reach`)
FALL_STEPS = 4000  # time steps of the fall bound (`fall_surface_speed`)
BRAKING_STEPS = 400  # time steps of the range-angle bound (`braking_range_angle`)

PARAMS = (
    Param("altitude0", "initial altitude (perilune)", "m", 15e3, 1e3, 100e3, 500,
          group="Initial orbit", display_unit="km", display_factor=1e-3,
          help="Altitude above the mean lunar radius where the engine ignites."),
    Param("omega_source", "initial angular rate from", "", 0, 0, 1, 1, group="Initial orbit",
          options=("given ω0", "vis-viva from apolune"),
          help="Use ω0 as given, or compute it as the perilune rate of an orbit whose apolune "
               "altitude is set below."),
    Param("omega0", "initial angular rate ω0", "rad/s", 9.65e-4, 1e-4, 1.4e-3, 1e-6,
          group="Initial orbit", display_unit="mrad/s", display_factor=1e3,
          help="The paper's 9.65e-4 rad/s is the 100 x 15 km perilune rate (9.6522e-4) rounded."),
    Param("apolune_altitude", "apolune altitude", "m", 100e3, 1e3, 2000e3, 1e3,
          group="Initial orbit", display_unit="km", display_factor=1e-3,
          help="Used when ω0 comes from vis-viva."),
    Param("mass0", "initial mass", "kg", 600.0, 50.0, 5000.0, 10.0, group="Vehicle"),
    Param("thrust", "thrust F", "N", 2000.0, 10.0, 20000.0, 10.0, group="Vehicle",
          help="Constant braking thrust (the paper's constant-thrust assumption)."),
    Param("exhaust_speed", "exhaust speed Isp·g0", "m/s", 2940.0, 500.0, 5000.0, 10.0,
          group="Vehicle", help="Isp = 300 s with g0 = 9.8 m/s² gives the paper's 2940 m/s."),
)

# Dragged in the 3D view: the ignition point moves along the local vertical (the display
# frame is Moon-centred, ignition on +x at R_MOON + altitude).
HANDLES = (
    Handle("ignition", "ignition altitude", (Axis("altitude0", offset=R_MOON), 0.0, 0.0)),
)

_TABLE_1 = "paper 002, table 1 (multiplier method)"
_PONTRYAGIN = "paper 002, Pontryagin (indirect) reference"
PUBLISHED = (
    Published("tf", 398.03868, "s", _TABLE_1, rtol=1e-4,
              note="0.01 %: the paper's method stops its multiplier iterations early"),
    Published("fuel", 270.77461, "kg", _TABLE_1, rtol=1e-4),
    Published("tf", 398.03873, "s", _PONTRYAGIN, rtol=1e-7,
              note="to the printed digits: every method here converges to the true optimum"),
    Published("fuel", 270.77465, "kg", _PONTRYAGIN, rtol=1e-7),
)

# Accuracy targets of the re-propagated touchdown (SI): 10 cm and 1 mm/s, a soft landing.
# The direct methods land within millimetres; the paper's method (ABM4, 4 steps a segment)
# within 6 cm at its 30 segments.
TOLERANCES = {"altitude_m": 0.1, "speed_m_s": 1e-3}

CONSISTENCY = (Consistency("tf", 1e-6, note="all three methods converge to the same optimum"),)

PRESETS = (
    Preset("Paper 002 case", {}, note="The published case: tf = 398.039 s, fuel 270.775 kg."),
    Preset("From the 100 × 15 km orbit (vis-viva ω0)", {"omega_source": 1}),
    Preset("Heavy lander, 3 kN", {"mass0": 1200.0, "thrust": 3000.0}),
    Preset("Paper method, bad guess ψ = 60°", {"psi_guess": 60 * DEG}, method="paper",
           cold=True),
    Preset("Paper method, bad guess, small σ", {"psi_guess": 60 * DEG, "sigma0": 0.2},
           method="paper", cold=True),
    Preset("Coarse mesh (6 intervals)", {}, method="hermite-simpson", nodes=6),
)

EQUATIONS = (
    ("Equations of motion (paper 002, eq. 1)",
     r"\dot r = v,\quad \dot v = \frac{F}{m}\sin\psi - \frac{\mu}{r^2} + r\omega^2,"
     r"\quad \dot\omega = -\frac{(F/m)\cos\psi + 2v\omega}{r},\quad \dot\theta = \omega,"
     r"\quad \dot m = -\frac{F}{I_{sp} g_0}"),
    ("Cost (eq. 2) and terminal conditions",
     r"J = m(0) - m(t_f) = \frac{F t_f}{I_{sp} g_0},\qquad r(t_f) = R,\ v(t_f) = 0,\ "
     r"\omega(t_f) = 0"),
)


def check_values(values: dict[str, float]) -> None:
    if values["omega_source"] == 1 and values["apolune_altitude"] < values["altitude0"]:
        raise ValueError(
            f"perilune altitude {values['altitude0'] / 1e3:g} km is above the apolune "
            f"altitude {values['apolune_altitude'] / 1e3:g} km"
        )


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    """The OCP's numeric parameters (SI) from validated mission values."""
    r0 = R_MOON + values["altitude0"]
    if values["omega_source"] == 1:
        omega0 = perilune_rate(r0, R_MOON + values["apolune_altitude"])
    else:
        omega0 = values["omega0"]
    return np.array([r0, omega0, values["mass0"], values["thrust"], values["exhaust_speed"]])


def time_guess(p: np.ndarray) -> float:
    """Burn time to cancel the orbital speed by the rocket equation (a cold-start guess)."""
    dv = 1.05 * p[P_R0] * p[P_W0]
    return float(p[P_M0] * p[P_C] / p[P_F] * (1 - np.exp(-dv / p[P_C])))


def precheck(p: np.ndarray) -> None:
    """Refuse a request that no trajectory within the OCP's bounds can land, naming the bound.

    Two necessary conditions (the thrust F is always on and |F/m| is the only non-gravity
    acceleration):
    - fuel: gravity is conservative, so e = V²/2 - μ/r + μ/R (zero at rest on the surface,
      >= V²/2 above it) obeys ė >= -(F/m)|V| >= -(F/m)√(2e); hence √(2e) falls by at most
      ∫F/m dt = c ln(m0/m): landing needs c ln(m0/m_min) >= √(2 e0);
    - fall: a lander falling from its start must stop its fall before the surface
      (`fall_surface_speed`);
    - thrust: braking the angular momentum to zero takes a range angle
      (`braking_range_angle`) that must stay below θ_max.
    """
    r0, w0, m0, thrust, c = (float(v) for v in p[:5])
    dv_energy = energy_speed(r0, w0)
    dv_budget = c * np.log(m0 / M_MIN)
    if dv_energy > dv_budget:
        raise Infeasible(
            f"the propellant cannot stop the lander: shedding the orbital energy needs at "
            f"least Δv = {dv_energy:.4g} m/s, but burning down to the mass bound m ≥ "
            f"{M_MIN:g} kg gives only c ln(m0/{M_MIN:g} kg) = {dv_budget:.4g} m/s: raise the "
            "exhaust speed or lower the orbital rate")
    falling = fall_surface_speed(p)
    if falling > 0:
        raise Infeasible(
            f"the thrust is too weak to stop the fall: at F = {thrust:g} N (F/m0 = "
            f"{thrust / m0:.3g} m/s²) and ω0 = {w0:.4g} rad/s the lander, even thrusting "
            f"straight up from ignition, still falls at {falling:.3g} m/s or more when it "
            "reaches the surface or its propellant runs out (the thrust never speeding up "
            "the orbital motion, |ψ| ≤ 90°): "
            "raise the thrust, lower the initial mass or raise the initial angular rate")
    reach = descent_reach(p)
    if reach < r0 - R_MOON:
        burn = (m0 - M_MIN) * c / thrust
        raise Infeasible(
            f"the lander cannot get down before its propellant is spent: at F = {thrust:g} N "
            f"the engine burns from m0 = {m0:g} kg to the mass bound m ≥ {M_MIN:g} kg within "
            f"{burn:.3g} s, and starting and ending at rest radially, with the radial speed "
            f"within ±{RADIAL_SPEED_MAX:g} m/s, it descends at most {reach / 1e3:.4g} km, "
            f"below its altitude of {(r0 - R_MOON) / 1e3:.4g} km: lower the thrust, or raise "
            "the initial mass or the exhaust speed")
    theta = braking_range_angle(p)
    if theta > THETA_MAX:
        raise Infeasible(
            f"the thrust is too weak: at F = {thrust:g} N (F/m0 = {thrust / m0:.3g} m/s²) "
            f"braking the orbital motion takes at least {theta:.3g} rad of range angle, "
            f"beyond the bound θ ≤ {THETA_MAX:g} rad: raise the thrust or lower the initial "
            "mass")


def energy_speed(r0: float, w0: float) -> float:
    """√(2 e0) = √(V0² + 2μ(1/R - 1/r0)) (m/s): the start's energy above rest on the surface
    as a speed, which the thrust changes by at most ∫F/m dt (`precheck`)."""
    return float(np.sqrt((r0 * w0) ** 2 + 2 * MU_MOON * (1 / R_MOON - 1 / r0)))


def braking_range_angle(p: np.ndarray) -> float:
    """A lower bound on the range angle θ (rad) flown before the angular momentum can first
    reach zero, which a landing needs (ω(tf) = 0); any thrust direction.

    The thrust adds energy at most at (F/m)|V|, so S = √(2(E + μ/R)) (E = V²/2 - μ/r) grows
    at most at F/m: S <= S0 + c ln(m0/m) and E <= Ē. With V >= h/r that bounds the radius:
    h²/(2r²) - μ/r <= Ē gives r <= ρ, the larger root (or the box R + ALTITUDE_MAX when Ē >= 0;
    h at its lower bound, which only widens ρ). The angular momentum falls at most at
    |ḣ| = r (F/m)|cos ψ| <= ρ F/m, so h >= h_lo, and θ̇ = h/r² >= h_lo/ρ² until h_lo = 0.
    Each of ρ, F/m grows and h_lo/ρ² falls with t, so each step uses its right end (its ρ from
    h_lo bounded with the box's rate over the step): every sum is on the safe side."""
    r0, w0, m0, thrust, c = (float(v) for v in p[:5])
    r_box = R_MOON + ALTITUDE_MAX
    h = r0 ** 2 * w0
    s0 = energy_speed(r0, w0)
    steps = BRAKING_STEPS
    dt = (m0 - M_MIN) * c / thrust / steps  # until the propellant is spent
    theta = 0.0
    for k in range(1, steps + 1):
        mass = m0 - thrust * k * dt / c
        accel = thrust / mass
        energy = 0.5 * (s0 + c * np.log(m0 / mass)) ** 2 - MU_MOON / R_MOON
        h_step = max(h - r_box * accel * dt, 0.0)  # the least h can be within the step
        if energy < 0:
            root = np.sqrt(max(MU_MOON ** 2 + 2 * energy * h_step ** 2, 0.0))
            rho = min(r_box, (MU_MOON + root) / (-2 * energy))
        else:
            rho = r_box
        h -= rho * accel * dt
        if h <= 0:
            return theta
        theta += h / rho ** 2 * dt
        if theta > THETA_MAX:
            return theta
    return float("inf")  # h cannot reach zero before the propellant is spent


def radial_support(h0: float, r_hi: float) -> float:
    """The largest centrifugal-minus-gravity acceleration h0²/r³ - μ/r² (m/s²) over
    R <= r <= r_hi: at an end, or at its one stationary point r = 1.5 h0²/μ."""
    radii = np.array([R_MOON, r_hi, np.clip(1.5 * h0 ** 2 / MU_MOON, R_MOON, r_hi)])
    return float(np.max(h0 ** 2 / radii ** 3 - MU_MOON / radii ** 2))


def fall_surface_speed(p: np.ndarray) -> float:
    """A lower bound on the falling speed (m/s) at which the lander reaches the surface when
    it cannot stop its fall, 0 when this bound cannot show it (a proof, for |ψ| ≤ 90°).

    With |ψ| ≤ 90° the angular momentum h = r²ω never grows (ḣ = -r (F/m) cos ψ, eq. 1) and
    must end at 0, so 0 <= h <= h0 throughout. The radial acceleration is then at most
    U(t) = max over R <= r <= r0 of (h0²/r³ - μ/r²) + F/m(t), with m(t) = m0 - F t/c. From
    v(0) = 0 the radial speed stays below V(t) = ∫U and the radius below r0 + ∫V while V < 0
    (r <= r0 then). If r0 + ∫V reaches R while V is still negative, the lander meets the
    surface falling at |V| or more and cannot land; if V stays negative until the propellant
    is spent (m = M_MIN), it cannot either. U grows with t (the mass falls), so
    right-endpoint sums bound V from above; each step adds the larger of its two ends' V."""
    r0, w0, m0, thrust, c = (float(v) for v in p[:5])
    h0 = r0 ** 2 * w0
    support = radial_support(h0, r0)
    burn = (m0 - M_MIN) * c / thrust  # the longest the engine can burn
    dt = burn / FALL_STEPS
    t = dt * np.arange(1, FALL_STEPS + 1)
    speed = np.cumsum(support + thrust / (m0 - thrust * t / c)) * dt  # V at t, an upper bound
    if speed[0] >= 0:
        return 0.0
    rising = np.flatnonzero(speed >= 0)
    end = int(rising[0]) if len(rising) else FALL_STEPS  # steps while V < 0
    upper = np.maximum(np.concatenate([[0.0], speed[:end - 1]]), speed[:end])
    radius = r0 + np.cumsum(upper) * dt
    below = np.flatnonzero(radius <= R_MOON)
    if len(below) == 0:
        return 0.0 if len(rising) else float(-speed[-1])
    return float(-upper[below[0]])


def descent_reach(p: np.ndarray) -> float:
    """An upper bound on how far (m) the lander can descend before its propellant is spent,
    inf when this bound does not apply (a proof, for |ψ| ≤ 90°).

    The thrust is always on, so the flight lasts at most T_b = (m0 - M_MIN) c / F (the mass
    bound). The radial speed starts and ends at 0 and stays within ±V_R (the state box).
    Falling, r̈ >= -μ/R² - F/m (eq. 1: the centrifugal term is >= 0), so the fall speed w is
    at most g_R t + c ln(m0/m(t)); braking, r̈ <= s + F/m with s the largest of
    h0²/r³ - μ/r² over the altitude box (h = r²ω never grows and ends at 0, as in
    `fall_surface_speed`), so w(t) <= s (T - t) + c ln(m(t)/m(T)). The descent ∫w dt is at
    most the integral of the least of the three; when s + F/m0 >= 0 it grows with T, so
    T = T_b bounds it. Each cell takes the forward bound at its right end and the braking
    bound (falling in t) at its left: the sum is on the safe side."""
    r0, w0, m0, thrust, c = (float(v) for v in p[:5])
    h0 = r0 ** 2 * w0
    support = radial_support(h0, R_MOON + ALTITUDE_MAX)
    if support + thrust / m0 < 0:
        return np.inf
    burn = (m0 - M_MIN) * c / thrust
    t = np.linspace(0.0, burn, REACH_STEPS + 1)
    mass = np.maximum(m0 - thrust * t / c, M_MIN)
    falling = MU_MOON / R_MOON ** 2 * t + c * np.log(m0 / mass)
    braking = support * (burn - t) + c * np.log(mass / M_MIN)
    cell = np.minimum(np.minimum(falling[1:], braking[:-1]), RADIAL_SPEED_MAX)
    return float(np.sum(np.maximum(cell, 0.0)) * burn / REACH_STEPS)


@cache
def ocp() -> OCP:
    """Minimum fuel = minimum time (constant thrust) with free final time."""

    def bounds(p):
        return Bounds(
            x_lb=np.array([R_MOON, -RADIAL_SPEED_MAX, -1.0, -0.01, M_MIN]),
            x_ub=np.array([R_MOON + ALTITUDE_MAX, RADIAL_SPEED_MAX, THETA_MAX, 0.01, p[P_M0]]),
            u_lb=np.array([-np.pi / 2]),
            u_ub=np.array([np.pi / 2]),
            T_lb=1.0,
            T_ub=p[P_M0] * p[P_C] / p[P_F],
        )

    def guess(p):
        T = time_guess(p)
        return Guess(
            x_final=np.array([R_MOON, 0.0, 0.5 * p[P_W0] * T, 0.0, p[P_M0] - p[P_F] * T / p[P_C]]),
            u=np.array([0.0]),
            T=T,
        )

    return OCP(
        states=STATES,
        state_units=STATE_UNITS,
        controls=("psi",),
        control_units=("rad",),
        n_params=5,
        dynamics=lambda x, u, p: descent_rhs(x, u[0], p[P_F], p[P_C]),
        initial_state=lambda p: ca.vertcat(p[P_R0], 0, 0, p[P_W0], p[P_M0]),
        terminal=lambda xf, p: ca.vertcat(xf[0] - R_MOON, xf[1], xf[3]),
        terminal_names=("altitude", "radial speed", "angular rate"),
        bounds=bounds,
        guess=guess,
        x_scale=np.array([1e4, 100.0, 0.1, 1e-3, 100.0]),
        x_offset=np.array([R_MOON, 0.0, 0.0, 0.0, 0.0]),
        u_scale=np.array([1.0]),
        T_scale=100.0,
        terminal_scale=np.array([1e3, 10.0, 1e-4]),
        cost_scale=100.0,
        mayer=lambda xf, T, p: p[P_M0] - xf[4],
    )


def touchdown_miss(x_final: np.ndarray) -> dict[str, float]:
    """Miss of each terminal condition at the end of a re-propagation (SI)."""
    r, v, _, w, _ = x_final
    return {
        "altitude_m": float(r - R_MOON),
        "radial_speed_m_s": float(v),
        "horizontal_speed_m_s": float(r * w),
        "speed_m_s": float(np.hypot(v, r * w)),
    }


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "r": Label("radius from the Moon's centre", "m"),
    "v": Label("radial speed", "m/s"),
    "theta": Label("downrange angle", "rad"),
    "omega": Label("angular rate", "rad/s"),
    "m": Label("mass", "kg"),
    "psi": Label("thrust angle above the horizontal", "rad"),
    "altitude_m": Label("touchdown altitude miss", "m"),
    "radial_speed_m_s": Label("touchdown radial speed miss", "m/s"),
    "horizontal_speed_m_s": Label("touchdown horizontal speed miss", "m/s"),
    "speed_m_s": Label("touchdown speed miss", "m/s"),
}
