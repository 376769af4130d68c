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

from .two_body import propagate_relative

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

    `control(t, x)` gives the acceleration in this frame; the propagation itself is
    `two_body.propagate_relative` in its LVLH axes (x radial, y along-track), so the
    components are permuted on the way in and out.
    """
    r_t0 = np.array([radius, 0.0, 0.0])
    v_t0 = np.array([0.0, radius * w, 0.0])
    _, rel, _ = propagate_relative(
        r_t0, v_t0, _to_lvlh(np.asarray(rel0, float)),
        lambda t: _to_lvlh(np.asarray(control(t, None), float)), breakpoints, mu,
    )
    return _from_lvlh(rel[-1])


def _to_lvlh(v: np.ndarray) -> np.ndarray:
    """(x = -along, y = radial, z) -> (radial, along, z), for 3- or 6-vectors."""
    out = v.reshape(-1, 3)[:, [1, 0, 2]] * np.array([1.0, -1.0, 1.0])
    return out.ravel()


def _from_lvlh(v: np.ndarray) -> np.ndarray:
    out = v.reshape(-1, 3)[:, [1, 0, 2]] * np.array([-1.0, 1.0, 1.0])
    return out.ravel()
