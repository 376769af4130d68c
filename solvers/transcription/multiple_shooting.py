"""Direct multiple shooting (paper 004): tau in [0, 1], t = T tau, T a parameter.

[0, 1] is divided into N equal intervals; the control is linear between the node values
P_i; node states S_i are NLP variables; each interval is integrated from S_i with fixed-step
RK4 (the running cost rides along as an extra state, the paper's Mayer form) and continuity
x(S_i, tau_i+1) = S_i+1 is imposed.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..nlp.fatrop import Stages
from ..ocp import OCP
from .costates import CostatePoints, Endpoints
from .direct import DirectTranscription
from .stages import stage_order

DEFAULT_SUBSTEPS = 8


class MultipleShooting(DirectTranscription):
    kind = "multiple-shooting"
    order = 4.0  # the RK4 steps inside each shooting interval
    symbolic = ca.MX

    def __init__(
        self, ocp: OCP, n_intervals: int, backend: str = "ipopt", substeps: int = DEFAULT_SUBSTEPS
    ) -> None:
        self.substeps = int(substeps)
        self._interval = _interval_function(ocp, int(n_intervals), self.substeps)
        super().__init__(ocp, n_intervals, backend)

    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        N, ocp = self.N, self.ocp
        ends, _, q = self._interval.map(N)(
            X[:, :-1], U[:, :-1], U[:, 1:], ca.repmat(T, 1, N), ca.repmat(p, 1, N)
        )
        gaps = (ends - X[:, 1:]) / ca.repmat(ca.DM(ocp.x_scale), 1, N)
        return ca.vec(gaps), ca.sum2(q)

    def _stages(self, p: ca.MX) -> Stages:
        """Stage k carries node k+1's control as its control (the control is linear across
        the interval) and the RK4 map gives the next state explicitly (`stages`)."""
        return stage_order(self, p, self._stage_intervals, explicit=True)

    def _stage_intervals(self, Xk: ca.MX, Uk: ca.MX, Xk1: None, Uk1: ca.MX, T: ca.MX,
                         p: ca.MX) -> tuple[ca.MX, ca.MX, None]:
        """End states and running cost of the intervals from their end nodes (columns) and
        final times T (a row: one copy per stage)."""
        ends, _, q = self._interval.map(self.N)(Xk, Uk, Uk1, T, ca.repmat(p, 1, self.N))
        return ends, ca.sum2(q), None

    def costate_points(self, mu: np.ndarray, X: np.ndarray, U: np.ndarray, T: float,
                       p: np.ndarray, ends: Endpoints, tau: np.ndarray) -> CostatePoints:
        """lambda(t_k+1) = mu_k: the gap phi_k - x_k+1 ties the end of interval k to the next
        node, so its multiplier is the sensitivity of the optimal cost to that node's state
        (the discrete adjoint of the RK4 map, Betts 2010, sec. 4.11; Hager 2000); the first
        node's follows one step back, lambda_0 = dq_0/dx_0 + (dphi_0/dx_0)^T mu_0. Costates
        at the nodes. Measured order 4 in the node spacing (the RK4 map's own; hovercraft
        and reentry against their indirect solutions, tests/core/test_costates.py)."""
        A, q_x = self._first_step_jacobian()(X[0], U[0], U[1], T, p)
        lam0 = np.asarray(q_x).ravel() + np.asarray(A).T @ mu[0]
        return CostatePoints(tau * T, np.vstack([lam0, mu]), X, U)

    def _first_step_jacobian(self) -> ca.Function:
        """(dphi/dx, dq/dx) of one interval's RK4 map at its start."""
        if not hasattr(self, "_step_jacobian"):
            ocp = self.ocp
            x, u0, u1 = (ca.SX.sym(n, k) for n, k in (("x", ocp.nx), ("u0", ocp.nu),
                                                       ("u1", ocp.nu)))
            T, p = ca.SX.sym("T"), ca.SX.sym("p", ocp.n_params)
            end, _, q = self._interval(x, u0, u1, T, p)
            self._step_jacobian = ca.Function("step_jacobian", [x, u0, u1, T, p],
                                              [ca.jacobian(end, x), ca.gradient(q, x)])
        return self._step_jacobian

    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int,
        tau: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The RK4 substeps of each interval (the method's own trajectory; equal steps, so
        `tau` is the method's own mesh)."""
        N, M = self.N, self.substeps
        _, traj, _ = self._interval.map(N)(
            X[:-1].T, U[:-1].T, U[1:].T, np.full((1, N), T), np.tile(p[:, None], (1, N))
        )
        traj = np.asarray(traj)  # nx x (N * M): substep states after the start of each interval
        xs, us, ts = [], [], []
        s = np.arange(M) / M
        for k in range(N):
            states = np.vstack([X[k], traj[:, k * M : (k + 1) * M - 1].T])
            xs.append(states)
            us.append(np.outer(1 - s, U[k]) + np.outer(s, U[k + 1]))
            ts.append((k + s) * T / N)
        xs.append(X[-1:])
        us.append(U[-1:])
        ts.append([T])
        return np.concatenate(ts), np.vstack(xs), np.vstack(us)


def _interval_function(ocp: OCP, N: int, M: int) -> ca.Function:
    """RK4 over one interval of length 1/N in tau with a linear control: returns the end
    state, the M substep states (for drawing) and the running-cost increment."""
    fn = ocp.functions()
    x = ca.SX.sym("x", ocp.nx)
    u0 = ca.SX.sym("u0", ocp.nu)
    u1 = ca.SX.sym("u1", ocp.nu)
    T = ca.SX.sym("T")
    p = ca.SX.sym("p", ocp.n_params)
    dtau = 1.0 / (N * M)

    def rhs(xq: ca.SX, s: float) -> ca.SX:
        xs = xq[: ocp.nx]
        u = u0 + (u1 - u0) * s
        dx = T * fn.f(xs, u, p)
        dq = T * fn.lagrange(xs, u, p) if fn.lagrange is not None else ca.SX(0)
        return ca.vertcat(dx, dq)

    xq = ca.vertcat(x, 0)
    states = []
    for j in range(M):
        s0 = j / M
        k1 = rhs(xq, s0)
        k2 = rhs(xq + dtau / 2 * k1, s0 + 0.5 / M)
        k3 = rhs(xq + dtau / 2 * k2, s0 + 0.5 / M)
        k4 = rhs(xq + dtau * k3, s0 + 1.0 / M)
        xq = xq + dtau / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        states.append(xq[: ocp.nx])
    return ca.Function(
        "interval", [x, u0, u1, T, p], [xq[: ocp.nx], ca.horzcat(*states), xq[ocp.nx]]
    )
