"""What a declared problem looks like with no view code: the path of its position states
(or of its position function) with start and end marked, plots of every state, control and
path constraint, and a help page generated from the declaration."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .. import palette
from ..mission import Mission, published_markdown
from ..presentation import Marker, PlotSeries, Presentation, plot_axes
from ..solution import Solution
from .build import parameter_vector
from .declaration import Declaration
from .errors import DeclarationError, call_user, function_location
from .functions import Traced
from .records import FreeTime, Named


def _columns(decl: Declaration, x: np.ndarray, p: np.ndarray) -> list[np.ndarray]:
    """The 1 to 3 display coordinates of state samples `x` (samples, nx)."""
    x = np.atleast_2d(np.asarray(x, float))
    n = len(x)
    if callable(decl.position):
        raw = call_user(decl.position, "position", Named(x, decl.state_names, "state"),
                        Named(np.asarray(p, float), decl.param_keys, "parameter"))
        cols = list(raw) if isinstance(raw, list | tuple) else [raw]
        if not 1 <= len(cols) <= 3:
            raise DeclarationError(f"position returns {len(cols)} coordinates, not 1 to 3",
                                   function_location(decl.position))
        return [np.broadcast_to(np.asarray(c, float).ravel(), (n,)) for c in cols]
    names = decl.position or decl.state_names[:3]
    return [x[:, decl.state_names.index(name)] for name in names]


def _positions(decl: Declaration, x: np.ndarray, p: np.ndarray) -> np.ndarray:
    """(samples, 3) display positions of state samples `x` (samples, nx)."""
    cols = _columns(decl, x, p)
    out = np.zeros((len(cols[0]), 3))
    out[:, : len(cols)] = np.column_stack(cols)
    return out


def _frame(decl: Declaration) -> tuple[str, str]:
    """(frame description, display unit)."""
    if callable(decl.position):
        return "the problem's position function", decl.position_unit or "m"
    names = decl.position or decl.state_names[:3]
    states = [decl.states[decl.state_names.index(n)] for n in names]
    units = {s.unit for s in states}
    unit = decl.position_unit or (units.pop() if len(units) == 1 else "")
    return "axes: " + ", ".join(s.label or s.name for s in states), unit


def _axis_names(decl: Declaration, unit: str) -> tuple[str, str]:
    """The names of a plane problem's two axes, each with its unit: "x [m]"."""
    if callable(decl.position):
        return (f"x [{unit}]", f"y [{unit}]") if unit else ("x", "y")
    names = decl.position or decl.state_names[:2]
    states = [decl.states[decl.state_names.index(n)] for n in names]
    return tuple(f"{s.label or s.name} [{s.unit}]" if s.unit else s.label or s.name
                 for s in states)


def present(decl: Declaration, traced: Traced, sol: Solution) -> Presentation:
    """The path, nodes, start and end, iterates and plots of one solution; a plane problem
    (two position coordinates) drawn as a 2-D plot: axes with ticks in the user's unit,
    x to the right and y up."""
    frame, unit = _frame(decl)
    if not sol.has_trajectory:  # a failed or refused solve: nothing to draw
        return Presentation(frame=frame, path=np.zeros((0, 3)), display_unit=unit)
    p = parameter_vector(decl, sol.values)
    path = _positions(decl, sol.x, p)
    nodes = _positions(decl, sol.node_x, p)
    pres = Presentation(
        frame=frame,
        path=path,
        nodes=nodes,
        display_unit=unit,
        markers=[Marker("start", tuple(path[0]), palette.START),
                 Marker("end", tuple(path[-1]), palette.TARGET)],
        plots=plots(decl, traced, sol, p),
        iterates=[(it.iteration, _positions(decl, it.x, p)) for it in sol.history],
        arc_names={"burn": "path", "coast": "path"},
    )
    if len(_columns(decl, sol.x[:1], p)) == 2:
        both = np.vstack([path, nodes])[:, :2]
        curves, ticks = plot_axes(tuple(both.min(axis=0)), tuple(both.max(axis=0)),
                                  _axis_names(decl, unit), palette.GRID, palette.AXIS,
                                  palette.LABEL)
        pres.curves, pres.up, pres.plan = curves, "+y", True
        pres.markers += ticks
    return pres


def plots(decl: Declaration, traced: Traced, sol: Solution, p: np.ndarray
          ) -> list[PlotSeries]:
    """Every state, every control, and every path constraint's value."""
    t, tn = sol.t, sol.node_t
    out = [PlotSeries(s.label or s.name, s.unit, t, sol.x[:, i], tn, sol.node_x[:, i])
           for i, s in enumerate(decl.states)]
    out += [PlotSeries(c.label or c.name, c.unit, t, sol.u[:, i], tn, sol.node_u[:, i],
                       group="control") for i, c in enumerate(decl.controls)]
    if traced.path is not None:
        dense = _path_values(traced, sol.x, sol.u, p)
        nodes = _path_values(traced, sol.node_x, sol.node_u, p)
        for i, c in enumerate(decl.path):
            out.append(PlotSeries(f"{c.name} {_range(c.lower, c.upper)}", c.unit, t,
                                  dense[:, i], tn, nodes[:, i], group="constraint"))
    return out


def _path_values(traced: Traced, x: np.ndarray, u: np.ndarray, p: np.ndarray) -> np.ndarray:
    n = len(x)
    values = traced.path.map(n)(x.T, u.T, np.tile(np.asarray(p, float)[:, None], (1, n)))
    return np.asarray(values, float).T.reshape(n, -1)


def _range(lower: float, upper: float) -> str:
    if lower == upper:
        return f"= {lower:g}"
    if math.isfinite(lower) and math.isfinite(upper):
        return f"∈ [{lower:g}, {upper:g}]"
    return f"≥ {lower:g}" if math.isfinite(lower) else f"≤ {upper:g}"


def _value(v: object) -> str:
    if v is None:
        return "free"
    return f"`{v}`" if isinstance(v, str) else f"{v:g}"


def help_markdown(mission: Mission, decl: Declaration, notes: str = "", targets: str = "",
                  warnings: Sequence[str] = ()) -> str:
    """The About text: summary, source, the declaration as tables, the accuracy targets'
    line, warnings, notes, published numbers."""
    lines = [mission.summary, ""] if mission.summary else []
    if mission.source:
        lines += [f"*Source:* {mission.source}", ""]
    lines += ["| state | unit | bounds | initial | final |", "|---|---|---|---|---|"]
    lines += [f"| {s.label or s.name} | {s.unit} | [{_value(s.bounds[0])}, "
              f"{_value(s.bounds[1])}] | {_value(s.initial)} | {_value(s.final)} |"
              for s in decl.states]
    lines += ["", "| control | unit | bounds |", "|---|---|---|"]
    lines += [f"| {c.label or c.name} | {c.unit} | [{_value(c.bounds[0])}, "
              f"{_value(c.bounds[1])}] |" for c in decl.controls]
    ft = decl.final_time
    time = (f"free (guess {ft.guess:g} s)" if isinstance(ft, FreeTime)
            else f"fixed: {_value(ft)} s")
    terms = [t for t, on in (("the final-state (Mayer) term", decl.mayer is not None),
                             ("the running (Lagrange) cost", decl.lagrange is not None),
                             ("the final time", decl.minimum_time)) if on]
    lines += ["", f"{'Maximise' if decl.maximize else 'Minimise'} {' + '.join(terms)}; "
              f"final time {time}."]
    for c in decl.path:
        lines.append(f"- path constraint {c.name} {_range(c.lower, c.upper)} {c.unit}")
    for c in decl.final:
        lines.append(f"- final constraint {c.name} {_range(c.lower, c.upper)} {c.unit}")
    if targets:
        lines += ["", targets]
    for warning in warnings:
        lines += ["", f"**Warning:** {warning}."]
    if notes:
        lines += ["", notes]
    if mission.published:
        lines += ["", published_markdown(mission.published)]
    return "\n".join(lines).strip()
