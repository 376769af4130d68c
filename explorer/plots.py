"""Plot panel from `Solution.plots`: one small subplot per series against time, NLP nodes
marked, in one plotly figure (one message per update, whatever the number of series)."""

from __future__ import annotations

import math

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from solvers.solution import PlotSeries

GROUP_COLORS = {"state": "#00c8ff", "control": "#ff8c00"}
OTHER_COLOR = "#b0e060"


def figure_aspect(n_series: int, panel_aspect: float) -> float:
    """Height/width of the figure: the panel's for up to two rows, taller beyond (the
    panel scrolls) so that a row never gets squeezed."""
    rows = grid(n_series)[0]
    return panel_aspect if rows <= 2 else rows * panel_aspect / 2


def grid(n_series: int) -> tuple[int, int]:
    """(rows, columns) for a wide, short panel: one row up to 3 series, then two rows."""
    rows = 1 if n_series <= 3 else 2 if n_series <= 8 else math.ceil(n_series / 4)
    return rows, max(1, math.ceil(n_series / rows))


def make_figure(series: list[PlotSeries], dim: bool = False) -> go.Figure:
    """Subplots of `series` (dense line + node markers); `dim` greys a stale result."""
    rows, columns = grid(len(series))
    titles = [f"{s.title} [{s.unit}]" if s.unit else s.title for s in series]
    fig = make_subplots(rows=rows, cols=columns, subplot_titles=titles or None,
                        horizontal_spacing=0.3 / columns, vertical_spacing=0.5 / rows)
    for i, s in enumerate(series):
        row, col = divmod(i, columns)
        color = "#777777" if dim else GROUP_COLORS.get(s.group, OTHER_COLOR)
        fig.add_trace(go.Scatter(x=np.asarray(s.t), y=np.asarray(s.y), mode="lines",
                                 line={"color": color, "width": 2}, name=s.title,
                                 hoverinfo="x+y"), row=row + 1, col=col + 1)
        if s.t_nodes is not None and s.y_nodes is not None:
            fig.add_trace(go.Scatter(x=np.asarray(s.t_nodes), y=np.asarray(s.y_nodes),
                                     mode="markers", name=f"{s.title} nodes",
                                     marker={"color": "#f5f5f5", "size": 3}, hoverinfo="x+y"),
                          row=row + 1, col=col + 1)
        if i + columns >= len(series):
            fig.update_xaxes(title_text="t [s]", title_standoff=2, row=row + 1, col=col + 1)
    fig.update_layout(
        template="plotly_dark", showlegend=False, margin={"l": 40, "r": 8, "t": 22, "b": 30},
        font={"size": 10}, paper_bgcolor="rgba(0,0,0,0)", plot_bgcolor="#15171c",
    )
    fig.update_annotations(font_size=11)
    return fig
