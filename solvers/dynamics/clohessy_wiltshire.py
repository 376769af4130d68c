"""Clohessy–Wiltshire relative motion about a circular target orbit (paper 000, eqs. 1–3).

Frame of paper 000 (target orbital frame): origin at the target, x opposite to the orbital
velocity, y away from the Earth, z completing the right-handed frame. State
(x, y, z, x', y', z') in m and m/s; control acceleration a·u with |u| <= 1:

    x'' - 2 w y'           = a ux
    y'' + 2 w x' - 3 w^2 y = a uy
    z'' + w^2 z            = a uz
"""

from __future__ import annotations

import casadi as ca
import numpy as np

MU_EARTH = 3.986004418e14  # m^3/s^2
R_EARTH = 6.378137e6  # m

STATES = ("x", "y", "z", "vx", "vy", "vz")
STATE_UNITS = ("m", "m", "m", "m/s", "m/s", "m/s")


def mean_motion(altitude: float, mu: float = MU_EARTH, radius: float = R_EARTH) -> float:
    """w of a circular orbit at this altitude [rad/s] (400 km gives 1.1314e-3)."""
    return float(np.sqrt(mu / (radius + altitude) ** 3))


def cw_rhs(x, acc, w):
    """x' of the CW equations; `acc` is the control acceleration vector [m/s^2].
    Works on CasADi symbols and numbers."""
    return ca.vertcat(
        x[3],
        x[4],
        x[5],
        2 * w * x[4] + acc[0],
        -2 * w * x[3] + 3 * w**2 * x[1] + acc[1],
        -(w**2) * x[2] + acc[2],
    )


def cw_stm(w, t):
    """6x6 state transition matrix Phi(t) of the homogeneous CW equations in this frame
    (paper 000, eq. 3). `t` may be a CasADi symbol (a coast duration variable)."""
    c, s = ca.cos(w * t), ca.sin(w * t)
    # Textbook CW STM in (radial, along-track, normal) coordinates ...
    std = ca.vertcat(
        ca.horzcat(4 - 3 * c, 0, 0, s / w, 2 * (1 - c) / w, 0),
        ca.horzcat(6 * (s - w * t), 1, 0, -2 * (1 - c) / w, (4 * s - 3 * w * t) / w, 0),
        ca.horzcat(0, 0, c, 0, 0, s / w),
        ca.horzcat(3 * w * s, 0, 0, c, 2 * s, 0),
        ca.horzcat(-6 * w * (1 - c), 0, 0, -2 * s, 4 * c - 3, 0),
        ca.horzcat(0, 0, -w * s, 0, 0, c),
    )
    # ... mapped to this frame: radial = y, along-track = -x, normal = z.
    P = ca.DM(_TO_STANDARD)
    return P.T @ std @ P


# Rows: standard (radial, along-track, normal, v_radial, v_along, v_normal) from this frame.
_TO_STANDARD = np.array(
    [
        [0, 1, 0, 0, 0, 0],
        [-1, 0, 0, 0, 0, 0],
        [0, 0, 1, 0, 0, 0],
        [0, 0, 0, 0, 1, 0],
        [0, 0, 0, -1, 0, 0],
        [0, 0, 0, 0, 0, 1],
    ],
    dtype=float,
)


def cw_stm_numeric(w: float, t: float | np.ndarray) -> np.ndarray:
    """Phi(t) as numbers: (6, 6) for a scalar t, (n, 6, 6) for an array of n times."""
    t_arr = np.atleast_1d(np.asarray(t, float))
    c, s, wt = np.cos(w * t_arr), np.sin(w * t_arr), w * t_arr
    z, o = np.zeros_like(t_arr), np.ones_like(t_arr)
    std = np.stack([
        np.stack([4 - 3 * c, z, z, s / w, 2 * (1 - c) / w, z], -1),
        np.stack([6 * (s - wt), o, z, -2 * (1 - c) / w, (4 * s - 3 * wt) / w, z], -1),
        np.stack([z, z, c, z, z, s / w], -1),
        np.stack([3 * w * s, z, z, c, 2 * s, z], -1),
        np.stack([-6 * w * (1 - c), z, z, -2 * s, 4 * c - 3, z], -1),
        np.stack([z, z, -w * s, z, z, c], -1),
    ], axis=1)
    out = _TO_STANDARD.T @ std @ _TO_STANDARD
    return out[0] if np.ndim(t) == 0 else out


def frame_axes(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Inertial unit vectors of the target frame's x, y, z when the target is at orbit
    angle theta on a circular orbit in the inertial XY plane (counter-clockwise):
    x = -velocity direction, y = radial, z = x cross y = +orbit normal."""
    theta = np.asarray(theta, float)
    radial = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    along = np.column_stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)])
    ex = -along
    return ex, radial, np.cross(ex, radial)


def nonlinear_relative_miss(
    rel0: np.ndarray,
    w: float,
    radius: float,
    control,
    breakpoints: np.ndarray,
    mu: float = MU_EARTH,
) -> np.ndarray:
    """Relative state (this frame) at the end when the chaser flies the same control under
    full two-body gravity while the target keeps its circular orbit of this radius.

    The control acceleration (given in the rotating target frame) is rotated into the
    inertial frame at each instant; integration by solve_ivp (DOP853, rtol 1e-10), restarted
    at every breakpoint where the control has kinks.
    """
    from scipy.integrate import solve_ivp

    omega = np.array([0.0, 0.0, w])

    def to_inertial(t: float, rel: np.ndarray) -> np.ndarray:
        ex, ey, ez = (a[0] for a in frame_axes(np.array([w * t])))
        R = np.column_stack([ex, ey, ez])
        r_t, v_t = radius * ey, radius * w * (-ex)
        return np.concatenate([r_t + R @ rel[:3], v_t + R @ (rel[3:] + np.cross(omega, rel[:3]))])

    def rhs(t: float, s: np.ndarray) -> np.ndarray:
        ex, ey, ez = (a[0] for a in frame_axes(np.array([w * t])))
        rel_x = np.zeros(6)
        acc = np.column_stack([ex, ey, ez]) @ np.asarray(control(t, rel_x), float)
        r = s[:3]
        return np.concatenate([s[3:], -mu * r / np.linalg.norm(r) ** 3 + acc])

    state = to_inertial(float(breakpoints[0]), np.asarray(rel0, float))
    for t0, t1 in zip(breakpoints[:-1], breakpoints[1:], strict=True):
        if t1 <= t0:
            continue
        sol = solve_ivp(rhs, (t0, t1), state, method="DOP853", rtol=1e-10, atol=1e-6)
        state = sol.y[:, -1]
    t_end = float(breakpoints[-1])
    ex, ey, ez = (a[0] for a in frame_axes(np.array([w * t_end])))
    R = np.column_stack([ex, ey, ez])
    r_t, v_t = radius * ey, radius * w * (-ex)
    rel_r = R.T @ (state[:3] - r_t)
    rel_v = R.T @ (state[3:] - v_t) - np.cross(omega, rel_r)
    return np.concatenate([rel_r, rel_v])
