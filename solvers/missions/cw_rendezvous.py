"""Mission `cw-rendezvous`: finite-thrust, minimum-burn-time rendezvous in a circular orbit
(paper 000, SPEC M1), Clohessy–Wiltshire relative motion, fixed total time.

Methods: the paper's burn/coast arc transcription (HS collocation on burns, the CW state
transition matrix on coasts; IPOPT or the paper's exterior penalty method), a free-structure
Hermite–Simpson transcription with an L1 cost whose bang–bang structure emerges by itself,
and direct multiple shooting on the same free-structure problem.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ..dynamics.clohessy_wiltshire import (
    MU_EARTH,
    R_EARTH,
    STATE_UNITS,
    STATES,
    cw_rhs,
    cw_stm,
    cw_stm_numeric,
    frame_axes,
    mean_motion,
    nonlinear_relative_miss,
)
from ..mission import Mission, SolveContext
from ..nlp.casadi_nlp import built_once
from ..ocp import OCP, Bounds, Guess
from ..problem import Method, Param, Preset, Published
from ..solution import Body, Curve, Marker, PlotSeries, Quantity, Scene, Solution
from ..transcription import direct_transcription
from ..transcription.burn_coast import ArcModel, BurnCoast, BurnCoastResult
from ..verify import repropagate

PAPER = "Finite-thrust rendezvous by direct collocation (paper 000)"
PLANAR = (0, 1, 3, 4)  # x, y, vx, vy
THROTTLE_ON = 0.5  # fraction of a above which a free-structure node counts as burning

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
    Param("view", "view", "", 0, 0, 1, 1, group="Display",
          options=("target orbital frame", "inertial (magnified)")),
    Param("magnify", "relative-motion magnification", "", 50.0, 1.0, 2000.0, 1.0,
          group="Display", help="Inertial view: relative motion drawn this many times larger."),
)

BURNS = Param("burns", "number of burns", "", 2, 1, 3, 1, group="Method", integer=True,
              help="Arc structure: burn (coast burn)*; a single burn is followed by a coast.")

METHODS = (
    Method(
        "paper", "Burn/coast arcs: HS collocation + CW STM coasts", PAPER,
        "Burn arcs collocated by Hermite–Simpson on equal sub-intervals, coast arcs closed by "
        "the CW state transition matrix, arc durations as variables, |u| = 1 at nodes, "
        "cost = total burn time (paper eqs. 4–11).",
        nodes=(4, 12, 40), nodes_label="sub-intervals per burn", params=(BURNS,),
        backends=("ipopt", "penalty-bfgs"),
    ),
    Method(
        "free-structure", "Free structure: HS with L1 cost", "direct collocation",
        "Hermite–Simpson over the whole transfer with |a u| <= s <= a and cost ∫ s/a dt: the "
        "burn/coast structure is not imposed but emerges (bang–bang).",
        nodes=(10, 60, 400), nodes_label="intervals", backends=("ipopt", "sqp"),
    ),
    Method(
        "multiple-shooting", "Direct multiple shooting (free structure)", "paper 004",
        "The free-structure problem by direct multiple shooting (RK4 per interval).",
        nodes=(10, 60, 400), nodes_label="intervals", backends=("ipopt", "sqp"),
    ),
)

PUBLISHED = (
    Published("nlp_variables", 159, "", "paper 000: 26 nodes, 159 variables (coplanar case)"),
    Published("nlp_equalities", 135, "", "paper 000: 135 equality constraints"),
    Published("nlp_inequalities", 3, "", "paper 000: 3 inequality constraints"),
)

HELP = """\
**Finite-thrust rendezvous** (paper 000). The chaser starts 15 km behind and 500 m below the
target, closing at 100 m/s, and must reach the target at rest after 600 s with as little
burn time (fuel) as possible. Relative motion follows the Clohessy–Wiltshire equations in the
target's orbital frame (x against the orbital velocity, y up, z along the orbit normal).

The paper gives neither the orbit nor the acceleration; defaults: 400 km circular orbit and
a = 0.5 m/s². It publishes the problem size (26 nodes, 159 variables, 135 equalities, 3
inequalities) and the shape of the solution (x and x' fall overall, y and y' oscillate about
zero, more near the end), both reproduced here; the optimum burn–coast–burn emerges by itself
in the free-structure method. With a large a the optimum arrives early and waits: the paper's
fixed burn–coast–burn structure then costs slightly more than the free structure.
"""


def _circular_ocp_params(values: dict[str, float]) -> np.ndarray:
    x0 = np.array([values[k] for k in ("x0", "y0", "z0", "vx0", "vy0", "vz0")])
    w = mean_motion(values["altitude"])
    return np.concatenate([x0, [w, values["accel"], values["total_time"]]])


@cache
def _free_ocp() -> OCP:
    """Free-structure problem: control (a_x, a_y, a_z, s), |a| <= s <= a, cost ∫ s/a dt."""

    def bounds(p):
        a = p[7]
        return Bounds(
            x_lb=np.full(6, -1e7), x_ub=np.full(6, 1e7),
            u_lb=np.array([-a, -a, -a, 0.0]), u_ub=np.array([a, a, a, a]), T_lb=0.0, T_ub=0.0,
        )

    def guess(p):
        return Guess(np.zeros(6), np.array([0.0, 0.0, 0.0, 0.5 * p[7]]), float(p[8]))

    return OCP(
        states=STATES, controls=("ax", "ay", "az", "s"), n_params=9,
        dynamics=lambda x, u, p: cw_rhs(x, u[:3], p[6]),
        initial_state=lambda p: p[:6],
        terminal=lambda xf, p: xf,
        bounds=bounds, guess=guess,
        x_scale=np.array([1e4, 1e4, 1e4, 100.0, 100.0, 100.0]),
        u_scale=np.ones(4), T_scale=100.0,
        terminal_scale=np.array([1.0, 1.0, 1.0, 1e-2, 1e-2, 1e-2]),
        cost_scale=100.0,
        lagrange=lambda x, u, p: u[3] / p[7],
        fixed_final_time=lambda p: p[8],
        path=lambda x, u, p: ca.sumsqr(u[:3]) - u[3] ** 2,
        path_lb=np.array([-np.inf]), path_ub=np.array([0.0]),
    )


@cache
def _arc_model(planar: bool) -> ArcModel:
    idx = list(PLANAR) if planar else list(range(6))
    nx = len(idx)
    nu = 2 if planar else 3

    def rhs(x, acc, p):
        full = ca.SX.zeros(6)
        for i, j in enumerate(idx):
            full[j] = x[i]
        acc3 = ca.vertcat(acc, 0) if planar else acc
        return cw_rhs(full, acc3, p[nx])[idx]

    return ArcModel(
        nx=nx, nu=nu, n_params=nx + 3, rhs=rhs,
        stm=lambda p, dt: cw_stm(p[nx], dt)[idx, idx],
        initial_state=lambda p: p[:nx],
        acceleration=lambda p: p[nx + 1],
        total_time=lambda p: p[nx + 2],
        x_scale=np.array([1e4, 1e4, 100.0, 100.0] if planar else [1e4] * 3 + [100.0] * 3),
        t_scale=100.0,
    )


@built_once
def _burn_coast(planar: bool, burns: int, k: int, backend: str) -> BurnCoast:
    return BurnCoast(_arc_model(planar), burns, k, backend)


class CWRendezvous(Mission):
    key = "cw-rendezvous"
    title = "Finite-thrust rendezvous (CW)"
    summary = "Minimum burn time rendezvous with a target in a circular orbit, fixed time."
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "burn time"
    cost_unit = "s"
    equations = (
        ("Clohessy–Wiltshire equations in the target orbital frame (paper 000, eq. 1)",
         r"\ddot x - 2\omega\dot y = a u_x,\quad \ddot y + 2\omega\dot x - 3\omega^2 y = "
         r"a u_y,\quad \ddot z + \omega^2 z = a u_z,\quad \lVert u\rVert \le 1"),
        ("Cost: total burn time for a fixed transfer time",
         r"J = \sum_{\text{burns}} T_b,\qquad \sum_{\text{arcs}} T_i = T"),
    )
    presets = (
        Preset("Paper 000 case", {}, note="Coplanar, 15 km behind, 600 s, a = 0.5 m/s²."),
        Preset("Strong engine: arrive early and wait", {"accel": 2.0}, method="free-structure"),
        Preset("Weak engine: no solution in 600 s", {"accel": 0.1}),
        Preset("Out-of-plane start", {"z0": 2000.0, "vz0": -5.0}),
        Preset("Exterior penalty method (paper eq. 12)", {}, method="paper"),
        Preset("Coarse mesh (4 sub-intervals)", {}, method="paper", nodes=4),
        Preset("Inertial view", {"view": 1}),
    )

    def _solve(
        self,
        values: dict[str, float],
        method: Method,
        nodes: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        p = _circular_ocp_params(values)
        if method.key == "paper":
            return self._solve_arcs(values, p, nodes, backend, warm, ctx)
        kind = "hermite-simpson" if method.key == "free-structure" else method.key
        transcription = direct_transcription(kind, _free_ocp(), nodes, backend)
        warm_start = warm.warm if warm is not None and warm.ok else None
        res = transcription.solve(p, warm_start, ctx)
        acc = res.U[:, :3]
        burning = res.U[:, 3] > THROTTLE_ON * values["accel"]
        arcs = _arcs_from_throttle(res.t_nodes, burning)
        message = _explain(res.status, res.message, values, "free-structure")
        sol = self._record(values, method.key, nodes, backend, p, res.status, message,
                           res.t_nodes, res.X, acc, res.t_dense, res.X_dense, res.U_dense[:, :3],
                           arcs, res.cost)
        res.record_nlp(sol)
        sol.history = [{"iteration": k, "positions": self._positions(values, p, t, X)}
                       for k, t, X in res.history]
        sol.checker = lambda: self._check(p, res.t_nodes, lambda t, x: res.control(t, x)[:3])
        return sol

    def _solve_arcs(
        self,
        values: dict[str, float],
        p: np.ndarray,
        k: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        planar = values["z0"] == 0 and values["vz0"] == 0
        burns = int(values["burns"])
        bc = _burn_coast(planar, burns, k, backend)
        idx = list(PLANAR) if planar else list(range(6))
        p_arc = np.concatenate([p[:6][idx], p[6:]])
        key = (planar, burns, k, backend)
        lam = None
        if warm is not None and warm.ok and isinstance(warm.warm, tuple) and warm.warm[0] == key:
            z0, lam = warm.warm[1], warm.warm[2]
        elif warm is not None and warm.ok and _same_structure(warm, bc):
            z0 = _resample_arcs(bc, warm, idx)
        else:
            z0 = _impulsive_guess(bc, p, idx)
        res = bc.solve(p_arc, z0, lam, ctx)
        t_nodes, X, U = _stack_burns(res, idx)
        acc = values["accel"] * U
        t_dense, X_dense, U_dense = _dense_arcs(
            res.kinds, res.durations, res.burn_x, res.burn_u, p, idx, values["accel"])
        arcs = _arcs_from_durations(res)
        message = _explain(res.status, res.message, values, "–".join(res.kinds))
        sol = self._record(values, "paper", k, backend, p, res.status, message, t_nodes, X,
                           acc, t_dense, X_dense, U_dense, arcs, res.cost)
        sol.stats.update(iterations=res.iterations, nlp_variables=res.n_variables,
                         nlp_constraints=res.n_equalities + res.n_inequalities,
                         nlp_equalities=res.n_equalities, nlp_inequalities=res.n_inequalities,
                         constraint_violation=res.max_violation)
        sol.history = []
        for it, z in res.history:
            ts, Xs, _ = _dense_arcs(res.kinds, *bc.unpack(z), p, idx, values["accel"], samples=3)
            sol.history.append({"iteration": it, "positions": self._positions(values, p, ts, Xs)})
        sol.warm = (key, res.z, (res.lam_x, res.lam_g))
        sol.check["max_defect"] = res.max_violation
        breaks = np.unique(np.concatenate([t_nodes, np.cumsum(res.durations)]))
        sol.checker = lambda: self._check(
            p, np.concatenate([[0.0], breaks[breaks > 0]]),
            lambda t, x: np.array([np.interp(t, t_dense, U_dense[:, j]) for j in range(3)]),
        )
        return sol

    # ---- shared record ----------------------------------------------------------------
    def _record(self, values, method, nodes, backend, p, status, message, t_nodes, X, acc,
                t_dense, X_dense, U_dense, arcs, cost) -> Solution:
        burn = sum(b - a for a, b, kind in arcs if kind == "burn")
        quantities = {
            "burn_time": Quantity(float(cost), "burn time", "s"),
            "delta_v": Quantity(float(cost * values["accel"]), "Δv", "m/s"),
            "burns": Quantity(float(sum(kind == "burn" for *_, kind in arcs)), "burns", ""),
            "arc_burn_time": Quantity(float(burn), "burn time from arcs", "s"),
        }
        sol = Solution(
            mission=self.key, method=method, nodes=nodes, backend=backend, status=status,
            message=message, cost=Quantity(float(cost), "burn time", "s"), values=values,
            quantities=quantities, state_names=STATES, state_units=STATE_UNITS,
            control_names=("ax", "ay", "az"), control_units=("m/s²",) * 3,
            node_t=t_nodes, node_x=X, node_u=acc, arcs=arcs, t=t_dense, x=X_dense, u=U_dense,
        )
        w = p[6]
        sol.positions = self._positions(values, p, t_dense, X_dense)
        sol.node_positions = self._positions(values, p, t_nodes, X)
        direction = acc / values["accel"]
        if values["view"] == 1:
            ex, ey, ez = frame_axes(w * t_nodes)
            direction = direction[:, :1] * ex + direction[:, 1:2] * ey + direction[:, 2:3] * ez
        sol.thrust = direction
        sol.scene = self._scene(values, p)
        sol.plots = _plots(t_dense, X_dense, U_dense, t_nodes, X, acc, values["accel"])
        return sol

    def _positions(self, values, p, t, X) -> np.ndarray:
        """Display-frame positions: relative (target frame) or inertial with magnified
        relative motion."""
        rel = X[:, :3]
        if values["view"] == 0:
            return rel.copy()
        w, radius = p[6], R_EARTH + values["altitude"]
        ex, ey, ez = frame_axes(w * t)
        target = radius * ey
        return target + values["magnify"] * (rel[:, :1] * ex + rel[:, 1:2] * ey + rel[:, 2:3] * ez)

    def _scene(self, values, p) -> Scene:
        if values["view"] == 0:
            extent = max(abs(values["x0"]), abs(values["y0"]), 1000.0)
            return Scene(
                frame="target orbital frame (x against velocity, y up, z orbit normal)",
                display_unit="km", display_scale=1e-3, up="+y",
                bodies=[Body("target (enlarged)", (0.0, 0.0, 0.0), 0.01 * extent, (230, 230, 240))],
                curves=[Curve("approach axis (x)", np.array([[0, 0, 0], [1.2 * extent, 0, 0]]),
                              (110, 110, 130), dashed=True)],
                markers=[Marker("target", (0.0, 0.0, 0.0)),
                         Marker("chaser start", (values["x0"], values["y0"], values["z0"]),
                                (255, 200, 80))],
            )
        radius = R_EARTH + values["altitude"]
        angle = np.linspace(0, 2 * np.pi, 361)
        orbit = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), 0 * angle])
        return Scene(
            frame=f"inertial, relative motion × {values['magnify']:g}",
            display_unit="km", display_scale=1e-3, up="+z",
            bodies=[Body("Earth", (0.0, 0.0, 0.0), R_EARTH, (60, 110, 200))],
            curves=[Curve("target orbit", orbit, (200, 200, 200))],
            markers=[Marker("target at start", (radius, 0.0, 0.0))],
        )

    def _check(self, p, breaks, control) -> dict[str, float]:
        f = _free_ocp().functions().f
        _, X = repropagate(
            f, p, p[:6], lambda t, x: np.concatenate([control(t, x), [0.0]]), breaks,
            atol=np.array([1e-7] * 3 + [1e-10] * 3),
        )
        miss = X[-1]
        out = {
            "position_m": float(np.linalg.norm(miss[:3])),
            "velocity_m_s": float(np.linalg.norm(miss[3:])),
        }
        radius = float(np.cbrt(MU_EARTH / p[6] ** 2))
        nl = nonlinear_relative_miss(p[:6], p[6], radius, control, breaks)
        out["nonlinear_position_m"] = float(np.linalg.norm(nl[:3]))
        out["nonlinear_velocity_m_s"] = float(np.linalg.norm(nl[3:]))
        return out


# ---- helpers ------------------------------------------------------------------------------
def _explain(status: str, message: str, values: dict[str, float], structure: str) -> str:
    """Say in words why an infeasible request has no solution."""
    if status != "infeasible":
        return message
    return (
        f"no {structure} trajectory reaches the target in {values['total_time']:g} s with "
        f"a = {values['accel']:g} m/s²: increase the thrust acceleration or the total time "
        f"({message})"
    )


def _arcs_from_throttle(t: np.ndarray, burning: np.ndarray) -> list[tuple[float, float, str]]:
    """Arcs from node throttle: a switch is placed midway between differing nodes."""
    arcs, start = [], 0.0
    for k in range(1, len(t)):
        if burning[k] != burning[k - 1]:
            mid = 0.5 * (t[k - 1] + t[k])
            arcs.append((start, mid, "burn" if burning[k - 1] else "coast"))
            start = mid
    arcs.append((start, float(t[-1]), "burn" if burning[-1] else "coast"))
    return arcs


def _arcs_from_durations(res: BurnCoastResult) -> list[tuple[float, float, str]]:
    starts = np.concatenate([[0.0], np.cumsum(res.durations)])
    return [(float(starts[i]), float(starts[i + 1]), kind) for i, kind in enumerate(res.kinds)]


def _embed(X: np.ndarray, idx: list[int]) -> np.ndarray:
    full = np.zeros((X.shape[0], 6))
    full[:, idx] = X
    return full


def _stack_burns(res: BurnCoastResult, idx: list[int]):
    t = np.concatenate(res.burn_t)
    X = _embed(np.vstack(res.burn_x), idx)
    U = np.vstack(res.burn_u)
    if U.shape[1] == 2:
        U = np.column_stack([U, np.zeros(len(U))])
    return t, X, U


def _impulsive_guess(bc: BurnCoast, p: np.ndarray, idx: list[int]) -> np.ndarray:
    """Cold start from the two-impulse CW transfer in the same time (closed form from the
    STM): the first burn along the departure impulse, the last along the arrival impulse,
    each lasting |dv|/a, node states on the impulsive trajectory."""
    w, a, T = p[6], p[7], p[8]
    x0 = p[:6]
    phi = cw_stm_numeric(w, T)
    v_dep = np.linalg.lstsq(phi[:3, 3:], -phi[:3, :3] @ x0[:3], rcond=None)[0]
    dv1 = v_dep - x0[3:]
    dv2 = -(phi[3:, :3] @ x0[:3] + phi[3:, 3:] @ v_dep)
    n_burns = sum(kind == "burn" for kind in bc.kinds)
    impulses = [dv1] + [0.01 * a * T * _unit(dv2)] * (n_burns - 2) + [dv2][: n_burns - 1]
    burn_time = [min(np.linalg.norm(dv) / a, T / (2 * n_burns)) for dv in impulses]
    coasts = [kind for kind in bc.kinds if kind == "coast"]
    coast_time = (T - sum(burn_time)) / len(coasts)
    durations, xs, us, b, t0 = [], [], [], 0, 0.0
    after = np.concatenate([x0[:3], v_dep])
    for kind in bc.kinds:
        if kind == "burn":
            d = burn_time[b]
            t = t0 + np.linspace(0.0, d, bc.K + 1)
            xs.append(np.array([cw_stm_numeric(w, tk) @ after for tk in t])[:, idx])
            us.append(np.tile(_unit(impulses[b])[idx[:2] if len(idx) == 4 else [0, 1, 2]],
                              (bc.K + 1, 1)))
            b += 1
        else:
            d = coast_time
        durations.append(d)
        t0 += d
    return bc.pack(np.array(durations), xs, us)


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    return v / n if n > 1e-12 else np.array([-1.0, 0.0, 0.0])


def _dense_arcs(kinds, durations, burn_x, burn_u, p, idx, accel, samples: int = 10):
    """Dense (t, X, acceleration): Hermite cubic on burns, the exact STM on coasts."""
    w = p[6]
    starts = np.concatenate([[0.0], np.cumsum(durations)])
    ts, xs, us = [], [], []
    b = 0
    x_end = None
    f = _free_ocp().functions().f
    for i, kind in enumerate(kinds):
        t0, t1 = starts[i], starts[i + 1]
        if kind == "burn":
            X = _embed(burn_x[b], idx)
            U = burn_u[b]
            U = np.column_stack([U, np.zeros(len(U))]) if U.shape[1] == 2 else U
            K = len(X) - 1
            h = (t1 - t0) / K
            pp = np.tile(p[:, None], (1, K + 1))
            acc = accel * U
            F = np.asarray(f.map(K + 1)(X.T, np.column_stack([acc, np.zeros(K + 1)]).T, pp)).T
            s = np.linspace(0, 1, samples + 1)[:-1]
            for k in range(K):
                h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
                h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
                xs.append(np.outer(h00, X[k]) + np.outer(h10 * h, F[k]) + np.outer(h01, X[k + 1])
                          + np.outer(h11 * h, F[k + 1]))
                us.append(np.outer(1 - s, acc[k]) + np.outer(s, acc[k + 1]))
                ts.append(t0 + (k + s) * h)
            ts.append([t1])
            xs.append(X[-1:])
            us.append(acc[-1:])
            x_end = X[-1]
            b += 1
        else:
            s = np.linspace(0, 1, 4 * samples + 1)  # with both ends: u steps at arc bounds
            xs.append(np.array([cw_stm_numeric(w, si * (t1 - t0)) @ x_end for si in s]))
            us.append(np.zeros((len(s), 3)))
            ts.append(t0 + s * (t1 - t0))
            x_end = cw_stm_numeric(w, t1 - t0) @ x_end
    ts.append([starts[-1]])
    xs.append(x_end[None, :])
    us.append(us[-1][-1:] if kinds[-1] == "burn" else np.zeros((1, 3)))
    return np.concatenate(ts), np.vstack(xs), np.vstack(us)


def _same_structure(warm: Solution, bc: BurnCoast) -> bool:
    return tuple(kind for *_, kind in warm.arcs) == bc.kinds


def _resample_arcs(bc: BurnCoast, warm: Solution, idx: list[int]) -> np.ndarray:
    """Seed the arc NLP from another solution with the same arc structure (any method or
    sub-interval count): its arc durations and its dense states/controls at the new nodes."""
    durations = np.array([b - a for a, b, _ in warm.arcs])
    xs, us = [], []
    for a, b, kind in warm.arcs:
        if kind != "burn":
            continue
        t = np.linspace(a, b, bc.K + 1)
        X = np.column_stack([np.interp(t, warm.t, warm.x[:, j]) for j in idx])
        U = np.column_stack([np.interp(t, warm.t, warm.u[:, j]) for j in range(bc.model.nu)])
        U /= np.maximum(np.linalg.norm(U, axis=1, keepdims=True), 1e-12)
        xs.append(X)
        us.append(U)
    return bc.pack(durations, xs, us)


def _plots(t, X, U, t_nodes, Xn, An, accel) -> list[PlotSeries]:
    angle = np.degrees(np.arctan2(U[:, 1], U[:, 0]))
    angle_nodes = np.degrees(np.arctan2(An[:, 1], An[:, 0]))
    return [
        PlotSeries("x", "km", t, X[:, 0] / 1e3, t_nodes, Xn[:, 0] / 1e3),
        PlotSeries("y", "km", t, X[:, 1] / 1e3, t_nodes, Xn[:, 1] / 1e3),
        PlotSeries("x'", "m/s", t, X[:, 3], t_nodes, Xn[:, 3]),
        PlotSeries("y'", "m/s", t, X[:, 4], t_nodes, Xn[:, 4]),
        PlotSeries("throttle |a u|/a", "", t, np.linalg.norm(U, axis=1) / accel, t_nodes,
                   np.linalg.norm(An, axis=1) / accel, group="control"),
        PlotSeries("thrust direction in x–y", "deg", t, angle, t_nodes, angle_nodes,
                   group="control"),
    ]


MISSION = CWRendezvous()
