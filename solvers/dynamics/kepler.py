"""Two-body (Kepler) motion, vectorised over leading array axes and free of units.

Every function takes the gravitational parameter `mu` in the units of its inputs (SI, or
AU and TU with mu = 1), so the same code serves the ephemerides (SI), the particle swarm
(canonical units) and the tests. Angles are radians; elements are
(a, e, i, raan, argp, mean anomaly) of elliptic orbits.
"""

from __future__ import annotations

import numpy as np

_KEPLER_TOL = 1e-15
_UNIVERSAL_TOL = 1e-14


def solve_kepler(mean_anomaly: np.ndarray | float, e: np.ndarray | float) -> np.ndarray:
    """Eccentric anomaly E with E - e sin E = M (elliptic, 0 <= e < 1), Newton iterations."""
    M = np.asarray(mean_anomaly, float)
    e = np.asarray(e, float)
    M = np.remainder(M + np.pi, 2 * np.pi) - np.pi
    E = np.where(e < 0.8, M + e * np.sin(M), np.pi * np.sign(M) + (M == 0))
    for _ in range(50):
        step = (E - e * np.sin(E) - M) / (1.0 - e * np.cos(E))
        E = E - step
        if np.all(np.abs(step) < _KEPLER_TOL):
            break
    return E


def perifocal_basis(inc: np.ndarray, raan: np.ndarray, argp: np.ndarray) -> np.ndarray:
    """Rotation (..., 3, 3) whose columns are the periapsis direction P, Q and the normal W."""
    cO, sO, ci, si, cw, sw = (np.cos(raan), np.sin(raan), np.cos(inc), np.sin(inc),
                              np.cos(argp), np.sin(argp))
    P = np.stack([cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si], axis=-1)
    Q = np.stack([-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si], axis=-1)
    W = np.stack([sO * si, -cO * si, ci * np.ones_like(sO)], axis=-1)
    return np.stack([P, Q, W], axis=-1)


def elements_to_state(elements: np.ndarray, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity (..., 3) from elements (..., 6) = (a, e, i, Ω, ω, M)."""
    el = np.asarray(elements, float)
    a, e, inc, raan, argp, M = np.moveaxis(el, -1, 0)
    E = solve_kepler(M, e)
    cE, sE = np.cos(E), np.sin(E)
    b = a * np.sqrt(1.0 - e * e)
    r = a * (1.0 - e * cE)
    edot = np.sqrt(mu / a) / r  # dE/dt * a
    pos_pf = np.stack([a * (cE - e), b * sE], axis=-1)
    vel_pf = np.stack([-a * sE * edot, b * cE * edot], axis=-1)
    R = perifocal_basis(inc, raan, argp)[..., :, :2]
    return np.einsum("...ij,...j->...i", R, pos_pf), np.einsum("...ij,...j->...i", R, vel_pf)


def state_to_elements(r: np.ndarray, v: np.ndarray, mu: float) -> np.ndarray:
    """Elements (..., 6) = (a, e, i, Ω, ω, M) of elliptic states (..., 3); Ω and ω in [0, 2π)."""
    r = np.asarray(r, float)
    v = np.asarray(v, float)
    rn = np.linalg.norm(r, axis=-1)
    h = np.cross(r, v)
    hn = np.linalg.norm(h, axis=-1)
    ev = np.cross(v, h) / mu - r / rn[..., None]
    e = np.linalg.norm(ev, axis=-1)
    a = 1.0 / (2.0 / rn - np.sum(v * v, axis=-1) / mu)
    inc = np.arccos(np.clip(h[..., 2] / hn, -1.0, 1.0))
    raan = np.arctan2(h[..., 0], -h[..., 1])
    node = np.stack([np.cos(raan), np.sin(raan), np.zeros_like(raan)], axis=-1)
    w_hat = h / hn[..., None]
    # Argument of periapsis and true anomaly measured in the orbit plane from the node line.
    m_hat = np.cross(w_hat, node)
    argp = np.arctan2(np.sum(ev * m_hat, axis=-1), np.sum(ev * node, axis=-1))
    u = np.arctan2(np.sum(r * m_hat, axis=-1), np.sum(r * node, axis=-1))
    f = u - argp
    E = 2.0 * np.arctan2(np.sqrt(1.0 - e) * np.sin(f / 2), np.sqrt(1.0 + e) * np.cos(f / 2))
    M = E - e * np.sin(E)
    two_pi = 2 * np.pi
    return np.stack([a, e, inc, np.remainder(raan, two_pi), np.remainder(argp, two_pi),
                     np.remainder(M, two_pi)], axis=-1)


def stumpff(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stumpff functions C(z), S(z), with series near z = 0 (no cancellation)."""
    z = np.asarray(z, float)
    small = np.abs(z) < 1e-3
    zs = np.where(small, 1.0, z)
    sq = np.sqrt(np.abs(zs))
    C = np.where(zs > 0, (1 - np.cos(sq)) / zs, (np.cosh(sq) - 1) / -zs)
    S = np.where(zs > 0, (sq - np.sin(sq)) / sq**3, (np.sinh(sq) - sq) / sq**3)
    C = np.where(small, 1 / 2 - z / 24 + z * z / 720 - z**3 / 40320, C)
    S = np.where(small, 1 / 6 - z / 120 + z * z / 5040 - z**3 / 362880, S)
    return C, S


def propagate(
    r0: np.ndarray, v0: np.ndarray, dt: np.ndarray | float, mu: float
) -> tuple[np.ndarray, np.ndarray]:
    """Kepler propagation by dt with universal variables (any conic), vectorised.

    Solves the universal Kepler equation for χ by the Laguerre–Conway iteration (globally
    convergent in practice), then applies the Lagrange f, g coefficients. Elliptic time
    spans longer than a period are reduced modulo the period first.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _propagate(np.asarray(r0, float), np.asarray(v0, float), dt, mu)


def _propagate(r0: np.ndarray, v0: np.ndarray, dt, mu: float) -> tuple[np.ndarray, np.ndarray]:
    shape = np.broadcast_shapes(r0.shape[:-1], v0.shape[:-1], np.shape(dt))
    r0 = np.broadcast_to(r0, (*shape, 3))
    v0 = np.broadcast_to(v0, (*shape, 3))
    dt = np.broadcast_to(np.asarray(dt, float), shape)
    rn = np.linalg.norm(r0, axis=-1)
    vr = np.sum(r0 * v0, axis=-1) / rn
    alpha = 2.0 / rn - np.sum(v0 * v0, axis=-1) / mu  # 1/a
    sqmu = np.sqrt(mu)
    ell = alpha > 1e-12
    period = np.where(ell, 2 * np.pi / (sqmu * np.abs(alpha) ** 1.5), np.inf)
    dt = np.where(ell, np.fmod(dt, period), dt)
    chi = np.where(ell, sqmu * alpha * dt, sqmu * dt / rn)
    # Vallado's starting value for hyperbolas (algorithm 8).
    hyp = alpha < -1e-12
    a_h = 1.0 / np.where(hyp, alpha, -1.0)
    sgn = np.where(dt >= 0, 1.0, -1.0)
    arg = (-2.0 * mu * alpha * dt
           / (np.sum(r0 * v0, axis=-1) + sgn * np.sqrt(-mu * a_h) * (1.0 - rn * alpha)))
    chi_h = sgn * np.sqrt(-a_h) * np.log(np.where(hyp & (arg > 0), arg, 1.0))
    chi = np.where(hyp & (arg > 0), chi_h, chi)
    n_lag = 5.0
    for _ in range(60):
        z = alpha * chi * chi
        C, S = stumpff(z)
        F = (rn * vr / sqmu * chi * chi * C + (1 - alpha * rn) * chi**3 * S + rn * chi
             - sqmu * dt)
        dF = rn * vr / sqmu * chi * (1 - z * S) + (1 - alpha * rn) * chi * chi * C + rn
        ddF = rn * vr / sqmu * (1 - z * C) + (1 - alpha * rn) * chi * (1 - z * S)
        disc = np.sqrt(np.abs((n_lag - 1) ** 2 * dF * dF - n_lag * (n_lag - 1) * F * ddF))
        step = n_lag * F / (dF + np.sign(dF) * disc)
        chi = chi - step
        if np.all(np.abs(step) <= _UNIVERSAL_TOL * np.maximum(np.abs(chi), 1e-300)):
            break
    z = alpha * chi * chi
    C, S = stumpff(z)
    f = 1 - chi * chi / rn * C
    g = dt - chi**3 / sqmu * S
    r = f[..., None] * r0 + g[..., None] * v0
    r_n = np.linalg.norm(r, axis=-1)
    fdot = sqmu / (r_n * rn) * (alpha * chi**3 * S - chi)
    gdot = 1 - chi * chi / r_n * C
    v = fdot[..., None] * r0 + gdot[..., None] * v0
    return r, v


def period(r: np.ndarray, v: np.ndarray, mu: float) -> np.ndarray:
    """Orbital period of elliptic states (inf for unbound ones)."""
    rn = np.linalg.norm(r, axis=-1)
    alpha = 2.0 / rn - np.sum(np.asarray(v) ** 2, axis=-1) / mu
    return np.where(alpha > 0, 2 * np.pi / np.sqrt(mu * np.abs(alpha) ** 3), np.inf)
