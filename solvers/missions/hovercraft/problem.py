"""The minimum-time hovercraft as a problem (paper 004, example 1; SPEC M5 case 1): parameters,
the two OCPs (thrust angle, thrust vector), published numbers, accuracy targets and presets."""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ...context import Infeasible
from ...handles import Axis, Handle
from ...ocp import OCP, Bounds, Guess
from ...optimality import PMP_TRAJECTORY
from ...problem import Consistency, Param, Preset, Published
from ...solution import Label
from .model import STATE_UNITS, STATES, T_LB, T_UB, X_LB, X_UB, rhs_angle, rhs_vector
from .reach import overshoot, travel_range

DEG = np.pi / 180
PAPER = "Wang, Cui & Hou 1988, Northwestern Polytechnical University (paper 004)"
# OCP parameter vector: A/m, initial state (4), final state (4), guess T, guess alpha, and
# the centre of the 2π window that bounds alpha (0: the paper's -π <= alpha <= π).
P_A, P_X0, P_XF, P_TG, P_AG, P_AC = 0, slice(1, 5), slice(5, 9), 9, 10, 11
N_PARAMS = 12
STEERING = ("angle α, started from the thrust vector", "angle α only (paper)",
            "thrust vector |u| ≤ 1")
ANGLE_VIA_VECTOR, ANGLE_ONLY, VECTOR = range(3)
# The key of the maximum-principle extremal in `Solution.references`.
REFERENCE = PMP_TRAJECTORY

PARAMS = (
    Param("accel", "thrust acceleration A/m", "m/s²", 3.0, 0.5, 10.0, 0.1, group="Vehicle",
          help="Constant thrust magnitude per unit mass; only its direction α is steered."),
    Param("x0", "initial x", "m", 0.0, X_LB[0], X_UB[0], 0.1, group="Initial state"),
    Param("y0", "initial y", "m", 0.0, X_LB[1], X_UB[1], 0.1, group="Initial state"),
    Param("vx0", "initial vx", "m/s", 5.0, X_LB[2], X_UB[2], 0.1, group="Initial state"),
    Param("vy0", "initial vy", "m/s", 0.0, X_LB[3], X_UB[3], 0.1, group="Initial state"),
    Param("xf", "final x", "m", 5.0, X_LB[0], X_UB[0], 0.1, group="Final state"),
    Param("yf", "final y", "m", 5.0, X_LB[1], X_UB[1], 0.1, group="Final state"),
    Param("vxf", "final vx", "m/s", 0.0, X_LB[2], X_UB[2], 0.1, group="Final state"),
    Param("vyf", "final vy", "m/s", 5.0, X_LB[3], X_UB[3], 0.1, group="Final state"),
    Param("T_guess", "initial guess T", "s", 2.0, 0.1, T_UB, 0.1, group="Initial guess",
          help="Paper: T0 = 2 (published 2.464) and T0 = 5 (published 2.529).",
          guess=True),
    Param("alpha_guess", "initial guess α (constant)", "rad", 0.0, -np.pi, np.pi, DEG,
          group="Initial guess", display_unit="deg", display_factor=1 / DEG,
          help="Paper: α = 0, states linear between the ends.", guess=True),
    Param("steering", "control variable", "", 0, 0, 2, 1, group="Method", options=STEERING,
          help="The paper steers with α. From α ≡ 0 the angle form is degenerate "
               "(∂v̇x/∂α = -A/m sin α = 0), so by default a cold start first solves the "
               "thrust-vector form (|u| ≤ 1, exact for minimum time) and then polishes α "
               "(LGL keeps the thrust vector)."),
)

# Dragged in the 3D view (ground plane, metres): the start and the target, and the tips of
# their velocity arrows (ARROW_S metres of arrow per m/s, from the point they start at).
ARROW_S = 0.2
HANDLES = (
    Handle("start", "start", ("x0", "y0", 0.0)),
    Handle("target", "target", ("xf", "yf", 0.0)),
    Handle("start_velocity", "start velocity", (Axis("vx0", ARROW_S, base="x0"),
                                                Axis("vy0", ARROW_S, base="y0"), 0.0)),
    Handle("target_velocity", "target velocity", (Axis("vxf", ARROW_S, base="xf"),
                                                  Axis("vyf", ARROW_S, base="yf"), 0.0)),
)

_EXAMPLE_1 = "paper 004, example 1"
T_STAR = 2.4954276  # s, the maximum-principle minimum (model.solve_min_time) to 8 digits
PUBLISHED = (
    # The maximum principle (linear tangent steering, solved to round-off here) is the
    # independent reference SPEC M5 asks for; at 10 nodes every method is within 1e-6 of it.
    Published("T", T_STAR, "s", "the maximum principle: linear tangent law, solved here",
              rtol=1e-6, note="the true minimum of the stated problem; every method reaches "
                              "it from both of the paper's guesses"),
    # The paper's numbers: the true minimum lies more than 0.02 s from each (it lies between
    # them), which is what the two records below assert.
    Published("T", 2.464, "s", f"{_EXAMPLE_1} (guess T0 = 2, 22 iterations)", rtol=0.0,
              atol=0.02, holds=False,
              note="1.26 % below the true minimum 2.4954276 s: no control meets the stated "
                   "boundary conditions in 2.464 s, so it is not a feasible answer"),
    Published("T", 2.529, "s", f"{_EXAMPLE_1} (guess T0 = 5)", rtol=0.0, atol=0.02,
              holds=False, case=Preset("Paper 004 case, guess T0 = 5", {"T_guess": 5.0}),
              note="1.35 % above the true minimum: the paper's SQP stopped short of the "
                   "optimum, which every method here reaches from this guess too"),
)

# Accuracy targets of the re-propagated end state (SI): 0.1 mm and 0.01 mm/s on a 5 m,
# 5 m/s manoeuvre, far below anything a hovercraft could steer to. At their default 10 nodes
# multiple shooting and LGL end within 1e-9 m, Hermite–Simpson (cubic states) within
# 3.5e-6 m and 4e-7 m/s: a margin of 25 or more for every method.
TOLERANCES = {"position_miss_m": 1e-4, "velocity_miss_m_s": 1e-5}

CONSISTENCY = (
    # Each method is within 1e-6 of the maximum principle at its default 10 nodes, so any
    # two within 2e-6 (they differ by 3e-7 here).
    Consistency("T", 2e-6, note="all three methods converge to the true minimum"),
    # The extremal is found from each method's own steering: the same to round-off.
    Consistency("T_pontryagin", 1e-12,
                note="the maximum-principle reference does not depend on its starting guess"),
)

PRESETS = (
    Preset("Paper 004 case (T0 = 2)", {}, note="Published 2.464; true minimum 2.4954276.",
           cold=True),
    Preset("Paper 004 case, guess T0 = 5", {"T_guess": 5.0},
           note="Published 2.529; the same true minimum is reached.", cold=True),
    Preset("Paper's angle form from α ≡ 0 (degenerate start)", {"steering": ANGLE_ONLY},
           note="Fails: the angle form cannot move away from α ≡ 0.", cold=True),
    Preset("Angle form from α = 120° (IPOPT)",
           {"steering": ANGLE_ONLY, "alpha_guess": 120 * DEG}, method="hermite-simpson",
           note="A non-degenerate guess: the paper's formulation converges with IPOPT.",
           cold=True),
    Preset("Thrust-vector form, 10 intervals", {"steering": VECTOR},
           method="multiple-shooting",
           note="Chord control between nodes: 0.2 % slower than the angle form."),
    Preset("LGL, 20 nodes", {}, method="lgl", nodes=20,
           note="Spectral accuracy: the true minimum to 1e-9."),
    Preset("Stronger thrust, A/m = 6", {"accel": 6.0}),
    Preset("Long hop to (10, 5): the bound y ≥ 0 is active", {"xf": 10.0},
           note="The unconstrained extremal would dip below y = 0; the optimum throttles "
                "(|u| < 1, the paper's thrust is F or zero) on the boundary, which the "
                "full-thrust angle form cannot do: the thrust-vector solution is shown."),
    Preset("Turn back to vy = −3: α sweeps past 180°", {"xf": 8.0, "yf": 4.0, "vyf": -3.0},
           note="The 2π window of α follows the turn (α from 105° to 263°)."),
)

EQUATIONS = (
    ("Hovercraft dynamics (paper 004, example 1, eq. 7)",
     r"\dot x = v_x,\quad \dot y = v_y,\quad \dot v_x = \frac{A}{m}\cos\alpha,\quad "
     r"\dot v_y = \frac{A}{m}\sin\alpha,\qquad \min T"),
    ("Minimum-time steering law (maximum principle): linear tangent",
     r"\tan\alpha(t) = \frac{c_3 - c_4 t}{c_1 - c_2 t}"),
)


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    """The OCP's numeric parameters from validated mission values (the window centre 0)."""
    return np.array([
        values["accel"], values["x0"], values["y0"], values["vx0"], values["vy0"],
        values["xf"], values["yf"], values["vxf"], values["vyf"], values["T_guess"],
        values["alpha_guess"], 0.0,
    ])


def precheck(p: np.ndarray) -> None:
    """Refuse a request that violates a necessary condition of the bounds, naming it.

    Both control forms accelerate by at most A/m (|u| <= 1), so |Δv| <= A/m T: the
    manoeuvre lasts at least T_low = |Δv| / (A/m), and T <= T_max. Along each axis the
    acceleration is at most A/m too and the speed stays in the state box, which bounds the
    distance covered in any duration from T_low to T_max (`reach.travel_range`; with vx >= 0
    x cannot decrease) and the room needed to stop before an edge of the position box or to
    arrive at the end speed (`reach.overshoot`)."""
    a = float(p[P_A])
    dv = float(np.linalg.norm(p[P_XF][2:] - p[P_X0][2:]))
    if dv / a > T_UB:
        raise Infeasible(
            f"the velocity change of {dv:.3g} m/s needs at least {dv / a:.3g} s of "
            f"thrust at A/m = {a:g} m/s², beyond the paper's bound T ≤ {T_UB:g} s"
        )
    (x0, xf) = p[P_X0][0], p[P_XF][0]
    if xf < x0:
        raise Infeasible(f"vx ≥ {X_LB[2]:g} m/s (the state bound) keeps x from decreasing, "
                         f"but the final x = {xf:g} m lies behind the initial x = {x0:g} m")
    t_low = max(dv / a, T_LB)
    for axis in (0, 1):
        _precheck_edges(p, axis, a, t_low)
        _precheck_travel(p, axis, a, t_low)


def _precheck_edges(p: np.ndarray, axis: int, a: float, t_low: float) -> None:
    """Braking before an edge of the position box at the start; time reversed, arriving at
    the end speed from inside the box."""
    name, lo, hi = STATES[axis], X_LB[axis], X_UB[axis]
    for when, state, sign in (("initial", p[P_X0], 1.0), ("final", p[P_XF], -1.0)):
        pos, v = float(state[axis]), float(state[axis + 2])
        out = overshoot(pos, sign * v, lo, hi, a, t_low)
        if out > 1e-9:
            edge = hi if sign * v > 0 else lo
            how = (f"moving at {v:g} m/s it needs {abs(pos - edge) + out:.3g} m to stop" if
                   sign > 0 else f"arriving at {v:g} m/s it needs {abs(pos - edge) + out:.3g} "
                   "m of run-up")
            raise Infeasible(
                f"the {when} {name} = {pos:g} m is {abs(pos - edge):.3g} m from the edge "
                f"{name} {'≤' if edge == hi else '≥'} {edge:g} m (the state box), but {how} "
                f"at A/m = {a:g} m/s²")


def _precheck_travel(p: np.ndarray, axis: int, a: float, t_low: float) -> None:
    """The distance from the initial to the final position along `axis`, within what
    |acceleration| <= A/m and the speed bounds allow in T_low <= T <= T_max."""
    name, speed = STATES[axis], STATES[axis + 2]
    v0, vf = float(p[P_X0][axis + 2]), float(p[P_XF][axis + 2])
    lo, hi = X_LB[axis + 2], X_UB[axis + 2]
    least, most = travel_range(v0, vf, lo, hi, a, (t_low, T_UB))
    distance = float(p[P_XF][axis] - p[P_X0][axis])
    if least <= distance + 1e-9 and distance <= most + 1e-9:
        return
    bound = f"{speed} ≥ {lo:g} m/s" if distance < least else f"{speed} ≤ {hi:g} m/s"
    raise Infeasible(
        f"changing {speed} from {v0:g} to {vf:g} m/s at A/m = {a:g} m/s² in a manoeuvre of "
        f"{t_low:.3g} s (the least the velocity change takes) to {T_UB:g} s (the bound on T), "
        f"with {bound} (the state bound), moves {name} by "
        + (f"at least {least:.3g} m, but only {distance:.3g} m remain between {name}0 and "
           f"{name}f" if distance < least else
           f"at most {most:.3g} m, but {distance:.3g} m separate {name}0 and {name}f"))


def _bounds(p: np.ndarray, vector: bool) -> Bounds:
    if vector:
        u_lb, u_ub = -np.ones(2), np.ones(2)
    else:
        u_lb, u_ub = np.array([p[P_AC] - np.pi]), np.array([p[P_AC] + np.pi])
    return Bounds(x_lb=np.array(X_LB), x_ub=np.array(X_UB), u_lb=u_lb, u_ub=u_ub,
                  T_lb=T_LB, T_ub=T_UB)


@cache
def stage_ocp(vector: bool) -> OCP:
    """The paper's problem with the angle control, or with the thrust vector |u| <= 1."""

    def guess(p: np.ndarray) -> Guess:
        a = p[P_AG]
        u = np.array([np.cos(a), np.sin(a)]) if vector else np.array([a])
        return Guess(x_final=np.asarray(p[P_XF]), u=u, T=float(p[P_TG]))

    extra = {}
    if vector:
        extra = dict(path=lambda x, u, p: ca.sumsqr(u), path_lb=np.array([-np.inf]),
                     path_ub=np.array([1.0]))
    return OCP(
        states=STATES,
        state_units=STATE_UNITS,
        controls=("ux", "uy") if vector else ("alpha",),
        control_units=("", "") if vector else ("rad",),
        n_params=N_PARAMS,
        dynamics=((lambda x, u, p: rhs_vector(x, u, p[P_A])) if vector
                  else (lambda x, u, p: rhs_angle(x, u[0], p[P_A]))),
        initial_state=lambda p: p[P_X0],
        terminal=lambda xf, p: xf - p[P_XF],
        terminal_names=("x", "y", "vx", "vy"),
        bounds=lambda p: _bounds(p, vector),
        guess=guess,
        x_scale=np.array([5.0, 5.0, 5.0, 5.0]),
        u_scale=np.ones(2) if vector else np.ones(1),
        T_scale=1.0,
        terminal_scale=np.ones(4),
        mayer=lambda xf, T, p: T,
        **extra,
    )


def end_miss(p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
    """Miss of the target position and velocity at the end of a re-propagation (SI)."""
    miss = np.asarray(x_final, float) - p[P_XF]
    return {
        "position_miss_m": float(np.hypot(miss[0], miss[1])),
        "velocity_miss_m_s": float(np.hypot(miss[2], miss[3])),
    }


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "alpha": Label("thrust angle", "rad"),
    "throttle": Label("throttle"),
    "position_miss_m": Label("final position miss", "m"),
    "velocity_miss_m_s": Label("final velocity miss", "m/s"),
}
