"""Hermite–Simpson collocation (compressed form): cubic Hermite state, linear control.

On each interval of length h the state is the cubic Hermite interpolant of the node states
and slopes; the collocation point is the midpoint, where
x_m = (x_k + x_k+1)/2 + h/8 (f_k - f_k+1) and u_m = (u_k + u_k+1)/2, and the defect is
x_k+1 - x_k - h/6 (f_k + 4 f_m + f_k+1) (papers 000 eqs. 6-8 and 003). The running cost
uses the same Simpson quadrature.

`hs_defects` and `hermite_dense` are the one implementation of the defect and of the dense
output: the general transcription below, the burn arcs of paper 000 and every mission's
drawing use them.
"""

from __future__ import annotations

from functools import cached_property

import casadi as ca
import numpy as np

from ..nlp.fatrop import Stages
from ..ocp import OCP
from .costates import CostatePoints, Endpoints, transversality
from .direct import DirectTranscription
from .stages import stage_order


def hs_defects(
    f: ca.Function, X: ca.SX, U: ca.SX, h: ca.SX | float, P: ca.SX
) -> tuple[ca.SX, ca.SX, ca.SX]:
    """Defects (nx, N) of node states X (nx, N+1) and controls U (nu, N+1) on intervals of
    length h (a scalar or a (1, N) row), with P the parameters repeated per node; also the
    midpoint states and controls (for a running cost on the same quadrature)."""
    N = X.shape[1] - 1
    h = h if isinstance(h, ca.SX | ca.MX | ca.DM) else ca.SX(h)
    F = f.map(N + 1)(X, U, P)
    H = ca.repmat(h, X.shape[0], 1) if h.shape[1] == N else h
    return hs_intervals(f, X[:, :-1], X[:, 1:], F[:, :-1], F[:, 1:], (U[:, :-1] + U[:, 1:]) / 2,
                        H, P[:, :-1])


def hs_intervals(
    f: ca.Function, Xk: ca.SX, Xk1: ca.SX, Fk: ca.SX, Fk1: ca.SX, Um: ca.SX, H: ca.SX, P: ca.SX
) -> tuple[ca.SX, ca.SX, ca.SX]:
    """Defects of intervals (columns) from their end states Xk, Xk1, the slopes there Fk,
    Fk1, the midpoint controls Um and lengths H (a scalar or one per entry); also the
    midpoint states and controls."""
    Xm = (Xk + Xk1) / 2 + H / 8 * (Fk - Fk1)
    Fm = f.map(Xk.shape[1])(Xm, Um, P)
    return Xk1 - Xk - H / 6 * (Fk + 4 * Fm + Fk1), Xm, Um


def hermite_dense(
    t_nodes: np.ndarray, X: np.ndarray, F: np.ndarray, per_interval: int
) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Hermite interpolation of node states X (rows) with their time derivatives F:
    `per_interval` samples per interval plus the last node (all intervals at once)."""
    s = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    h = np.diff(t_nodes)[:, None]  # (K, 1)
    basis = lambda b: b[None, :, None]  # noqa: E731 - (1, samples, 1) against (K, 1, nx)
    xs = (basis(h00) * X[:-1, None] + basis(h10) * (h * F[:-1])[:, None]
          + basis(h01) * X[1:, None] + basis(h11) * (h * F[1:])[:, None])
    ts = t_nodes[:-1, None] + s[None, :] * h
    return np.concatenate([ts.ravel(), t_nodes[-1:]]), np.vstack([xs.reshape(-1, X.shape[1]),
                                                                  X[-1:]])


def linear_dense(t_nodes: np.ndarray, U: np.ndarray, per_interval: int) -> np.ndarray:
    """Node values (rows) linear between nodes, sampled like `hermite_dense`."""
    s = np.linspace(0.0, 1.0, per_interval + 1)[:-1][None, :, None]
    parts = (1 - s) * U[:-1, None] + s * U[1:, None]
    return np.vstack([parts.reshape(-1, U.shape[1]), U[-1:]])


class HermiteSimpson(DirectTranscription):
    kind = "hermite-simpson"
    order = 4.0  # Hermite cubic states, Simpson quadrature

    def __init__(self, ocp: OCP, n_intervals: int, backend: str = "ipopt",
                 variable_mesh: int = 0, midpoint_path: int = 0) -> None:
        """`variable_mesh` 1: the interval lengths are a parameter of the NLP (any mesh
        re-solves it, `solve(..., tau=...)`); 0: equal steps, as numbers in the NLP.
        `midpoint_path` 1: the path constraints hold at the interval midpoints too, where
        Simpson's rule samples the dynamics and the running cost. Without it a nonconvex
        bound such as |T| >= ρ1 can be undercut there (the average of two thrust vectors
        of norm ρ1 is shorter), and the answer spends less than the true optimum."""
        self.variable_mesh = bool(variable_mesh)
        self.midpoint_path = bool(midpoint_path)
        super().__init__(ocp, n_intervals, backend)

    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        N, ocp = self.N, self.ocp
        h = T * self._steps if self.variable_mesh else T / N  # (1, N) or one length
        P = ca.repmat(p, 1, N + 1)
        defects, Xm, Um = hs_defects(self.fn.f, X, U, h, P)
        self._midpoints = (Xm, Um)
        defects = defects / ca.repmat(ca.DM(ocp.x_scale), 1, N)
        running = ca.SX(0)
        if self.fn.lagrange is not None:
            L = self.fn.lagrange.map(N + 1)(X, U, P)
            Lm = self.fn.lagrange.map(N)(Xm, Um, P[:, :-1])
            if self.variable_mesh:
                running = ca.sum2(h * (L[:, :-1] + 4 * Lm + L[:, 1:])) / 6
            else:
                running = h / 6 * (ca.sum2(L[:, :-1]) + 4 * ca.sum2(Lm) + ca.sum2(L[:, 1:]))
        return ca.vec(defects), running

    def _stages(self, p: ca.SX) -> Stages:
        """Stage k carries node k+1's state and control as controls: the defect involves
        f(x_k+1), so it is a constraint of stage k and the gap a copy (`stages`)."""
        return stage_order(self, p, self._stage_intervals, explicit=False)

    def _stage_intervals(self, Xk: ca.SX, Uk: ca.SX, Xk1: ca.SX, Uk1: ca.SX, T: ca.SX,
                         p: ca.SX) -> tuple[ca.SX, ca.SX, tuple[ca.SX, ca.SX] | None]:
        """Scaled defects, Simpson running cost and midpoints of the intervals from their
        end nodes (columns) and final times T (a row: one copy per stage)."""
        N, ocp, f = self.N, self.ocp, self.fn.f
        h = T * self._steps if self.variable_mesh else T / N
        P = ca.repmat(p, 1, N)
        defects, Xm, Um = hs_intervals(f, Xk, Xk1, f.map(N)(Xk, Uk, P), f.map(N)(Xk1, Uk1, P),
                                       (Uk + Uk1) / 2, ca.repmat(h, ocp.nx, 1), P)
        running = ca.SX(0)
        if self.fn.lagrange is not None:
            L = self.fn.lagrange.map(N)
            running = ca.sum2(h * (L(Xk, Uk, P) + 4 * L(Xm, Um, P) + L(Xk1, Uk1, P))) / 6
        return (defects / ca.repmat(ca.DM(ocp.x_scale), 1, N), running,
                (Xm, Um) if self.midpoint_path else None)

    def _path_points(self, X: ca.SX, U: ca.SX) -> tuple[ca.SX, ca.SX]:
        if not self.midpoint_path:
            return X, U
        Xm, Um = self._midpoints
        return ca.horzcat(X, Xm), ca.horzcat(U, Um)

    def costate_points(self, mu: np.ndarray, X: np.ndarray, U: np.ndarray, T: float,
                       p: np.ndarray, ends: Endpoints, tau: np.ndarray) -> CostatePoints:
        """lambda(t_k+1/2) = -mu_k: the defect of interval k approximates
        -integral (f - x') dt over it, so its multiplier is minus the costate at the
        interval's midpoint (Betts 2010, Practical Methods for Optimal Control, sec. 4.11;
        compressed HS is the Lobatto IIIA pair, whose discrete adjoint is consistent: Hager
        2000, Numer. Math. 87). The multiplier is the costate averaged over the interval, so
        the midpoint value is second-order: measured order 2 in the mesh size (lunar landing
        against its Pontryagin extremal; 4 where the costate is linear in t, as for the
        hovercraft; tests/core/test_costates.py). At t0 and tf, where a textbook states its
        costates, the closure conditions give them: the transversality conditions from the
        end multipliers (`costates.transversality`, as for LGL)."""
        F = self._node_slopes(X, U, p)
        h = np.diff(tau) * T
        Xm = (X[:-1] + X[1:]) / 2 + h[:, None] / 8 * (F[:-1] - F[1:])
        Um = (U[:-1] + U[1:]) / 2
        lam0, lamf = transversality(self.ocp, ends, p)
        t = np.concatenate([[0.0], (tau[:-1] + tau[1:]) / 2 * T, [T]])
        return CostatePoints(t, np.vstack([lam0, -mu, lamf]), np.vstack([X[0], Xm, X[-1]]),
                             np.vstack([U[0], Um, U[-1]]))

    @cached_property
    def _f_at_nodes(self) -> ca.Function:
        """f mapped over the N + 1 nodes (built once: a map costs more than its call)."""
        return self.fn.f.map(self.N + 1)

    def _node_slopes(self, X: np.ndarray, U: np.ndarray, p: np.ndarray) -> np.ndarray:
        return np.asarray(self._f_at_nodes(X.T, U.T, np.tile(p[:, None], (1, self.N + 1)))).T

    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int,
        tau: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        F = self._node_slopes(X, U, p)
        t_nodes = tau * T
        t, Xd = hermite_dense(t_nodes, X, F, per_interval)
        return t, Xd, linear_dense(t_nodes, U, per_interval)
