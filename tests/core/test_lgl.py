"""Legendre–Gauss–Lobatto nodes, weights, differentiation and interpolation
(solvers/lgl.py; paper 001, eqs. 2–4)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.polynomial import legendre as leg

from solvers.lgl import (
    interpolate,
    lgl_differentiation,
    lgl_nodes,
    lgl_weights,
)

DEGREES = (8, 9, 16, 31, 32, 64, 100, 127, 128)


def _random_legendre_series(degree: int, seed: int) -> np.ndarray:
    """Coefficients of a random polynomial of exactly this degree in the Legendre basis
    (well conditioned on [-1, 1] even at degree 128, unlike monomials)."""
    rng = np.random.default_rng(seed)
    return rng.standard_normal(degree + 1)


@pytest.mark.parametrize("N", DEGREES)
def test_nodes_are_endpoints_and_zeros_of_legendre_derivative(N: int) -> None:
    t = lgl_nodes(N)
    assert t.shape == (N + 1,)
    assert t[0] == -1.0 and t[-1] == 1.0
    assert np.all(np.diff(t) > 0)
    np.testing.assert_allclose(t, -t[::-1], atol=1e-14)  # symmetric
    dLN = leg.legval(t[1:-1], leg.legder(np.eye(N + 1)[N]))
    # L'_N has size ~N^2 near the ends: compare with that scale.
    assert np.max(np.abs(dLN)) < 1e-11 * N**2


@pytest.mark.parametrize("N", DEGREES)
def test_weights_match_paper_formula(N: int) -> None:
    t, w = lgl_nodes(N), lgl_weights(N)
    LN = leg.legval(t, np.eye(N + 1)[N])
    np.testing.assert_allclose(w, 2.0 / (N * (N + 1) * LN**2), rtol=1e-12)
    assert abs(w.sum() - 2.0) < 1e-13


@pytest.mark.parametrize("N", DEGREES)
def test_differentiation_exact_for_degree_up_to_N(N: int) -> None:
    t, D = lgl_nodes(N), lgl_differentiation(N)
    for degree in (0, 1, N // 2, N - 1, N):
        c = _random_legendre_series(degree, seed=degree)
        p, dp = leg.legval(t, c), leg.legval(t, leg.legder(c))
        scale = max(np.max(np.abs(dp)), 1.0)
        assert np.max(np.abs(D @ p - dp)) < 1e-10 * scale, f"degree {degree}"


@pytest.mark.parametrize("N", DEGREES)
def test_differentiation_matrix_corners(N: int) -> None:
    """Paper eq. 4: D_00 = -N(N+1)/4, D_NN = N(N+1)/4, other diagonal entries zero."""
    D = lgl_differentiation(N)
    assert D[0, 0] == pytest.approx(-N * (N + 1) / 4, rel=1e-10)
    assert D[N, N] == pytest.approx(N * (N + 1) / 4, rel=1e-10)
    assert np.max(np.abs(np.diag(D)[1:-1])) < 1e-9 * N**2


@pytest.mark.parametrize("N", DEGREES)
def test_quadrature_exact_for_degree_up_to_2N_minus_1(N: int) -> None:
    t, w = lgl_nodes(N), lgl_weights(N)
    for degree in (0, 1, N, 2 * N - 2, 2 * N - 1):
        c = _random_legendre_series(degree, seed=degree + 1)
        exact = 2.0 * c[0]  # only L_0 has a non-zero integral over [-1, 1]
        quad = w @ leg.legval(t, c)
        assert abs(quad - exact) < 1e-12 * max(1.0, np.abs(c).sum()), f"degree {degree}"


@pytest.mark.parametrize("N", (8, 16, 64))
def test_quadrature_not_exact_at_degree_2N(N: int) -> None:
    """The bound is sharp: L_N^2 (degree 2N) is integrated wrongly (the test can fail)."""
    t, w = lgl_nodes(N), lgl_weights(N)
    LN = leg.legval(t, np.eye(N + 1)[N])
    assert abs(w @ LN**2 - 2.0 / (2 * N + 1)) > 1e-3 / N


@pytest.mark.parametrize("N", (8, 64, 128))
def test_interpolation_reproduces_polynomials_of_degree_N(N: int) -> None:
    t = lgl_nodes(N)
    c = _random_legendre_series(N, seed=3)
    s = np.linspace(-1.0, 1.0, 257)
    values = np.column_stack([leg.legval(t, c), leg.legval(t, 2 * c)])
    out = interpolate(t, values, s)
    assert out.shape == (257, 2)
    exact = leg.legval(s, c)
    np.testing.assert_allclose(out[:, 0], exact, atol=1e-10 * np.max(np.abs(exact)))
    np.testing.assert_allclose(out[:, 1], 2 * exact, atol=2e-10 * np.max(np.abs(exact)))
    # at the nodes themselves the values come back unchanged
    np.testing.assert_array_equal(interpolate(t, values[:, 0], t), values[:, 0])


def test_exactness_for_every_degree_8_to_128() -> None:
    """D exact for degree <= N and quadrature exact for degree <= 2N - 1, all N in 8..128."""
    for N in range(8, 129):
        t, w, D = lgl_nodes(N), lgl_weights(N), lgl_differentiation(N)
        c = _random_legendre_series(N, seed=N)
        dp = leg.legval(t, leg.legder(c))
        assert np.max(np.abs(D @ leg.legval(t, c) - dp)) < 1e-10 * np.max(np.abs(dp)), N
        c2 = _random_legendre_series(2 * N - 1, seed=N)
        assert abs(w @ leg.legval(t, c2) - 2.0 * c2[0]) < 1e-12 * np.abs(c2).sum(), N
