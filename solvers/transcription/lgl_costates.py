"""Costates of the LGL pseudospectral transcription from its multipliers, with the closure
conditions.

The defects sum_j D_ij x_j - (T/2) f_i weigh the integral of lambda^T (x' - f) by the LGL
quadrature, so lambda(t_i) = -mu_i / w_i (Fahroo & Ross 2001, J. Guid. Control Dyn. 24(2)).
Taken alone that mapping fails at LGL nodes: the stationarity conditions of the NLP at the
N-1 interior nodes,

    sum_i D_ij mu_i - (T/2) A_j^T mu_j = (running-cost and path terms),   A = df/dx,   (1)

leave 2 nx free directions where the continuous adjoint leaves nx, and the NLP's own
multipliers carry a spurious part in them: a sawtooth close to L_N(t_i) (v_i = w_i L_N(t_i)
annihilates D exactly, since sum_i v_i (D q)_i is the exact quadrature of L_N q' = 0 for every
polynomial q of degree N), the well-known non-convergence of LGL costates (Garg et al. 2010,
Automatica 46). The covector mapping theorem (Gong, Ross, Kang & Fahroo 2008, Comput. Optim.
Appl. 41) restores it with closure conditions: the costate must also meet the transversality
conditions at both ends. So the estimate is the solution of (1) (the NLP's multipliers plus a
combination of the null space of (1)) that meets lambda(t0) and lambda(tf) from the end
multipliers (`costates.transversality`) and, in the directions those leave open, has the
least energy in the top Legendre modes (a smooth costate has negligible top coefficients).
Measured: spectral convergence, like the states (tests).
"""

from __future__ import annotations

import numpy as np

from ..lgl import lgl_differentiation, lgl_nodes, lgl_weights


def lgl_costates(mu: np.ndarray, A: np.ndarray, T: float,
                 ends: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Costates (N+1, nx) at the LGL nodes from the defect multipliers `mu` (unscaled),
    the state Jacobians A (N+1, nx, nx) and the transversality values (lambda_0, lambda_N)."""
    N1, nx = mu.shape
    N = N1 - 1
    w = lgl_weights(N)
    lam = -mu / w[:, None]
    basis = _null_space(_interior_equations(A, T)).reshape(N1, nx, -1) / -w[:, None, None]
    if basis.shape[2] == 0:
        return lam
    # Closure: the end values, in the least-squares sense.
    E = np.vstack([basis[0], basis[-1]])
    c = np.linalg.lstsq(E, np.concatenate([ends[0] - lam[0], ends[1] - lam[-1]]),
                        rcond=None)[0]
    lam = lam + basis @ c
    # The directions the ends leave open: the smoothest member.
    free = _null_space(E)
    if free.shape[1]:
        top = _top_modes(N)
        R = np.einsum("mi,iak->mak", top, basis @ free).reshape(-1, free.shape[1])
        d = np.linalg.lstsq(R, -(top @ lam).ravel(), rcond=None)[0]
        lam = lam + basis @ (free @ d)
    return lam


def _interior_equations(A: np.ndarray, T: float) -> np.ndarray:
    """The homogeneous part of (1): rows (interior node j, component a), columns (node i,
    component b) of mu."""
    N1, nx, _ = A.shape
    N = N1 - 1
    D = lgl_differentiation(N)
    M = np.kron(D[:, 1:N].T, np.eye(nx))
    for j in range(1, N):
        M[(j - 1) * nx:j * nx, j * nx:(j + 1) * nx] -= T / 2 * A[j].T
    return M


def _null_space(M: np.ndarray, rtol: float = 1e-10) -> np.ndarray:
    """Orthonormal basis (columns) of the null space of M."""
    _, sv, Vt = np.linalg.svd(M)
    rank = int(np.sum(sv > (sv[0] if sv.size else 0.0) * rtol))
    return Vt[rank:].T


def _top_modes(N: int) -> np.ndarray:
    """Rows: the discrete Legendre coefficients of degrees N - m + 1 .. N at the LGL nodes
    (m = max(2, N // 4)), normalised in the LGL inner product."""
    m = max(2, N // 4)
    w = lgl_weights(N)
    V = np.polynomial.legendre.legvander(lgl_nodes(N), N)[:, N - m + 1:]
    return (V * w[:, None]).T / np.sum(w[:, None] * V**2, axis=0)[:, None]
