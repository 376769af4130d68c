"""The cart drawn on its rail (x along the rail, velocity up, so the path is the phase
portrait), with the maximum-principle optimum dashed over it: full acceleration to the
middle, full braking after, the two parabolic arcs v = √(2ax) and v = √(2a(d − x))."""

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
    u = sol.node_u[:, 0] / a
    return Presentation(
        frame="phase plane: position along the rail (x), velocity (up)",
        path=plane(sol.x), nodes=plane(sol.node_x),
        thrust=np.column_stack([u, np.zeros_like(u), np.zeros_like(u)]),
        curves=[Curve("rail", np.array([[0.0, 0, 0], [d, 0, 0]]), palette.AXIS),
                Curve("maximum-principle optimum", plane(optimum(d, a)), palette.REFERENCE,
                      dashed=True)],
        markers=[Marker("start", (0.0, 0.0, 0.0), palette.START),
                 Marker("target", (d, 0.0, 0.0), palette.TARGET)],
        plots=[PlotSeries("x", "m", sol.t, sol.x[:, 0], sol.node_t, sol.node_x[:, 0]),
               PlotSeries("v", "m/s", sol.t, sol.x[:, 1], sol.node_t, sol.node_x[:, 1]),
               PlotSeries("u", "m/s²", sol.t, sol.u[:, 0], sol.node_t, sol.node_u[:, 0],
                          group="control")],
        iterates=[(it.iteration, plane(it.x)) for it in sol.history],
        vehicle=sol.mission,
        arrow_name="acceleration u (length u/a)",
        arc_names={"burn": "phase path (x, v)", "coast": "phase path (x, v)"},
    )


def optimum(d: float, a: float, samples: int = 401) -> np.ndarray:
    """(samples, 2) points (x, v) of the bang–bang optimum, sampled evenly in time over
    T* = 2√(d/a) (dense where v = √(2ax) rises steeply from rest): x = at²/2 up to the
    switch at T*/2, then the mirror image x = d − a(T* − t)²/2 (Kirk 1970, ex. 5.3-1)."""
    total = 2.0 * np.sqrt(d / a)
    t = np.linspace(0.0, total, samples)
    left = np.minimum(t, total - t)  # time from the nearer end
    x = np.where(t <= total / 2, 0.5 * a * left**2, d - 0.5 * a * left**2)
    return np.column_stack([x, a * left])
