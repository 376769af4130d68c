"""What the explorer draws, built by a mission's view from a numeric `Solution`.

A `Presentation` holds positions in the mission's display frame, thrust arrows, the bodies,
reference curves and markers around the path, the plots and maps. It never goes back into
the numerics: changing a view option (frame, magnification, altitude exaggeration) builds a
new presentation from the same solution without re-solving. Lengths are metres (the explorer
multiplies by `display_scale`), times are seconds (plots multiply by `time_scale`), colours are
names from `palette.py`, never literals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

RGB = tuple[int, int, int]


@dataclass
class PlotSeries:
    """One curve for a plot panel: dense samples plus the NLP node samples (times in s)."""

    title: str
    unit: str
    t: np.ndarray
    y: np.ndarray
    t_nodes: np.ndarray | None = None
    y_nodes: np.ndarray | None = None
    group: str = "state"


@dataclass
class Body:
    """A sphere in the display frame (metres): the Moon, the Earth, the Sun, a target.
    `track` is where it is at each dense time `Solution.t` (bodies that move with the
    vehicle in the animation); None = fixed."""

    name: str
    center: tuple[float, float, float]
    radius: float
    color: RGB
    track: np.ndarray | None = None


@dataclass
class Curve:
    """A reference polyline in the display frame (metres): an orbit, an approach axis."""

    name: str
    points: np.ndarray
    color: RGB
    dashed: bool = False


@dataclass
class Marker:
    """A labelled point in the display frame (metres): a landing site, a launch date; with
    `point` False a label alone (an axis tick), placed by its `anchor` corner (a viser
    label anchor such as "top-center")."""

    name: str
    position: tuple[float, float, float]
    color: RGB = (255, 255, 255)
    point: bool = True
    anchor: str = "bottom-left"


@dataclass
class ColorBy:
    """A scalar along the dense path (one value per `Solution.t` sample) to colour it by,
    e.g. heating rate or thrust magnitude; the explorer picks the colour map."""

    name: str
    unit: str
    values: np.ndarray


@dataclass
class GridMap:
    """A scalar over a 2-D grid shown as a contour map beside the plots (e.g. launch C3 over
    launch date and flight time), with this solution marked. `z` has shape (len(x), len(y));
    values above `z_max` are clipped."""

    title: str
    x_label: str
    x: np.ndarray
    y_label: str
    y: np.ndarray
    z_label: str
    z: np.ndarray
    z_max: float
    marker: tuple[float, float] | None = None
    marker_label: str = "this solution"


@dataclass
class Presentation:
    """Everything the explorer draws for one solution in one set of view options."""

    frame: str
    path: np.ndarray  # (len(Solution.t), 3) metres, display frame
    nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    thrust: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # per node, |.| = throttle
    # The throttle's bounds (fractions of the |.| = 1 thrust, e.g. ρ1/T_max, ρ2/T_max): the
    # explorer draws them as rings around the arrows' bases, the tips between them.
    thrust_bounds: tuple[float, float] | None = None
    display_unit: str = "m"
    display_scale: float = 1.0
    up: str = "+z"
    bodies: list[Body] = field(default_factory=list)
    curves: list[Curve] = field(default_factory=list)
    markers: list[Marker] = field(default_factory=list)
    color_by: ColorBy | None = None
    plots: list[PlotSeries] = field(default_factory=list)
    maps: list[GridMap] = field(default_factory=list)
    iterates: list[tuple[int, np.ndarray]] = field(default_factory=list)  # (iteration, path)
    time_unit: str = "s"
    time_scale: float = 1.0  # display time = seconds x time_scale (e.g. 1/86400 for days)
    vehicle: str = "default"  # a mesh name of assets/vehicles.json
    arrow_name: str = "thrust direction"  # what the arrows show, in the legend
    arc_names: dict[str, str] = field(  # legend names of the burn- and coast-coloured path
        default_factory=lambda: {"burn": "burn arc", "coast": "coast arc"})
    plan: bool = False  # the default camera looks straight at the path's plane (a 2-D plot)


def nice_step(span: float, count: int = 5) -> float:
    """A round tick step (1, 2 or 5 times a power of ten) giving about `count` ticks."""
    if not span > 0:
        return 1.0
    raw = span / count
    power = 10.0 ** math.floor(math.log10(raw))
    return min((m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= raw), default=raw)


def plot_axes(lo: tuple[float, float], hi: tuple[float, float], names: tuple[str, str],
              grid_color: RGB, axis_color: RGB, label_color: RGB
              ) -> tuple[list[Curve], list[Marker]]:
    """A 2-D plot's frame in the z = 0 plane (x right, y up, lengths in the user's unit):
    the x and y axes along the box's lower and left edges, a grid at round ticks, tick
    labels and the axis names `names` (each with its unit) at the axes' ends."""
    ticks = []
    for k in range(2):
        step = nice_step(hi[k] - lo[k])
        start, stop = math.floor(lo[k] / step) * step, math.ceil(hi[k] / step) * step
        if stop - start < step / 2:  # a flat coordinate: one step around it
            start, stop = start - step, stop + step
        ticks.append(np.arange(start, stop + step / 2, step))
    (x0, x1), (y0, y1) = (t[[0, -1]] for t in ticks)
    grid = []
    for i, gx in enumerate(ticks[0]):
        grid += [(gx, y0), (gx, y1)] if i % 2 == 0 else [(gx, y1), (gx, y0)]
    for gy in ticks[1][::-1] if grid[-1][1] == y1 else ticks[1]:
        grid += [(grid[-1][0], gy), (x0 if grid[-1][0] == x1 else x1, gy)]
    flat = np.column_stack([np.array(grid, float), np.zeros(len(grid))])
    axes = np.array([[x1, y0, 0.0], [x0, y0, 0.0], [x0, y1, 0.0]])
    dx, dy = 0.02 * (x1 - x0), 0.02 * (y1 - y0)
    labels = [Marker(f"{v:g}", (float(v), y0 - dy, 0.0), label_color, False, "top-center")
              for v in ticks[0]]
    labels += [Marker(f"{v:g}", (x0 - dx, float(v), 0.0), label_color, False, "center-right")
               for v in ticks[1]]
    labels += [Marker(names[0], (x1 + 2 * dx, y0, 0.0), label_color, False, "center-left"),
               Marker(names[1], (x0, y1 + 2 * dy, 0.0), label_color, False, "bottom-center")]
    return [Curve("grid", flat, grid_color), Curve("axes", axes, axis_color)], labels
