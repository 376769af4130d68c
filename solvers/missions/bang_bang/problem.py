"""A cart on a rail, minimum time: the textbook bang–bang problem.

x' = v, v' = u, |u| <= a; from rest at 0 to rest at d in the least time T. The maximum
principle gives full acceleration to the midpoint and full braking after it:
T* = 2 sqrt(d / a) (e.g. Bryson & Ho 1975, §7.3; Kirk 1970, example 5.3-1).
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ...handles import Handle
from ...ocp import OCP, Bounds, Guess
from ...problem import Consistency, Param, Preset, Published
from ...solution import Label

SOURCE = "textbook minimum-time problem (Kirk 1970, ex. 5.3-1; Bryson & Ho 1975, §7.3)"
P_D, P_A = range(2)

PARAMS = (
    Param("distance", "distance d", "m", 1.0, 0.1, 100.0, 0.1, group="Cart"),
    Param("accel", "acceleration bound a", "m/s²", 1.0, 0.1, 10.0, 0.1, group="Cart"),
)

# Dragged in the 3D view: the target along the rail (the phase plane's x axis).
HANDLES = (Handle("target", "target", ("distance", 0.0, 0.0)),)

# T* = 2 sqrt(d/a) = 2 s at the defaults. A direct method places the switch between nodes,
# so T converges like the node spacing: within 2e-3 relative at the default meshes.
PUBLISHED = (
    Published("T", 2.0, "s", "analytic optimum T* = 2 sqrt(d/a)", rtol=2e-3),
    Published("T", 2.0 * np.sqrt(10.0 / 2.0), "s", "analytic optimum T* = 2 sqrt(d/a)",
              rtol=2e-3, case=Preset("10 m at 2 m/s²", {"distance": 10.0, "accel": 2.0})),
)
TOLERANCES = {"position_miss_m": 1e-3, "velocity_miss_m_s": 1e-3}
CONSISTENCY = (Consistency("T", 2e-3, note="every method finds the same switch"),)
PRESETS = (Preset("10 m at 2 m/s²", {"distance": 10.0, "accel": 2.0}),)
EQUATIONS = (
    ("Dynamics and cost", r"\dot x = v,\quad \dot v = u,\quad |u| \le a,\qquad \min T"),
    ("The maximum principle: bang–bang, one switch at T/2",
     r"u^* = a\ (t < T/2),\ -a\ (t > T/2),\qquad T^* = 2\sqrt{d/a}"),
)


def parameter_vector(values: dict[str, float]) -> np.ndarray:
    return np.array([values["distance"], values["accel"]])


def optimal_time(p: np.ndarray) -> float:
    return float(2.0 * np.sqrt(p[P_D] / p[P_A]))


@cache
def ocp() -> OCP:
    def bounds(p):
        reach = 2.0 * p[P_D] + 1.0
        return Bounds(x_lb=np.array([-reach, -np.inf]), x_ub=np.array([reach, np.inf]),
                      u_lb=np.array([-p[P_A]]), u_ub=np.array([p[P_A]]),
                      T_lb=1e-3, T_ub=100.0 * optimal_time(p))

    def guess(p):
        return Guess(x_final=np.array([p[P_D], 0.0]), u=np.array([0.0]),
                     T=1.5 * optimal_time(p))

    return OCP(
        states=("x", "v"), state_units=("m", "m/s"), controls=("u",), control_units=("m/s²",),
        n_params=2,
        dynamics=lambda x, u, p: ca.vertcat(x[1], u[0]),
        initial_state=lambda p: ca.vertcat(0.0, 0.0),
        terminal=lambda xf, p: ca.vertcat(xf[0] - p[P_D], xf[1]),
        terminal_names=("position", "velocity"), terminal_scale=np.array([1.0, 1.0]),
        bounds=bounds, guess=guess,
        x_scale=np.array([1.0, 1.0]), u_scale=np.array([1.0]), T_scale=1.0,
        mayer=lambda xf, T, p: T,
    )


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "x": Label("position", "m"),
    "v": Label("velocity", "m/s"),
    "u": Label("acceleration", "m/s²"),
    "position_miss_m": Label("final position miss", "m"),
    "velocity_miss_m_s": Label("final velocity miss", "m/s"),
}
