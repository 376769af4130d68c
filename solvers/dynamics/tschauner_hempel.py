"""Linearised relative motion about an elliptic target orbit (paper 001, SPEC M2).

Frame: LVLH with x radial (from the attracting centre to the target), y along-track, z along
the orbit normal. Physical relative state x = (x, y, z, vx, vy, vz) [m, m/s], time derivatives
seen in the rotating frame.

Tschauner–Hempel (TH) form (paper eqs. 1 and 11): with the true anomaly f as independent
variable, rho = 1 + e cos f and the scaled state X = (x~, y~, z~, x~', y~', z~'),
(x~, y~, z~) = rho (x, y, z) and ' = d/df,

    x~'' = 3 x~ / rho + 2 y~' + Ux / rho^3
    y~'' = -2 x~'             + Uy / rho^3
    z~'' = -z~                + Uz / rho^3,      U = u / k^4 (the paper's scaled control)

with k^2 = h / p^2 = mu^2 / h^3 (so df/dt = k^2 rho^2). The homogeneous solution is the
Yamanaka–Ankersen state transition matrix (J. Guidance 2002, 25(1); paper section 1). The
same linearisation written with time as independent variable (paper section 1, first
display) is the model of the re-propagation check and of the controllability Gramian.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp

MU_EARTH = 3.986004418e14  # m^3/s^2
R_EARTH = 6.378137e6  # m (equatorial)

IN_PLANE = (0, 1, 3, 4)  # x~, y~, x~', y~' in the 6-state
OUT_OF_PLANE = (2, 5)  # z~, z~'


# --- Kepler helpers -----------------------------------------------------------------------


def eccentric_from_true(f: np.ndarray | float, e: float) -> np.ndarray:
    """Eccentric anomaly E(f), continuous in f over any number of revolutions."""
    f = np.asarray(f, float)
    beta = e / (1.0 + np.sqrt(1.0 - e * e))
    return f - 2.0 * np.arctan2(beta * np.sin(f), 1.0 + beta * np.cos(f))


def mean_from_true(f: np.ndarray | float, e: float) -> np.ndarray:
    """Mean anomaly M(f), continuous in f (Kepler's equation M = E - e sin E)."""
    E = eccentric_from_true(f, e)
    return E - e * np.sin(E)


def true_from_mean(M: np.ndarray | float, e: float) -> np.ndarray:
    """True anomaly f(M), continuous in M: Newton on Kepler's equation, then E -> f."""
    M = np.asarray(M, float)
    E = M + e * np.sin(M) / np.maximum(1.0 - e * np.cos(M), 1e-3)
    for _ in range(50):
        step = (E - e * np.sin(E) - M) / (1.0 - e * np.cos(E))
        E = E - step
        if np.all(np.abs(step) < 1e-15 * np.maximum(1.0, np.abs(M))):
            break
    beta = e / (1.0 + np.sqrt(1.0 - e * e))
    return E + 2.0 * np.arctan2(beta * np.sin(E), 1.0 - beta * np.cos(E))


def true_anomaly_clock(e: float, n: float, f0: float) -> Callable[[float], float]:
    """Fast scalar t -> f (unwrapped, t from the pass through f0) for integrator right-hand
    sides: Newton on Kepler's equation warm-started from the previous call."""
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    M0 = float(mean_from_true(f0, e))
    E_prev = [float(eccentric_from_true(f0, e))]

    def f_at(t: float) -> float:
        M = M0 + n * t
        E = E_prev[0]
        for _ in range(30):
            step = (E - e * math.sin(E) - M) / (1.0 - e * math.cos(E))
            E -= step
            if abs(step) < 1e-14 * max(1.0, abs(M)):
                break
        E_prev[0] = E
        return E + 2.0 * math.atan2(beta * math.sin(E), 1.0 - beta * math.cos(E))

    return f_at


@dataclass(frozen=True)
class KeplerOrbit:
    """The target's elliptic orbit: size, shape and the TH constants derived from them."""

    a: float
    e: float
    mu: float = MU_EARTH

    @cached_property
    def p(self) -> float:
        """Semi-latus rectum [m]."""
        return self.a * (1.0 - self.e**2)

    @cached_property
    def h(self) -> float:
        """Specific angular momentum [m^2/s]."""
        return float(np.sqrt(self.mu * self.p))

    @cached_property
    def n(self) -> float:
        """Mean motion [rad/s]."""
        return float(np.sqrt(self.mu / self.a**3))

    @cached_property
    def k2(self) -> float:
        """k^2 = h / p^2 [1/s]: df/dt = k^2 (1 + e cos f)^2."""
        return self.h / self.p**2

    @property
    def period(self) -> float:
        return 2.0 * np.pi / self.n

    def rho(self, f: np.ndarray | float) -> np.ndarray:
        return 1.0 + self.e * np.cos(f)

    def radius(self, f: np.ndarray | float) -> np.ndarray:
        return self.p / self.rho(f)

    def time_since(self, f: np.ndarray | float, f0: float) -> np.ndarray:
        """t(f) - t(f0) [s] along the orbit (f unwrapped: f > f0 + 2 pi is a later revolution)."""
        return (mean_from_true(f, self.e) - mean_from_true(f0, self.e)) / self.n

    def true_anomaly_after(self, t: np.ndarray | float, f0: float) -> np.ndarray:
        """f at time t after the target passed f0 (unwrapped)."""
        return true_from_mean(mean_from_true(f0, self.e) + self.n * np.asarray(t, float), self.e)

    def to_scaled(self, f: np.ndarray | float, x: np.ndarray) -> np.ndarray:
        """Physical LVLH states (..., 6) at true anomalies f to TH scaled states (..., 6)."""
        x = np.asarray(x, float)
        f = np.asarray(f, float)[..., None]
        rho = 1.0 + self.e * np.cos(f)
        pos, vel = x[..., :3], x[..., 3:]
        return np.concatenate(
            [rho * pos, -self.e * np.sin(f) * pos + vel / (self.k2 * rho)], axis=-1
        )

    def from_scaled(self, f: np.ndarray | float, X: np.ndarray) -> np.ndarray:
        """TH scaled states (..., 6) at true anomalies f to physical LVLH states (..., 6)."""
        X = np.asarray(X, float)
        f = np.asarray(f, float)[..., None]
        rho = 1.0 + self.e * np.cos(f)
        Xp, Xd = X[..., :3], X[..., 3:]
        return np.concatenate(
            [Xp / rho, self.k2 * (rho * Xd + self.e * np.sin(f) * Xp)], axis=-1
        )


# --- Tschauner–Hempel equations in true anomaly ----------------------------------------------


def th_rhs(X, U, f, e):
    """X' = dX/df of the TH equations (paper eq. 1/11), control U = u / k^4.

    CasADi-symbolic (SX/MX): X (6, n), U (3, n) and f (1, n) hold n samples column-wise
    (n = 1 for a single state); returns (6, n). `th_matrices` is the numpy form.
    """
    rho = 1 + e * ca.cos(f)
    return ca.vertcat(
        X[3, :],
        X[4, :],
        X[5, :],
        3 * X[0, :] / rho + 2 * X[4, :] + U[0, :] / rho**3,
        -2 * X[3, :] + U[1, :] / rho**3,
        -X[2, :] + U[2, :] / rho**3,
    )


def th_matrices(f: np.ndarray, e: float) -> tuple[np.ndarray, np.ndarray]:
    """A(f) (n, 6, 6) and B(f) (n, 6, 3) with X' = A X + B U at the true anomalies f (n,)."""
    f = np.atleast_1d(np.asarray(f, float))
    rho = 1.0 + e * np.cos(f)
    A = np.zeros((f.size, 6, 6))
    A[:, 0, 3] = A[:, 1, 4] = A[:, 2, 5] = 1.0
    A[:, 3, 0] = 3.0 / rho
    A[:, 3, 4] = 2.0
    A[:, 4, 3] = -2.0
    A[:, 5, 2] = -1.0
    B = np.zeros((f.size, 6, 3))
    for j in range(3):
        B[:, 3 + j, j] = rho**-3
    return A, B


# --- Yamanaka–Ankersen state transition matrix ---------------------------------------------


def _trig(f: np.ndarray, e: float):
    rho = 1.0 + e * np.cos(f)
    s, c = rho * np.sin(f), rho * np.cos(f)
    ds = np.cos(f) + e * np.cos(2 * f)
    dc = -(np.sin(f) + e * np.sin(2 * f))
    return rho, s, c, ds, dc


def ya_fundamental(f: np.ndarray, J: np.ndarray, e: float) -> np.ndarray:
    """In-plane fundamental matrix (n, 4, 4) for (x~, y~, x~', y~') (paper section 1).

    Columns are independent homogeneous solutions; J = k^2 (t - t0) carries the secular
    (drifting) one.
    """
    f = np.atleast_1d(np.asarray(f, float))
    J = np.broadcast_to(np.asarray(J, float), f.shape)
    rho, s, c, ds, dc = _trig(f, e)
    Y = np.zeros((f.size, 4, 4))
    Y[:, 0] = np.stack([s, 0 * s, 2 - 3 * e * s * J, -c], axis=-1)
    Y[:, 1] = np.stack([c * (1 + 1 / rho), 1 + 0 * s, -3 * rho**2 * J, s * (1 + 1 / rho)], -1)
    Y[:, 2] = np.stack([ds, 0 * s, -3 * e * (ds * J + s / rho**2), -dc], axis=-1)
    Y[:, 3] = np.stack([-2 * s, 0 * s, -3 * (1 - 2 * e * s * J), 2 * c - e], axis=-1)
    return Y


def ya_fundamental_inverse(f: np.ndarray, e: float) -> np.ndarray:
    """Closed-form inverse (n, 4, 4) of the fundamental matrix at J = 0 (paper section 1)."""
    f = np.atleast_1d(np.asarray(f, float))
    rho, s, c, _, _ = _trig(f, e)
    z = 0 * s
    rows = [
        [-3 * s * (1 / rho + e**2 / rho**2), z, c - 2 * e, -s * (1 + 1 / rho)],
        [-3 * e * s * (1 / rho + 1 / rho**2), z + 1 - e**2, e * c - 2, -e * s * (1 + 1 / rho)],
        [3 * rho + e**2 - 1, z, e * s, rho**2],
        [3 * (c / rho + e), z, s, c * (1 + 1 / rho) + e],
    ]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2) / (1.0 - e**2)


def ya_stm(f: np.ndarray | float, f0: np.ndarray | float, e: float) -> np.ndarray:
    """Phi(f, f0) (n, 6, 6) of the TH scaled state: Yamanaka–Ankersen in-plane, harmonic
    out-of-plane. `f` and `f0` broadcast against each other."""
    f, f0 = np.broadcast_arrays(np.atleast_1d(np.asarray(f, float)),
                                np.atleast_1d(np.asarray(f0, float)))
    J = (mean_from_true(f, e) - mean_from_true(f0, e)) / (1.0 - e * e) ** 1.5
    inplane = ya_fundamental(f, J, e) @ ya_fundamental_inverse(f0, e)
    Phi = np.zeros((f.size, 6, 6))
    Phi[np.ix_(range(f.size), IN_PLANE, IN_PLANE)] = inplane
    dz = f - f0
    Phi[:, 2, 2] = Phi[:, 5, 5] = np.cos(dz)
    Phi[:, 2, 5] = np.sin(dz)
    Phi[:, 5, 2] = -np.sin(dz)
    return Phi


def drift_free_vy(orbit: KeplerOrbit, f: float, x: np.ndarray) -> float:
    """Along-track velocity vy [m/s] that removes the secular (drifting) YA mode, so the
    uncontrolled relative motion is periodic; x gives (x, y, z, vx) (vy, vz are ignored).

    The drift mode's coefficient is the third row of the inverse fundamental matrix
    (3 rho + e^2 - 1) x~ + e s x~' + rho^2 y~' = 0.
    """
    X = orbit.to_scaled(f, np.array([x[0], x[1], x[2], x[3], 0.0, 0.0]))
    rho, s, *_ = _trig(np.asarray(f, float), orbit.e)
    dy_scaled = -((3 * rho + orbit.e**2 - 1) * X[0] + orbit.e * s * X[3]) / rho**2
    return float(orbit.k2 * rho * (dy_scaled + orbit.e * np.sin(f) * x[1]))


# --- the same linearisation with time as independent variable --------------------------------


def lvlh_matrix(f: np.ndarray, orbit: KeplerOrbit, time_unit: float = 1.0) -> np.ndarray:
    """A(t) (n, 6, 6) of the time-domain linearised model x_dot = A x + [0; I] u at the
    target's true anomalies f (paper section 1: w = df/dt, w_dot, mu / r^3).

    With `time_unit` T the state is (position, velocity T) and the derivative is per T
    (the control then enters as u T^2).
    """
    f = np.atleast_1d(np.asarray(f, float))
    rho = 1.0 + orbit.e * np.cos(f)
    k4 = orbit.k2**2
    w = orbit.k2 * rho**2
    wdot = -2.0 * k4 * orbit.e * np.sin(f) * rho**3
    mu_r3 = k4 * rho**3
    A = np.zeros((f.size, 6, 6))
    A[:, 0, 3] = A[:, 1, 4] = A[:, 2, 5] = 1.0
    A[:, 3, 0] = w**2 + 2 * mu_r3
    A[:, 3, 1] = wdot
    A[:, 3, 4] = 2 * w
    A[:, 4, 0] = -wdot
    A[:, 4, 1] = w**2 - mu_r3
    A[:, 4, 3] = -2 * w
    A[:, 5, 2] = -mu_r3
    A[:, 3:, :3] *= time_unit**2
    A[:, 3:, 3:] *= time_unit
    return A


def lvlh_linear_rhs(x, u, p):
    """Time-domain linearised relative motion with the target's true anomaly as 7th state.

    x = (x, y, z, vx, vy, vz, f), u = LVLH acceleration [m/s^2], p = (e, k^2). CasADi-symbolic
    or numeric (the form `solvers.verify.repropagate` integrates).
    """
    e, k2 = p[0], p[1]
    f = x[6]
    rho = 1 + e * ca.cos(f)
    w = k2 * rho**2
    wdot = -2 * k2**2 * e * ca.sin(f) * rho**3
    mu_r3 = k2**2 * rho**3
    return ca.vertcat(
        x[3],
        x[4],
        x[5],
        2 * w * x[4] + wdot * x[1] + (w**2 + 2 * mu_r3) * x[0] + u[0],
        -2 * w * x[3] - wdot * x[0] + (w**2 - mu_r3) * x[1] + u[1],
        -mu_r3 * x[2] + u[2],
        w,
    )


def controllability_gramian(
    orbit: KeplerOrbit, f0: float, duration: float, rtol: float = 1e-12
) -> tuple[np.ndarray, np.ndarray]:
    """(Phi(tf, t0), W) of the time-domain model over [t0, t0 + duration], integrated
    numerically (independently of the YA STM) in the time unit 1/n.

    W = integral of Phi(tf, s) B B^T Phi(tf, s)^T ds from the Lyapunov equation
    W_dot = A W + W A^T + B B^T. Units: state (m, m/(1/n)), so the minimum-energy cost
    1/2 d^T W^-1 d (d in those units) is J n^-3 in SI.
    """
    n = orbit.n
    BBt = np.zeros((6, 6))
    BBt[3:, 3:] = np.eye(3)

    def rhs(_tau: float, y: np.ndarray) -> np.ndarray:
        A = lvlh_matrix(y[-1:], orbit, 1.0 / n)[0]
        Phi = y[:36].reshape(6, 6)
        W = y[36:72].reshape(6, 6)
        dW = A @ W + W @ A.T + BBt
        df = orbit.k2 * (1 + orbit.e * np.cos(y[-1])) ** 2 / n
        return np.concatenate([(A @ Phi).ravel(), dW.ravel(), [df]])

    y0 = np.concatenate([np.eye(6).ravel(), np.zeros(36), [f0]])
    sol = solve_ivp(rhs, (0.0, n * duration), y0, method="DOP853", rtol=rtol, atol=1e-14)
    if not sol.success:
        raise RuntimeError(f"Gramian integration failed: {sol.message}")
    y = sol.y[:, -1]
    return y[:36].reshape(6, 6), y[36:72].reshape(6, 6)
