"""Burn/coast arc transcription for a linear relative-motion model (paper 000, eqs. 4–11).

The transfer is a fixed sequence of arcs, e.g. burn – coast – burn. Each burn arc is divided
into K equal sub-intervals and collocated with Hermite–Simpson (the shared `hs_defects`:
cubic Hermite state, linear control, midpoint defect, eqs. 6–8); each coast arc is closed by
the model's state transition matrix, Phi(T_coast) x_start - x_end = 0 (eq. 9). Node states
and controls of every burn and every arc duration are the NLP variables; |u| = 1 at every
burn node; the durations are non-negative and add up to the total time; the cost is the
total burn time (eqs. 10–11).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...context import SolveContext
from ...nlp.casadi_nlp import NLP, status_of
from ...transcription.hermite_simpson import hs_defects

RHS = Callable[[ca.SX, ca.SX, ca.SX], ca.SX]  # (x, acceleration, p) -> x'
STM = Callable[[ca.SX, ca.SX], ca.SX]  # (p, duration) -> Phi


@dataclass(frozen=True)
class ArcModel:
    """The linear model and boundary data the transcription needs (SI units)."""

    nx: int
    nu: int
    n_params: int
    rhs: RHS
    stm: STM
    initial_state: Callable[[ca.SX], ca.SX]
    acceleration: Callable[[ca.SX], ca.SX]  # p -> thrust acceleration a
    total_time: Callable[[ca.SX], ca.SX]  # p -> T
    x_scale: np.ndarray
    t_scale: float


@dataclass
class BurnCoastResult:
    """Arc durations, node trajectories per burn, and NLP bookkeeping."""

    kinds: tuple[str, ...]
    durations: np.ndarray
    burn_t: list[np.ndarray]
    burn_x: list[np.ndarray]
    burn_u: list[np.ndarray]
    cost: float
    status: str
    message: str
    iterations: int
    n_variables: int
    n_equalities: int
    n_inequalities: int
    max_violation: float
    history: list[tuple[int, np.ndarray]]
    z: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray


def arc_kinds(n_burns: int) -> tuple[str, ...]:
    """burn (coast burn)*; a single burn is followed by a coast (arrive, then wait)."""
    if n_burns == 1:
        return ("burn", "coast")
    return tuple(["burn"] + ["coast", "burn"] * (n_burns - 1))


class BurnCoast:
    """Builds the NLP once per (model, number of burns, sub-intervals, back end)."""

    def __init__(self, model: ArcModel, n_burns: int, subintervals: int, backend: str) -> None:
        self.model = model
        self.kinds = arc_kinds(n_burns)
        self.K = int(subintervals)
        self.n_burns = n_burns
        nx, nu, K = model.nx, model.nu, self.K
        p = ca.SX.sym("p", model.n_params)
        x_sym, u_sym = ca.SX.sym("x", nx), ca.SX.sym("u", nu)
        # x' with u the unit thrust direction (acceleration a u), for `hs_defects`.
        self.f = ca.Function("arc_f", [x_sym, u_sym, p],
                             [model.rhs(x_sym, model.acceleration(p) * u_sym, p)])
        self.f_nodes = self.f.map(K + 1)  # x' at a burn's K + 1 nodes (dense output)
        xs = ca.DM(model.x_scale)
        ts = model.t_scale
        z_parts, eq, ineq = [], [], []
        durations = []
        x_end = None
        for arc, kind in enumerate(self.kinds):
            d = ca.SX.sym(f"d{arc}")
            durations.append(d * ts)
            z_parts.append(d)
            if kind == "burn":
                Xs = ca.SX.sym(f"X{arc}", nx, K + 1)
                U = ca.SX.sym(f"U{arc}", nu, K + 1)
                z_parts += [ca.vec(Xs), ca.vec(U)]
                X = ca.repmat(xs, 1, K + 1) * Xs
                start = X[:, 0]
                if x_end is None:
                    eq.append((start - model.initial_state(p)) / xs)
                else:
                    eq.append((x_end - start) / xs)
                defects, _, _ = hs_defects(self.f, X, U, durations[-1] / K,
                                           ca.repmat(p, 1, K + 1))
                eq.append(ca.vec(defects / ca.repmat(xs, 1, K)))
                eq.append(ca.sum1(U**2).T - 1)
                x_end = X[:, K]
            else:
                x_end = model.stm(p, durations[-1]) @ x_end
            ineq.append(d)
        eq.append(x_end / xs)  # final state: the target (origin)
        total = sum(durations[1:], durations[0])
        eq.append((total - model.total_time(p)) / ts)
        burn_time = sum(
            (dur for dur, kind in zip(durations, self.kinds, strict=True) if kind == "burn"),
            ca.SX(0),
        )
        g_eq = ca.vertcat(*eq)
        g_in = ca.vertcat(*ineq)
        self.n_eq = int(g_eq.numel())
        self.n_in = int(g_in.numel())
        z = ca.vertcat(*z_parts)
        self.nlp = NLP(z, burn_time / ts, ca.vertcat(g_eq, g_in), p, backend, name="burn_coast")

    # ---- numeric side ----------------------------------------------------------------
    def _layout(self) -> list[tuple[str, int, int]]:
        """(kind, start, length) of each block of z, in order."""
        nx, nu, K = self.model.nx, self.model.nu, self.K
        out, i = [], 0
        for kind in self.kinds:
            out.append(("d", i, 1))
            i += 1
            if kind == "burn":
                out.append(("X", i, nx * (K + 1)))
                i += nx * (K + 1)
                out.append(("U", i, nu * (K + 1)))
                i += nu * (K + 1)
        return out

    def pack(self, durations: np.ndarray, xs: list[np.ndarray], us: list[np.ndarray]) -> np.ndarray:
        """Flatten arc durations and per-burn node arrays ((K+1, nx), (K+1, nu))."""
        parts, b = [], 0
        scale = np.asarray(self.model.x_scale)
        for arc, kind in enumerate(self.kinds):
            parts.append([durations[arc] / self.model.t_scale])
            if kind == "burn":
                parts += [(xs[b] / scale).ravel(), us[b].ravel()]
                b += 1
        return np.concatenate(parts)

    def unpack(self, z: np.ndarray) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
        """Arc durations and per-burn node states and controls from z (inverse of `pack`)."""
        nx, nu, K = self.model.nx, self.model.nu, self.K
        durations, xs, us = [], [], []
        for kind, start, length in self._layout():
            block = z[start : start + length]
            if kind == "d":
                durations.append(float(block[0]) * self.model.t_scale)
            elif kind == "X":
                xs.append(block.reshape(K + 1, nx) * np.asarray(self.model.x_scale))
            else:
                us.append(block.reshape(K + 1, nu))
        return np.array(durations), xs, us

    def solve(
        self,
        p: np.ndarray,
        z0: np.ndarray,
        lam: tuple[np.ndarray, np.ndarray] | None,
        ctx: SolveContext | None,
    ) -> BurnCoastResult:
        """Solve for parameters p = (initial state, w, a, T) from z0 (and multipliers)."""
        n = self.nlp.n_x
        lbg = np.concatenate([np.zeros(self.n_eq), np.zeros(self.n_in)])
        ubg = np.concatenate([np.zeros(self.n_eq), np.full(self.n_in, np.inf)])
        lam_x, lam_g = lam if lam is not None else (None, None)
        res = self.nlp.solve(z0, p, np.full(n, -np.inf), np.full(n, np.inf), lbg, ubg,
                             lam_x, lam_g, ctx)
        status, message = status_of(res)
        durations, xs, us = self.unpack(res.x)
        starts = np.concatenate([[0.0], np.cumsum(durations)])
        burn_t = [
            np.linspace(starts[i], starts[i + 1], self.K + 1)
            for i, kind in enumerate(self.kinds) if kind == "burn"
        ]
        return BurnCoastResult(
            kinds=self.kinds, durations=durations, burn_t=burn_t, burn_x=xs, burn_u=us,
            cost=res.f * self.model.t_scale, status=status, message=message,
            iterations=res.iterations, n_variables=n, n_equalities=self.n_eq,
            n_inequalities=self.n_in, max_violation=res.max_violation,
            history=res.history, z=res.x, lam_x=res.lam_x, lam_g=res.lam_g,
        )
