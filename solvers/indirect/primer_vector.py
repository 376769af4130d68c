"""Primer-vector (Pontryagin) solution of minimum-burn-time rendezvous with the CW equations.

An independent check of the direct methods of paper 000. With cost ∫ σ dt (throttle σ in
[0, 1], acceleration a σ û) the Hamiltonian H = σ + λᵀ(A x + a σ B û) is minimised by
û = -λ_v/|λ_v| and σ = 1 where the switching function a|λ_v| - 1 > 0 (bang–bang). The
costate obeys λ' = -Aᵀλ, so λ(t) = Φ(-t)ᵀ λ0 in closed form. Shooting on λ0 until the
chaser reaches the target at T gives the optimum without any discretisation of the control.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root

from ..dynamics.clohessy_wiltshire import cw_stm_numeric

GRID = 4000  # samples of the switching function per transfer


@dataclass
class PrimerSolution:
    lambda0: np.ndarray
    switches: np.ndarray
    burns: list[tuple[float, float]]
    burn_time: float
    miss: np.ndarray
    converged: bool


def _system(w: float, idx: list[int]) -> np.ndarray:
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
        return self._primer_map(t) @ lam0

    def switching(self, lam0: np.ndarray) -> np.ndarray:
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
