"""Finite-thrust rendezvous as a problem (paper 000, SPEC M1): parameters and view options,
the free-structure OCP the general methods solve, published numbers, presets, the quantities
every method reports and the re-propagation check."""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import casadi as ca
import numpy as np

from ...context import Infeasible
from ...dynamics.clohessy_wiltshire import (
    MU_EARTH,
    STATE_UNITS,
    STATES,
    cw_rhs,
    mean_motion,
    nonlinear_relative_miss,
)
from ...handles import Axis, Handle
from ...ocp import OCP, Bounds, Guess
from ...optimality import PMP_COSTATES, PMP_TRAJECTORY, record_costate_error
from ...problem import Consistency, Param, Preset, Published
from ...solution import Label, Quantity, Series, Solution, costate_units
from ...verify import repropagate
from .primer import fit_initial_costate, min_acceleration, solve_primer, switching

PAPER = "Finite-thrust rendezvous by direct collocation (paper 000)"
# Parameter vector: initial relative state (6), CW rate w, thrust acceleration a, total time T.
P_W, P_A, P_T = 6, 7, 8
CONTROLS = ("ax", "ay", "az")
CONTROL_UNITS = ("m/s²",) * 3
THROTTLE_ON = 0.5  # fraction of a above which a free-structure node counts as burning
CHECK_ATOL = np.array([1e-7] * 3 + [1e-10] * 3)  # re-propagation: m, m/s

PARAMS = (
    Param("x0", "initial x (behind target)", "m", 15000.0, -100e3, 100e3, 100.0,
          group="Initial relative state", display_unit="km", display_factor=1e-3,
          help="x points opposite to the target's orbital velocity."),
    Param("y0", "initial y (radial, up)", "m", -500.0, -50e3, 50e3, 50.0,
          group="Initial relative state", display_unit="km", display_factor=1e-3),
    Param("z0", "initial z (orbit normal)", "m", 0.0, -50e3, 50e3, 50.0,
          group="Initial relative state", display_unit="km", display_factor=1e-3),
    Param("vx0", "initial x'", "m/s", -100.0, -500.0, 500.0, 1.0,
          group="Initial relative state"),
    Param("vy0", "initial y'", "m/s", 10.0, -500.0, 500.0, 1.0, group="Initial relative state"),
    Param("vz0", "initial z'", "m/s", 0.0, -500.0, 500.0, 1.0, group="Initial relative state"),
    Param("total_time", "total transfer time", "s", 600.0, 60.0, 20000.0, 10.0, group="Transfer"),
    Param("accel", "thrust acceleration a", "m/s²", 0.5, 0.01, 10.0, 0.01, group="Vehicle",
          help="Constant thrust acceleration while burning (paper: not given; default 0.5)."),
    Param("altitude", "target orbit altitude", "m", 400e3, 160e3, 40000e3, 10e3,
          group="Target orbit", display_unit="km", display_factor=1e-3,
          help="Circular orbit; sets the CW rate w (400 km: 1.1314e-3 rad/s)."),
)

VIEW_PARAMS = (
    Param("view", "view", "", 0, 0, 1, 1, group="Display",
          options=("target orbital frame", "inertial (magnified)")),
    Param("magnify", "relative-motion magnification", "", 50.0, 1.0, 2000.0, 1.0,
          group="Display", help="Inertial view: relative motion drawn this many times larger."),
)

# Dragged in the 3D view: the chaser's start and the tip of its velocity arrow (20 m of
# arrow per m/s), in the target orbital frame (metres; the magnified inertial view has no
# handle: its axes turn with the orbit).
ARROW_S = 20.0
HANDLES = (
    Handle("start", "chaser start", ("x0", "y0", "z0"), views={"view": 0}),
    Handle("start_velocity", "start velocity", (Axis("vx0", ARROW_S, base="x0"),
                                                Axis("vy0", ARROW_S, base="y0"),
                                                Axis("vz0", ARROW_S, base="z0")),
           views={"view": 0}),
)

_SIZE = "paper 000, section 3 (coplanar case, 2 burns × 12 sub-intervals, 26 nodes)"
PUBLISHED = (
    Published("nlp_variables", 159, "", _SIZE, rtol=0.0, methods=("paper",),
              note="26 nodes × (4 states + 2 controls) + 3 arc durations"),
    Published("nlp_equalities", 135, "", _SIZE, rtol=0.0, methods=("paper",),
              note="burn defects, coast STM, |u| = 1, boundary states, total time"),
    Published("nlp_inequalities", 3, "", _SIZE, rtol=0.0, methods=("paper",),
              note="every arc duration >= 0"),
)

# Accuracy targets of the re-propagated (linear CW) arrival, SI: 1 m and 1 mm/s, a docking
# approach's entry gate. The default solutions of every method miss by less than 3e-5 m and
# 5e-8 m/s; the nonlinear two-body miss (about 3 m) is the model's error, not the method's,
# and is reported beside it.
TOLERANCES = {"position_m": 1.0, "velocity_m_s": 1e-3}

CONSISTENCY = (
    Consistency("cost", 1e-3, note="the paper's arcs, HS and multiple shooting find the same "
                                   "minimum burn time (the arcs converge to it from above)"),
    Consistency("burns", 0.0, note="the free structure finds the paper's two burns by itself"),
)

PRESETS = (
    Preset("Paper 000 case", {}, note="Coplanar, 15 km behind, 600 s, a = 0.5 m/s²."),
    Preset("Strong engine: arrive early and wait", {"accel": 2.0}, method="hermite-simpson"),
    Preset("Weak engine: no solution in 600 s", {"accel": 0.1}),
    Preset("Out-of-plane start", {"z0": 2000.0, "vz0": -5.0}),
    Preset("Exterior penalty method (paper eq. 12)", {}, method="paper"),
    Preset("Coarse mesh (4 sub-intervals)", {}, method="paper", nodes=4),
    Preset("Inertial view", {}, view={"view": 1}),
)

EQUATIONS = (
    ("Clohessy–Wiltshire equations in the target orbital frame (paper 000, eq. 1)",
     r"\ddot x - 2\omega\dot y = a u_x,\quad \ddot y + 2\omega\dot x - 3\omega^2 y = "
     r"a u_y,\quad \ddot z + \omega^2 z = a u_z,\quad \lVert u\rVert \le 1"),
    ("Cost: total burn time for a fixed transfer time (eq. 10)",
     r"J = \sum_{\text{burns}} T_b,\qquad \sum_{\text{arcs}} T_i = T"),
)


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    """(x0, y0, z0, vx0, vy0, vz0, w, a, T) in SI from validated mission values."""
    x0 = np.array([values[k] for k in ("x0", "y0", "z0", "vx0", "vy0", "vz0")])
    w = mean_motion(values["altitude"])
    return np.concatenate([x0, [w, values["accel"], values["total_time"]]])


@cache
def free_ocp() -> OCP:
    """Free-structure problem: control (a_x, a_y, a_z, s), |a| <= s <= a, cost ∫ s/a dt
    (an L1 cost: the burn/coast structure is not imposed but emerges, bang–bang)."""

    def bounds(p: np.ndarray) -> Bounds:
        a = p[P_A]
        return Bounds(
            x_lb=np.full(6, -1e7), x_ub=np.full(6, 1e7),
            u_lb=np.array([-a, -a, -a, 0.0]), u_ub=np.array([a, a, a, a]), T_lb=0.0, T_ub=0.0,
        )

    def guess(p: np.ndarray) -> Guess:
        return Guess(np.zeros(6), np.array([0.0, 0.0, 0.0, 0.5 * p[P_A]]), float(p[P_T]))

    return OCP(
        states=STATES, state_units=STATE_UNITS, controls=(*CONTROLS, "s"),
        control_units=(*CONTROL_UNITS, "m/s²"), n_params=9,
        dynamics=lambda x, u, p: cw_rhs(x, u[:3], p[P_W]),
        initial_state=lambda p: p[:6],
        terminal=lambda xf, p: xf,
        terminal_names=STATES,
        bounds=bounds, guess=guess,
        x_scale=np.array([1e4, 1e4, 1e4, 100.0, 100.0, 100.0]),
        u_scale=np.ones(4), T_scale=100.0,
        terminal_scale=np.array([1.0, 1.0, 1.0, 1e-2, 1e-2, 1e-2]),
        cost_scale=100.0,
        lagrange=lambda x, u, p: u[3] / p[P_A],
        fixed_final_time=lambda p: p[P_T],
        path=lambda x, u, p: ca.sumsqr(u[:3]) - u[3] ** 2,
        path_lb=np.array([-np.inf]), path_ub=np.array([0.0]),
        path_cones=lambda x, u, p: [(u[:3], u[3])],  # the same row as the cone |a| <= s
        controls_from_shown=lambda a: np.column_stack([a, np.linalg.norm(a, axis=1)]),
    )


def precheck(p: np.ndarray) -> None:
    """Refuse a thrust acceleration below the least that can reach the target in the total
    time (the primer-vector bound, `primer.min_acceleration`): a proof, not a guess."""
    a_min = min_acceleration(tuple(p[:6]), float(p[P_W]), float(p[P_T]))
    if p[P_A] < a_min * (1 - 1e-6):
        raise Infeasible(
            f"no trajectory reaches the target in {p[P_T]:g} s with a = {p[P_A]:g} m/s²: "
            f"the least thrust acceleration that can is {a_min:.4g} m/s² (primer-vector "
            "bound on the reachable set): increase the thrust acceleration or the total time")


def explain(status: str, message: str, values: dict[str, float], structure: str) -> str:
    """Say in words why a request above the acceleration bound still has no answer."""
    if status == "optimal":
        return message
    a_min = min_acceleration(tuple(parameter_vector(values)[:6]),
                             mean_motion(values["altitude"]), values["total_time"])
    return (f"no {structure} trajectory found ({message}); the least thrust acceleration "
            f"that can reach the target in {values['total_time']:g} s is {a_min:.4g} m/s², "
            f"a = {values['accel']:g} m/s² is above it, so the request is possible: a "
            "structure with more burns, or another guess, may solve it")


def arcs_from_throttle(t: np.ndarray, burning: np.ndarray) -> list[tuple[float, float, str]]:
    """Arcs from node throttle: a switch is placed midway between differing nodes."""
    arcs, start = [], 0.0
    for k in range(1, len(t)):
        if burning[k] != burning[k - 1]:
            mid = float(0.5 * (t[k - 1] + t[k]))
            arcs.append((start, mid, "burn" if burning[k - 1] else "coast"))
            start = mid
    arcs.append((start, float(t[-1]), "burn" if burning[-1] else "coast"))
    return arcs


def quantities(cost: float, accel: float, arcs: list[tuple[float, float, str]],
               surrogate: float | None = None) -> dict[str, Quantity]:
    """Burn time (the cost), the NLP's surrogate of it beside it (if any), Δv = a × burn
    time, the number of burns, burn time from arcs."""
    burn = sum(b - a for a, b, kind in arcs if kind == "burn")
    extra = {} if surrogate is None else {
        "surrogate_burn_time": Quantity(surrogate, "NLP surrogate ∫s/a dt", "s")}
    return {
        "burn_time": Quantity(float(cost), "burn time", "s"),
        **extra,
        "delta_v": Quantity(float(cost * accel), "Δv", "m/s"),
        "burns": Quantity(float(sum(kind == "burn" for *_, kind in arcs)), "burns", ""),
        "arc_burn_time": Quantity(float(burn), "burn time from arcs", "s"),
    }


def terminal_miss(x_final: np.ndarray) -> dict[str, float]:
    """Distance and speed from the target at the end of a re-propagation (SI)."""
    return {"position_m": float(np.linalg.norm(x_final[:3])),
            "velocity_m_s": float(np.linalg.norm(x_final[3:]))}


def check(p: np.ndarray, breaks: np.ndarray,
          control: Callable[[float, np.ndarray], np.ndarray]) -> dict[str, float]:
    """Re-propagate an acceleration law (DOP853) in the CW model and in full two-body
    gravity (target on its circular orbit); the arrival miss of each."""
    _, X = repropagate(free_ocp().functions().f, p, p[:6],
                       lambda t, x: np.concatenate([control(t, x), [0.0]]), breaks,
                       atol=CHECK_ATOL)
    out = terminal_miss(X[-1])
    radius = float(np.cbrt(MU_EARTH / p[P_W] ** 2))
    nl = nonlinear_relative_miss(p[:6], p[P_W], radius, control, breaks)
    out["nonlinear_position_m"] = float(np.linalg.norm(nl[:3]))
    out["nonlinear_velocity_m_s"] = float(np.linalg.norm(nl[3:]))
    return out


def store_primer(sol: Solution, p: np.ndarray) -> None:
    """Shoot the primer-vector extremal from the costate estimate and store it (SI): the
    trajectory with the switching function, the costates, its burn time and the costate
    agreement; say so when the shooting does not converge."""
    est = sol.costates
    lam0 = fit_initial_costate(est.t, np.asarray(est.values), p[P_W])
    ext = solve_primer(p[:6], p[P_W], p[P_A], p[P_T], lam0)
    if not ext.converged:
        sol.message += (f" (the primer-vector shooting did not converge from the costate "
                        f"estimate: miss {ext.residual:.2g} m)")
        return
    S = switching(ext.lam, p[P_A])
    sol.references[PMP_TRAJECTORY] = Series(ext.t, np.column_stack([ext.x, S]),
                                            (*STATES, "S"), (*STATE_UNITS, ""))
    sol.references[PMP_COSTATES] = Series(ext.t, ext.lam, STATES,
                                          costate_units("s", STATE_UNITS))
    sol.quantities["burn_time_pontryagin"] = Quantity(ext.burn_time,
                                                      "burn time (primer vector)", "s")
    record_costate_error(sol)


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "ax": Label("thrust acceleration, radial", "m/s²"),
    "ay": Label("thrust acceleration, along-track", "m/s²"),
    "az": Label("thrust acceleration, cross-track", "m/s²"),
    "position_m": Label("arrival position miss", "m"),
    "velocity_m_s": Label("arrival velocity miss", "m/s"),
    "nonlinear_position_m": Label("arrival position miss (nonlinear model)", "m"),
    "nonlinear_velocity_m_s": Label("arrival velocity miss (nonlinear model)", "m/s"),
}
