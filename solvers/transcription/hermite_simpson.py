"""Hermite–Simpson collocation (compressed form): cubic Hermite state, linear control.

On each of N equal intervals of length h the state is the cubic Hermite interpolant of the
node states and slopes; the collocation point is the midpoint, where
x_m = (x_k + x_k+1)/2 + h/8 (f_k - f_k+1) and u_m = (u_k + u_k+1)/2, and the defect is
x_k+1 - x_k - h/6 (f_k + 4 f_m + f_k+1) (papers 000 eqs. 6-8 and 003). The running cost
uses the same Simpson quadrature.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from .direct import DirectTranscription


class HermiteSimpson(DirectTranscription):
    kind = "hermite-simpson"

    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        N, ocp = self.N, self.ocp
        h = T / N
        P = ca.repmat(p, 1, N + 1)
        F = self.fn.f.map(N + 1)(X, U, P)
        Xk, Xk1, Fk, Fk1 = X[:, :-1], X[:, 1:], F[:, :-1], F[:, 1:]
        Xm = (Xk + Xk1) / 2 + h / 8 * (Fk - Fk1)
        Um = (U[:, :-1] + U[:, 1:]) / 2
        Fm = self.fn.f.map(N)(Xm, Um, P[:, :-1])
        defects = (Xk1 - Xk - h / 6 * (Fk + 4 * Fm + Fk1)) / ca.repmat(ca.DM(ocp.x_scale), 1, N)
        running = ca.SX(0)
        if self.fn.lagrange is not None:
            L = self.fn.lagrange.map(N + 1)(X, U, P)
            Lm = self.fn.lagrange.map(N)(Xm, Um, P[:, :-1])
            running = h / 6 * (ca.sum2(L[:, :-1]) + 4 * ca.sum2(Lm) + ca.sum2(L[:, 1:]))
        return ca.vec(defects), running

    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        N = self.N
        h = T / N
        F = np.asarray(self.fn.f.map(N + 1)(X.T, U.T, np.tile(p[:, None], (1, N + 1)))).T
        s = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
        # Cubic Hermite basis on [0, 1].
        h00 = 2 * s**3 - 3 * s**2 + 1
        h10 = s**3 - 2 * s**2 + s
        h01 = -2 * s**3 + 3 * s**2
        h11 = s**3 - s**2
        xs, us, ts = [], [], []
        for k in range(N):
            xs.append(
                np.outer(h00, X[k]) + np.outer(h10 * h, F[k]) + np.outer(h01, X[k + 1])
                + np.outer(h11 * h, F[k + 1])
            )
            us.append(np.outer(1 - s, U[k]) + np.outer(s, U[k + 1]))
            ts.append((k + s) * h)
        xs.append(X[-1:])
        us.append(U[-1:])
        ts.append([T])
        return np.concatenate(ts), np.vstack(xs), np.vstack(us)
