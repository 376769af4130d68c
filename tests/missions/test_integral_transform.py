"""Paper 002's integral transformation + multiplier method + BFGS (solvers/transcription/
integral_transform.py, solvers/nlp/multiplier_method.py, solvers/nlp/bfgs.py)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from solvers.missions.lunar_landing.integral_transform import (
    STEPS_PER_SEGMENT,
    _params,
    decode_trajectory,
    solve_integral_transform,
)
from solvers.nlp.bfgs import minimize_bfgs
from solvers.nlp.multiplier_method import solve_multiplier_method

PAPER = dict(r0=1.753e6, omega0=9.65e-4, m0=600.0, thrust=2000.0, exhaust_speed=2940.0,
             mu=4.90275e12, radius=1.738e6)
PAPER_TF = 398.03868  # s, paper 002 (integral transformation); Pontryagin: 398.03873
PAPER_FUEL = 270.77461  # kg; Pontryagin: 270.77465


@pytest.fixture(scope="module")
def paper_solution():
    return solve_integral_transform(**PAPER, n_segments=30, sigma0=20.0, psi_guess=0.0)


def test_paper_case(paper_solution):
    r = paper_solution
    assert r.converged, r.message
    assert r.tf == pytest.approx(PAPER_TF, rel=1e-4)
    assert r.fuel == pytest.approx(PAPER_FUEL, rel=1e-4)
    assert r.fuel == pytest.approx(PAPER["thrust"] * r.tf / PAPER["exhaust_speed"])
    assert r.constraint_violation < 1e-4
    assert abs(r.x_dense[-1, 0] - PAPER["radius"]) < 1e-4
    assert abs(r.x_dense[-1, 1]) < 1e-5
    assert r.n_variables == 31 and r.n_constraints == 2
    assert r.psi_nodes.shape == (31,) and r.varpi_nodes.shape == (31,)
    assert r.x_nodes.shape == (31, 5) and r.t_nodes.shape == (31,)
    k = 30 * r.steps_per_segment + 1
    assert r.x_dense.shape == (k, 5) and r.t_dense.shape == (k,) and r.psi_dense.shape == (k,)
    assert r.varpi_nodes[0] == pytest.approx(-PAPER["omega0"]) and r.varpi_nodes[-1] == 0.0
    np.testing.assert_allclose(r.x_nodes[:, 3], -r.varpi_nodes)
    assert r.x_nodes[0, 0] == PAPER["r0"] and r.x_nodes[0, 4] == PAPER["m0"]
    assert r.t_nodes[0] == 0.0 and r.t_nodes[-1] == pytest.approx(r.tf)
    assert np.all(np.diff(r.t_dense) > 0)
    # The optimal steering rises almost linearly from a few degrees down to ~28 deg up.
    assert np.all(np.abs(np.degrees(r.psi_nodes)) < 35)
    assert r.outer_iterations >= 1 and r.inner_iterations >= r.outer_iterations
    assert r.integrations >= r.inner_iterations
    its = [h[0] for h in r.history]
    assert its[0] == 0 and its == sorted(its) and len(its) >= 2
    for _, t_nodes, x_nodes in r.history:
        assert t_nodes.shape == (31,) and x_nodes.shape == (31, 5)


def _transformed_ivp(psi_nodes, p, rtol=1e-10):
    """Terminal (r, v, theta, t) of the transformed ODE by DOP853, segment by segment."""
    r0, omega0, m0, thrust, c, mu, _ = p
    n = psi_nodes.size - 1
    grid = np.linspace(-omega0, 0.0, n + 1)

    def rhs(w, y):
        r, v, _, t = y
        psi = np.interp(w, grid, psi_nodes)
        acc = thrust / (m0 - thrust / c * t)
        rate = (acc * np.cos(psi) - 2 * v * w) / r
        return np.array([v, acc * np.sin(psi) - mu / r**2 + r * w**2, -w, 1.0]) / rate

    y = np.array([r0, 0.0, 0.0, 0.0])
    for a, b in zip(grid[:-1], grid[1:], strict=True):
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=rtol, atol=1e-12 * np.abs(y) + 1e-9)
        y = sol.y[:, -1]
    return y


def test_abm4_accuracy(paper_solution):
    p = _params(*PAPER.values())
    psi = paper_solution.psi_nodes
    s = STEPS_PER_SEGMENT
    _, t1, x1, _ = decode_trajectory(psi, p, 30, s)
    _, t2, x2, _ = decode_trajectory(psi, p, 30, 2 * s)
    assert abs(t2[-1] - t1[-1]) < 1e-6 * t1[-1]
    ref = _transformed_ivp(psi, p)
    assert x1[-1, 0] == pytest.approx(ref[0], rel=1e-6)
    assert abs(x1[-1, 1] - ref[1]) < 1e-6 * 1.7e3  # relative to the orbital speed
    assert x1[-1, 2] == pytest.approx(ref[2], rel=1e-6)
    assert t1[-1] == pytest.approx(ref[3], rel=1e-6)


@pytest.mark.parametrize(("guess_deg", "sigma0"), [(-20, 20.0), (20, 20.0), (40, 20.0),
                                                   (-30, 0.2), (70, 0.2)])
def test_convergence_from_constant_guesses(guess_deg, sigma0, paper_solution):
    r = solve_integral_transform(**PAPER, sigma0=sigma0, psi_guess=np.radians(guess_deg))
    assert r.converged, r.message
    assert r.tf == pytest.approx(paper_solution.tf, rel=1e-7)
    np.testing.assert_allclose(r.psi_nodes, paper_solution.psi_nodes, atol=1e-3)


def test_warm_start_new_thrust_and_node_count(paper_solution):
    r = solve_integral_transform(**dict(PAPER, thrust=2020.0), warm_psi=paper_solution.psi_nodes)
    assert r.converged, r.message
    assert r.tf < paper_solution.tf
    r20 = solve_integral_transform(**PAPER, n_segments=20, warm_psi=paper_solution.psi_nodes,
                                   warm_lam=paper_solution.lam)
    assert r20.converged, r20.message
    assert r20.psi_nodes.shape == (21,)
    assert r20.tf == pytest.approx(paper_solution.tf, rel=1e-5)


@pytest.mark.parametrize("case", [dict(thrust=300.0), dict(psi_guess=np.radians(100.0))])
def test_not_integrable_is_reported(case):
    kw = dict(PAPER)
    kw.update({k: v for k, v in case.items() if k != "psi_guess"})
    r = solve_integral_transform(**kw, psi_guess=case.get("psi_guess", 0.0))
    assert not r.converged
    assert "cannot be integrated" in r.message


def test_bfgs_rosenbrock():
    calls = 0

    def rosen(z):
        nonlocal calls
        calls += 1
        x, y = z
        f = 100 * (y - x**2) ** 2 + (1 - x) ** 2
        g = np.array([-400 * x * (y - x**2) - 2 * (1 - x), 200 * (y - x**2)])
        return f, g

    r = minimize_bfgs(rosen, [-1.2, 1.0], max_iter=200, gtol=1e-9)
    assert r.converged, r.message
    np.testing.assert_allclose(r.z, [1.0, 1.0], atol=1e-7)
    assert r.evaluations == calls and r.iterations < 100


def test_bfgs_rejects_non_finite_trial_points():
    # f is undefined (NaN) for x <= 0; the minimum of x - log x is at x = 1.
    def fun(z):
        x = z[0]
        if x <= 0:
            return float("nan"), np.array([np.nan])
        return x - np.log(x), np.array([1 - 1 / x])

    r = minimize_bfgs(fun, [5.0], gtol=1e-10)
    assert r.converged
    assert r.z[0] == pytest.approx(1.0, abs=1e-8)


def test_multiplier_method_circle():
    # min x + y  s.t.  x^2 + y^2 = 2  ->  (-1, -1); with L = f - lam h, lam = -1/2.
    def f_and_grad(z):
        return z[0] + z[1], np.array([1.0, 1.0])

    def h_and_jac(z):
        return np.array([z @ z - 2.0]), 2 * z.reshape(1, 2)

    r = solve_multiplier_method(f_and_grad, h_and_jac, [0.5, -0.2], sigma0=1.0, beta=2.0,
                                gamma=0.5, lam0=[0.0], tol_h=1e-10, inner_gtol=1e-9)
    assert r.converged, r.message
    np.testing.assert_allclose(r.z, [-1.0, -1.0], atol=1e-8)
    assert r.lam[0] == pytest.approx(-0.5, abs=1e-6)
    assert r.f == pytest.approx(-2.0)
    assert r.history[0][0] == 0 and r.history[-1][0] == r.outer_iterations
