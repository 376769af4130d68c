"""The elliptic-transfer case (paper 001, SPEC M2): the validated request in the form the laws
use, the time-domain linear model of the re-propagation, and the independent minimum-energy
reference from the controllability Gramian.

The Tschauner–Hempel equations, the Yamanaka–Ankersen STM and the two-body propagation are
generic models in `solvers.dynamics`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ...dynamics.tschauner_hempel import (
    MU_EARTH,
    KeplerOrbit,
    controllability_gramian,
    drift_free_vy,
    lvlh_linear_rhs,
)
from ...dynamics.two_body import elements_to_state
from ...lgl import barycentric_weights
from ...nlp.cache import built_once

STATES = ("x", "y", "z", "vx", "vy", "vz")
STATE_UNITS = ("m", "m", "m", "m/s", "m/s", "m/s")
CONTROLS = ("ux", "uy", "uz")
CONTROL_UNITS = ("m/s^2",) * 3


@dataclass(frozen=True)
class Case:
    """A validated request in the form the laws use (SI)."""

    orbit: KeplerOrbit
    f0: float
    fT: float
    duration: float
    x0: np.ndarray
    xT: np.ndarray
    inclination: float
    raan: float
    argp: float

    def target_state(self, f: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """The target's inertial position and velocity at true anomalies f."""
        o = self.orbit
        return elements_to_state(o.a, o.e, self.inclination, self.raan, self.argp, f, o.mu)


def make_case(values: dict[str, float]) -> Case:
    """Case from mission values (vy0 replaced by the drift-free value when asked)."""
    orbit = KeplerOrbit(values["a"], values["e"], MU_EARTH)
    f0 = values["f0"]
    duration = values["periods"] * orbit.period
    x0 = np.array([values[k] for k in ("x0", "y0", "z0", "vx0", "vy0", "vz0")])
    if values["vy_source"] == 1:
        x0[4] = drift_free_vy(orbit, f0, x0)
    fT = float(orbit.true_anomaly_after(duration, f0))
    return Case(orbit, f0, fT, duration, x0, np.zeros(6), values["inclination"],
                values["raan"], values["argp"])


def gramian_cost(case: Case) -> float:
    """Minimum energy J = ½ d^T W^-1 d [m²/s³] from the controllability Gramian of the
    time-domain linear model (independent of the STM and of the LGL discretisation)."""
    Phi, W = _gramian(case.orbit.e, case.f0, case.duration * case.orbit.n)
    n = case.orbit.n
    scale = np.array([1, 1, 1, 1 / n, 1 / n, 1 / n])
    d = case.xT * scale - Phi @ (case.x0 * scale)
    return 0.5 * float(d @ np.linalg.solve(W, d)) * n**3


@lru_cache(maxsize=16)
def _gramian(e: float, f0: float, duration_nd: float) -> tuple[np.ndarray, np.ndarray]:
    return controllability_gramian(KeplerOrbit(1.0, e, 1.0), f0, duration_nd)


@built_once
def linear_function() -> ca.Function:
    """The time-domain linear model f(x, u, p) for `repropagate` (x includes f, p = (e, k²))."""
    x, u, p = ca.SX.sym("x", 7), ca.SX.sym("u", 3), ca.SX.sym("p", 2)
    return ca.Function("lvlh_linear", [x, u, p], [lvlh_linear_rhs(x, u, p)])


def polynomial(nodes: np.ndarray, values: np.ndarray) -> Callable[[float], np.ndarray]:
    """Fast scalar evaluation of the LGL polynomial through (nodes, values) (barycentric)."""
    bw = barycentric_weights(nodes)

    def at(s: float) -> np.ndarray:
        d = s - nodes
        k = int(np.argmin(np.abs(d)))
        if d[k] == 0.0:
            return values[k]
        c = bw / d
        return (c @ values) / c.sum()

    return at
