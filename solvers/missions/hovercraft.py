"""Mission `hovercraft`: minimum-time steering with a thrust of constant magnitude (paper 004,
example 1; SPEC M5 case 1).

Three direct methods solve the paper's problem (direct multiple shooting, the paper's own;
Hermite–Simpson collocation; LGL pseudospectral collocation), and the maximum principle
solves it semi-analytically (`solvers/indirect/hovercraft.py`) as an independent reference
shown beside every solution.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ..dynamics.hovercraft import (
    STATE_UNITS,
    STATES,
    T_LB,
    T_UB,
    X_LB,
    X_UB,
    rhs_angle,
    rhs_vector,
)
from ..indirect.hovercraft import guess_from_steering, solve_min_time
from ..mission import Infeasible, Mission, SolveContext
from ..ocp import OCP, Bounds, Guess, OCPResult, WarmStart
from ..problem import Method, Param, Preset, Published
from ..solution import Curve, Marker, PlotSeries, Quantity, Scene, Solution
from ..transcription import direct_transcription
from ..transcription.direct import DirectTranscription
from ..verify import repropagate

DEG = np.pi / 180
PAPER = "Wang, Cui & Hou 1988, Northwestern Polytechnical University (paper 004)"
# OCP parameter vector: A/m, initial state (4), final state (4), guess T, guess alpha, and
# the centre of the 2π window that bounds alpha (0: the paper's -π <= alpha <= π).
P_A, P_X0, P_XF, P_TG, P_AG, P_AC = 0, slice(1, 5), slice(5, 9), 9, 10, 11
N_PARAMS = 12
STEERING = ("angle α, started from the thrust vector", "angle α only (paper)",
            "thrust vector |u| ≤ 1")
ANGLE_VIA_VECTOR, ANGLE_ONLY, VECTOR = range(3)

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
          help="Paper: T0 = 2 (published 2.464) and T0 = 5 (published 2.529)."),
    Param("alpha_guess", "initial guess α (constant)", "rad", 0.0, -np.pi, np.pi, DEG,
          group="Initial guess", display_unit="deg", display_factor=1 / DEG,
          help="Paper: α = 0, states linear between the ends."),
    Param("steering", "control variable", "", 0, 0, 2, 1, group="Method", options=STEERING,
          help="The paper steers with α. From α ≡ 0 the angle form is degenerate "
               "(∂v̇x/∂α = -A/m sin α = 0), so by default a cold start first solves the "
               "thrust-vector form (|u| ≤ 1, exact for minimum time) and then polishes α "
               "(LGL keeps the thrust vector)."),
)

METHODS = (
    Method(
        "multiple-shooting", "Direct multiple shooting (paper 004)", PAPER,
        "τ ∈ [0, 1] with t = Tτ, T a parameter; the control linear between node values; RK4 "
        "on each interval; continuity of the node states; SQP as in the paper.",
        nodes=(2, 10, 120), nodes_label="intervals", backends=("sqp", "ipopt"),
    ),
    Method(
        "hermite-simpson", "Hermite–Simpson collocation", "direct collocation",
        "Cubic Hermite state, control linear between nodes, midpoint defects.",
        nodes=(2, 10, 300), nodes_label="intervals", backends=("ipopt", "sqp"),
    ),
    Method(
        "lgl", "LGL pseudospectral collocation", "paper 001's LGL nodes",
        "State and control are polynomials through N+1 Legendre–Gauss–Lobatto nodes; the "
        "dynamics are collocated with the differentiation matrix (spectral accuracy).",
        nodes=(4, 10, 60), nodes_label="LGL degree", backends=("ipopt", "sqp"),
    ),
)

PUBLISHED = (
    Published("T", 2.464, "s", "paper 004, example 1 (guess T0 = 2, 22 iterations)",
              "below the true minimum of the stated problem: not a feasible answer"),
    Published("T", 2.529, "s", "paper 004, example 1 (guess T0 = 5)",
              "above the true minimum: the paper's SQP stopped short"),
)

HELP = """\
**Minimum-time hovercraft** (paper 004, example 1). A hovercraft with constant thrust
acceleration A/m = 3 steers its thrust angle α to go from (x, y, vx, vy) = (0, 0, 5, 0) to
(5, 5, 0, 5) in the least time, inside the paper's box (0, 0, 0, -10) ≤ (x, y, vx, vy) ≤
(30, 30, 20, 10), |α| ≤ π, 0 ≤ T ≤ 15.

*The true minimum is T = 2.4954276 s.* The maximum principle gives it semi-analytically:
the position costate is constant, the velocity costate linear in t, so tan(α − φ) is linear
in time (linear tangent steering; here φ = 135° and α falls from 166.9° to 103.1°). Solving
those five shooting equations (quadrature to round-off, `solvers/indirect/hovercraft.py`)
gives T = 2.49542764 s; LGL collocation with 20 or more nodes gives the same to 1e-9, and
multiple shooting and Hermite–Simpson converge to it as 1/N⁴ (2.4954278 and 2.4954286 s at
10 intervals). All three reach it from both of the paper's guesses, T0 = 2 and T0 = 5.

*Bounds:* the paper's −π ≤ α ≤ π admits every direction. After the thrust-vector start
the same 2π window is centred on the solution's mean direction, so a turn through 180°
(preset "Turn back") stays continuous; "angle α only" keeps the paper's window. The paper
allows thrust F or zero; the thrust vector with |u| ≤ 1 allows throttling too, which only
matters where a state bound is active (preset "Long hop"): there the relaxation is no longer
exact and the thrust-vector solution is shown. At the paper's case no bound is active and
the maximum principle gives the optimum; when its extremal leaves the box it is not shown.

*The paper's numbers:* 2.464 (from T0 = 2) lies 1.26 % *below* the true minimum, so it
cannot satisfy the stated boundary conditions (with exact integration every feasible
control takes at least T*); 2.529 (from T0 = 5) lies 1.35 % above it: the paper's SQP
presumably stopped before the optimum.

*Why a two-stage start:* the paper's guess α ≡ 0 makes the angle form degenerate
(∂v̇x/∂α = −(A/m) sin α = 0 at every node, so the x-equations cannot be steered and the
constraint Jacobian is singular): IPOPT and SQP both fail from it (choose "angle α only" to
see this). IPOPT solves the angle form from other constant guesses such as α = 120°;
CasADi's SQP (BFGS Hessian, qrqp) cannot start it from the paper's linear state guess at
all: its first QP step is zero. The thrust-vector form u = (ux, uy), |u| ≤ 1, has no
degenerate point and the same minimum (the maximum principle makes |u| = 1). By default a
cold start solves it first and then re-solves the paper's angle form from there; warm
re-solves go straight to the angle form. Between nodes a linear thrust *vector* is shorter
than 1, which costs 0.18 % of T at 10 intervals: that is why multiple shooting and
Hermite–Simpson polish the angle form. LGL keeps the thrust vector: it collocates only at its
nodes, where |u| = 1 holds, and its angle form has spurious optima (a node jumping to ±π).
"""


def _dynamics_angle(x, u, p):
    return rhs_angle(x, u[0], p[P_A])


def _dynamics_vector(x, u, p):
    return rhs_vector(x, u, p[P_A])


def _bounds(p: np.ndarray, vector: bool) -> Bounds:
    if vector:
        u_lb, u_ub = -np.ones(2), np.ones(2)
    else:
        u_lb, u_ub = np.array([p[P_AC] - np.pi]), np.array([p[P_AC] + np.pi])
    return Bounds(x_lb=np.array(X_LB), x_ub=np.array(X_UB), u_lb=u_lb, u_ub=u_ub,
                  T_lb=T_LB, T_ub=T_UB)


@cache
def _ocp(vector: bool) -> OCP:
    """The paper's problem with the angle control, or with the thrust vector |u| <= 1."""

    def guess(p):
        a = p[P_AG]
        u = np.array([np.cos(a), np.sin(a)]) if vector else np.array([a])
        return Guess(x_final=np.asarray(p[P_XF]), u=u, T=float(p[P_TG]))

    extra = {}
    if vector:
        extra = dict(path=lambda x, u, p: ca.sumsqr(u), path_lb=np.array([-np.inf]),
                     path_ub=np.array([1.0]))
    return OCP(
        states=STATES,
        controls=("ux", "uy") if vector else ("alpha",),
        n_params=N_PARAMS,
        dynamics=_dynamics_vector if vector else _dynamics_angle,
        initial_state=lambda p: p[P_X0],
        terminal=lambda xf, p: xf - p[P_XF],
        bounds=lambda p: _bounds(p, vector),
        guess=guess,
        x_scale=np.array([5.0, 5.0, 5.0, 5.0]),
        u_scale=np.ones(2) if vector else np.ones(1),
        T_scale=1.0,
        terminal_scale=np.ones(4),
        mayer=lambda xf, T, p: T,
        **extra,
    )


def _transcription(kind: str, n: int, backend: str, vector: bool) -> DirectTranscription:
    return direct_transcription(kind, _ocp(vector), n, backend)


def _converted(warm: WarmStart, U: np.ndarray) -> WarmStart:
    """A start in the other control form: primal nodes only, re-interpolated by the
    transcription (its own kind never matches "converted", so no stale duals are used)."""
    empty = np.zeros(0)
    return WarmStart("converted", warm.n_intervals, warm.tau, warm.X, U, warm.T, empty, empty,
                     empty)


def _as_angle(warm: WarmStart) -> WarmStart:
    return _converted(warm, np.unwrap(np.arctan2(warm.U[:, 1], warm.U[:, 0]))[:, None])


def _as_vector(warm: WarmStart) -> WarmStart:
    return _converted(warm, np.column_stack([np.cos(warm.U[:, 0]), np.sin(warm.U[:, 0])]))


class Hovercraft(Mission):
    key = "hovercraft"
    title = "Hovercraft minimum time"
    summary = "Steer a constant thrust to reach a point and velocity in the least time."
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "final time"
    cost_unit = "s"
    equations = (
        ("Hovercraft dynamics (paper 004, example 1)",
         r"\dot x = v_x,\quad \dot y = v_y,\quad \dot v_x = \frac{A}{m}\cos\alpha,\quad "
         r"\dot v_y = \frac{A}{m}\sin\alpha,\qquad \min T"),
        ("Minimum-time steering law (maximum principle): linear tangent",
         r"\tan\alpha(t) = \frac{c_3 - c_4 t}{c_1 - c_2 t}"),
    )
    presets = (
        Preset("Paper 004 case (T0 = 2)", {}, note="Published 2.464; true minimum 2.4954276."),
        Preset("Paper 004 case, guess T0 = 5", {"T_guess": 5.0},
               note="Published 2.529; the same true minimum is reached."),
        Preset("Paper's angle form from α ≡ 0 (degenerate start)", {"steering": ANGLE_ONLY},
               note="Fails: the angle form cannot move away from α ≡ 0."),
        Preset("Angle form from α = 120° (IPOPT)",
               {"steering": ANGLE_ONLY, "alpha_guess": 120 * DEG}, method="hermite-simpson",
               note="A non-degenerate guess: the paper's formulation converges with IPOPT."),
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

    @staticmethod
    def parameter_vector(values: dict[str, float]) -> np.ndarray:
        return np.array([
            values["accel"], values["x0"], values["y0"], values["vx0"], values["vy0"],
            values["xf"], values["yf"], values["vxf"], values["vyf"], values["T_guess"],
            values["alpha_guess"], 0.0,
        ])

    def _solve(
        self, values: dict[str, float], method: Method, nodes: int, backend: str,
        warm: Solution | None, ctx: SolveContext,
    ) -> Solution:
        p = self.parameter_vector(values)
        dv = float(np.linalg.norm(p[P_XF][2:] - p[P_X0][2:]))
        if dv / p[P_A] > T_UB:
            raise Infeasible(
                f"the velocity change of {dv:.3g} m/s needs at least {dv / p[P_A]:.3g} s of "
                f"thrust at A/m = {p[P_A]:g} m/s², beyond the paper's bound T ≤ {T_UB:g} s"
            )
        mode = int(values["steering"])
        if mode == ANGLE_VIA_VECTOR and method.key == "lgl":
            # LGL collocates only at its nodes, where |u| = 1 holds exactly: there is no
            # chord loss to polish away, and the angle form's end-node controls admit
            # spurious KKT points (one node jumps to ±π at N = 40).
            mode = VECTOR
        prev = warm.warm if warm is not None and warm.ok and warm.warm is not None else None
        stages: list[OCPResult] = []
        if mode == VECTOR:
            start = _as_vector(prev) if prev is not None and prev.U.shape[1] == 1 else prev
            stages.append(_transcription(method.key, nodes, backend, True).solve(p, start, ctx))
        else:
            start = _as_angle(prev) if prev is not None and prev.U.shape[1] == 2 else prev
            if mode == ANGLE_VIA_VECTOR and start is None:
                first = _transcription(method.key, nodes, backend, True).solve(p, None, ctx)
                stages.append(first)
                start = _as_angle(first.warm) if first.status == "optimal" else None
            if mode == ANGLE_ONLY or start is not None:
                p_angle = p.copy()
                if mode == ANGLE_VIA_VECTOR:
                    # The same 2π of directions as the paper's -π <= α <= π, centred on the
                    # start so that a turn through 180° stays continuous.
                    p_angle[P_AC] = float(np.mean(start.U[:, 0]))
                stages.append(_transcription(method.key, nodes, backend, False).solve(
                    p_angle, start, ctx))
        res = stages[-1]
        if res.status != "optimal" and len(stages) == 2 and stages[0].status == "optimal":
            res = stages[0]
            throttle = float(np.min(np.hypot(res.U[:, 0], res.U[:, 1])))
            res.message += (" (the angle form, always at full thrust, did not converge from "
                            "the thrust-vector solution, whose thrust falls to "
                            f"|u| = {throttle:.2f}: showing the thrust-vector solution)")
        return self._record(values, method.key, nodes, backend, p, stages, res)

    def _record(
        self, values: dict[str, float], method: str, nodes: int, backend: str, p: np.ndarray,
        stages: list[OCPResult], res: OCPResult,
    ) -> Solution:
        vector = res.U.shape[1] == 2
        alpha_nodes = _angles(res.U)
        alpha_dense = _angles(res.U_dense)
        throttle = np.hypot(res.U[:, 0], res.U[:, 1]) if vector else np.ones(len(res.U))
        form = "thrust vector" if vector else "angle α"
        message = res.message + f" [{form}" + (", after a thrust-vector start]"
                                               if len(stages) == 2 and not vector else "]")
        quantities = {"T": Quantity(res.T, "final time", "s")}
        sol = Solution(
            mission=self.key, method=method, nodes=nodes, backend=backend, status=res.status,
            message=message, cost=Quantity(res.T, "final time", "s"), values=values,
            quantities=quantities, state_names=STATES, state_units=STATE_UNITS,
            control_names=("alpha",), control_units=("rad",), node_t=res.t_nodes, node_x=res.X,
            node_u=alpha_nodes[:, None], arcs=[(0.0, res.T, "burn")], t=res.t_dense,
            x=res.X_dense, u=alpha_dense[:, None],
        )
        sol.positions = _plane(res.X_dense)
        sol.node_positions = _plane(res.X)
        sol.thrust = np.column_stack([throttle * np.cos(alpha_nodes),
                                      throttle * np.sin(alpha_nodes), np.zeros(len(res.U))])
        offset = 0
        for stage in stages:
            sol.history += [{"iteration": offset + k, "positions": _plane(Xk)}
                            for k, _, Xk in stage.history]
            offset += stage.iterations + 1
        sol.stats.update(
            iterations=sum(s.iterations for s in stages),
            nlp_variables=res.n_variables,
            nlp_constraints=res.n_constraints,
            constraint_violation=res.max_violation,
            stages=len(stages),
        )
        sol.warm = res.warm
        curves = []
        pontryagin = None
        if res.status == "optimal":
            pontryagin = solve_min_time(
                p[P_X0], p[P_XF], p[P_A],
                guess_from_steering(res.t_nodes, alpha_nodes, p[P_X0], p[P_A]))
        if pontryagin is not None and pontryagin.converged:
            t_ref = np.linspace(0.0, pontryagin.T, 201)
            X_ref = pontryagin.states(t_ref, p[P_X0], p[P_A])
            if np.any(X_ref < np.array(X_LB) - 1e-9) or np.any(X_ref > np.array(X_UB) + 1e-9):
                # A state bound is active at the optimum: the unconstrained extremal is no
                # reference for the bounded problem.
                sol.message += (" (the unconstrained maximum-principle extremal leaves the "
                                "state box here, so it is not shown as a reference)")
                pontryagin = None
        if pontryagin is not None and pontryagin.converged:
            quantities["T_pontryagin"] = Quantity(pontryagin.T, "T (maximum principle)", "s")
            quantities["T_error"] = Quantity(res.T - pontryagin.T, "T − T(maximum principle)",
                                             "s")
            curves.append(Curve("maximum-principle optimum", _plane(X_ref), (255, 120, 200),
                                dashed=True))
        sol.scene = _scene(p, sol.positions, curves)
        sol.plots = _plots(res, alpha_dense, alpha_nodes, pontryagin)
        sol.check["max_defect"] = res.max_violation
        if res.status == "optimal":
            control = res.control
            sol.checker = lambda: _check(p, res, control, vector)
        return sol


def _angles(U: np.ndarray) -> np.ndarray:
    """Thrust angles from either control form, continuous along the trajectory."""
    if U.shape[1] == 2:
        return np.unwrap(np.arctan2(U[:, 1], U[:, 0]))
    return U[:, 0].copy()


def _check(p: np.ndarray, res: OCPResult, control, vector: bool) -> dict[str, float]:
    """Re-propagate the control with DOP853 and report the terminal miss."""
    fn = _ocp(vector).functions()
    _, X = repropagate(fn.f, p, p[P_X0], control, res.t_nodes, atol=1e-12)
    miss = X[-1] - p[P_XF]
    return {
        "position_miss_m": float(np.hypot(miss[0], miss[1])),
        "velocity_miss_m_s": float(np.hypot(miss[2], miss[3])),
    }


def _plane(X: np.ndarray) -> np.ndarray:
    """(x, y) to the display frame: the z = 0 plane, metres."""
    X = np.atleast_2d(X)
    return np.column_stack([X[:, 0], X[:, 1], np.zeros(len(X))])


def _scene(p: np.ndarray, positions: np.ndarray, curves: list[Curve]) -> Scene:
    """A 1 m grid around the manoeuvre and the paper's bounds x >= 0, y >= 0."""
    pts = np.vstack([positions[:, :2], p[P_X0][None, :2], p[P_XF][None, :2]])
    lo = np.floor(pts.min(axis=0)) - 1
    hi = np.ceil(pts.max(axis=0)) + 1
    return Scene(
        frame="ground plane (x east, y north)",
        display_unit="m",
        display_scale=1.0,
        curves=[Curve("1 m grid", _grid(lo, hi), (90, 90, 100)),
                Curve("bounds x ≥ 0, y ≥ 0",
                      np.array([[hi[0], 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, hi[1], 0.0]]),
                      (200, 120, 80)),
                *curves],
        markers=[Marker("start", (p[1], p[2], 0.0), (255, 200, 80)),
                 Marker("target", (p[5], p[6], 0.0), (120, 255, 120))],
    )


def _grid(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """A 1 m grid as one serpentine polyline (its joins run along the border)."""
    pts = []
    for i, gx in enumerate(np.arange(lo[0], hi[0] + 0.5)):
        ys = (lo[1], hi[1]) if i % 2 == 0 else (hi[1], lo[1])
        pts += [(gx, ys[0]), (gx, ys[1])]
    corner = pts[-1]
    ys = np.arange(lo[1], hi[1] + 0.5)
    for i, gy in enumerate(ys if corner[1] == lo[1] else ys[::-1]):
        xs = (corner[0], lo[0]) if i % 2 == 0 else (lo[0], corner[0])
        pts += [(xs[0], gy), (xs[1], gy)]
    pts = np.array(pts, float)
    return np.column_stack([pts, np.zeros(len(pts))])


def _plots(res: OCPResult, alpha_dense, alpha_nodes, pontryagin) -> list[PlotSeries]:
    t, X, tn, Xn = res.t_dense, res.X_dense, res.t_nodes, res.X
    plots = [
        PlotSeries("x", "m", t, X[:, 0], tn, Xn[:, 0]),
        PlotSeries("y", "m", t, X[:, 1], tn, Xn[:, 1]),
        PlotSeries("vx", "m/s", t, X[:, 2], tn, Xn[:, 2]),
        PlotSeries("vy", "m/s", t, X[:, 3], tn, Xn[:, 3]),
        PlotSeries("thrust angle α", "deg", t, alpha_dense / DEG, tn, alpha_nodes / DEG,
                   group="control"),
    ]
    if pontryagin is not None and pontryagin.converged:
        tp = np.linspace(0.0, pontryagin.T, 201)
        plots.append(PlotSeries("α, maximum principle", "deg", tp,
                                np.unwrap(pontryagin.alpha(tp)) / DEG, group="control"))
    return plots


MISSION = Hovercraft()
