"""What every direct transcription of an `OCP` shares: the variable layout (scaled node
states, node controls, final time), bounds, guesses, warm starts and decoding.

A subclass supplies only the dynamics constraints (collocation defects or shooting gaps),
the running-cost quadrature and the dense interpolation that goes with them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import casadi as ca
import numpy as np

from ..mission import SolveContext
from ..nlp.casadi_nlp import NLP, status_of
from ..ocp import OCP, OCPResult, WarmStart


class DirectTranscription(ABC):
    """Nodes at tau_k = k/N on t = T tau; states and controls at every node."""

    kind: str = "direct"
    # How the control is defined between nodes: "linear" or "polynomial" (through all nodes).
    control_interpolation: str = "linear"

    @staticmethod
    def mesh(n_intervals: int) -> np.ndarray:
        """Node positions tau in [0, 1]: equally spaced unless a method says otherwise."""
        return np.linspace(0.0, 1.0, n_intervals + 1)

    def __init__(self, ocp: OCP, n_intervals: int, backend: str = "ipopt") -> None:
        self.ocp = ocp
        self.N = int(n_intervals)
        self.fn = ocp.functions()
        nx, nu, N = ocp.nx, ocp.nu, self.N
        self.tau = self.mesh(N)
        self.free_T = ocp.fixed_final_time is None
        Xs = ca.SX.sym("X", nx, N + 1)
        Us = ca.SX.sym("U", nu, N + 1)
        p = ca.SX.sym("p", ocp.n_params)
        Ts = ca.SX.sym("T") if self.free_T else ca.SX(0, 1)
        T = Ts * ocp.T_scale if self.free_T else ocp.fixed_final_time(p)
        X = ca.repmat(ca.DM(ocp.offset), 1, N + 1) + ca.repmat(ca.DM(ocp.x_scale), 1, N + 1) * Xs
        U = ca.repmat(ca.DM(ocp.u_scale), 1, N + 1) * Us
        defects, running = self._dynamics(X, U, T, p)
        cost = running
        if ocp.mayer is not None:
            cost = cost + ocp.mayer(X[:, N], T, p)
        g = [defects, ocp.terminal(X[:, N], p) / ca.DM(ocp.terminal_scale)]
        self.n_path = 0
        if ocp.path is not None:
            path = ca.horzcat(*[ocp.path(X[:, k], U[:, k], p) for k in range(N + 1)])
            self.n_path = int(path.size1())
            g.append(ca.vec(path))
        self.n_defects = int(defects.numel())
        self.n_terminal = int(np.size(ocp.terminal_scale))
        z = ca.vertcat(ca.vec(Xs), ca.vec(Us), Ts)
        self.nlp = NLP(
            z, cost / ocp.cost_scale, ca.vertcat(*g), p, backend, name=self.kind.replace("-", "_")
        )

    @abstractmethod
    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Scaled dynamics constraints (vector) and the running cost in SI."""

    @abstractmethod
    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense (t, X, U) as the method defines the trajectory between nodes."""

    # ---- variable layout -------------------------------------------------------------
    def _pack(self, X: np.ndarray, U: np.ndarray, T: float) -> np.ndarray:
        ocp = self.ocp
        Xs = (X - ocp.offset) / ocp.x_scale
        Us = U / ocp.u_scale
        parts = [Xs.ravel(), Us.ravel()]
        if self.free_T:
            parts.append([T / ocp.T_scale])
        return np.concatenate(parts)

    def _unpack(self, z: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        ocp, N = self.ocp, self.N
        nX, nU = ocp.nx * (N + 1), ocp.nu * (N + 1)
        X = ocp.offset + ocp.x_scale * z[:nX].reshape(N + 1, ocp.nx)
        U = ocp.u_scale * z[nX : nX + nU].reshape(N + 1, ocp.nu)
        T = float(z[-1] * ocp.T_scale) if self.free_T else float(self.fn.fixed_T(p))
        return X, U, T

    def _box(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ocp, N = self.ocp, self.N
        b = ocp.bounds(p)
        x0 = np.asarray(self.fn.x0(p)).ravel()
        xlb = np.tile((b.x_lb - ocp.offset) / ocp.x_scale, (N + 1, 1))
        xub = np.tile((b.x_ub - ocp.offset) / ocp.x_scale, (N + 1, 1))
        xlb[0] = xub[0] = (x0 - ocp.offset) / ocp.x_scale
        ulb = np.tile(b.u_lb / ocp.u_scale, (N + 1, 1))
        uub = np.tile(b.u_ub / ocp.u_scale, (N + 1, 1))
        lb = [xlb.ravel(), ulb.ravel()]
        ub = [xub.ravel(), uub.ravel()]
        if self.free_T:
            lb.append([b.T_lb / ocp.T_scale])
            ub.append([b.T_ub / ocp.T_scale])
        return np.concatenate(lb), np.concatenate(ub)

    def _g_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        n_eq = self.n_defects + self.n_terminal
        lb = [np.zeros(n_eq)]
        ub = [np.zeros(n_eq)]
        if self.n_path:
            reps = self.N + 1
            lb.append(np.tile(self.ocp.path_lb, reps))
            ub.append(np.tile(self.ocp.path_ub, reps))
        return np.concatenate(lb), np.concatenate(ub)

    def _cold_guess(self, p: np.ndarray) -> np.ndarray:
        guess = self.ocp.guess(p)
        x0 = np.asarray(self.fn.x0(p)).ravel()
        X = x0 + np.outer(self.tau, np.asarray(guess.x_final) - x0)
        U = np.tile(np.asarray(guess.u, float), (self.N + 1, 1))
        T = guess.T if self.free_T else float(self.fn.fixed_T(p))
        return self._pack(X, U, T)

    def _warm_guess(self, warm: WarmStart, p: np.ndarray) -> np.ndarray:
        """Re-interpolate another solution onto this mesh (node count or method changed)."""
        X = _resample(self.tau, warm.tau, warm.X)
        U = _resample(self.tau, warm.tau, warm.U)
        x0 = np.asarray(self.fn.x0(p)).ravel()
        X[0] = x0
        T = warm.T if self.free_T else float(self.fn.fixed_T(p))
        return self._pack(X, U, T)

    # ---- solve -----------------------------------------------------------------------
    def solve(
        self,
        p: np.ndarray,
        warm: WarmStart | None = None,
        ctx: SolveContext | None = None,
        dense_per_interval: int = 10,
    ) -> OCPResult:
        """Solve for numeric parameters `p`, warm-started when `warm` fits this mesh."""
        p = np.asarray(p, float)
        lbx, ubx = self._box(p)
        lbg, ubg = self._g_bounds()
        lam_x = lam_g = None
        if warm is not None and warm.kind == self.kind and warm.n_intervals == self.N:
            z0 = warm.z.copy()
            lam_x, lam_g = warm.lam_x, warm.lam_g
        elif warm is not None:
            z0 = self._warm_guess(warm, p)
        else:
            z0 = self._cold_guess(p)
        z0 = np.clip(z0, lbx, ubx)
        res = self.nlp.solve(z0, p, lbx, ubx, lbg, ubg, lam_x, lam_g, ctx)
        X, U, T = self._unpack(res.x, p)
        status, message = status_of(res)
        t_dense, X_dense, U_dense = self.dense(T, X, U, p, dense_per_interval)
        history = []
        for k, z in res.history:
            Xk, _, Tk = self._unpack(z, p)
            history.append((k, self.tau * Tk, Xk))
        return OCPResult(
            T=T,
            t_nodes=self.tau * T,
            X=X,
            U=U,
            t_dense=t_dense,
            X_dense=X_dense,
            U_dense=U_dense,
            cost=res.f * self.ocp.cost_scale,
            status=status,
            message=message,
            iterations=res.iterations,
            n_variables=self.nlp.n_x,
            n_constraints=self.nlp.n_g,
            max_violation=res.max_violation,
            history=history,
            warm=WarmStart(self.kind, self.N, self.tau, X, U, T, res.x, res.lam_x, res.lam_g),
            control_interpolation=self.control_interpolation,
        )


def _resample(tau: np.ndarray, tau_from: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Linear re-interpolation of node values (rows) onto another normalised mesh."""
    return np.column_stack([np.interp(tau, tau_from, col) for col in values.T])
