"""Primer-vector theory for the minimum-burn-time rendezvous (Lawden 1963; paper 000's
problem): the least thrust acceleration that can reach the target, the switching function,
and the extremal by shooting on the initial costate.

With the free-structure cost J = int s/a dt (|a u| <= s <= a) the Hamiltonian
H = s/a + lambda^T (A x + B a_vec) is least for a_vec = -s lambda_v/|lambda_v| and

    s = a where S(t) = a |lambda_v(t)| - 1 > 0 (burn), s = 0 where S < 0 (coast),   (1)

the switching function S being the primer magnitude a|lambda_v| less one. The costate obeys
lambda' = -A^T lambda, so lambda(t) = Phi(-t)^T lambda(0) with the CW transition matrix.

Reachability: x(T) = Phi(T) x0 + a int_0^T Phi(T-s) B u ds with |u| <= 1, so the target is
reachable iff -Phi(T) x0 lies in a K, K = {int Phi(T-s) B u ds}, convex and symmetric, i.e.
iff c^T lambda <= a int |B^T Phi(T-s)^T lambda| ds for every lambda (c = Phi(T) x0). Hence

    a_min = max_lambda c^T lambda / int |B^T Phi(T-s)^T lambda| ds                    (2)

(a convex problem: minimise the integral subject to c^T lambda = 1). Any lambda certifies
a lower bound, so a request with a below the computed a_min is proven impossible.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq, minimize, root

from ...dynamics.clohessy_wiltshire import cw_stm_numeric

PANELS, POINTS = 64, 8  # composite Gauss-Legendre rule for the integrals over [0, T]
_XI, _WI = np.polynomial.legendre.leggauss(POINTS)
ARC_POINTS = 24  # Gauss points per burn arc in the shooting
GRID = 2001  # samples of S(t) to find the switches


def _quadrature(T: float) -> tuple[np.ndarray, np.ndarray]:
    edges = np.linspace(0.0, T, PANELS + 1)
    mid, half = (edges[1:] + edges[:-1]) / 2, np.diff(edges) / 2
    return (mid[:, None] + half[:, None] * _XI).ravel(), (half[:, None] * _WI).ravel()


@lru_cache(maxsize=64)
def min_acceleration(x0: tuple[float, ...], w: float, T: float) -> float:
    """a_min of eq. (2) [m/s^2] for the initial state `x0` (6), CW rate `w` and time `T`."""
    c = cw_stm_numeric(w, T) @ np.asarray(x0, float)
    if not np.any(c):
        return 0.0
    s, wq = _quadrature(T)
    M = cw_stm_numeric(w, T - s)[:, :, 3:].transpose(0, 2, 1)  # B^T Phi(T-s)^T: (Q, 3, 6)
    base = c / (c @ c)
    basis = np.linalg.svd(c[None, :])[2][1:].T  # c-orthogonal directions (6, 5)

    def h(y: np.ndarray) -> tuple[float, np.ndarray]:
        lam = base + basis @ y
        v = M @ lam
        n = np.maximum(np.linalg.norm(v, axis=1), 1e-300)
        grad = np.einsum("q,qi,qij->j", wq / n, v, M)
        return float(wq @ n), basis.T @ grad

    best = minimize(h, np.zeros(5), jac=True, method="BFGS", options={"gtol": 1e-12})
    return 1.0 / best.fun


def costate_path(lam0: np.ndarray, w: float, t: np.ndarray) -> np.ndarray:
    """lambda(t) = Phi(-t)^T lambda(0): rows (len(t), 6)."""
    return np.einsum("kji,j->ki", cw_stm_numeric(w, -np.atleast_1d(t)), lam0)


def switching(lam: np.ndarray, accel: float) -> np.ndarray:
    """S = a |lambda_v| - 1 of eq. (1) for costate rows."""
    return accel * np.linalg.norm(lam[:, 3:], axis=1) - 1.0


@dataclass
class PrimerExtremal:
    """The extremal: initial costate, burn arcs, samples of states, costates and S."""

    lam0: np.ndarray
    burns: list[tuple[float, float]]
    t: np.ndarray
    x: np.ndarray
    lam: np.ndarray
    converged: bool
    residual: float

    @property
    def burn_time(self) -> float:
        return float(sum(b - a for a, b in self.burns))


def _burns(lam0: np.ndarray, w: float, accel: float, T: float) -> list[tuple[float, float]]:
    """Arcs where S > 0, their ends refined by root finding."""
    t = np.linspace(0.0, T, GRID)
    S = switching(costate_path(lam0, w, t), accel)

    def f(tau: float) -> float:
        return float(switching(costate_path(lam0, w, np.array([tau])), accel)[0])

    edges = [0.0] if S[0] > 0 else []
    for k in np.flatnonzero(np.sign(S[1:]) != np.sign(S[:-1])):
        edges.append(brentq(f, t[k], t[k + 1], xtol=1e-12))
    if S[-1] > 0:
        edges.append(T)
    return list(zip(edges[::2], edges[1::2], strict=True))


def _final_state(lam0: np.ndarray, x0: np.ndarray, w: float, accel: float, T: float,
                 burns: list[tuple[float, float]]) -> np.ndarray:
    """x(T) = Phi(T) x0 + a int_burns Phi(T-s) B (-lambda_v/|lambda_v|) ds (Gauss rule on
    every burn arc, where the integrand is smooth)."""
    xi, wi = np.polynomial.legendre.leggauss(ARC_POINTS)
    out = cw_stm_numeric(w, T) @ x0
    for a, b in burns:
        s = (a + b) / 2 + (b - a) / 2 * xi
        lam_v = costate_path(lam0, w, s)[:, 3:]
        u = -lam_v / np.linalg.norm(lam_v, axis=1, keepdims=True)
        out = out + accel * np.einsum("q,qij,qj->i", (b - a) / 2 * wi,
                                      cw_stm_numeric(w, T - s)[:, :, 3:], u)
    return out


def fit_initial_costate(t: np.ndarray, lam: np.ndarray, w: float) -> np.ndarray:
    """lambda(0) whose CW costate path fits costate samples best (least squares)."""
    P = cw_stm_numeric(w, -np.asarray(t, float)).transpose(0, 2, 1)  # rows Phi(-t)^T
    return np.linalg.lstsq(P.reshape(-1, 6), np.asarray(lam, float).ravel(), rcond=None)[0]


def solve_primer(x0: np.ndarray, w: float, accel: float, T: float, lam0: np.ndarray,
                 samples: int = 401) -> PrimerExtremal:
    """Shoot on lambda(0) (started at `lam0`) until the bang-bang primer control of eq. (1)
    reaches the target: x(T) = 0. Unknowns scaled to (T lambda_r, lambda_v), residual to
    (x / 1e4 m, v / 100 m/s)."""
    scale = np.array([T] * 3 + [1.0] * 3)
    res_scale = np.array([1e4] * 3 + [100.0] * 3)

    def residual(z: np.ndarray) -> np.ndarray:
        lam = z / scale
        return _final_state(lam, x0, w, accel, T, _burns(lam, w, accel, T)) / res_scale

    sol = root(residual, np.asarray(lam0, float) * scale, method="hybr",
               options={"xtol": 1e-13})
    lam0 = sol.x / scale
    burns = _burns(lam0, w, accel, T)
    miss = float(np.max(np.abs(residual(sol.x) * res_scale / np.array([1.0] * 3 + [1e-3] * 3))))
    t = np.union1d(np.linspace(0.0, T, samples), np.ravel(burns))
    x = np.array([_final_state(lam0, x0, w, accel, tk, [(a, min(b, tk)) for a, b in burns
                                                        if a < tk]) for tk in t])
    return PrimerExtremal(lam0=lam0, burns=burns, t=t, x=x, lam=costate_path(lam0, w, t),
                          converged=bool(miss < 1.0), residual=miss)
