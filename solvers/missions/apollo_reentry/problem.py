"""Apollo reentry with minimum heating as a problem (paper 004, example 2; SPEC M5 case 2):
parameters (SI), the OCP in S&B's units (1e5 ft, s) that the general methods solve, the
published numbers, accuracy targets and presets; and the record of a solution in SI."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache

import casadi as ca
import numpy as np

from ...context import Infeasible
from ...handles import Axis, CurveHandle, Handle
from ...nlp.cache import built_once
from ...ocp import OCP, Bounds, Guess, OCPResult
from ...problem import Consistency, Param, Preset, Published
from ...solution import Iterate, Label, Quantity, Solution
from ...transcription.costates import rescale
from . import model, reach

DEG = np.pi / 180
PAPER = "Wang, Cui & Hou 1988, Northwestern Polytechnical University (paper 004)"
LU = model.LENGTH_UNIT  # m per 1e5 ft
COST_UNIT = "(S&B units)"
# RK4 steps of about 3 s for multiple shooting whatever the node count (T is about 225 s).
RK4_STEPS_PER_RUN = 80

# OCP parameters, model units: boundary values, guesses, bounds.
(P_V0, P_G0, P_XI0, P_VF, P_GF, P_XIF, P_TG, P_UG, P_VLB, P_VUB, P_GLB, P_GUB, P_XIUB,
 P_UMAX, P_TLB, P_TUB) = range(16)
N_PARAMS = 16

PARAMS = (
    Param("v0", "entry speed v(0)", "m/s", 0.36 * LU, 6000.0, 12000.0, 10.0,
          group="Boundary values", display_unit="km/s", display_factor=1e-3,
          help="S&B: 0.36e5 ft/s."),
    Param("gamma0", "entry flight-path angle γ(0)", "rad", -8.1 * DEG, -20 * DEG, -1 * DEG,
          0.1 * DEG, group="Boundary values", display_unit="deg", display_factor=1 / DEG),
    Param("h0", "entry altitude h(0)", "m", 4.0 * LU, 60e3, 180e3, 100.0,
          group="Boundary values", display_unit="km", display_factor=1e-3,
          help="S&B: 4e5 ft (ξ(0) = 4/R)."),
    Param("vf", "final speed v(T)", "m/s", 0.27 * LU, 4000.0, 12000.0, 10.0,
          group="Boundary values", display_unit="km/s", display_factor=1e-3),
    Param("gammaf", "final flight-path angle γ(T)", "rad", 0.0, -10 * DEG, 10 * DEG,
          0.1 * DEG, group="Boundary values", display_unit="deg", display_factor=1 / DEG),
    Param("hf", "final altitude h(T)", "m", 2.5 * LU, 30e3, 180e3, 100.0,
          group="Boundary values", display_unit="km", display_factor=1e-3,
          help="S&B: 2.5e5 ft."),
    Param("u_max", "control bound |u| ≤", "rad", np.pi / 2, 10 * DEG, np.pi / 2, DEG,
          group="Bounds", display_unit="deg", display_factor=1 / DEG),
    Param("T_min", "final time ≥", "s", 200.0, 10.0, 1000.0, 1.0, group="Bounds"),
    Param("T_max", "final time ≤", "s", 500.0, 50.0, 2000.0, 1.0, group="Bounds"),
    Param("v_min", "speed ≥", "m/s", 0.1 * LU, 100.0, 8000.0, 10.0, group="Bounds",
          display_unit="km/s", display_factor=1e-3),
    Param("v_max", "speed ≤", "m/s", 0.5 * LU, 8000.0, 20000.0, 10.0, group="Bounds",
          display_unit="km/s", display_factor=1e-3),
    Param("gamma_min", "flight-path angle ≥", "rad", -0.2, -0.5, 0.0, 0.001, group="Bounds",
          display_unit="deg", display_factor=1 / DEG),
    Param("gamma_max", "flight-path angle ≤", "rad", 0.1, 0.0, 0.5, 0.001, group="Bounds",
          display_unit="deg", display_factor=1 / DEG),
    Param("h_max", "altitude ≤", "m", 0.03 * model.R_EARTH, 100e3, 400e3, 100.0,
          group="Bounds", display_unit="km", display_factor=1e-3,
          help="Paper: ξ ≤ 0.03 (and ξ ≥ 0)."),
    Param("T_guess", "initial guess T", "s", 230.0, 50.0, 1000.0, 1.0, group="Initial guess",
          help="Paper: 230 s; the paper found its method sensitive to this guess only.",
          guess=True),
    Param("u_guess", "initial guess u (constant)", "rad", 0.0, -np.pi / 2, np.pi / 2, DEG,
          group="Initial guess", display_unit="deg", display_factor=1 / DEG, guess=True),
)

VIEW_PARAMS = (
    Param("exaggerate", "exaggerate altitude", "×", 20.0, 1.0, 100.0, 1.0, group="Display",
          help="Display only: altitudes are drawn this many times higher so the path "
               "stands off the Earth."),
)

ENTRY_ARROW = 350e3  # m: the drawn length of the entry direction's arrow (display frame)


def _entry_point(values: Mapping[str, float], view: Mapping[str, float]) -> tuple[float, ...]:
    """The entry in the display frame: on +x at R_EARTH + exaggeration × altitude."""
    return model.R_EARTH + float(view["exaggerate"]) * float(values["h0"]), 0.0, 0.0


def _entry_direction_tip(gamma: np.ndarray, values: Mapping[str, float],
                         view: Mapping[str, float]) -> np.ndarray:
    """The tip of the entry direction as drawn: the flight-path angle γ steepened by the
    altitude exaggeration k, tan γ_drawn = k (R + h) tan γ / (R + k h) (`view.force_arrows`),
    downrange along +y."""
    k, h = float(view["exaggerate"]), float(values["h0"])
    drawn = np.arctan2(k * (model.R_EARTH + h) * np.sin(gamma),
                       (model.R_EARTH + k * h) * np.cos(gamma))
    x, y, z = _entry_point(values, view)
    return np.column_stack([x + ENTRY_ARROW * np.sin(drawn), y + ENTRY_ARROW * np.cos(drawn),
                            np.full_like(drawn, z)])


# Dragged in the 3D view: the entry point moves along the local vertical; the tip of the entry
# direction turns about it with the flight-path angle (a curve handle: the drawn angle is
# not affine in γ).
HANDLES = (
    Handle("entry", "entry altitude",
           (Axis("h0", offset=model.R_EARTH, view="exaggerate"), 0.0, 0.0)),
    CurveHandle("entry_angle", "entry flight-path angle", "gamma0", _entry_direction_tip,
                start=_entry_point),
)

_EXAMPLE_2 = "paper 004, example 2"
_INDIRECT = "indirect multiple shooting on the maximum principle, solved here (S&B constants)"
PUBLISHED = (
    # Our optimum (`model.solve_indirect`, agreeing with Hermite–Simpson at 160 intervals to
    # 1e-6): at their default node counts all methods are within 0.1 %.
    Published("J", 2.7782409e-2, COST_UNIT, _INDIRECT, rtol=1e-3,
              note="the reference the paper's numbers are compared with"),
    Published("T", 224.90076, "s", _INDIRECT, rtol=1e-3),
    # SPEC M5: with S&B's constants the optimum J is about 10 % above the published one;
    # more than 5 % off is what "does not hold" asserts (the mission test bounds it by 20 %).
    Published("J", 2.4967e-2, COST_UNIT, f"{_EXAMPLE_2} (10 nodes, 20 iterations)",
              rtol=0.05, holds=False,
              note="ours is 11.3 % higher (2.7782e-2). A direct method with an accurate "
                   "integrator can only land above the true minimum, so a J this far below "
                   "means a different problem: the paper omits its constants and we use "
                   "Stoer & Bulirsch's"),
    # SPEC M5: "T near 225 s"; ours is 0.6 % shorter.
    Published("T", 226.3, "s", _EXAMPLE_2, rtol=0.0, atol=3.0,
              note="ours 224.90 s, 0.6 % shorter: within 3 s"),
    # Fixing u on the first tenth restricts the control, so the paper's restricted J bounds
    # the unrestricted optimum from above: that is the claim checked here.
    Published("J", 2.53e-2, COST_UNIT, f"{_EXAMPLE_2}, u fixed at 1.5 on τ ∈ [0, 0.1]",
              rtol=0.05, relation="at-most", holds=False,
              note="a restricted control can only raise J, yet this is 9 % below our "
                   "unrestricted optimum: again a difference in the model's constants"),
)

# Accuracy targets of the re-propagated end state (SI) and heat load: the end of the
# manoeuvre (8.2 km/s at 76 km) within 200 m, 5 m/s and 0.06°, and J within 0.1 %, the
# agreement of the methods with each other. A user steering a capsule by these numbers
# would not notice the difference; the default solutions meet them with a margin of 2 to 5
# (Hermite–Simpson at 40 intervals, the largest: 89 m, 1.9 m/s, 2.1e-4 rad, 5.5e-4 in J).
TOLERANCES = {"altitude_miss_m": 200.0, "speed_miss_m_s": 5.0, "gamma_miss_rad": 1e-3,
              "J_repropagated_rel_error": 1e-3}

CONSISTENCY = (
    Consistency("cost", 1e-3, note="the three methods agree within 0.1 % at their defaults"),
    Consistency("T", 1e-3),
)

PRESETS = (
    Preset("Paper 004 case: multiple shooting, 10 intervals", {},
           method="multiple-shooting", nodes=10,
           note="The paper's mesh: J about 1 % above the converged optimum.", cold=True),
    Preset("Reference: Hermite–Simpson, 160 intervals", {}, method="hermite-simpson",
           nodes=160, note="Agrees with the indirect solution to 1e-6."),
    Preset("Reference: LGL, 60 nodes", {}, method="lgl", nodes=60),
    Preset("Shallower entry, γ(0) = −6.5°", {"gamma0": -6.5 * DEG},
           note="Bornemann's exercise. The trim angle saturates at ±90°: the optimum is "
                "no longer smooth and the methods stop at different local optima."),
    Preset("Steepest feasible entry, γ(0) = −8.2°", {"gamma0": -8.2 * DEG},
           note="About −8.25° and steeper cannot reach the end state: infeasible."),
    Preset("Lift limited, |u| ≤ 60°", {"u_max": 60 * DEG}),
)

EQUATIONS = (
    ("Apollo-type reentry (Stoer & Bulirsch; paper 004, example 2, eq. 8)",
     r"\dot v = -\frac{S\rho v^2 C_D(u)}{2m} - \frac{g\sin\gamma}{(1+\xi)^2},\quad "
     r"\dot\gamma = \frac{S\rho v C_L(u)}{2m} + \frac{v\cos\gamma}{R(1+\xi)} - "
     r"\frac{g\cos\gamma}{v(1+\xi)^2},\quad \dot\xi = \frac{v\sin\gamma}{R}"),
    ("Atmosphere, aerodynamics and the heating cost",
     r"\rho = \rho_0 e^{-\beta R\xi},\quad C_D = 1.174 - 0.9\cos u,\quad C_L = 0.6\sin u,"
     r"\qquad J = \int_0^T 10\, v^3\sqrt{\rho}\, dt"),
)


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    """OCP parameters in the model's units (1e5 ft, s) from SI values."""
    xi = 1.0 / model.R_EARTH
    return np.array([
        values["v0"] / LU, values["gamma0"], values["h0"] * xi,
        values["vf"] / LU, values["gammaf"], values["hf"] * xi,
        values["T_guess"], values["u_guess"],
        values["v_min"] / LU, values["v_max"] / LU, values["gamma_min"],
        values["gamma_max"], values["h_max"] * xi, values["u_max"],
        values["T_min"], values["T_max"],
    ])


def check_values(values: dict[str, float]) -> None:
    """Each lower bound must lie below its upper bound."""
    for lo, hi in (("v_min", "v_max"), ("gamma_min", "gamma_max"), ("T_min", "T_max")):
        if values[lo] >= values[hi]:
            raise ValueError(f"bound {lo} = {values[lo]:g} is not below {hi} = "
                             f"{values[hi]:g}")


def precheck(values: dict[str, float]) -> None:
    """Refuse a request that violates a necessary condition of the bounds, naming it.

    The boundary values must lie inside the state bounds. Gravity is conservative and drag
    (C_D >= 1.174 - 0.9 > 0) only dissipates, so E = v²/2 - g R²/(R + h) cannot rise. And
    ḣ = v sin γ with v <= v_max and γ_min <= γ <= γ_max bounds the climb and the descent
    over at most T_max. An end descending high up needs a top of the path above it, in air
    too thin to matter, and a low start or end keeps the capsule in air dense enough for a
    while that drag takes more than the ends allow (`reach`)."""
    checks = (("v0", "v_min", "v_max"), ("vf", "v_min", "v_max"),
              ("gamma0", "gamma_min", "gamma_max"), ("gammaf", "gamma_min", "gamma_max"))
    for key, lo, hi in checks:
        if not values[lo] <= values[key] <= values[hi]:
            raise Infeasible(f"{key} = {values[key]:g} lies outside the bounds "
                             f"[{values[lo]:g}, {values[hi]:g}] ({lo}, {hi})")
    for key in ("h0", "hf"):
        if values[key] > values["h_max"]:
            raise Infeasible(f"{key} = {values[key]:g} m is above h_max = {values['h_max']:g} m")
    _precheck_energy(values)
    _precheck_altitude(values)
    _precheck_thin_air(values)
    _precheck_dense_air(values)
    _precheck_pull_up(values)


def _precheck_energy(values: dict[str, float]) -> None:
    """Drag only removes energy: the final speed is at most what the height lost gives."""
    e_0 = reach.energy_momentum(values["v0"], 0.0, values["h0"])[0]
    reachable = float(np.sqrt(2 * (e_0 + reach.MU / (model.R_EARTH + values["hf"]))))
    if values["vf"] > reachable:
        raise Infeasible(
            f"vf = {values['vf']:g} m/s needs more energy than the capsule has: drag only "
            f"removes energy, so from v0 = {values['v0']:g} m/s at h0 = {values['h0']:g} m "
            f"the speed at hf = {values['hf']:g} m is at most {reachable:.6g} m/s")


def _precheck_altitude(values: dict[str, float]) -> None:
    """The altitude changes at most v_max sin(γ) per second, within the γ bounds."""
    change, horizon = values["hf"] - values["h0"], values["T_max"] * values["v_max"]
    if change < 0:
        limit, bound, word = horizon * np.sin(-values["gamma_min"]), "gamma_min", "descend"
    else:
        limit, bound, word = horizon * np.sin(values["gamma_max"]), "gamma_max", "climb"
    if abs(change) > limit:
        raise Infeasible(
            f"the capsule cannot {word} {abs(change):g} m: with {bound} = "
            f"{values[bound]:g} rad, v ≤ v_max = {values['v_max']:g} m/s and T ≤ T_max = "
            f"{values['T_max']:g} s it changes altitude by at most {limit:.4g} m")


def _precheck_thin_air(values: dict[str, float]) -> None:
    """Ending high up descending (γf < 0) needs a top of the path above hf (`reach`)."""
    top = reach.top_before_descent(values)
    if top is None:
        return
    where = (f"that top lies at {top:.4g} m or higher" if np.isfinite(top) else
             "the end state is on an escape path, with no top at all")
    raise Infeasible(
        f"to end at hf = {values['hf']:g} m descending (γf = {values['gammaf']:g} rad) the "
        f"capsule must come over a top of its path after it was last lower, where the air is "
        f"too thin above hf to change its energy and angular momentum much within T_max = "
        f"{values['T_max']:g} s: {where}, above the bound h_max = {values['h_max']:g} m")


def _precheck_dense_air(values: dict[str, float]) -> None:
    """Near a low start or end the air is dense: drag takes more energy there within T_min
    than the ends allow (`reach.dense_air_loss`)."""
    allowed, forced = reach.dense_air_loss(values)
    if forced > allowed:
        raise Infeasible(
            f"drag takes at least {forced:.4g} J/kg from the capsule near its start and end "
            f"(in T ≥ T_min = {values['T_min']:g} s it can leave h0 = {values['h0']:g} m and "
            f"reach hf = {values['hf']:g} m only so fast, with v ≤ v_max = "
            f"{values['v_max']:g} m/s and gamma in [{values['gamma_min']:g}, "
            f"{values['gamma_max']:g}] rad), but from v0 to vf it may lose only "
            f"{allowed:.4g} J/kg: lower T_min, or ask for a slower end")


def _precheck_pull_up(values: dict[str, float]) -> None:
    """A steep dive at the start (or climb at the end) the air cannot turn before the ground
    (`reach.pull_up_floor`)."""
    pull = reach.pull_up_floor(values)
    if pull.lowest < 0:
        how = ("dives too steeply at its start" if pull.end == "start" else
               "climbs too steeply at its end (seen backwards in time, a dive)")
        raise Infeasible(
            f"the capsule {how} for the air to turn it above the ground (altitude ≥ 0): "
            f"drag may take only E0 − Ef of its energy, so lift and drag change its vertical "
            f"speed by at most {pull.air:.4g} m/s (|u| ≤ u_max = {values['u_max']:g} rad), "
            f"so {pull.after:.4g} s from its {pull.end} it would be at least "
            f"{-pull.lowest:.4g} m below the ground: a shallower gamma0 or gammaf, a larger "
            f"u_max or a slower end")


def substeps(nodes: int) -> int:
    """RK4 steps per multiple-shooting interval: about 3 s each, at least 2."""
    return max(2, -(-RK4_STEPS_PER_RUN // nodes))


@cache
def ocp() -> OCP:
    """Minimum heat load with free final time, in the model's units (paper 004, eq. 8)."""

    def bounds(p: np.ndarray) -> Bounds:
        return Bounds(
            x_lb=np.array([p[P_VLB], p[P_GLB], 0.0]),
            x_ub=np.array([p[P_VUB], p[P_GUB], p[P_XIUB]]),
            u_lb=np.array([-p[P_UMAX]]),
            u_ub=np.array([p[P_UMAX]]),
            T_lb=float(p[P_TLB]),
            T_ub=float(p[P_TUB]),
        )

    def guess(p: np.ndarray) -> Guess:
        return Guess(x_final=np.asarray(p[P_VF : P_XIF + 1]), u=np.array([p[P_UG]]),
                     T=float(p[P_TG]))

    return OCP(
        states=("v", "gamma", "xi"),
        state_units=("1e5 ft/s", "rad", "R"),
        controls=("u",),
        control_units=("rad",),
        n_params=N_PARAMS,
        dynamics=lambda x, u, p: model.rhs(x, u[0]),
        initial_state=lambda p: p[P_V0 : P_XI0 + 1],
        terminal=lambda xf, p: xf - p[P_VF : P_XIF + 1],
        terminal_names=("speed", "flight-path angle", "altitude"),
        bounds=bounds,
        guess=guess,
        x_scale=np.array([0.1, 0.1, 0.01]),
        u_scale=np.ones(1),
        T_scale=100.0,
        terminal_scale=np.array([0.01, 0.01, 0.001]),
        lagrange=lambda x, u, p: model.heating_rate(x),
        cost_scale=0.01,
    )


def record(sol: Solution, res: OCPResult) -> None:
    """The SI interface: states (v [m/s], gamma, h [m]) and iterates in SI, the mission's
    quantities, the whole manoeuvre as one unpowered arc."""
    t, X, u = res.t_dense, res.X_dense, res.U_dense[:, 0]
    sol.state_names, sol.state_units = model.STATES, model.STATE_UNITS
    sol.x, sol.node_x = model.to_si(X), model.to_si(res.X)
    sol.history = [Iterate(it.iteration, it.t, model.to_si(it.x)) for it in res.history]
    sol.arcs = [(0.0, res.T, "coast")]
    sol.costates = rescale(sol.costates, state_factor=np.array([LU, 1.0, model.R_EARTH]),
                           cost_factor=1.0, time_factor=1.0, cost_unit=COST_UNIT,
                           state_units=model.STATE_UNITS, names=model.STATES)
    # A diverged iterate (e.g. SQP leaving the atmosphere) may overflow exp(-beta R xi).
    with np.errstate(over="ignore", invalid="ignore"):
        heating = model.heating_rate(X)
        decel = model.drag_deceleration(X, u)
        theta = model.downrange(t, sol.x)
    sol.quantities = {
        "T": Quantity(res.T, "final time", "s"),
        "J": Quantity(res.cost, "heat load J", COST_UNIT),
        "peak_heating": Quantity(float(heating.max()), "peak heating rate 10 v³√ρ",
                                 COST_UNIT + "/s"),
        "peak_deceleration": Quantity(float(decel.max()), "peak deceleration", "m/s²"),
        "min_altitude": Quantity(float(sol.x[:, 2].min()), "lowest altitude", "m"),
        "downrange": Quantity(float(theta[-1] * model.R_EARTH), "downrange", "m"),
    }


def terminal_miss(p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
    """Miss of the end state (model units in) in SI."""
    miss = np.asarray(x_final[:3], float) - p[P_VF : P_XIF + 1]
    return {
        "speed_miss_m_s": float(miss[0] * LU),
        "gamma_miss_rad": float(miss[1]),
        "altitude_miss_m": float(miss[2] * model.R_EARTH),
    }


@built_once
def augmented() -> ca.Function:
    """(x, heat)' = (f, L), to re-propagate the heat load with the state."""
    x = ca.SX.sym("x", 4)
    u = ca.SX.sym("u", 1)
    p = ca.SX.sym("p", N_PARAMS)
    return ca.Function("reentry_aug", [x, u, p],
                       [ca.vertcat(model.rhs(x[:3], u[0]), model.heating_rate(x[:3]))])


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "v": Label("speed", "m/s"),
    "gamma": Label("flight-path angle", "rad"),
    "h": Label("altitude", "m"),
    "u": Label("angle of attack", "rad"),
    "speed_miss_m_s": Label("final speed miss", "m/s"),
    "gamma_miss_rad": Label("final flight-path angle miss", "rad"),
    "altitude_miss_m": Label("final altitude miss", "m"),
    "J_repropagated_rel_error": Label("heat load re-propagated (relative error)"),
}
