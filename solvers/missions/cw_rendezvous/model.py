"""The mission's own model pieces: the planar state subset, the CW model handed to the
burn/coast arc transcription (paper 000, eqs. 1 and 3), and the primer-vector (Pontryagin)
solution of minimum-burn-time rendezvous.

The primer-vector solution is an independent check of the direct methods of paper 000. With
cost ∫ σ dt (throttle σ in [0, 1], acceleration a σ û) the Hamiltonian
H = σ + λᵀ(A x + a σ B û) is minimised by û = -λ_v/|λ_v| and σ = 1 where the switching
function a|λ_v| - 1 > 0 (bang–bang). The costate obeys λ' = -Aᵀλ, so λ(t) = Φ(-t)ᵀ λ0 in
closed form. Shooting on λ0 until the chaser reaches the target at T gives the optimum
without any discretisation of the control.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root

from ...dynamics.clohessy_wiltshire import cw_rhs, cw_stm, cw_stm_numeric
from .burn_coast import ArcModel

PLANAR = (0, 1, 3, 4)  # x, y, vx, vy: the coplanar case's states
GRID = 4000  # samples of the switching function per transfer


def state_indices(planar: bool) -> list[int]:
    """Indices of the full CW state the arc transcription carries."""
    return list(PLANAR) if planar else list(range(6))


@cache
def arc_model(planar: bool) -> ArcModel:
    """The CW equations (paper 000, eq. 1) and their STM (eq. 3) on the planar (x, y, x',
    y') or the full state; parameters (initial state, w, a, T)."""
    idx = state_indices(planar)
    nx = len(idx)
    nu = 2 if planar else 3

    def rhs(x: ca.SX, acc: ca.SX, p: ca.SX) -> ca.SX:
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


@dataclass
class PrimerSolution:
    """The extremal: initial costate, switch times, burn intervals, burn time, final miss."""

    lambda0: np.ndarray
    switches: np.ndarray
    burns: list[tuple[float, float]]
    burn_time: float
    miss: np.ndarray
    converged: bool


def _system(w: float, idx: list[int]) -> np.ndarray:
    """The CW system matrix A (x' = A x + B a u) on the state subset `idx`."""
    A = np.zeros((6, 6))
    A[0:3, 3:6] = np.eye(3)
    A[3, 4] = 2 * w
    A[4, 3] = -2 * w
    A[4, 1] = 3 * w**2
    A[5, 2] = -(w**2)
    return A[np.ix_(idx, idx)]


class PrimerVectorShooting:
    """Shooting function and solver for one (x0, w, a, T) on the state subset `idx`."""

    def __init__(self, x0: np.ndarray, w: float, accel: float, total_time: float,
                 idx: list[int]) -> None:
        self.idx = idx
        self.n = len(idx)
        self.x0 = np.asarray(x0, float)[idx]
        self.w, self.a, self.T = w, accel, total_time
        self.A = _system(w, idx)
        self.vel = [i for i, j in enumerate(idx) if j >= 3]
        self.grid = np.linspace(0.0, total_time, GRID + 1)
        self._primer_maps = self._primer_map(self.grid)

    def _primer_map(self, t: float | np.ndarray) -> np.ndarray:
        """Rows of Φ(-t)ᵀ giving λ_v(t) from λ0 (stacked for an array of times)."""
        phi = cw_stm_numeric(self.w, -np.asarray(t))[..., self.idx, :][..., self.idx]
        return np.swapaxes(phi, -1, -2)[..., self.vel, :]

    def lambda_v(self, lam0: np.ndarray, t: float) -> np.ndarray:
        """The primer vector λ_v(t) (velocity costate)."""
        return self._primer_map(t) @ lam0

    def switching(self, lam0: np.ndarray) -> np.ndarray:
        """Switching function a|λ_v| - 1 on the sampling grid (burn where > 0)."""
        return self.a * np.linalg.norm(self._primer_maps @ lam0, axis=1) - 1.0

    def burns(self, lam0: np.ndarray) -> list[tuple[float, float]]:
        """Burn intervals: where the switching function is positive, roots refined."""
        s = self.switching(lam0)
        f = lambda t: self.a * np.linalg.norm(self.lambda_v(lam0, t)) - 1.0  # noqa: E731
        edges = []
        for k in np.nonzero(np.sign(s[:-1]) != np.sign(s[1:]))[0]:
            edges.append(brentq(f, self.grid[k], self.grid[k + 1], xtol=1e-13))
        points = [0.0, *edges, self.T]
        out = []
        for t0, t1 in zip(points[:-1], points[1:], strict=True):
            if f(0.5 * (t0 + t1)) > 0:
                out.append((t0, t1))
        return out

    def propagate(self, lam0: np.ndarray) -> np.ndarray:
        """Final state under the primer-vector control (burns integrated, coasts by STM)."""
        x, t = self.x0.copy(), 0.0
        B = np.zeros((self.n, len(self.vel)))
        B[self.vel, np.arange(len(self.vel))] = 1.0

        def rhs(t: float, x: np.ndarray) -> np.ndarray:
            lv = self.lambda_v(lam0, t)
            return self.A @ x - self.a * B @ (lv / np.linalg.norm(lv))

        for t0, t1 in self.burns(lam0):
            x = cw_stm_numeric(self.w, t0 - t)[np.ix_(self.idx, self.idx)] @ x
            sol = solve_ivp(rhs, (t0, t1), x, method="DOP853", rtol=1e-12, atol=1e-9)
            x, t = sol.y[:, -1], t1
        return cw_stm_numeric(self.w, self.T - t)[np.ix_(self.idx, self.idx)] @ x

    def initial_costate(self, t_nodes: np.ndarray, directions: np.ndarray,
                        first_switch: float) -> np.ndarray:
        """λ0 from a direct solution: λ_v(t_k) antiparallel to its thrust directions at the
        burn nodes (a homogeneous linear fit), scaled so a|λ_v| = 1 at its first switch."""
        rows = []
        for t, u in zip(t_nodes, directions, strict=True):
            M = self._primer_map(t)
            u = u[: len(self.vel)]
            if len(self.vel) == 2:
                rows.append(u[0] * M[1] - u[1] * M[0])
            else:
                rows.extend(np.cross(u, M.T).T)
        lam = np.linalg.svd(np.array(rows))[2][-1]
        if np.mean([self.lambda_v(lam, t) @ u[: len(self.vel)]
                    for t, u in zip(t_nodes, directions, strict=True)]) > 0:
            lam = -lam
        return lam / (self.a * np.linalg.norm(self.lambda_v(lam, first_switch)))

    def solve(self, lam_guess: np.ndarray) -> PrimerSolution:
        """Shoot on λ0 (Powell hybrid) until the chaser reaches the target at T."""
        scale = np.where(np.arange(self.n) < self.n // 2, 1e4, 100.0)
        sol = root(lambda lam: self.propagate(lam) / scale, lam_guess, method="hybr",
                   options={"xtol": 1e-13})
        lam = sol.x
        burns = self.burns(lam)
        miss = self.propagate(lam)
        return PrimerSolution(
            lambda0=lam, switches=np.array([t for b in burns for t in b]), burns=burns,
            burn_time=float(sum(t1 - t0 for t0, t1 in burns)), miss=miss,
            converged=bool(np.linalg.norm(miss[: self.n // 2]) < 1e-3),
        )
