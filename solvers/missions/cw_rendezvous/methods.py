"""The paper's own method for the CW rendezvous (paper 000): the burn/coast arc transcription
(Hermite–Simpson on burn arcs, the CW state transition matrix on coasts, arc durations as
variables) solved by IPOPT or the paper's exterior penalty method (eq. 12)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...context import SolveContext
from ...dynamics.clohessy_wiltshire import STATE_UNITS, STATES, cw_stm_numeric
from ...nlp.cache import built_once
from ...problem import Method, Param
from ...solution import Iterate, Quantity, Solution, WarmStart
from ...transcription.hermite_simpson import hermite_dense, linear_dense
from .burn_coast import BurnCoast, BurnCoastResult
from .model import arc_model, state_indices
from .problem import CONTROL_UNITS, CONTROLS, P_A, P_T, P_W, PAPER, check, explain, quantities

BURNS = Param("burns", "number of burns", "", 2, 1, 3, 1, group="Method", integer=True,
              help="Arc structure: burn (coast burn)*; a single burn is followed by a coast.")

PAPER_METHOD = Method(
    "paper", "Burn/coast arcs: HS collocation + CW STM coasts", PAPER,
    "Burn arcs collocated by Hermite–Simpson on equal sub-intervals, coast arcs closed by "
    "the CW state transition matrix, arc durations as variables, |u| = 1 at nodes, "
    "cost = total burn time (paper eqs. 4–11).",
    nodes=(4, 12, 40), nodes_label="sub-intervals per burn", params=(BURNS,),
    backends=("ipopt", "penalty-bfgs"),
    equations=(
        ("Coast arcs closed by the CW state transition matrix (paper 000, eq. 9)",
         r"C_N = \Phi(T_N)\,X_N^{\text{start}} - X_N^{\text{end}} = 0"),
        ("Exterior penalty function (paper 000, eq. 12; back end penalty-bfgs)",
         r"\min F(D) = f(D) + m\,P\,C^T"),
    ),
)

GAUSS_POINTS = 8  # Gauss–Legendre points per interval of the burn-time quadrature


def control_burn_time(controls: Callable[[np.ndarray], np.ndarray], t_nodes: np.ndarray,
                      accel: float) -> float:
    """∫ |u|/a dt of a method's own control (`controls`: times -> (len, 3+) accelerations,
    m/s²) by Gauss–Legendre on every interval between nodes, s: the burn time of what is
    drawn, not the NLP's L1 surrogate ∫ s/a dt (the slack s sits above |u| where the mesh
    cannot follow a switch)."""
    nodes, weights = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    t0, h = np.asarray(t_nodes[:-1], float), np.diff(np.asarray(t_nodes, float))
    t = (t0[:, None] + 0.5 * h[:, None] * (nodes + 1.0)).ravel()
    speed = np.linalg.norm(np.asarray(controls(t))[:, :3], axis=1).reshape(len(h), -1)
    return float(np.sum(0.5 * h * (speed @ weights)) / accel)


WARM_KIND = "burn-coast"
DENSE_PER_INTERVAL = 10  # dense samples per burn sub-interval (a coast gets 4x as many)


@dataclass(frozen=True)
class ArcLayout:
    """What fixes the arc NLP besides the sub-interval count: the state subset and burns."""

    planar: bool
    burns: int
    backend: str

    @property
    def idx(self) -> list[int]:
        """Indices of the full CW state the arcs carry."""
        return state_indices(self.planar)


@built_once
def burn_coast(planar: bool, burns: int, k: int, backend: str) -> BurnCoast:
    """The arc NLP, built once per (state subset, burns, sub-intervals, back end)."""
    return BurnCoast(arc_model(planar), burns, k, backend)


def solve_paper(values: dict[str, float], p: np.ndarray, k: int, backend: str,
                warm: Solution | None, ctx: SolveContext) -> Solution:
    """Paper 000's method: restart from the same NLP's optimum (primal and dual), from
    another solution with the same arc structure, or from the two-impulse transfer."""
    layout = ArcLayout(values["z0"] == 0 and values["vz0"] == 0, int(values["burns"]), backend)
    bc = burn_coast(layout.planar, layout.burns, k, backend)
    idx = layout.idx
    p_arc = np.concatenate([p[:6][idx], p[6:]])
    start = warm.warm if warm is not None and warm.converged else None
    lam = None
    if _reuses(start, layout, k):
        z0, lam = start.z, (start.lam_x, start.lam_g)
    elif warm is not None and warm.converged and _same_structure(warm, bc):
        z0 = _resample_arcs(bc, warm, idx)
    else:
        z0 = _impulsive_guess(bc, p, idx)
    res = bc.solve(p_arc, z0, lam, ctx)
    t_nodes, X, U = _stack_burns(res, idx)
    acc = values["accel"] * U
    t_dense, X_dense, U_dense = dense_arcs(bc, res.durations, res.burn_x, res.burn_u, p, idx)
    arcs = _arcs_from_durations(res)
    sol = Solution(
        mission="cw-rendezvous", method="paper", nodes=k, backend=backend, status=res.status,
        message=explain(res.status, res.message, values, "–".join(res.kinds)),
        cost=Quantity(float(res.cost), "burn time", "s"), values=values,
        quantities=quantities(res.cost, values["accel"], arcs), state_names=STATES,
        state_units=STATE_UNITS, control_names=CONTROLS, control_units=CONTROL_UNITS,
        node_t=t_nodes, node_x=X, node_u=acc, arcs=arcs, t=t_dense, x=X_dense, u=U_dense,
        control_interpolation="dense",  # linear on burns, zero on coasts: steps at arc ends
    )
    sol.stats.update(iterations=res.iterations, nlp_variables=res.n_variables,
                     nlp_constraints=res.n_equalities + res.n_inequalities,
                     nlp_equalities=res.n_equalities, nlp_inequalities=res.n_inequalities,
                     constraint_violation=res.max_violation)
    for it, z in res.history:
        ts, Xs, _ = dense_arcs(bc, *bc.unpack(z), p, idx, per_interval=3)
        sol.history.append(Iterate(it, ts, Xs))
    sol.warm = WarmStart(WARM_KIND, k, t_nodes / p[P_T], X, acc, float(p[P_T]), z=res.z,
                         lam_x=res.lam_x, lam_g=res.lam_g,
                         data={"planar": layout.planar, "burns": layout.burns,
                               "backend": backend})
    sol.check["max_defect"] = res.max_violation
    breaks = np.unique(np.concatenate([t_nodes, np.cumsum(res.durations)]))
    # Arc durations may come out a round-off below zero: keep the sample times monotone.
    t_mono = np.maximum.accumulate(t_dense)
    sol.checker = lambda: check(
        p, np.concatenate([[0.0], breaks[breaks > 0]]),
        lambda t, x: np.array([np.interp(t, t_mono, U_dense[:, j]) for j in range(3)]),
    )
    return sol


def _reuses(warm: WarmStart | None, layout: ArcLayout, k: int) -> bool:
    """Whether `warm` is the optimum of this very arc NLP (its z and multipliers fit)."""
    return (warm is not None and warm.kind == WARM_KIND and warm.n_intervals == k
            and warm.data == {"planar": layout.planar, "burns": layout.burns,
                              "backend": layout.backend})


def _arcs_from_durations(res: BurnCoastResult) -> list[tuple[float, float, str]]:
    starts = np.concatenate([[0.0], np.cumsum(res.durations)])
    return [(float(starts[i]), float(starts[i + 1]), kind) for i, kind in enumerate(res.kinds)]


def _embed(X: np.ndarray, idx: list[int]) -> np.ndarray:
    """States on the subset `idx` as full 6-states (the others zero)."""
    full = np.zeros((X.shape[0], 6))
    full[:, idx] = X
    return full


def _stack_burns(res: BurnCoastResult, idx: list[int]
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Node times, full states and 3-D thrust directions of all burns, in order."""
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
    w, a, T = p[P_W], p[P_A], p[P_T]
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


def dense_arcs(bc: BurnCoast, durations: np.ndarray, burn_x: list[np.ndarray],
               burn_u: list[np.ndarray], p: np.ndarray, idx: list[int], *,
               per_interval: int = DENSE_PER_INTERVAL
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Dense (t, X, acceleration): the shared cubic Hermite interpolation (`hermite_dense`)
    with linear control on burns, the exact STM on coasts (both ends sampled, so the control
    steps at the arc bounds)."""
    w, accel = p[P_W], p[P_A]
    p_arc = np.concatenate([p[:6][idx], p[6:]])
    starts = np.concatenate([[0.0], np.cumsum(durations)])
    ts, xs, us = [], [], []
    b = 0
    x_end = np.zeros(6)
    for i, kind in enumerate(bc.kinds):
        t0, t1 = starts[i], starts[i + 1]
        if kind == "burn":
            Xr, U = burn_x[b], burn_u[b]
            F = np.asarray(bc.f_nodes(Xr.T, U.T, np.tile(p_arc[:, None], bc.K + 1))).T
            t_nodes = np.linspace(t0, t1, bc.K + 1)
            t, X = hermite_dense(t_nodes, _embed(Xr, idx), _embed(F, idx), per_interval)
            U3 = np.column_stack([U, np.zeros(len(U))]) if U.shape[1] == 2 else U
            ts.append(t)
            xs.append(X)
            us.append(accel * linear_dense(t_nodes, U3, per_interval))
            x_end = X[-1]
            b += 1
        else:
            s = np.linspace(0, 1, 4 * per_interval + 1)
            xs.append(cw_stm_numeric(w, s * (t1 - t0)) @ x_end)
            us.append(np.zeros((len(s), 3)))
            ts.append(t0 + s * (t1 - t0))
            x_end = cw_stm_numeric(w, t1 - t0) @ x_end
    ts.append([starts[-1]])
    xs.append(x_end[None, :])
    us.append(us[-1][-1:] if bc.kinds[-1] == "burn" else np.zeros((1, 3)))
    return np.concatenate(ts), np.vstack(xs), np.vstack(us)


def _same_structure(warm: Solution, bc: BurnCoast) -> bool:
    return tuple(kind for *_, kind in warm.arcs) == bc.kinds


def _resample_arcs(bc: BurnCoast, warm: Solution, idx: list[int]) -> np.ndarray:
    """Seed the arc NLP from another solution with the same arc structure (any sub-interval
    count): its arc durations and its dense states/controls at the new nodes."""
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
