"""The record every method returns, so the explorer never asks which method made it."""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

STATUSES = ("optimal", "infeasible", "iteration-limit", "time-limit", "cancelled", "failed")


@dataclass
class Quantity:
    """A labelled scalar in SI units."""

    value: float
    label: str
    unit: str

    def to_dict(self) -> dict[str, Any]:
        return {"value": _num(self.value), "label": self.label, "unit": self.unit}


@dataclass
class PlotSeries:
    """One curve for a plot panel: dense samples plus the NLP node samples."""

    title: str
    unit: str
    t: np.ndarray
    y: np.ndarray
    t_nodes: np.ndarray | None = None
    y_nodes: np.ndarray | None = None
    group: str = "state"


@dataclass
class Body:
    """A sphere in the display frame (metres): the Moon, the Earth, the Sun, a target."""

    name: str
    center: tuple[float, float, float]
    radius: float
    color: tuple[int, int, int]
    # Where the body is at each dense time `Solution.t` (metres, display frame), for bodies
    # that move with the vehicle in the animation (a planet, a target); None = fixed.
    track: np.ndarray | None = None


@dataclass
class Curve:
    """A reference polyline in the display frame (metres): an orbit, an approach axis."""

    name: str
    points: np.ndarray
    color: tuple[int, int, int]
    dashed: bool = False


@dataclass
class Marker:
    """A labelled point in the display frame (metres): a landing site, a launch date."""

    name: str
    position: tuple[float, float, float]
    color: tuple[int, int, int] = (255, 255, 255)


@dataclass
class ColorBy:
    """A scalar along the dense trajectory (one value per `Solution.t` sample) to colour the
    path by, e.g. heating rate or thrust magnitude; the view picks the colour map."""

    name: str
    unit: str
    values: np.ndarray


@dataclass
class GridMap:
    """A scalar over a 2-D grid shown as a contour map beside the plots (e.g. launch C3 over
    launch date and flight time), with this solution marked on it. `z` has shape
    (len(x), len(y)); values above `z_max` are clipped."""

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
class Scene:
    """Everything a 3D view needs besides the trajectory itself."""

    frame: str
    display_unit: str
    display_scale: float
    bodies: list[Body] = field(default_factory=list)
    curves: list[Curve] = field(default_factory=list)
    markers: list[Marker] = field(default_factory=list)
    up: str = "+z"


@dataclass
class Solution:
    """Result of `Mission.solve`, identical in shape for every mission and method.

    Times in s, states/controls in SI (`state_units`, `control_units`), `positions` and
    `node_positions` in metres in the mission's display frame, `thrust` one vector per node
    (display frame, unit length scaled by throttle).
    """

    mission: str
    method: str
    nodes: int
    status: str
    message: str
    cost: Quantity
    values: dict[str, float] = field(default_factory=dict)
    backend: str = ""
    quantities: dict[str, Quantity] = field(default_factory=dict)
    state_names: tuple[str, ...] = ()
    state_units: tuple[str, ...] = ()
    control_names: tuple[str, ...] = ()
    control_units: tuple[str, ...] = ()
    node_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    node_x: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    node_u: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    arcs: list[tuple[float, float, str]] = field(default_factory=list)
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    x: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    u: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    node_positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    thrust: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    scene: Scene | None = None
    color_by: ColorBy | None = None
    plots: list[PlotSeries] = field(default_factory=list)
    maps: list[GridMap] = field(default_factory=list)
    stats: dict[str, float] = field(default_factory=dict)
    history: list[dict[str, Any]] = field(default_factory=list)
    check: dict[str, float] = field(default_factory=dict)
    warm: Any = field(default=None, repr=False)
    checker: Callable[[], dict[str, float]] | None = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        return self.status == "optimal"

    def run_check(self) -> dict[str, float]:
        """Run the deferred re-propagation check (see `Mission.solve(verify=False)`). A check
        that fails is reported in `message`, never raised: the solution stays usable."""
        if self.checker is not None:
            checker, self.checker = self.checker, None
            try:
                self.check.update(checker())
            except Exception as exc:  # noqa: BLE001 - a failed check is reported, not fatal
                self.check["error"] = float("nan")
                self.message += f" (re-propagation check failed: {exc})"
        return self.check

    @property
    def has_trajectory(self) -> bool:
        return len(self.t) > 1

    def summary(self) -> str:
        """One line for a status bar or a terminal."""
        parts = [f"{self.status}", f"{self.cost.label} {self.cost.value:.6g} {self.cost.unit}"]
        for q in self.quantities.values():
            if q.label != self.cost.label:
                parts.append(f"{q.label} {q.value:.6g} {q.unit}".rstrip())
        if "iterations" in self.stats:
            parts.append(f"{int(self.stats['iterations'])} it")
        if "wall_s" in self.stats:
            parts.append(f"{1e3 * self.stats['wall_s']:.0f} ms")
        return " | ".join(parts)

    def to_dict(self, dense: bool = False) -> dict[str, Any]:
        """JSON-ready dict; `dense=True` adds the dense samples."""
        out: dict[str, Any] = {
            "mission": self.mission,
            "method": self.method,
            "backend": self.backend,
            "nodes": self.nodes,
            "status": self.status,
            "message": self.message,
            "values": self.values,
            "cost": self.cost.to_dict(),
            "quantities": {k: _num(q.value) for k, q in self.quantities.items()},
            "quantity_units": {k: q.unit for k, q in self.quantities.items()},
            "stats": {k: _num(v) for k, v in self.stats.items()},
            "check": {k: _num(v) for k, v in self.check.items()},
            "arcs": [[_num(a), _num(b), kind] for a, b, kind in self.arcs],
            "state_names": list(self.state_names),
            "state_units": list(self.state_units),
            "control_names": list(self.control_names),
            "control_units": list(self.control_units),
            "node_t": _arr(self.node_t),
            "node_x": _arr(self.node_x),
            "node_u": _arr(self.node_u),
        }
        if dense:
            out.update(t=_arr(self.t), x=_arr(self.x), u=_arr(self.u))
        return out

    def to_json(self, dense: bool = False) -> str:
        return json.dumps(self.to_dict(dense=dense), allow_nan=False)

    def to_csv(self) -> str:
        """Dense samples as CSV: t, states, controls (SI units in the header)."""
        buf = io.StringIO()
        writer = csv.writer(buf)
        header = ["t [s]"]
        header += [f"{n} [{u}]" for n, u in zip(self.state_names, self.state_units, strict=False)]
        header += [
            f"{n} [{u}]" for n, u in zip(self.control_names, self.control_units, strict=False)
        ]
        writer.writerow(header)
        for i in range(len(self.t)):
            row = [self.t[i], *np.atleast_1d(self.x[i]), *np.atleast_1d(self.u[i])]
            writer.writerow([f"{v:.12g}" for v in row])
        return buf.getvalue()


def _num(v: Any) -> Any:
    """JSON-safe number (NaN/inf become None)."""
    if isinstance(v, str | None):
        return v
    f = float(v)
    return f if np.isfinite(f) else None


def _arr(a: np.ndarray) -> Any:
    a = np.asarray(a, dtype=float)
    if not a.size:
        return []
    obj = a.astype(object)
    obj[~np.isfinite(a)] = None
    return obj.tolist()
