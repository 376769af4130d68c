"""Shapes drawn in the 3D view (issue 19): obstacles and constraint surfaces a mission or a
mission file declares in its display frame, each a unit mesh scaled and placed by numbers or
parameters (metres; an angle in radians).

- `Sphere(key, label, center, radius)`: a keep-out zone;
- `Cylinder(key, label, center, radius, height)`: a column standing on the display z axis,
  centred on `center` (a round obstacle of a planar field, seen from the side too);
- `Cone(key, label, apex, angle, height)`: a glide-slope cone, the apex at `apex`, opening up
  the display z axis, the surface at `angle` above the horizontal (z = tan(angle) · ρ);
- `Box(key, label, center, size)`: a block, `size` = its three edges;
- `Plane(key, label, center, size, normal)`: a square of side `size` through `center`,
  perpendicular to the display axis `normal` ("x", "y" or "z"): a floor, a wall, a ceiling.

A centre bound to parameters drags like a `Handle`; sizes and angles follow their sliders.
Everything here is SI and pure numerics: the explorer draws them (`explorer/handles.py`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache
from typing import ClassVar, Literal

import numpy as np

from .handles import Axis, Coordinate, Handle, as_axis, coordinate

Mesh = tuple[np.ndarray, np.ndarray]  # vertices (n, 3) float32, faces (m, 3) uint32
MIN_SLOPE = 1e-3  # tan of the flattest cone drawn (a flat one would be infinitely wide)


@dataclass(frozen=True)
class Shape:
    """A shape placed at `center` in the display frame; `views` as for a `Handle`."""

    key: str
    label: str
    center: tuple[Coordinate, Coordinate, Coordinate]
    views: Mapping[str, float] = field(default_factory=dict, kw_only=True)
    kind: ClassVar[str] = ""

    @property
    def handle(self) -> Handle:
        """The centre as a handle (what drags the shape)."""
        return Handle(self.key, self.label, self.center, self.views)

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        """The coordinates that size the shape (radius, height, angle, edges)."""
        return ()

    @property
    def axes(self) -> tuple[Axis | None, ...]:
        """Every parameter binding: the centre's and the sizes' (checked like a handle's)."""
        return (*self.handle.axes, *(as_axis(c) for c in self.sizes))

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        """Display metres per unit of `unit_mesh` along x, y, z."""
        raise NotImplementedError

    def unit_mesh(self) -> Mesh:
        return unit_mesh(self.kind)


@dataclass(frozen=True)
class Sphere(Shape):
    radius: Coordinate = 1.0
    kind: ClassVar[str] = "sphere"

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        return (self.radius,)

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        r = coordinate(self.radius, values, view)
        return r, r, r


@dataclass(frozen=True)
class Cylinder(Shape):
    radius: Coordinate = 1.0
    height: Coordinate = 1.0
    kind: ClassVar[str] = "cylinder"

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        return self.radius, self.height

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        r = coordinate(self.radius, values, view)
        return r, r, coordinate(self.height, values, view)


@dataclass(frozen=True)
class Cone(Shape):
    angle: Coordinate = math.pi / 4  # rad above the horizontal: the glide slope
    height: Coordinate = 1.0
    kind: ClassVar[str] = "cone"

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        return self.angle, self.height

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        h = coordinate(self.height, values, view)
        rim = h / max(math.tan(coordinate(self.angle, values, view)), MIN_SLOPE)
        return rim, rim, h


@dataclass(frozen=True)
class Box(Shape):
    size: tuple[Coordinate, Coordinate, Coordinate] = (1.0, 1.0, 1.0)
    kind: ClassVar[str] = "box"

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        return self.size

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        a, b, c = (coordinate(s, values, view) for s in self.size)
        return a, b, c


@dataclass(frozen=True)
class Plane(Shape):
    size: Coordinate = 1.0
    normal: Literal["x", "y", "z"] = "z"
    kind: ClassVar[str] = "plane"

    def __post_init__(self) -> None:
        if self.normal not in ("x", "y", "z"):
            raise ValueError(f"plane '{self.key}': normal must be 'x', 'y' or 'z'")

    @property
    def sizes(self) -> tuple[Coordinate, ...]:
        return (self.size,)

    def scale(self, values: Mapping[str, float], view: Mapping[str, float]
              ) -> tuple[float, float, float]:
        s = coordinate(self.size, values, view)
        return s, s, s

    def unit_mesh(self) -> Mesh:
        return unit_mesh(f"plane-{self.normal}")


@cache
def unit_mesh(kind: str) -> Mesh:
    """The unit mesh of a kind: sphere and cylinder of radius 1 (the cylinder 1 high,
    centred), a cone with its apex at the origin and its rim of radius 1 at z = 1, a unit
    cube centred, a unit square through the origin (`plane-x|y|z`: its normal)."""
    import trimesh

    if kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=3)
    elif kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=1.0, height=1.0, sections=32)
    elif kind == "cone":  # trimesh's apex is at the top: turn it upside down
        mesh = trimesh.creation.cone(radius=1.0, height=1.0, sections=32)
        vertices = np.asarray(mesh.vertices, np.float32) * (1, 1, -1) + (0, 0, 1)
        faces = np.asarray(mesh.faces, np.uint32)[:, ::-1]
        open_rim = ~np.all(vertices[faces, 2] > 1 - 1e-6, axis=1)  # no lid: see inside
        return vertices, faces[open_rim]
    elif kind == "box":
        mesh = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    elif kind.startswith("plane-"):
        square = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
        normal = "xyz".index(kind[-1])
        vertices = np.insert(square, normal, 0.0, axis=1)
        return vertices.astype(np.float32), np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    else:
        raise ValueError(f"no shape '{kind}'")
    return np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.uint32)
