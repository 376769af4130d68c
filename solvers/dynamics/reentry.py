"""Apollo-type lifting reentry (paper 004, eq. 8; Stoer & Bulirsch's multiple-shooting example;
SPEC M5 case 2).

State (v, gamma, xi): speed [1e5 ft/s], flight-path angle [rad], normalised altitude
xi = h/R; control u [rad], the bank/cone angle with C_D = c1 - c2 cos u, C_L = c3 sin u.
Lengths are in units of 1e5 ft and time in seconds, the units of the published numbers; the
mission converts to SI at its interface (`FT = 0.3048 m`).

    v'     = -(S/m) rho v^2 C_D / 2 - g sin(gamma) / (1 + xi)^2
    gamma' =  (S/m) rho v C_L / 2 + v cos(gamma) / (R (1 + xi)) - g cos(gamma) / (v (1 + xi)^2)
    xi'    =  v sin(gamma) / R
    rho    =  rho0 exp(-beta R xi)

Running cost (convective heating rate at the stagnation point): 10 v^3 sqrt(rho).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

# Stoer & Bulirsch's constants (SPEC M5), units of 1e5 ft and s.
R = 209.0
BETA = 4.26
RHO0 = 2.704e-3
G = 3.2172e-4
S_OVER_M = 53200.0
C1, C2, C3 = 1.174, 0.9, 0.6

FT = 0.3048  # m per ft
LENGTH_UNIT = 1e5 * FT  # m per model length unit (1e5 ft)

STATES = ("v", "gamma", "h")
STATE_UNITS = ("m/s", "rad", "m")


def rhs(x, u):
    """(v, gamma, xi)' for the model (CasADi symbols)."""
    v, gamma, xi = x[0], x[1], x[2]
    rho = RHO0 * ca.exp(-BETA * R * xi)
    cd = C1 - C2 * ca.cos(u)
    cl = C3 * ca.sin(u)
    return ca.vertcat(
        -S_OVER_M * rho * v**2 * cd / 2 - G * ca.sin(gamma) / (1 + xi) ** 2,
        S_OVER_M * rho * v * cl / 2 + v * ca.cos(gamma) / (R * (1 + xi))
        - G * ca.cos(gamma) / (v * (1 + xi) ** 2),
        v * ca.sin(gamma) / R,
    )


def heating_rate(x):
    """10 v^3 sqrt(rho): the integrand of the cost (S&B units); symbols or arrays (..., 3)."""
    if _numeric(x):
        x = np.asarray(x, float)
        return 10 * x[..., 0] ** 3 * np.sqrt(RHO0) * np.exp(-BETA * R * x[..., 2] / 2)
    return 10 * x[0] ** 3 * ca.sqrt(RHO0) * ca.exp(-BETA * R * x[2] / 2)


def downrange_rate(x: np.ndarray) -> np.ndarray:
    """Central angle rate v cos(gamma) / (R (1 + xi)) [rad/s] for rows of (v, gamma, xi)."""
    x = np.asarray(x, float)
    return x[..., 0] * np.cos(x[..., 1]) / (R * (1 + x[..., 2]))


def _numeric(x) -> bool:
    return not isinstance(x, ca.SX | ca.MX | ca.DM)
