"""Shapes a mission or mission file draws in the 3D view (issue 19): each unit mesh scaled by
its parameters has the size its record states (a sphere's radius, a cylinder's radius and
height, a cone's rim at its glide-slope angle, a box's edges, a plane's side across its
normal), and a shape bound to an unknown parameter is refused where the file declares it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from solvers.shapes import Box, Cone, Cylinder, Plane, Sphere
from solvers.userproblem import Control, DeclarationError, Param, State, UserMission


def _extent(shape, values) -> tuple[np.ndarray, np.ndarray]:
    vertices, faces = shape.unit_mesh()
    assert faces.max() < len(vertices) and faces.dtype == np.uint32
    placed = vertices * np.array(shape.scale(values, {}))
    return placed.min(axis=0), placed.max(axis=0)


def test_every_shape_has_the_size_its_parameters_give() -> None:
    values = {"r": 2.0, "h": 3.0, "gamma": math.radians(30.0), "a": 4.0}
    lo, hi = _extent(Sphere("s", "s", (0.0, 0.0, 0.0), "r"), values)
    assert hi == pytest.approx([2.0] * 3, rel=1e-6) and lo == pytest.approx([-2.0] * 3, rel=1e-6)
    lo, hi = _extent(Cylinder("c", "c", (0.0, 0.0, 0.0), "r", "h"), values)
    assert hi == pytest.approx([2.0, 2.0, 1.5], rel=1e-3) and lo[2] == pytest.approx(-1.5)
    cone = Cone("k", "k", (0.0, 0.0, 0.0), "gamma", "h")
    vertices, _ = cone.unit_mesh()
    placed = vertices * np.array(cone.scale(values, {}))
    rho = np.hypot(placed[:, 0], placed[:, 1])
    on_surface = rho > 1e-9  # the apex aside: every vertex on z = tan γ · ρ
    assert placed[:, 2][on_surface] == pytest.approx(math.tan(values["gamma"]) * rho[on_surface],
                                                     rel=1e-5)
    assert placed[:, 2].min() == 0.0 and placed[:, 2].max() == pytest.approx(3.0)
    lo, hi = _extent(Box("b", "b", (0.0, 0.0, 0.0), ("a", 1.0, "h")), values)
    assert hi - lo == pytest.approx([4.0, 1.0, 3.0])
    for normal, axis in (("x", 0), ("y", 1), ("z", 2)):
        lo, hi = _extent(Plane("p", "p", (0.0, 0.0, 0.0), "a", normal), values)
        width = hi - lo
        assert width[axis] == 0.0 and np.delete(width, axis) == pytest.approx([4.0, 4.0])
    with pytest.raises(ValueError, match="normal"):
        Plane("p", "p", (0.0, 0.0, 0.0), 1.0, "w")  # type: ignore[arg-type]


def test_a_shape_bound_to_an_unknown_parameter_is_refused_at_its_declaration() -> None:
    def declare(shape):
        return UserMission(
            key="shape-check", title="t",
            params=(Param("d", "distance", "m", 1.0, 0.5, 2.0, 0.1),),
            states=(State("x", "m", bounds=(-5, 5), initial=0.0, final="d"),
                    State("v", "m/s", bounds=(-5, 5), initial=0.0, final=0.0)),
            controls=(Control("a", "m/s²", bounds=(-10, 10)),),
            dynamics=lambda x, u, p: [x.v, u.a], lagrange=lambda x, u, p: u.a**2,
            final_time=1.0, shapes=(shape,))

    assert declare(Cone("ok", "ok", ("d", 0.0, 0.0), 0.5, 1.0)).shapes[0].handle.params == ("d",)
    with pytest.raises(DeclarationError, match="'height' is not a numeric parameter"):
        declare(Cylinder("bad", "bad", (0.0, 0.0, 0.0), "d", "height"))
