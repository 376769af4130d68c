"""Mars powered descent in a target-fixed frame (Açıkmeşe & Ploen 2007; Blackmore, Açıkmeşe &
Scharf 2010): x downrange, y crossrange, z up, target at the origin, flat ground, constant
gravity, no atmosphere.

State (r, v, z): position [m], velocity [m/s], z = ln m [ln kg]; control T: thrust [N].

    r' = v,   v' = g + T e^{-z},   z' = -|T| e^{-z} / c,   c = Isp g0

Numeric parameter vector p (SI): see the P_* indices. Its start (P_RX..P_RZ) is relative to
the target: the mission's values give the start and the target in a surface-fixed frame (as
drawn), and the dynamics do not depend on where the target is (`target`).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

G0 = 9.80665  # m/s², standard gravity (the Isp convention)
STATES = ("x", "y", "z_up", "vx", "vy", "vz", "log_mass")
STATE_UNITS = ("m", "m", "m", "m/s", "m/s", "m/s", "ln kg")
CONTROLS = ("Tx", "Ty", "Tz")
CONTROL_UNITS = ("N", "N", "N")

(P_RX, P_RY, P_RZ, P_VX, P_VY, P_VZ, P_MWET, P_MDRY, P_C, P_RHO1, P_RHO2, P_G, P_TAN_GS,
 P_VMAX, P_COS_POINT) = range(15)
N_PARAMS = 15


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    """The numeric parameters (SI) from validated mission values, the start relative to the
    target (the problem is translation invariant). The effective exhaust
    speed c is Isp g0 cos(cant): the canted thrusters burn propellant for their whole
    thrust but push along the axis with its cosine (Açıkmeşe & Ploen 2007, Eq. 3:
    α = 1/(Isp g_e cos φ))."""
    t_max = values["thrusters"] * values["thrust_each"] * np.cos(values["cant"])
    tx, ty, _ = target(values)
    return np.array([
        values["downrange0"] - tx, values["crossrange0"] - ty, values["altitude0"],
        values["vx0"], values["vy0"], values["vz0"],
        values["mass_wet"], values["mass_dry"], values["isp"] * G0 * np.cos(values["cant"]),
        values["throttle_min"] * t_max, values["throttle_max"] * t_max, values["gravity"],
        np.tan(values["glide_slope"]), values["max_speed"], np.cos(values["pointing"]),
    ])


def target(values: dict[str, float]) -> np.ndarray:
    """The landing target in the surface-fixed frame (m): on the ground, z = 0. The states
    are relative to it; a point of the drawing is a state's position plus this."""
    return np.array([values["target_downrange"], values["target_crossrange"], 0.0])


def gravity(p) -> ca.SX:
    return ca.vertcat(0.0, 0.0, -p[P_G])


def descent_rhs(x, u, p):
    """x' on CasADi symbols (the nonconvex original: thrust in newtons, z = ln m)."""
    inv_m = ca.exp(-x[6])
    thrust = ca.sqrt(ca.sumsqr(u[:3]))
    return ca.vertcat(x[3:6], gravity(p) + u[:3] * inv_m, -thrust * inv_m / p[P_C])


def flight_time_bounds(p: np.ndarray) -> tuple[float, float]:
    """Açıkmeşe & Ploen's bracket of the free final time: t_min = (m_wet - m_dry) |v0| / ρ2
    (no descent is shorter), t_max = m_fuel c / ρ1 (all fuel at the lowest thrust)."""
    fuel = p[P_MWET] - p[P_MDRY]
    speed = float(np.linalg.norm(p[P_VX:P_VZ + 1]))
    return max(fuel * speed / p[P_RHO2], 1.0), fuel * p[P_C] / p[P_RHO1]
