"""How the Mars descent is drawn: a surface-fixed frame (x downrange, y crossrange, z up,
the target at (tx, ty, 0) where it was dragged), the surface patch, the glide-slope cone, the
path with thrust vectors (length = throttle of T_max) and the throttle bounds ρ1, ρ2 as rings
around them, the start, the target and the touchdown."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...presentation import ColorBy, Curve, Marker, PlotSeries, Presentation
from ...solution import Solution
from .model import P_RHO1, P_RHO2, P_TAN_GS, parameter_vector, target

MARS: tuple[int, int, int] = (190, 110, 70)  # the surface patch (a body colour of its own)


TOGETHER = 0.02  # of the drawing's extent: closer than this, target and touchdown share a label


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The descent in the surface-fixed frame, the target at (tx, ty, 0): the solution's
    states are relative to the target (`model.target`), so every point moves by it. This
    mission has no view options."""
    values = sol.values
    p = parameter_vector(values)
    aim = target(values)
    t_max = values["thrusters"] * values["thrust_each"] * np.cos(values["cant"])
    thrust = np.linalg.norm(sol.u, axis=1)
    # Around the target: the patch and cone centred on it reach past the whole path.
    extent = 1.2 * max(float(np.max(np.abs(sol.x[:, :3]))), values["altitude0"], 500.0)
    touchdown = tuple(float(c) for c in sol.x[-1, :3] + aim)
    return Presentation(
        frame=f"surface-fixed: x downrange, y crossrange, z up (Mars surface at z = 0), the "
              f"target at ({aim[0]:g}, {aim[1]:g}) m",
        path=sol.x[:, :3] + aim, nodes=sol.node_x[:, :3] + aim,
        thrust=sol.node_u / t_max, thrust_bounds=(values["throttle_min"],
                                                  values["throttle_max"]),
        display_unit="km", display_scale=1e-3,
        curves=[*surface(extent, aim), *cone(p[P_TAN_GS], values["altitude0"] * 1.1, extent,
                                             aim)],
        markers=[Marker("start", tuple(float(c) for c in sol.x[0, :3] + aim), palette.START),
                 *landing_markers(touchdown, aim, extent)],
        color_by=ColorBy("thrust", "N", thrust),
        plots=plots(sol, p),
        iterates=[(it.iteration, it.x[:, :3] + aim) for it in sol.history],
        vehicle="lunar-landing",
    )


def landing_markers(touchdown: tuple[float, float, float], aim: np.ndarray, extent: float
                    ) -> list[Marker]:
    """The target `aim` and the touchdown (surface-fixed, m): one label when they meet (two
    would overlap), two when the target is out of reach (minimum landing error, Blackmore
    et al.'s problem 1: the miss is the distance drawn)."""
    where = tuple(float(c) for c in aim)
    miss = float(np.hypot(touchdown[0] - aim[0], touchdown[1] - aim[1]))
    if miss <= TOGETHER * extent:
        return [Marker(f"target: touched down {miss:.1f} m from it", where, palette.TARGET)]
    return [Marker("target", where, palette.TARGET),
            Marker(f"touchdown ({miss:.1f} m from the target)", touchdown, palette.LABEL)]


def surface(extent: float, aim: np.ndarray, lines: int = 9) -> list[Curve]:
    """A square grid on the ground centred on the target `aim`, as one polyline (back and
    forth)."""
    ticks = np.linspace(-extent, extent, lines)
    points = []
    for i, c in enumerate(ticks):
        ends = [-extent, extent][:: 1 if i % 2 == 0 else -1]
        points += [[c, ends[0], 0.0], [c, ends[1], 0.0]]
    for i, c in enumerate(ticks[::-1]):
        ends = [extent, -extent][:: 1 if i % 2 == 0 else -1]
        points += [[ends[0], c, 0.0], [ends[1], c, 0.0]]
    return [Curve("Mars surface", np.array(points) + aim, MARS)]


def cone(tan_gs: float, height: float, extent: float, aim: np.ndarray, generators: int = 12
         ) -> list[Curve]:
    """The glide-slope cone z = tan γ · ρ (dashed), its apex at the target `aim`, as one
    polyline: generators from the apex up to the rim and the rim between them, clipped to
    the view."""
    if tan_gs <= 0:
        return []
    radius = min(height / tan_gs, 2 * extent)
    top = radius * tan_gs
    points = []
    angles = np.linspace(0.0, 2 * np.pi, generators + 1)
    for a0, a1 in zip(angles[:-1], angles[1:], strict=True):
        rim = np.linspace(a0, a1, 8)
        points.append([0.0, 0.0, 0.0])
        points += [[radius * np.cos(a), radius * np.sin(a), top] for a in rim]
    points.append([0.0, 0.0, 0.0])
    return [Curve("glide-slope cone", np.array(points) + aim, palette.BOUND, dashed=True)]


def plots(sol: Solution, p: np.ndarray) -> list[PlotSeries]:
    t, tn = sol.t, sol.node_t
    thrust, thrust_n = np.linalg.norm(sol.u, axis=1), np.linalg.norm(sol.node_u, axis=1)
    ones = np.ones_like(t)
    return [
        PlotSeries("altitude", "m", t, sol.x[:, 2], tn, sol.node_x[:, 2]),
        PlotSeries("downrange from the target", "m", t, sol.x[:, 0], tn, sol.node_x[:, 0]),
        PlotSeries("speed", "m/s", t, np.linalg.norm(sol.x[:, 3:6], axis=1), tn,
                   np.linalg.norm(sol.node_x[:, 3:6], axis=1)),
        PlotSeries("mass", "kg", t, np.exp(sol.x[:, 6]), tn, np.exp(sol.node_x[:, 6])),
        PlotSeries("|T|", "kN", t, thrust / 1e3, tn, thrust_n / 1e3, group="control"),
        PlotSeries("ρ1 (lower thrust bound)", "kN", t, ones * p[P_RHO1] / 1e3, group="control"),
        PlotSeries("ρ2 (upper thrust bound)", "kN", t, ones * p[P_RHO2] / 1e3, group="control"),
        PlotSeries("thrust angle from vertical", "deg", t, np.degrees(np.arccos(np.clip(
            sol.u[:, 2] / np.maximum(thrust, 1e-9), -1, 1))), tn, np.degrees(np.arccos(
                np.clip(sol.node_u[:, 2] / np.maximum(thrust_n, 1e-9), -1, 1))),
                   group="control"),
    ]
