"""How the CW rendezvous is drawn: in the target orbital frame (x against the velocity, y up,
z orbit normal) or inertially around the Earth with the relative motion magnified; thrust
arrows, and the plots of paper 000's figures 3–4."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...dynamics.clohessy_wiltshire import R_EARTH, frame_axes, mean_motion
from ...presentation import Body, Curve, Marker, PlotSeries, Presentation
from ...solution import Solution


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The rendezvous in the view chosen by `view["view"]` (0: target frame, 1: inertial,
    relative motion × `view["magnify"]`)."""
    values = sol.values
    inertial = view["view"] == 1
    w = mean_motion(values["altitude"])

    def place(t: np.ndarray, X: np.ndarray) -> np.ndarray:
        return _positions(values, view, w, t, X)

    direction = sol.node_u / values["accel"]
    if inertial:
        ex, ey, ez = frame_axes(w * sol.node_t)
        direction = direction[:, :1] * ex + direction[:, 1:2] * ey + direction[:, 2:3] * ez
    pres = Presentation(
        frame="", path=place(sol.t, sol.x), nodes=place(sol.node_t, sol.node_x),
        thrust=direction, display_unit="km", display_scale=1e-3,
        plots=plots(sol), iterates=[(it.iteration, place(it.t, it.x)) for it in sol.history],
    )
    if inertial:
        _inertial_scene(pres, values, view["magnify"])
    else:
        _relative_scene(pres, values)
    return pres


def _positions(values: Mapping[str, float], view: Mapping[str, float], w: float,
               t: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Display-frame positions: relative (target frame) or inertial with magnified
    relative motion."""
    rel = X[:, :3]
    if view["view"] == 0:
        return rel.copy()
    ex, ey, ez = frame_axes(w * t)
    target = (R_EARTH + values["altitude"]) * ey
    return target + view["magnify"] * (rel[:, :1] * ex + rel[:, 1:2] * ey + rel[:, 2:3] * ez)


def _relative_scene(pres: Presentation, values: Mapping[str, float]) -> None:
    """The target, the approach axis and the chaser's start in the target frame."""
    extent = max(abs(values["x0"]), abs(values["y0"]), 1000.0)
    pres.frame = "target orbital frame (x against velocity, y up, z orbit normal)"
    pres.up = "+y"
    pres.bodies = [Body("target (enlarged)", (0.0, 0.0, 0.0), 0.01 * extent,
                        palette.TARGET_BODY)]
    pres.curves = [Curve("approach axis (x)", np.array([[0, 0, 0], [1.2 * extent, 0, 0]]),
                         palette.AXIS, dashed=True)]
    pres.markers = [Marker("target", (0.0, 0.0, 0.0), palette.TARGET),
                    Marker("chaser start", (values["x0"], values["y0"], values["z0"]),
                           palette.START)]


def _inertial_scene(pres: Presentation, values: Mapping[str, float], magnify: float) -> None:
    """The Earth and the target's circular orbit (target at angle 0 at the start)."""
    radius = R_EARTH + values["altitude"]
    angle = np.linspace(0, 2 * np.pi, 361)
    orbit = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), 0 * angle])
    pres.frame = f"inertial, relative motion × {magnify:g}"
    pres.up = "+z"
    pres.bodies = [Body("Earth", (0.0, 0.0, 0.0), R_EARTH, palette.EARTH)]
    pres.curves = [Curve("target orbit", orbit, palette.ORBIT)]
    pres.markers = [Marker("target at start", (radius, 0.0, 0.0), palette.TARGET)]


def plots(sol: Solution) -> list[PlotSeries]:
    """x, y, x', y' (paper figs. 3–4), throttle and thrust direction in the x–y plane."""
    t, X, U, tn, Xn, An = sol.t, sol.x, sol.u, sol.node_t, sol.node_x, sol.node_u
    accel = sol.values["accel"]
    angle = np.degrees(np.arctan2(U[:, 1], U[:, 0]))
    angle_nodes = np.degrees(np.arctan2(An[:, 1], An[:, 0]))
    return [
        PlotSeries("x", "km", t, X[:, 0] / 1e3, tn, Xn[:, 0] / 1e3),
        PlotSeries("y", "km", t, X[:, 1] / 1e3, tn, Xn[:, 1] / 1e3),
        PlotSeries("x'", "m/s", t, X[:, 3], tn, Xn[:, 3]),
        PlotSeries("y'", "m/s", t, X[:, 4], tn, Xn[:, 4]),
        PlotSeries("throttle |a u|/a", "", t, np.linalg.norm(U, axis=1) / accel, tn,
                   np.linalg.norm(An, axis=1) / accel, group="control"),
        PlotSeries("thrust direction in x–y", "deg", t, angle, tn, angle_nodes,
                   group="control"),
    ]
