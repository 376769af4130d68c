"""Lambert's problem by Izzo's method (Izzo 2015, Celest. Mech. Dyn. Astron. 121:1–15),
vectorised over any number of (r1, r2, time-of-flight) triples, single or multi-revolution.

For each triple the non-dimensional time T(x) of Lancaster–Blanchard (Battin's series near
the parabola x = 1) is inverted by Householder iterations from Izzo's starting guesses; the
terminal velocities follow from x. Units are free: pass `mu` in the units of r and tof.
"""

from __future__ import annotations

import numpy as np

_BATTIN = 0.01
_LAGRANGE = 0.2
_MAX_ITER = 20
_TOL_X = 1e-13


def lambert(
    r1: np.ndarray,
    r2: np.ndarray,
    tof: np.ndarray | float,
    mu: float,
    revs: int = 0,
    branch: str | np.ndarray = "left",
    prograde: bool = True,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocities (v1, v2) (..., 3) of the conic from r1 to r2 in `tof`, and a validity mask.

    `revs` full revolutions (0: single-revolution arc); with revs > 0 there are two
    solutions, chosen by `branch` ("left": Izzo's x < x(Tmin) branch, "right": the other,
    or a boolean array, True for left, per triple). `prograde` picks the sense of motion
    about +z. Invalid entries (tof below the multi-revolution minimum, r1 parallel to r2)
    are NaN with mask False.
    """
    r1 = np.asarray(r1, float)
    r2 = np.asarray(r2, float)
    shape = np.broadcast_shapes(r1.shape[:-1], r2.shape[:-1], np.shape(tof))
    r1 = np.broadcast_to(r1, (*shape, 3))
    r2 = np.broadcast_to(r2, (*shape, 3))
    tof = np.broadcast_to(np.asarray(tof, float), shape)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return _lambert(r1, r2, tof, mu, revs, branch, prograde)


def _lambert(r1, r2, tof, mu, revs, branch, prograde):
    R1 = np.linalg.norm(r1, axis=-1)
    R2 = np.linalg.norm(r2, axis=-1)
    c = np.linalg.norm(r2 - r1, axis=-1)
    s = 0.5 * (R1 + R2 + c)
    ir1 = r1 / R1[..., None]
    ir2 = r2 / R2[..., None]
    ih = np.cross(ir1, ir2)
    ih = ih / np.linalg.norm(ih, axis=-1, keepdims=True)
    lam = np.sqrt(np.maximum(1.0 - c / s, 0.0))
    long_way = ih[..., 2] < 0.0
    lam = np.where(long_way, -lam, lam)
    sign_t = np.where(long_way, -1.0, 1.0)[..., None]
    it1 = sign_t * np.cross(ih, ir1)
    it2 = sign_t * np.cross(ih, ir2)
    if not prograde:
        lam, it1, it2 = -lam, -it1, -it2
    T = np.sqrt(2.0 * mu / s**3) * tof

    if revs == 0:
        x = _householder(T, _single_rev_guess(lam, T), lam, 0, np.isfinite(T * lam))
        valid = np.isfinite(x)
    else:
        feasible = T >= _minimum_time(lam, revs)
        tmp_left = ((revs * np.pi + np.pi) / (8.0 * T)) ** (2.0 / 3.0)
        tmp_right = ((8.0 * T) / (revs * np.pi)) ** (2.0 / 3.0)
        tmp = np.where(_left_mask(branch, T.shape), tmp_left, tmp_right)
        x = _householder(T, (tmp - 1.0) / (tmp + 1.0), lam, revs, feasible)
        valid = np.isfinite(x) & feasible & (np.abs(x) < 1.0)

    gamma = np.sqrt(mu * s / 2.0)
    rho = (R1 - R2) / c
    sigma = np.sqrt(np.maximum(1.0 - rho * rho, 0.0))
    y = np.sqrt(1.0 - lam * lam + lam * lam * x * x)
    vr1 = gamma * ((lam * y - x) - rho * (lam * y + x)) / R1
    vr2 = -gamma * ((lam * y - x) + rho * (lam * y + x)) / R2
    vt = gamma * sigma * (y + lam * x)
    v1 = vr1[..., None] * ir1 + (vt / R1)[..., None] * it1
    v2 = vr2[..., None] * ir2 + (vt / R2)[..., None] * it2
    valid = valid & np.all(np.isfinite(v1), axis=-1) & np.all(np.isfinite(v2), axis=-1)
    nan = np.full_like(v1, np.nan)
    return np.where(valid[..., None], v1, nan), np.where(valid[..., None], v2, nan), valid


def _left_mask(branch: str | np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    if isinstance(branch, str):
        if branch not in ("left", "right"):
            raise ValueError(f"branch must be 'left' or 'right', got {branch!r}")
        return np.full(shape, branch == "left")
    return np.broadcast_to(np.asarray(branch, bool), shape)


def _single_rev_guess(lam: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Izzo's starting x for zero revolutions (eq. 30 of Izzo 2015)."""
    T00 = np.arccos(lam) + lam * np.sqrt(1.0 - lam * lam)
    T1 = 2.0 / 3.0 * (1.0 - lam**3)
    x_long = -(T - T00) / (T - T00 + 4.0)
    x_short = T1 * (T1 - T) / (0.4 * (1.0 - lam**5) * T) + 1.0
    x_mid = (T / T00) ** (np.log(2.0) / np.log(T1 / T00)) - 1.0
    return np.where(T >= T00, x_long, np.where(T <= T1, x_short, x_mid))


def _minimum_time(lam: np.ndarray, revs: int) -> np.ndarray:
    """Smallest non-dimensional time with `revs` revolutions (Halley iterations on dT/dx = 0)."""
    x = np.zeros_like(lam)
    T = _tof(x, lam, revs)
    for _ in range(15):
        dT, ddT, dddT = _derivatives(x, T, lam)
        step = np.where(dT != 0.0, dT * ddT / (ddT * ddT - dT * dddT / 2.0), 0.0)
        x = x - step
        T = _tof(x, lam, revs)
        if np.all(np.abs(step) < _TOL_X):
            break
    return T


def _householder(
    T: np.ndarray, x: np.ndarray, lam: np.ndarray, revs: int, active: np.ndarray
) -> np.ndarray:
    """Solve T(x) = T with third-order Householder steps (Izzo 2015, eq. 26) where `active`
    (the others are NaN)."""
    x = np.where(active, x, 0.0)
    for _ in range(_MAX_ITER):
        tof = _tof(x, lam, revs)
        dT, ddT, dddT = _derivatives(x, tof, lam)
        delta = tof - T
        dT2 = dT * dT
        step = delta * (dT2 - delta * ddT / 2.0) / (dT * (dT2 - delta * ddT)
                                                     + dddT * delta * delta / 6.0)
        step = np.where(np.isfinite(step) & active, step, 0.0)
        x = x - step
        if np.all(np.abs(step) < _TOL_X):
            break
    converged = np.abs(_tof(x, lam, revs) - T) <= 1e-9 * np.maximum(T, 1.0)
    return np.where(active & converged, x, np.nan)


def _derivatives(x: np.ndarray, T: np.ndarray, lam: np.ndarray):
    """dT/dx, d²T/dx², d³T/dx³ (Izzo 2015, eq. 22)."""
    l2 = lam * lam
    l3 = l2 * lam
    umx2 = 1.0 - x * x
    y = np.sqrt(1.0 - l2 * umx2)
    dT = (3.0 * T * x - 2.0 + 2.0 * l3 * x / y) / umx2
    ddT = (3.0 * T + 5.0 * x * dT + 2.0 * (1.0 - l2) * l3 / y**3) / umx2
    dddT = (7.0 * x * ddT + 8.0 * dT - 6.0 * (1.0 - l2) * l2 * l3 * x / y**5) / umx2
    return dT, ddT, dddT


def _tof(x: np.ndarray, lam: np.ndarray, revs: int) -> np.ndarray:
    """Non-dimensional time of flight T(x): Battin's series near x = 1, Lagrange's form
    for 0.01 <= |x - 1| < 0.2, Lancaster's elsewhere (as in Izzo's reference code)."""
    dist = np.abs(x - 1.0)
    K = lam * lam
    E = x * x - 1.0
    rho = np.abs(E)
    z = np.sqrt(1.0 + K * E)
    # Battin's series with the hypergeometric function 2F1(3, 1; 5/2; S1).
    eta = z - lam * x
    S1 = 0.5 * (1.0 - lam - x * eta)
    Q = _hypergeometric(np.where(dist < _BATTIN, S1, 0.0)) * 4.0 / 3.0
    t_battin = (eta**3 * Q + 4.0 * lam * eta) / 2.0 + revs * np.pi / rho**1.5
    # Lancaster.
    y = np.sqrt(rho)
    g = x * z - lam * E
    d_ell = revs * np.pi + np.arccos(np.clip(g, -1.0, 1.0))
    d_hyp = np.log(np.maximum(y * (z - lam * x) + g, 1e-300))
    d = np.where(E < 0.0, d_ell, d_hyp)
    t_lancaster = (x - lam * z - d / y) / E
    return np.where(dist < _BATTIN, t_battin,
                    np.where(dist < _LAGRANGE, _tof_lagrange(x, lam, revs), t_lancaster))


def _tof_lagrange(x: np.ndarray, lam: np.ndarray, revs: int) -> np.ndarray:
    a = 1.0 / (1.0 - x * x)
    sgn = np.where(lam < 0.0, -1.0, 1.0)
    alfa_e = 2.0 * np.arccos(np.clip(x, -1.0, 1.0))
    beta_e = sgn * 2.0 * np.arcsin(np.sqrt(np.clip(lam * lam / a, 0.0, 1.0)))
    t_ell = a * np.sqrt(np.abs(a)) * ((alfa_e - np.sin(alfa_e)) - (beta_e - np.sin(beta_e))
                                      + 2.0 * np.pi * revs) / 2.0
    alfa_h = 2.0 * np.arccosh(np.maximum(x, 1.0))
    beta_h = sgn * 2.0 * np.arcsinh(np.sqrt(np.maximum(-lam * lam / a, 0.0)))
    t_hyp = -a * np.sqrt(np.abs(a)) * ((beta_h - np.sinh(beta_h)) - (alfa_h - np.sinh(alfa_h)))
    return np.where(a > 0.0, t_ell, t_hyp / 2.0)


def _hypergeometric(z: np.ndarray, terms: int = 60) -> np.ndarray:
    """2F1(3, 1; 5/2; z) by its series (|z| small where Battin's branch is used)."""
    total = np.ones_like(z)
    term = np.ones_like(z)
    for j in range(terms):
        term = term * (3.0 + j) * (1.0 + j) / (2.5 + j) * z / (j + 1)
        total = total + term
        if np.all(np.abs(term) < 1e-16):
            break
    return total
