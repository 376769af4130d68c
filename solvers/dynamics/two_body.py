"""Nonlinear two-body motion of a target and a chaser, and LVLH <-> inertial conversion.

Generic for relative-motion missions: the LVLH frame here has x radial (from the attracting
centre to the target), y completing the right-handed frame in the orbit plane (along the
motion for a circular orbit) and z along the orbit normal r x v. Relative states are
(x, y, z, vx, vy, vz) [m, m/s] with velocities as seen in the rotating LVLH frame. Missions
that draw another axis convention permute these components.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..verify import integrate_piecewise

Control = Callable[[float], np.ndarray]


def elements_to_state(
    a: float, e: float, inc: float, raan: float, argp: float, f: np.ndarray | float, mu: float
) -> tuple[np.ndarray, np.ndarray]:
    """Inertial position and velocity (..., 3) from classical elements at true anomaly f."""
    f = np.asarray(f, float)
    p = a * (1.0 - e * e)
    r = p / (1.0 + e * np.cos(f))
    pos_pf = np.stack([r * np.cos(f), r * np.sin(f), 0 * f], axis=-1)
    vel_pf = np.sqrt(mu / p) * np.stack([-np.sin(f), e + np.cos(f), 0 * f], axis=-1)
    R = _perifocal_to_inertial(inc, raan, argp)
    return pos_pf @ R.T, vel_pf @ R.T


def _perifocal_to_inertial(inc: float, raan: float, argp: float) -> np.ndarray:
    cO, sO, ci, si, cw, sw = (np.cos(raan), np.sin(raan), np.cos(inc), np.sin(inc),
                              np.cos(argp), np.sin(argp))
    return np.array([
        [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
        [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
        [sw * si, cw * si, ci],
    ])


def lvlh_basis(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Matrix (..., 3, 3) whose columns are the LVLH axes (x radial, y, z = orbit normal);
    r and v may be single vectors or stacks (..., 3)."""
    x = r / np.linalg.norm(r, axis=-1, keepdims=True)
    h = np.cross(r, v)
    z = h / np.linalg.norm(h, axis=-1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=-1)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def _basis_fast(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """`lvlh_basis` for one state, without numpy's per-call overhead (integrator RHS)."""
    x = r / np.sqrt(r @ r)
    h = _cross(r, v)
    z = h / np.sqrt(h @ h)
    return np.column_stack([x, _cross(z, x), z])


def _frame_rate(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angular velocity of the LVLH frame, inertial components: (r x v) / |r|^2 for a target
    on a Keplerian orbit (the orbit plane does not turn)."""
    return np.cross(r, v) / np.dot(r, r)


def lvlh_to_inertial(
    r_t: np.ndarray, v_t: np.ndarray, rel: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Chaser inertial position and velocity from the target's and the LVLH relative state."""
    R = lvlh_basis(r_t, v_t)
    rho = R @ rel[:3]
    return r_t + rho, v_t + R @ rel[3:] + np.cross(_frame_rate(r_t, v_t), rho)


def inertial_to_lvlh(
    r_t: np.ndarray, v_t: np.ndarray, r_c: np.ndarray, v_c: np.ndarray
) -> np.ndarray:
    """LVLH relative state (6,) of the chaser from both inertial states."""
    R = lvlh_basis(r_t, v_t)
    rho = r_c - r_t
    drho = v_c - v_t - np.cross(_frame_rate(r_t, v_t), rho)
    return np.concatenate([R.T @ rho, R.T @ drho])


def _gravity_difference(r: np.ndarray, d: np.ndarray, mu: float) -> np.ndarray:
    """-mu (r + d)/|r + d|^3 + mu r/|r|^3 without cancelling to noise for small d."""
    rc = r + d
    nr, nc = np.linalg.norm(r), np.linalg.norm(rc)
    # 1/nc^3 - 1/nr^3 from the small difference nr^2 - nc^2 = -(2 r.d + d.d).
    q = -(2.0 * np.dot(r, d) + np.dot(d, d))
    inv_diff = q * (nr**2 + nr * nc + nc**2) / ((nr + nc) * nr**3 * nc**3)
    return -mu * (d / nc**3 + r * inv_diff)


def propagate_relative(
    r_t0: np.ndarray,
    v_t0: np.ndarray,
    rel0: np.ndarray,
    control: Control,
    breakpoints: np.ndarray,
    mu: float,
    rtol: float = 1e-10,
    samples_per_piece: int = 0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nonlinear two-body motion of target and chaser; the chaser also feels control(t), an
    acceleration in LVLH components [m/s^2].

    Integrates the target and the inertial relative state (d, d_dot) = chaser - target, so
    the relative motion keeps full precision. Restarts at every breakpoint (e.g. node
    times). Returns (t, rel (n, 6) LVLH, target position (n, 3) inertial).
    """
    scale = float(np.linalg.norm(r_t0))
    speed = float(np.linalg.norm(v_t0))
    # A floor of 1 km: with (nearly) no relative motion an absolute tolerance below the
    # round-off of the gravity difference (~1e-12 m over a minute) stalls the integrator.
    rel_scale = max(float(np.linalg.norm(rel0[:3])), 1e3)
    atol = np.concatenate([np.full(3, 1e-3 * scale * rtol), np.full(3, 1e-3 * speed * rtol),
                           np.full(3, 1e-3 * rel_scale * rtol),
                           np.full(3, 1e-3 * rel_scale * rtol * speed / scale)])

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        r, v, d, dd = y[:3], y[3:6], y[6:9], y[9:]
        a_t = -mu * r / np.linalg.norm(r) ** 3
        a_rel = _gravity_difference(r, d, mu) + _basis_fast(r, v) @ control(t)
        return np.concatenate([v, a_t, dd, a_rel])

    r_c, v_c = lvlh_to_inertial(r_t0, v_t0, rel0)
    y0 = np.concatenate([r_t0, v_t0, r_c - r_t0, v_c - v_t0])
    ts, Y = integrate_piecewise(rhs, y0, breakpoints, rtol, atol, samples_per_piece)
    rel = np.array([
        inertial_to_lvlh(row[:3], row[3:6], row[:3] + row[6:9], row[3:6] + row[9:])
        for row in Y
    ])
    return ts, rel, Y[:, :3]
