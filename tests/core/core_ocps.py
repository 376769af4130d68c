"""Small OCPs with known optima that the core tests share."""

from __future__ import annotations

import casadi as ca
import numpy as np

from solvers.ocp import OCP, Bounds, Guess


def double_integrator(min_time: bool = False, v_max: float | None = None,
                       boundary: bool = False) -> OCP:
    """x'' = u from rest at 0 to rest at 1. Min-energy on T = 1 (u = 6 - 12 t, J = 6; the
    speed peaks at 1.5 mid-way, so a path bound v <= v_max < 1.5 is active) or min-time with
    |u| <= 1 (T = 2, bang-bang). `boundary`: the end point as a boundary condition on
    (x0, xf) instead of a terminal one."""
    def bounds(p):
        ulim = 1.0 if min_time else 50.0
        return Bounds(np.array([-5.0, -5.0]), np.array([5.0, 5.0]), np.array([-ulim]),
                      np.array([ulim]), 0.1, 10.0)

    return OCP(
        states=("x", "v"), controls=("u",), n_params=1,
        dynamics=lambda x, u, p: ca.vertcat(x[1], u[0]),
        initial_state=lambda p: ca.vertcat(0, 0),
        terminal=None if boundary else (lambda xf, p: ca.vertcat(xf[0] - 1, xf[1])),
        terminal_scale=np.ones(0 if boundary else 2),
        boundary=(lambda pt, p: ca.vertcat(pt.xf[0] - pt.x0[0] - 1, pt.xf[1])) if boundary
        else None,
        boundary_lb=np.zeros(2), boundary_ub=np.zeros(2),
        bounds=bounds,
        guess=lambda p: Guess(np.array([1.0, 0.0]), np.array([0.0]), 1.5),
        x_scale=np.ones(2), u_scale=np.ones(1), T_scale=1.0,
        mayer=(lambda xf, T, p: T) if min_time else None,
        lagrange=None if min_time else (lambda x, u, p: 0.5 * u[0] ** 2),
        fixed_final_time=None if min_time else (lambda p: 1.0),
        path=(lambda x, u, p: x[1]) if v_max is not None else None,
        path_lb=np.array([-np.inf]), path_ub=np.array([v_max if v_max is not None else 0.0]),
    )
