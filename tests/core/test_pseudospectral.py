"""LGL pseudospectral collocation of a generic OCP against closed-form optima."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from solvers.lgl import lgl_nodes
from solvers.ocp import OCP, Bounds, Guess
from solvers.transcription.hermite_simpson import HermiteSimpson
from solvers.transcription.pseudospectral import LGLPseudospectral
from solvers.verify import repropagate


def _box(n: int, lim: float = 100.0) -> Bounds:
    return Bounds(x_lb=-lim * np.ones(n), x_ub=lim * np.ones(n), u_lb=-lim * np.ones(1),
                  u_ub=lim * np.ones(1), T_lb=0.0, T_ub=10.0)


def _rest_to_rest() -> OCP:
    """x'' = u, x: 0 -> 1 at rest in T = 1, min ∫ u²/2: u = 6 - 12 t, J = 6 (a cubic)."""
    return OCP(
        states=("x", "v"), controls=("u",), n_params=1,
        dynamics=lambda x, u, p: ca.vertcat(x[1], u[0]),
        initial_state=lambda p: ca.vertcat(0, 0),
        terminal=lambda xf, p: xf - ca.vertcat(1, 0),
        bounds=lambda p: _box(2), guess=lambda p: Guess(np.array([1.0, 0.0]), np.zeros(1), 1.0),
        x_scale=np.ones(2), u_scale=np.ones(1), T_scale=1.0, terminal_scale=np.ones(2),
        lagrange=lambda x, u, p: u[0] ** 2 / 2, fixed_final_time=lambda p: p[0],
    )


def _regulator() -> OCP:
    """x' = u, x(0) = 1, free end, min ∫ (x² + u²)/2 on [0, T]: x = cosh(T - t)/cosh(T),
    J = tanh(T)/2 — smooth but not polynomial, so the error shows the convergence rate."""
    return OCP(
        states=("x",), controls=("u",), n_params=1,
        dynamics=lambda x, u, p: u,
        initial_state=lambda p: ca.DM([1.0]),
        terminal=lambda xf, p: ca.SX(0, 1),
        bounds=lambda p: _box(1), guess=lambda p: Guess(np.array([1.0]), np.zeros(1), 1.0),
        x_scale=np.ones(1), u_scale=np.ones(1), T_scale=1.0, terminal_scale=np.zeros(0),
        lagrange=lambda x, u, p: (x[0] ** 2 + u[0] ** 2) / 2, fixed_final_time=lambda p: p[0],
    )


def test_polynomial_optimum_is_exact_at_low_degree():
    res = LGLPseudospectral(_rest_to_rest(), 4).solve(np.array([1.0]))
    assert res.status == "optimal"
    assert res.cost == pytest.approx(6.0, abs=1e-9)
    np.testing.assert_allclose(res.U[:, 0], 6 - 12 * res.t_nodes, atol=1e-8)
    np.testing.assert_allclose(res.t_nodes, (lgl_nodes(4) + 1) / 2, atol=1e-15)


def test_spectral_convergence_beats_hermite_simpson():
    T = 2.0
    exact = np.tanh(T) / 2
    errors = [abs(LGLPseudospectral(_regulator(), n).solve(np.array([T])).cost - exact)
              for n in (4, 8, 12)]
    hs = abs(HermiteSimpson(_regulator(), 12).solve(np.array([T])).cost - exact)
    assert errors[2] < 1e-10 < errors[0]
    assert errors[1] < 1e-3 * errors[0]
    # Same number of nodes, many orders of magnitude apart.
    assert errors[2] < 1e-3 * hs


def test_dense_polynomial_passes_through_nodes_and_matches_the_dynamics():
    tr = LGLPseudospectral(_regulator(), 10)
    T = 2.0
    res = tr.solve(np.array([T]))
    idx = np.searchsorted(res.t_dense, res.t_nodes)
    np.testing.assert_allclose(res.X_dense[idx], res.X, atol=1e-13)
    exact = np.cosh(T - res.t_dense) / np.cosh(T)
    assert np.max(np.abs(res.X_dense[:, 0] - exact)) < 1e-6
    # Re-propagating the polynomial control reproduces the polynomial state.
    assert res.control_interpolation == "polynomial"
    _, X = repropagate(tr.fn.f, np.array([T]), np.array([1.0]),
                       res.control, res.t_nodes)
    np.testing.assert_allclose(X[:, 0], res.X[:, 0], atol=1e-6)


def test_warm_start_from_another_method_converges_faster():
    hs = HermiteSimpson(_rest_to_rest(), 10).solve(np.array([1.0]))
    tr = LGLPseudospectral(_rest_to_rest(), 6)
    cold = tr.solve(np.array([1.0]))
    warm = tr.solve(np.array([1.0]), hs.warm)
    assert warm.status == cold.status == "optimal"
    assert warm.cost == pytest.approx(cold.cost, abs=1e-9)
    assert warm.iterations <= cold.iterations
    # Its own warm start re-solves in at most a couple of iterations.
    again = tr.solve(np.array([1.0]), warm.warm)
    assert again.iterations <= 2


def test_hermite_simpson_on_a_mesh_given_per_solve():
    """With `variable_mesh` the interval lengths are a parameter of the one built NLP: on
    equal steps it gives the fixed-mesh answer; on a graded mesh it keeps fourth order
    (J = tanh(T)/2 closed form); its nodes sit on the mesh; a mesh that is not one is
    refused, and so is any mesh for a method that places its own nodes."""
    T, exact = 2.0, np.tanh(2.0) / 2
    fixed = HermiteSimpson(_regulator(), 12).solve(np.array([T]))
    free = HermiteSimpson(_regulator(), 12, variable_mesh=1)
    assert free.solve(np.array([T])).cost == pytest.approx(fixed.cost, abs=1e-13)
    graded = np.linspace(0.0, 1.0, 13) ** 1.5
    res = free.solve(np.array([T]), tau=graded)
    assert res.status == "optimal"
    np.testing.assert_allclose(res.t_nodes, graded * T, atol=1e-15)
    np.testing.assert_allclose(res.warm.tau, graded)
    assert 0 < abs(res.cost - exact) < 10 * abs(fixed.cost - exact)
    finer = HermiteSimpson(_regulator(), 24, variable_mesh=1).solve(
        np.array([T]), tau=np.linspace(0.0, 1.0, 25) ** 1.5)
    assert abs(finer.cost - exact) < abs(res.cost - exact) / 10  # ~2^4 at order 4
    # A warm start from another mesh of the same NLP is taken node for node.
    back = free.solve(np.array([T]), res.warm, tau=np.linspace(0.0, 1.0, 13))
    assert back.cost == pytest.approx(fixed.cost, abs=1e-12)
    for bad in (graded[::-1], graded[:-1], np.r_[graded[:-1], 0.99]):
        with pytest.raises(ValueError, match="increasing positions from 0 to 1"):
            free.solve(np.array([T]), tau=bad)
    with pytest.raises(ValueError, match="takes no mesh"):
        LGLPseudospectral(_regulator(), 4).solve(np.array([T]), tau=np.linspace(0, 1, 5))
