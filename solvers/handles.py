"""Things a person drags in the 3D view, bound to parameters: `Handle` (a point: a start, a
target; or an arrow's tip: a velocity) and `CurveHandle` (a point on a curve of one
parameter: an arrow that turns with a flight-path angle); the shapes whose centres drag as
handles are in `shapes.py`.

A coordinate of the display frame is either fixed (a number, metres) or an `Axis`: an
affine function of one parameter, display metres = offset + scale × value (× a view option,
e.g. an altitude exaggeration), plus, for an arrow's tip, the value of its `base` parameter
(the tail: a velocity's tip at start + scale × v). Dragging moves only the bound axes (the
others are locked) and the inverse of that function gives the new values, clamped to the
parameters' ranges. Everything here is SI and pure numerics: the explorer draws and drags
(`explorer/handles.py`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from .problem import Param


@dataclass(frozen=True)
class Axis:
    """One display coordinate bound to parameter `param`: offset + scale × value, the scale
    multiplied by the view option `view` when given (metres of the display frame)."""

    param: str
    scale: float = 1.0
    offset: float = 0.0
    view: str | None = None
    base: str | None = None  # a parameter (metres) the coordinate starts from: a tail

    def __post_init__(self) -> None:
        if self.scale == 0:
            raise ValueError(f"Axis {self.param}: scale must not be zero")

    def factor(self, view: Mapping[str, float]) -> float:
        """Display metres per SI unit of the parameter in these view options."""
        return self.scale * (float(view[self.view]) if self.view is not None else 1.0)

    def tail(self, values: Mapping[str, float]) -> float:
        """The coordinate at a zero value: the offset, plus the base parameter's value."""
        return self.offset + (float(values[self.base]) if self.base is not None else 0.0)

    def where(self, values: Mapping[str, float], view: Mapping[str, float]) -> float:
        return self.tail(values) + self.factor(view) * float(values[self.param])

    def value_at(self, coordinate: float, view: Mapping[str, float],
                 values: Mapping[str, float]) -> float:
        """The parameter value that puts this coordinate at `coordinate` (unclamped)."""
        return (coordinate - self.tail(values)) / self.factor(view)


Coordinate = float | str | Axis  # a str is Axis(str): the parameter's value in metres


def as_axis(c: Coordinate) -> Axis | None:
    """The `Axis` of a coordinate (None: a fixed number)."""
    if isinstance(c, Axis):
        return c
    return Axis(c) if isinstance(c, str) else None


def shown_in(views: Mapping[str, float], view: Mapping[str, float]) -> bool:
    """Whether a handle restricted to `views` (option → value) shows in `view`."""
    return all(view.get(k) == v for k, v in views.items())


def coordinate(c: Coordinate, values: Mapping[str, float], view: Mapping[str, float]) -> float:
    axis = as_axis(c)
    return float(c) if axis is None else axis.where(values, view)  # type: ignore[arg-type]


@dataclass(frozen=True)
class Handle:
    """A draggable point of the display frame, e.g. the chaser's start (x0, y0, z0).

    `position` gives the three display coordinates (numbers are locked, `Axis`/str ones
    drag); `views` restricts the handle to view options where that mapping holds (e.g. the
    target frame, not the magnified inertial view): a view option key → the value it needs.
    """

    key: str
    label: str
    position: tuple[Coordinate, Coordinate, Coordinate]
    views: Mapping[str, float] = field(default_factory=dict)

    @property
    def axes(self) -> tuple[Axis | None, Axis | None, Axis | None]:
        a, b, c = (as_axis(x) for x in self.position)
        return a, b, c

    @property
    def active_axes(self) -> tuple[bool, bool, bool]:
        """Which display axes drag (the gizmo's arrows and planes)."""
        a, b, c = (axis is not None for axis in self.axes)
        return a, b, c

    @property
    def params(self) -> tuple[str, ...]:
        return tuple(axis.param for axis in self.axes if axis is not None)

    def shown_in(self, view: Mapping[str, float]) -> bool:
        return shown_in(self.views, view)

    def where(self, values: Mapping[str, float], view: Mapping[str, float]) -> tuple[float, ...]:
        """Display-frame position (metres) for these values and view options."""
        return tuple(coordinate(c, values, view) for c in self.position)

    @property
    def is_arrow(self) -> bool:
        """An arrow's tip: some axis starts from a base parameter."""
        return any(axis is not None and axis.base is not None for axis in self.axes)

    def tail(self, values: Mapping[str, float], view: Mapping[str, float]
             ) -> tuple[float, ...]:
        """Where an arrow starts (metres): every bound value at zero."""
        return tuple(float(c) if axis is None else axis.tail(values)  # type: ignore[arg-type]
                     for c, axis in zip(self.position, self.axes, strict=True))


Point = Callable[[np.ndarray, Mapping[str, float], Mapping[str, float]], np.ndarray]
Tail = Callable[[Mapping[str, float], Mapping[str, float]], Sequence[float]]
CURVE_SAMPLES = 241  # a curve handle's first look along its parameter's range


@dataclass(frozen=True)
class CurveHandle:
    """A point that moves along a curve as one parameter changes, e.g. an arrow's tip that
    turns with a flight-path angle: `point(v, values, view)` gives the display positions
    (metres, shape (n, 3)) for an array `v` of the parameter's values, `start(values, view)`
    an arrow's tail. Dragged, it takes the value whose point
    is nearest the hand (a search over the parameter's range: the curve need not be
    affine, nor invertible in closed form). A curve that comes round again (an orbit, one
    point per year) gives `span`: the search stays within ±span/2 of the current value, so
    the hand moves the date along the orbit instead of jumping a year."""

    key: str
    label: str
    param: str
    point: Point
    active_axes: tuple[bool, bool, bool] = (True, True, False)
    start: Tail | None = None
    span: float | None = None
    views: Mapping[str, float] = field(default_factory=dict)

    @property
    def axes(self) -> tuple[Axis | None, ...]:
        return (Axis(self.param),)

    @property
    def params(self) -> tuple[str, ...]:
        return (self.param,)

    @property
    def is_arrow(self) -> bool:
        return self.start is not None

    def shown_in(self, view: Mapping[str, float]) -> bool:
        return shown_in(self.views, view)

    def points(self, v: np.ndarray, values: Mapping[str, float], view: Mapping[str, float]
               ) -> np.ndarray:
        return np.asarray(self.point(np.asarray(v, float), values, view), float).reshape(-1, 3)

    def where(self, values: Mapping[str, float], view: Mapping[str, float]) -> tuple[float, ...]:
        a, b, c = self.points(np.array([float(values[self.param])]), values, view)[0]
        return float(a), float(b), float(c)

    def tail(self, values: Mapping[str, float], view: Mapping[str, float]
             ) -> tuple[float, ...]:
        start = self.start(values, view) if self.start is not None else self.where(values, view)
        return tuple(float(c) for c in start)

    def value_at(self, position: Sequence[float], p: Param, values: Mapping[str, float],
                 view: Mapping[str, float]) -> float:
        """The value in [p.min, p.max] whose point is nearest `position` along the active
        axes: the best of an even sampling, then a bounded search beside it."""
        from scipy.optimize import minimize_scalar

        mask = np.array(self.active_axes, bool)
        target = np.asarray(position, float)[mask]

        def gaps(v: np.ndarray) -> np.ndarray:
            return np.sum((self.points(v, values, view)[:, mask] - target)**2, axis=1)

        def gap(v: float) -> float:
            return float(gaps(np.array([v]))[0])

        lo, hi = p.min, p.max
        if self.span is not None and self.param in values:
            now = float(values[self.param])
            lo, hi = max(lo, now - 0.5 * self.span), min(hi, now + 0.5 * self.span)
        grid = np.linspace(lo, hi, CURVE_SAMPLES)
        i = int(np.argmin(gaps(grid)))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
        best = minimize_scalar(gap, bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-10 * (p.max - p.min)})
        return float(best.x) if best.fun <= gap(grid[i]) else float(grid[i])


AnyHandle = Handle | CurveHandle


@dataclass(frozen=True)
class Moved:
    """What a drag to a position asks for: the new values (SI, within the ranges) and the
    parameters held at an end of their range (the hint to show)."""

    values: dict[str, float]
    held: tuple[str, ...] = ()


def values_at(handle: AnyHandle, position: Sequence[float], params: Sequence[Param],
              view: Mapping[str, float], current: Mapping[str, float] | None = None) -> Moved:
    """The parameter values that put `handle` at display `position` (metres): each bound
    axis inverted, clamped to its parameter's [min, max] (as a slider stops at its ends),
    whole numbers rounded. Locked axes are ignored; an arrow's tail comes from `current`.
    A curve handle takes its nearest point's value, held when that is a range's end."""
    by_key = {p.key: p for p in params}
    values: dict[str, float] = {}
    held: list[str] = []
    if isinstance(handle, CurveHandle):
        p = by_key[handle.param]
        value = handle.value_at(position, p, current or {}, view)
        value = float(round(value)) if p.integer else value
        at_end = min(value - p.min, p.max - value) <= 1e-9 * (p.max - p.min)  # not the span's
        return Moved({p.key: value}, (p.key,) if at_end else ())
    for axis, coordinate in zip(handle.axes, position, strict=True):
        if axis is None:
            continue
        p = by_key[axis.param]
        raw = axis.value_at(float(coordinate), view, current or {})
        value = min(max(raw, p.min), p.max)
        if p.integer:
            value = float(round(value))
        if value != raw and (value == p.min or value == p.max):
            held.append(p.key)
        values[p.key] = value
    return Moved(values, tuple(held))


class Bound(Protocol):
    """What binds parameters: a `Handle`, or a shape (its centre and sizes)."""

    key: str

    @property
    def axes(self) -> tuple[Axis | None, ...]: ...

    @property
    def views(self) -> Mapping[str, float]: ...


def check_bindings(handles: Sequence[Bound], params: Sequence[Param],
                   view_params: Sequence[Param]) -> None:
    """Raise `ValueError` naming a handle or shape bound to an unknown parameter or view
    option, or to a choice (a choice is no length)."""
    by_key = {p.key: p for p in params}
    views = {p.key for p in view_params}
    for h in handles:
        for axis in h.axes:
            if axis is None:
                continue
            p = by_key.get(axis.param)
            for key in (axis.param, axis.base):
                q = by_key.get(key) if key is not None else p
                if q is None or q.is_choice:
                    raise ValueError(f"handle '{h.key}': '{key}' is not a numeric "
                                     f"parameter (known: {', '.join(sorted(by_key))})")
            if axis.view is not None and axis.view not in views:
                raise ValueError(f"handle '{h.key}': '{axis.view}' is not a view option")
        for key in h.views:
            if key not in views:
                raise ValueError(f"handle '{h.key}': '{key}' is not a view option")
