"""How the lunar landing is drawn: the Moon, the descent orbit, the path in the descent plane
(Moon-centred, km), braking-thrust arrows and the plots of paper 002's figures."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...presentation import Body, Curve, Marker, PlotSeries, Presentation
from ...solution import Solution
from .model import R_MOON, conic_points
from .problem import DEG, P_R0, P_W0, parameter_vector


def plane_to_3d(r: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Orbit-plane polar coordinates to the display frame (Moon-centred, plane z = 0)."""
    return np.column_stack([r * np.cos(theta), r * np.sin(theta), np.zeros_like(r)])


def thrust_directions(theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Braking thrust: up by ψ from the local horizontal, against the motion (+θ)."""
    e_r = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    e_t = np.column_stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)])
    return np.sin(psi)[:, None] * e_r - np.cos(psi)[:, None] * e_t


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The landing in the descent plane (this mission has no view options)."""
    p = parameter_vector(sol.values)
    path = plane_to_3d(sol.x[:, 0], sol.x[:, 2])
    orbit = conic_points(p[P_R0], 0.0, p[P_W0])
    ignition = plane_to_3d(np.array([p[P_R0]]), np.zeros(1))[0]
    return Presentation(
        frame="Moon-centred, descent plane",
        path=path,
        nodes=plane_to_3d(sol.node_x[:, 0], sol.node_x[:, 2]),
        thrust=thrust_directions(sol.node_x[:, 2], sol.node_u[:, 0]),
        display_unit="km",
        display_scale=1e-3,
        bodies=[Body("Moon", (0.0, 0.0, 0.0), R_MOON, palette.MOON)],
        curves=[Curve("descent orbit", np.column_stack([orbit, np.zeros(len(orbit))]),
                      palette.EARTH_ORBIT, dashed=True)],
        markers=[Marker("ignition", tuple(ignition), palette.START),
                 Marker("touchdown", tuple(path[-1]), palette.TARGET)],
        plots=plots(sol),
        iterates=[(it.iteration, plane_to_3d(it.x[:, 0], it.x[:, 2])) for it in sol.history],
        vehicle=sol.mission,
    )


def plots(sol: Solution) -> list[PlotSeries]:
    t, X, psi, tn, Xn, psin = sol.t, sol.x, sol.u[:, 0], sol.node_t, sol.node_x, sol.node_u[:, 0]

    def series(title: str, unit: str, y: np.ndarray, y_nodes: np.ndarray,
               group: str = "state") -> PlotSeries:
        return PlotSeries(title, unit, t, y, tn, y_nodes, group)

    return [
        series("altitude", "km", (X[:, 0] - R_MOON) / 1e3, (Xn[:, 0] - R_MOON) / 1e3),
        series("radial speed", "m/s", X[:, 1], Xn[:, 1]),
        series("angular rate ω", "mrad/s", X[:, 3] * 1e3, Xn[:, 3] * 1e3),
        series("thrust angle ψ", "deg", psi / DEG, psin / DEG, group="control"),
        series("mass", "kg", X[:, 4], Xn[:, 4]),
    ]
