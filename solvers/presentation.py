"""What the explorer draws, built by a mission's view from a numeric `Solution`.

A `Presentation` holds positions in the mission's display frame, thrust arrows, the bodies,
reference curves and markers around the path, the plots and maps. It never goes back into
the numerics: changing a view option (frame, magnification, altitude exaggeration) builds a
new presentation from the same solution without re-solving. Lengths are metres (the explorer
multiplies by `display_scale`), times are seconds (plots multiply by `time_scale`), colours are
names from `palette.py`, never literals.
"""

from __future__ import annotations

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
    """A labelled point in the display frame (metres): a landing site, a launch date."""

    name: str
    position: tuple[float, float, float]
    color: RGB = (255, 255, 255)


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
