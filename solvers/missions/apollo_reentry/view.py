"""How the reentry is drawn: the Earth to scale, the path in the entry plane with its altitude
exaggerated (a view option: redrawn without re-solving), arrows along the aerodynamic force,
the path coloured by heating rate, and the plots of the states, the trim angle, the heating
rate and the deceleration."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...presentation import Body, ColorBy, Marker, PlotSeries, Presentation
from ...solution import Solution
from . import model
from .problem import COST_UNIT, DEG

G0 = 9.80665  # m/s^2, only to express decelerations in g


def display(theta: np.ndarray, h: np.ndarray, k: float) -> np.ndarray:
    """Earth-centred display frame (m), path in the z = 0 plane, altitude exaggerated k×."""
    r = model.R_EARTH + k * np.asarray(h)
    return np.column_stack([r * np.cos(theta), r * np.sin(theta), np.zeros_like(r)])


def force_arrows(P: np.ndarray, x: np.ndarray, u: np.ndarray, theta: np.ndarray,
                 k: float) -> np.ndarray:
    """Unit arrows along the aerodynamic force C_D (-v^) + C_L n^, with v^ the tangent of
    the *drawn* (exaggerated) path so the arrows read correctly against it (SI rows of
    (v, gamma, h) at the drawn points P)."""
    gamma_drawn = np.arctan2(k * (model.R_EARTH + x[:, 2]) * np.sin(x[:, 1]),
                             np.linalg.norm(P, axis=1) * np.cos(x[:, 1]))
    e_r = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    e_t = np.column_stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)])
    v_hat = np.cos(gamma_drawn)[:, None] * e_t + np.sin(gamma_drawn)[:, None] * e_r
    n_hat = -np.sin(gamma_drawn)[:, None] * e_t + np.cos(gamma_drawn)[:, None] * e_r
    cd = model.C1 - model.C2 * np.cos(u)
    cl = model.C3 * np.sin(u)
    force = -cd[:, None] * v_hat + cl[:, None] * n_hat
    return force / np.linalg.norm(force, axis=1, keepdims=True)


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The reentry in the entry plane with view option `exaggerate` (altitude factor)."""
    k = float(view["exaggerate"])
    with np.errstate(over="ignore", invalid="ignore"):  # a diverged iterate may overflow
        theta = model.downrange(sol.t, sol.x)
        heating = model.heating_rate(model.to_model(sol.x))
    theta_nodes = np.interp(sol.node_t, sol.t, theta)
    path = display(theta, sol.x[:, 2], k)
    nodes = display(theta_nodes, sol.node_x[:, 2], k)
    return Presentation(
        frame=f"Earth-centred, entry plane (altitude exaggerated {k:g}×)",
        path=path,
        nodes=nodes,
        thrust=force_arrows(nodes, sol.node_x, sol.node_u[:, 0], theta_nodes, k),
        display_unit="km",
        display_scale=1e-3,
        bodies=[Body("Earth", (0.0, 0.0, 0.0), model.R_EARTH, palette.EARTH)],
        markers=[Marker("entry", tuple(path[0]), palette.START),
                 Marker("end of manoeuvre", tuple(path[-1]), palette.TARGET)],
        color_by=ColorBy("heating rate 10 v³√ρ", COST_UNIT + "/s", heating),
        plots=plots(sol, heating),
        iterates=[(it.iteration, display(model.downrange(it.t, it.x), it.x[:, 2], k))
                  for it in sol.history],
        vehicle=sol.mission,
        arrow_name="aerodynamic force direction (lift + drag)",
    )


def plots(sol: Solution, heating: np.ndarray) -> list[PlotSeries]:
    t, x, u, tn, xn, un = sol.t, sol.x, sol.u[:, 0], sol.node_t, sol.node_x, sol.node_u[:, 0]
    with np.errstate(over="ignore", invalid="ignore"):
        decel = model.drag_deceleration(model.to_model(x), u)
    return [
        PlotSeries("speed v", "km/s", t, x[:, 0] / 1e3, tn, xn[:, 0] / 1e3),
        PlotSeries("flight-path angle γ", "deg", t, x[:, 1] / DEG, tn, xn[:, 1] / DEG),
        PlotSeries("altitude", "km", t, x[:, 2] / 1e3, tn, xn[:, 2] / 1e3),
        PlotSeries("trim angle u", "deg", t, u / DEG, tn, un / DEG, group="control"),
        PlotSeries("heating rate 10 v³√ρ", COST_UNIT + "/s", t, heating, tn,
                   np.interp(tn, t, heating), group="output"),
        PlotSeries("deceleration", "g", t, decel / G0, group="output"),
    ]
