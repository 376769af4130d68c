"""The cart drawn on its rail (x along the rail, velocity up, so the path is the phase
portrait), with the maximum-principle switch marked."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...presentation import Curve, Marker, PlotSeries, Presentation
from ...solution import Solution


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """Phase plane (x, v) in metres and metres per second, drawn as x and height."""
    def plane(X: np.ndarray) -> np.ndarray:
        return np.column_stack([X[:, 0], np.zeros(len(X)), X[:, 1]])

    d = sol.values["distance"]
    a = sol.values["accel"]
    v_peak = float(np.sqrt(a * d))
    u = sol.node_u[:, 0] / a
    return Presentation(
        frame="phase plane: position along the rail (x), velocity (up)",
        path=plane(sol.x), nodes=plane(sol.node_x),
        thrust=np.column_stack([u, np.zeros_like(u), np.zeros_like(u)]),
        curves=[Curve("rail", np.array([[0.0, 0, 0], [d, 0, 0]]), palette.AXIS),
                Curve("maximum-principle optimum", plane(np.array(
                    [[0.0, 0.0], [d / 2, v_peak], [d, 0.0]])), palette.REFERENCE, dashed=True)],
        markers=[Marker("start", (0.0, 0.0, 0.0), palette.START),
                 Marker("target", (d, 0.0, 0.0), palette.TARGET)],
        plots=[PlotSeries("x", "m", sol.t, sol.x[:, 0], sol.node_t, sol.node_x[:, 0]),
               PlotSeries("v", "m/s", sol.t, sol.x[:, 1], sol.node_t, sol.node_x[:, 1]),
               PlotSeries("u", "m/s²", sol.t, sol.u[:, 0], sol.node_t, sol.node_u[:, 0],
                          group="control")],
        iterates=[(it.iteration, plane(it.x)) for it in sol.history],
        vehicle=sol.mission,
    )
