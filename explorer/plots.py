"""Plot panel from `Solution.plots`: one small subplot per series against time, NLP nodes
marked, in one plotly figure (one message per update, whatever the number of series); a
comparison overlays several solutions' series in their colours; `marker_shapes` is the
vertical line through every subplot that marks the animation's time."""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cache

import numpy as np
import plotly.graph_objects as go
import plotly.io as pio

from solvers.presentation import GridMap, PlotSeries

from .panels.status import unit_text

GROUP_COLORS = {"state": "#00c8ff", "control": "#ff8c00", "costate": "#c890ff"}
REFERENCE_COLOR = "#ff78c8"  # palette.REFERENCE: an independent optimum, dashed
OTHER_COLOR = "#b0e060"
MAX_NODE_MARKS = 80  # more node markers than this would hide the line they sit on
MARKER_COLOR = {True: "#ffe14d", False: "#c06000"}  # time marker on dark / light

Overlay = tuple[str, tuple[int, int, int], Sequence[PlotSeries]]  # name, colour, series


def figure_aspect(n_series: int, panel_aspect: float) -> float:
    """Height/width of the figure: the panel's for up to two rows, taller beyond (the
    panel scrolls) so that a row never gets squeezed."""
    rows = grid(n_series)[0]
    return panel_aspect if rows <= 2 else rows * panel_aspect / 2


def grid(n_series: int) -> tuple[int, int]:
    """(rows, columns) for a wide, short panel: one row up to 3 series, then two rows."""
    rows = 1 if n_series <= 3 else 2 if n_series <= 8 else math.ceil(n_series / 4)
    return rows, max(1, math.ceil(n_series / rows))


def _rgb(c: tuple[int, int, int]) -> str:
    return f"rgb({c[0]},{c[1]},{c[2]})"


def make_figure(series: Sequence[PlotSeries], dim: bool = False, dark: bool = True,
                overlays: Sequence[Overlay] = (), time_unit: str = "s",
                time_scale: float = 1.0) -> go.Figure:
    """`figure_tree` as a plotly figure (exports)."""
    return go.Figure(figure_tree(series, dim, dark, overlays, time_unit, time_scale),
                     _validate=False)


def figure_tree(series: Sequence[PlotSeries], dim: bool = False, dark: bool = True,
                overlays: Sequence[Overlay] = (), time_unit: str = "s",
                time_scale: float = 1.0) -> dict:
    """Subplots of `series` (dense line + node markers) against time shown in `time_unit`
    (seconds x `time_scale`); `dim` greys a stale result; `overlays` (a comparison) draw other
    solutions' series of the same titles in their own colours, with a legend.

    Built as plain plotly JSON (axes laid out here, no `make_subplots`, no validation, lists
    not arrays): plotly's validating constructors cost ~25 ms per subplot and its `to_json`
    6 ms a figure, far too slow for a figure redrawn on every slider move; `json.dumps` of
    this tree takes 0.5 ms."""
    # A "reference" series is drawn dashed into the subplot of the series of its title.
    own = [s for s in series if s.group != "reference"]
    references = [s for s in series if s.group == "reference"]
    series = own
    titles_src = list(series) or (list(overlays[0][2]) if overlays else [])
    where = {s.title: i for i, s in enumerate(titles_src)}
    node_color = "#f5f5f5" if dark else "#303030"
    data: list[dict] = []

    def line(s: PlotSeries, i: int, **style) -> dict:
        return {"type": "scatter", "x": _list(time_scale * np.asarray(s.t)),
                "y": _list(s.y),
                "mode": "lines",
                "xaxis": _axis("x", i), "yaxis": _axis("y", i), **style}

    for s in series:
        i = where[s.title]
        color = "#777777" if dim else GROUP_COLORS.get(s.group, OTHER_COLOR)
        data.append(line(s, i, line={"color": color, "width": 2}, name=s.title,
                         showlegend=False, hoverinfo="x+y"))
        if s.t_nodes is not None and s.y_nodes is not None and len(s.t_nodes) <= MAX_NODE_MARKS:
            data.append({"type": "scatter", "x": _list(time_scale * np.asarray(s.t_nodes)),
                         "y": _list(s.y_nodes), "mode": "markers",
                         "xaxis": _axis("x", i), "yaxis": _axis("y", i),
                         "name": f"{s.title} nodes", "showlegend": False,
                         "marker": {"color": node_color, "size": 3}, "hoverinfo": "x+y"})
    for s in references:
        if s.title in where:
            data.append(line(s, where[s.title], name=f"{s.title} (maximum principle)",
                             line={"color": REFERENCE_COLOR, "width": 1.5, "dash": "dash"},
                             showlegend=False, hoverinfo="x+y"))
    for name, rgb, overlay in overlays:
        first = True
        for s in overlay:
            if s.title in where:
                data.append(line(s, where[s.title], line={"color": _rgb(rgb), "width": 2},
                                 name=name, legendgroup=name, showlegend=first,
                                 hoverinfo="x+y+name"))
                first = False
    return {"data": data, "layout": _layout(titles_src, dark, bool(overlays), time_unit)}


def _layout(titles_src: Sequence[PlotSeries], dark: bool, legend: bool, time_unit: str) -> dict:
    """The subplot grid of `figure_tree`: one titled axis pair per series, time labelled
    under the bottom subplot of each column; room for a legend under a comparison."""
    n = len(titles_src)
    rows, columns = grid(n)
    layout = {
        "template": _template(dark), "showlegend": legend,
        "legend": {"orientation": "h", "y": -0.18, "x": 0.0, "font": {"size": 10}},
        "margin": {"l": 40, "r": 8, "t": 22, "b": 50 if legend else 30},
        "font": {"size": 10}, "paper_bgcolor": "rgba(0,0,0,0)",
        "plot_bgcolor": "#15171c" if dark else "#fafafa", "annotations": [],
    }
    h_gap, v_gap = 0.3 / columns, 0.5 / rows
    width = (1.0 - h_gap * (columns - 1)) / columns
    height = (1.0 - v_gap * (rows - 1)) / rows
    for i, s in enumerate(titles_src):
        row, col = divmod(i, columns)
        x0 = col * (width + h_gap)
        y1 = 1.0 - row * (height + v_gap)
        xaxis = {"domain": _unit_interval(x0, x0 + width), "anchor": _axis("y", i)}
        if i + columns >= n:  # bottom subplot of its column
            xaxis["title"] = {"text": f"t [{time_unit}]", "standoff": 2}
        layout[_axis("xaxis", i)] = xaxis
        layout[_axis("yaxis", i)] = {"domain": _unit_interval(y1 - height, y1),
                                     "anchor": _axis("x", i)}
        title = f"{s.title} [{unit_text(s.unit)}]" if s.unit else s.title
        layout["annotations"].append({
            "text": title, "x": x0 + width / 2, "y": y1, "xref": "paper", "yref": "paper",
            "xanchor": "center", "yanchor": "bottom", "showarrow": False, "font": {"size": 11}})
    return layout


def _list(values: Sequence[float] | np.ndarray) -> list[float | None]:
    """Plain floats for JSON, a non-finite value as null (plotly leaves a gap)."""
    array = np.asarray(values, float)
    return [None if not math.isfinite(v) else v for v in array.tolist()] \
        if not np.all(np.isfinite(array)) else array.tolist()


def _unit_interval(lo: float, hi: float) -> list[float]:
    """A subplot domain inside [0, 1] (rounding can step just outside)."""
    return [min(max(lo, 0.0), 1.0), min(max(hi, 0.0), 1.0)]


def _axis(kind: str, i: int) -> str:
    """Plotly's name of the i-th subplot's axis: x, x2, x3 ... (xaxis, xaxis2 ... in layout)."""
    return kind if i == 0 else f"{kind}{i + 1}"


@cache
def _template(dark: bool) -> dict:
    """The plotly template as JSON (a template name is resolved only by validation)."""
    return pio.templates["plotly_dark" if dark else "plotly_white"].to_plotly_json()


def marker_shapes(n_series: int, t: float | None, dark: bool = True) -> list[dict]:
    """The time marker: a vertical line at `t` in each of the first `n_series` subplots."""
    if t is None:
        return []
    return [{"type": "line", "xref": _axis("x", i), "yref": f"{_axis('y', i)} domain",
             "x0": t, "x1": t, "y0": 0.0, "y1": 1.0,
             "line": {"color": MARKER_COLOR[dark], "width": 1.5}} for i in range(n_series)]


def map_figure(grid_map: GridMap, dark: bool = True) -> go.Figure:
    """A `GridMap` as a filled contour (values above `z_max` clipped) with the solution
    marked; e.g. paper 003's launch-C3 map."""
    z = np.clip(np.asarray(grid_map.z, float).T, 0.0, grid_map.z_max)
    fig = go.Figure(go.Contour(
        x=np.asarray(grid_map.x), y=np.asarray(grid_map.y), z=z,
        contours={"start": 0.0, "end": grid_map.z_max, "size": grid_map.z_max / 10,
                  "coloring": "heatmap"},
        colorscale="Viridis", colorbar={"title": grid_map.z_label},
        hovertemplate="%{x:.0f}, %{y:.0f}: %{z:.3g}<extra></extra>",
    ))
    if grid_map.marker is not None:
        fig.add_trace(go.Scatter(
            x=[grid_map.marker[0]], y=[grid_map.marker[1]], mode="markers+text",
            text=[grid_map.marker_label], textposition="top center",
            marker={"symbol": "x", "size": 12, "color": "#ff3030"}, showlegend=False))
    fig.update_layout(
        title={"text": grid_map.title, "font": {"size": 12}},
        xaxis_title=grid_map.x_label, yaxis_title=grid_map.y_label,
        margin={"l": 50, "r": 10, "t": 40, "b": 40},
        template="plotly_dark" if dark else "plotly_white",
    )
    return fig
