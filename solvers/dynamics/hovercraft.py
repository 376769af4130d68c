"""Hovercraft in the plane with a thrust of constant magnitude (paper 004, eq. 7; SPEC M5).

State x = (x, y, vx, vy) [m, m/s]; the thrust acceleration A/m [m/s^2] is constant and only
its direction is steered. Two control forms share one right-hand side:
- the paper's thrust angle alpha [rad]: acceleration A/m (cos alpha, sin alpha);
- the thrust vector u = (ux, uy) with |u| <= 1: acceleration A/m u. For minimum time the
  maximum principle makes |u| = 1 wherever the velocity costate is non-zero, so this convex
  relaxation has the same optimum, and it has no degenerate point such as alpha = 0
  (where the angle form's d(vx')/d(alpha) = -A/m sin(alpha) vanishes).
"""

from __future__ import annotations

import casadi as ca

STATES = ("x", "y", "vx", "vy")
STATE_UNITS = ("m", "m", "m/s", "m/s")
# The paper's state box (x, y, vx, vy) and final-time bounds.
X_LB = (0.0, 0.0, 0.0, -10.0)
X_UB = (30.0, 30.0, 20.0, 10.0)
T_LB, T_UB = 0.0, 15.0


def rhs_angle(x, alpha, accel):
    """x' with the paper's thrust angle (eq. 7); CasADi symbols or numbers."""
    return ca.vertcat(x[2], x[3], accel * ca.cos(alpha), accel * ca.sin(alpha))


def rhs_vector(x, u, accel):
    """x' with the thrust vector u, |u| <= 1 (the relaxed form)."""
    return ca.vertcat(x[2], x[3], accel * u[0], accel * u[1])
