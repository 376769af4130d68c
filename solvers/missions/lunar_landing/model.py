"""Planar powered descent about a spherical, non-rotating Moon (paper 002, eq. 1).

State x = (r, v, theta, omega, m): radius [m], radial speed [m/s], range angle [rad],
angular rate theta' [rad/s], mass [kg]. Control psi: thrust angle from the local horizontal,
positive up [rad]; the thrust F is braking and constant (the paper's constant-thrust
assumption), exhaust speed c = Isp g0.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

MU_MOON = 4.90275e12  # m^3/s^2 (paper: 4902.75 km^3/s^2)
R_MOON = 1.738e6  # m (paper: 1738 km)
G0 = 9.8  # m/s^2, the paper's Isp-to-exhaust-speed factor (Isp = 300 s -> c = 2940 m/s)

STATES = ("r", "v", "theta", "omega", "m")
STATE_UNITS = ("m", "m/s", "rad", "rad/s", "kg")


def descent_rhs(x, psi, thrust, exhaust_speed, mu=MU_MOON):
    """x' for the paper's eq. 1; works on CasADi symbols and on numpy arrays."""
    r, v, omega, m = x[0], x[1], x[3], x[4]
    acc = thrust / m
    return ca.vertcat(
        v,
        acc * ca.sin(psi) - mu / r**2 + r * omega**2,
        omega,
        -(acc * ca.cos(psi) + 2 * v * omega) / r,
        -thrust / exhaust_speed,
    )


def perilune_rate(perilune_radius: float, apolune_radius: float, mu: float = MU_MOON) -> float:
    """Angular rate at perilune of the orbit with these apsides (vis-viva)."""
    a = 0.5 * (perilune_radius + apolune_radius)
    speed = np.sqrt(mu * (2.0 / perilune_radius - 1.0 / a))
    return float(speed / perilune_radius)


def conic_points(
    r0: float, v0: float, omega0: float, mu: float = MU_MOON, n: int = 361
) -> np.ndarray:
    """(n, 2) points (x, y) in the orbit plane of the coasting conic through the initial
    state, with the initial point at angle 0; the arc is clipped where it leaves 5 R_moon."""
    h = r0**2 * omega0
    p = h**2 / mu
    # Eccentricity vector from r = (r0, 0), velocity = (v0, r0 omega0).
    ex = (r0 * omega0) ** 2 * r0 / mu - 1.0
    ey = -v0 * r0 * omega0 * r0 / mu
    e = np.hypot(ex, ey)
    arg_peri = np.arctan2(ey, ex)
    theta = np.linspace(0.0, 2 * np.pi, n)
    denom = 1 + e * np.cos(theta - arg_peri)
    r = np.where(denom > 1e-6, p / np.maximum(denom, 1e-6), np.nan)
    r = np.where(r < 5 * R_MOON, r, np.nan)
    return np.column_stack([r * np.cos(theta), r * np.sin(theta)])
