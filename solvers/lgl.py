"""Legendre–Gauss–Lobatto nodes, quadrature weights and differentiation matrix (paper 001,
eq. 4).

For degree N the N+1 nodes are -1, the N-1 zeros of L'_N and +1; the weights are
w_i = 2 / (N (N+1) L_N(t_i)^2); D maps values at the nodes to the derivative of their
interpolating polynomial at the nodes. Quadrature is exact for degree <= 2N - 1.
"""

from __future__ import annotations

from functools import cache

import numpy as np


def _legendre_table(N: int, t: np.ndarray) -> np.ndarray:
    """Rows L_0(t) .. L_N(t) by the three-term recurrence."""
    table = np.zeros((N + 1, t.size))
    table[0] = 1.0
    if N >= 1:
        table[1] = t
    for k in range(2, N + 1):
        table[k] = ((2 * k - 1) * t * table[k - 1] - (k - 1) * table[k - 2]) / k
    return table


@cache
def _lgl(N: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    if N < 1:
        raise ValueError(f"LGL degree must be >= 1, got {N}")
    # Newton iteration on (1 - t^2) L'_N(t) = 0 from the Chebyshev–Gauss–Lobatto points,
    # using (1 - t^2) L'_N = N (L_{N-1} - t L_N).
    t = -np.cos(np.pi * np.arange(N + 1) / N)
    for _ in range(100):
        L = _legendre_table(N, t)
        step = (t * L[N] - L[N - 1]) / ((N + 1) * L[N])
        t = t - step
        if np.max(np.abs(step)) < 1e-16:
            break
    LN = _legendre_table(N, t)[N]
    w = 2.0 / (N * (N + 1) * LN**2)
    diff = t[:, None] - t[None, :]
    np.fill_diagonal(diff, 1.0)
    D = (LN[:, None] / LN[None, :]) / diff
    np.fill_diagonal(D, 0.0)
    # Diagonal by the "negative sum trick" (rows annihilate constants exactly): more
    # accurate than the closed form D_00 = -N(N+1)/4, D_NN = N(N+1)/4 at large N.
    np.fill_diagonal(D, -D.sum(axis=1))
    for arr in (t, w, D):
        arr.setflags(write=False)
    return t, w, D


def lgl_nodes(N: int) -> np.ndarray:
    """The N+1 LGL nodes on [-1, 1], ascending."""
    return _lgl(N)[0]


def lgl_weights(N: int) -> np.ndarray:
    """Quadrature weights at the N+1 LGL nodes."""
    return _lgl(N)[1]


def lgl_differentiation(N: int) -> np.ndarray:
    """(N+1) x (N+1) differentiation matrix at the LGL nodes."""
    return _lgl(N)[2]


def barycentric_weights(nodes: np.ndarray) -> np.ndarray:
    """Weights for barycentric Lagrange interpolation through `nodes`."""
    diff = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(diff, 1.0)
    # Product in log space avoids overflow for large N.
    sign = np.prod(np.sign(diff), axis=1)
    logabs = np.sum(np.log(np.abs(diff)), axis=1)
    logabs -= logabs.max()
    return sign * np.exp(-logabs)


def interpolate(nodes: np.ndarray, values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Evaluate the polynomial through (nodes, values) at t (barycentric formula).

    `values` may be (n,) or (n, k); the result has shape (len(t),) or (len(t), k).
    """
    bw = barycentric_weights(nodes)
    t = np.atleast_1d(np.asarray(t, float))
    diff = t[:, None] - nodes[None, :]
    exact = np.isclose(diff, 0.0, atol=1e-15, rtol=0)
    diff[exact] = 1.0
    terms = bw[None, :] / diff
    vals = np.asarray(values, float)
    out = (terms @ vals) / terms.sum(axis=1)[(...,) + (None,) * (vals.ndim - 1)]
    rows, cols = np.nonzero(exact)
    out[rows] = vals[cols]
    return out
