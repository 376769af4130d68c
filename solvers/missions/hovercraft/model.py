"""Hovercraft in the plane with a thrust of constant magnitude (paper 004, eq. 7; SPEC M5
case 1), and its minimum-time steering by the maximum principle.

State x = (x, y, vx, vy) [m, m/s]; the thrust acceleration A/m [m/s^2] is constant and only
its direction is steered. Two control forms share one right-hand side:
- the paper's thrust angle alpha [rad]: acceleration A/m (cos alpha, sin alpha);
- the thrust vector u = (ux, uy) with |u| <= 1: acceleration A/m u. For minimum time the
  maximum principle makes |u| = 1 wherever the velocity costate is non-zero, so this convex
  relaxation has the same optimum, and it has no degenerate point such as alpha = 0
  (where the angle form's d(vx')/d(alpha) = -A/m sin(alpha) vanishes).

Maximum principle: with H = 1 + p_r·v + p_v·(A/m) d and |d| = 1, the position costate
p_r = lam is constant, the velocity costate is p_v(t) = c - lam t, and the optimal thrust
direction is d = -p_v / |p_v|, i.e. tan(alpha) = (lam_y t - c_y) / (lam_x t - c_x): the
bilinear tangent law (linear tangent when one component of lam vanishes). Free final time
with an autonomous H gives H = 0, so one shooting problem in z = (lam, c, T) remains:

    r(T) = r_f,  v(T) = v_f,  H(0) = 1 + lam·v0 - (A/m) |c| = 0.

v(T) and r(T) are integrals of the analytic d(t); composite Gauss–Legendre quadrature
evaluates them to round-off, so the answer does not depend on any ODE integrator or mesh.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np
from scipy.optimize import root

STATES = ("x", "y", "vx", "vy")
STATE_UNITS = ("m", "m", "m/s", "m/s")
# The paper's state box (x, y, vx, vy) and final-time bounds.
X_LB = (0.0, 0.0, 0.0, -10.0)
X_UB = (30.0, 30.0, 20.0, 10.0)
T_LB, T_UB = 0.0, 15.0


def rhs_angle(x: ca.SX, alpha: ca.SX, accel: float | ca.SX) -> ca.SX:
    """x' with the paper's thrust angle (eq. 7); CasADi symbols or numbers."""
    return ca.vertcat(x[2], x[3], accel * ca.cos(alpha), accel * ca.sin(alpha))


def rhs_vector(x: ca.SX, u: ca.SX, accel: float | ca.SX) -> ca.SX:
    """x' with the thrust vector u, |u| <= 1 (the relaxed form)."""
    return ca.vertcat(x[2], x[3], accel * u[0], accel * u[1])


_PANELS = 16
_GAUSS_POINTS = 16


@dataclass
class SteeringSolution:
    """The extremal: costate constants, final time and the shooting residual."""

    T: float
    lam: np.ndarray
    c: np.ndarray
    converged: bool
    residual: float
    message: str

    def direction(self, t: np.ndarray) -> np.ndarray:
        """Unit thrust directions (len(t), 2) of the bilinear tangent law."""
        w = np.outer(np.atleast_1d(t), self.lam) - self.c
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    def costates(self, t: np.ndarray) -> np.ndarray:
        """(p_x, p_y, p_vx, p_vy) at times t: p_r = lam, p_v = c - lam t (s per unit)."""
        t = np.atleast_1d(np.asarray(t, float))
        return np.column_stack([np.tile(self.lam, (len(t), 1)), self.c - np.outer(t, self.lam)])

    def alpha(self, t: np.ndarray) -> np.ndarray:
        d = self.direction(t)
        return np.arctan2(d[:, 1], d[:, 0])

    def states(self, t: np.ndarray, x0: np.ndarray, accel: float) -> np.ndarray:
        """States (len(t), 4) along the extremal, by the same quadrature."""
        return _propagate_many(self.lam, self.c, t, x0, accel)


_XI, _WI = np.polynomial.legendre.leggauss(_GAUSS_POINTS)
# Composite rule on [0, 1]: nodes and weights of `_PANELS` equal panels.
_S01 = ((np.arange(_PANELS)[:, None] + (_XI[None, :] + 1) / 2) / _PANELS).ravel()
_W01 = np.tile(_WI / (2 * _PANELS), _PANELS)


def _propagate_many(lam: np.ndarray, c: np.ndarray, T: np.ndarray, x0: np.ndarray,
                    accel: float) -> np.ndarray:
    """States (len(T), 4) at times T: v = v0 + a ∫ d, r = r0 + v0 T + a ∫ (T - s) d(s) ds."""
    T = np.atleast_1d(np.asarray(T, float))
    s = T[:, None] * _S01[None, :]  # (K, Q) quadrature nodes on each [0, T_k]
    w = T[:, None] * _W01[None, :]
    wv = s[..., None] * lam - c  # (K, Q, 2)
    d = wv / np.linalg.norm(wv, axis=-1, keepdims=True)
    dv = accel * np.einsum("kq,kqj->kj", w, d)
    dr = accel * np.einsum("kq,kqj->kj", w * (T[:, None] - s), d)
    r0, v0 = np.asarray(x0[:2], float), np.asarray(x0[2:], float)
    return np.column_stack([r0 + np.outer(T, v0) + dr, v0 + dv])


def _residual(z: np.ndarray, x0: np.ndarray, xf: np.ndarray, accel: float) -> np.ndarray:
    lam, c, T = z[:2], z[2:4], z[4]
    end = _propagate_many(lam, c, T, x0, accel)[0]
    hamiltonian0 = 1.0 + lam @ x0[2:] - accel * np.linalg.norm(c)
    return np.concatenate([end - xf, [hamiltonian0]])


def guess_from_steering(
    t: np.ndarray, alpha: np.ndarray, x0: np.ndarray, accel: float
) -> np.ndarray:
    """(lam, c, T) fitted to a direct solution's steering angles at its nodes.

    d(t) parallel to lam t - c is linear and homogeneous in (lam, c): the right singular
    vector of the smallest singular value fits it; H(0) = 0 fixes the scale.
    """
    d = np.column_stack([np.cos(alpha), np.sin(alpha)])
    rows = np.column_stack([-d[:, 1] * t, d[:, 0] * t, d[:, 1], -d[:, 0]])
    z = np.linalg.svd(rows)[2][-1]
    lam, c = z[:2], z[2:]
    if np.mean(np.sum(d * (np.outer(t, lam) - c), axis=1)) < 0:
        lam, c = -lam, -c
    scale = 1.0 / (accel * np.linalg.norm(c) - lam @ x0[2:])
    return np.concatenate([scale * lam, scale * c, [t[-1]]])


def cold_guess(x0: np.ndarray, xf: np.ndarray, accel: float) -> np.ndarray:
    """Constant thrust along the velocity change, for T = |dv| / a (no direct solution)."""
    dv = np.asarray(xf[2:], float) - np.asarray(x0[2:], float)
    speed_change = max(float(np.linalg.norm(dv)), 1e-3)
    d = dv / speed_change if np.linalg.norm(dv) > 0 else np.array([1.0, 0.0])
    return np.concatenate([[0.0, 0.0], -d / accel, [speed_change / accel]])


def solve_min_time(
    x0: np.ndarray, xf: np.ndarray, accel: float, guess: np.ndarray | None = None,
    tol: float = 1e-13,
) -> SteeringSolution:
    """Solve the shooting equations (r(T) = r_f, v(T) = v_f, H(0) = 0) from `guess` (see
    `guess_from_steering`, `cold_guess`)."""
    x0, xf = np.asarray(x0, float), np.asarray(xf, float)
    z0 = cold_guess(x0, xf, accel) if guess is None else np.asarray(guess, float)
    sol = root(_residual, z0, args=(x0, xf, accel), method="hybr", options={"xtol": tol})
    z = sol.x
    res = float(np.max(np.abs(_residual(z, x0, xf, accel))))
    converged = bool(res < 1e-9 and z[4] > 0)
    message = "extremal found" if converged else f"shooting did not converge ({sol.message})"
    return SteeringSolution(T=float(z[4]), lam=z[:2].copy(), c=z[2:4].copy(),
                            converged=converged, residual=res, message=message)
