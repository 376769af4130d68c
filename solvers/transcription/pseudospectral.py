"""Legendre–Gauss–Lobatto pseudospectral collocation of a generic `OCP`.

The state and the control are global polynomials of degree N through the N+1 LGL nodes,
mapped from [-1, 1] to tau in [0, 1] (t = T tau). The dynamics are collocated at every node
with the LGL differentiation matrix, D X = (T/2) f(X, U), and the running cost uses the LGL
quadrature (T/2) sum w_i L_i (paper 001, eq. 4: nodes, weights and D). For smooth problems the
error falls faster than any power of 1/N, which is why a few dozen nodes match hundreds of
Hermite–Simpson intervals.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..lgl import interpolate, lgl_differentiation, lgl_nodes, lgl_weights
from .costates import CostatePoints, Endpoints, transversality
from .direct import DirectTranscription
from .lgl_costates import lgl_costates


class LGLPseudospectral(DirectTranscription):
    """Nodes at the LGL points on [0, 1] instead of equal spacing; same variable layout."""

    kind = "lgl"
    order = 4.0  # spectral for smooth problems; 4 is a cautious stand-in
    control_interpolation = "polynomial"

    @staticmethod
    def mesh(n_intervals: int) -> np.ndarray:
        return (lgl_nodes(n_intervals) + 1.0) / 2.0

    def _dynamics(self, X: ca.SX, U: ca.SX, T: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        N, ocp = self.N, self.ocp
        D = ca.DM(lgl_differentiation(N))
        P = ca.repmat(p, 1, N + 1)
        F = self.fn.f.map(N + 1)(X, U, P)
        # dX/dtau at the nodes is X D^T on [-1, 1]; dt = (T/2) d(-1..1).
        defects = (ca.mtimes(X, D.T) - T / 2 * F) / ca.repmat(ca.DM(ocp.x_scale), 1, N + 1)
        running = ca.SX(0)
        if self.fn.lagrange is not None:
            L = self.fn.lagrange.map(N + 1)(X, U, P)
            running = T / 2 * ca.mtimes(L, ca.DM(lgl_weights(N)))
        return ca.vec(defects), running

    def costate_points(self, mu: np.ndarray, X: np.ndarray, U: np.ndarray, T: float,
                       p: np.ndarray, ends: Endpoints, tau: np.ndarray) -> CostatePoints:
        """The LGL covector mapping with closure conditions (`lgl_costates`)."""
        A = np.asarray(self._state_jacobian()(X.T, U.T, np.tile(p[:, None], (1, self.N + 1))))
        A = A.reshape(self.ocp.nx, self.N + 1, self.ocp.nx).transpose(1, 0, 2)
        lam = lgl_costates(mu, A, T, transversality(self.ocp, ends, p))
        return CostatePoints(tau * T, lam, X, U)

    def defect_points(self, g: np.ndarray, T: float, tau: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
        """The collocation residuals D x - (T/2) f at the nodes, weighted by the quadrature
        weights (each node's share of the integral of x' - f: a state difference)."""
        rows = np.asarray(g, float).reshape(self.N + 1, -1) * np.asarray(self.ocp.x_scale)
        return tau * T, rows * lgl_weights(self.N)[:, None]

    def _state_jacobian(self) -> ca.Function:
        """df/dx at every node (mapped)."""
        if not hasattr(self, "_jac_x"):
            x = ca.SX.sym("x", self.ocp.nx)
            u = ca.SX.sym("u", self.ocp.nu)
            q = ca.SX.sym("p", self.ocp.n_params)
            self._jac_x = ca.Function("f_x", [x, u, q], [ca.jacobian(self.fn.f(x, u, q), x)]
                                      ).map(self.N + 1)
        return self._jac_x

    def dense(
        self, T: float, X: np.ndarray, U: np.ndarray, p: np.ndarray, per_interval: int,
        tau: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The interpolating polynomials of states and controls, sampled evenly plus at the
        nodes (so a plot passes exactly through the node markers)."""
        s = np.union1d(np.linspace(0.0, 1.0, self.N * per_interval + 1), tau)
        return s * T, interpolate(tau, X, s), interpolate(tau, U, s)


