"""How the hovercraft is drawn: the ground plane with a 1 m grid and the paper's bounds
x ≥ 0, y ≥ 0, the path, thrust arrows, the maximum-principle extremal as a dashed reference,
and the states and the thrust angle over time."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...presentation import Curve, Marker, PlotSeries, Presentation
from ...solution import Series, Solution
from .problem import DEG, REFERENCE


def plane(X: np.ndarray) -> np.ndarray:
    """(x, y) to the display frame: the z = 0 plane, metres."""
    X = np.atleast_2d(X)
    return np.column_stack([X[:, 0], X[:, 1], np.zeros(len(X))])


def thrust_arrows(u_nodes: np.ndarray) -> np.ndarray:
    """Thrust per node: direction α, length the throttle (1 in the angle form)."""
    alpha = u_nodes[:, 0]
    throttle = u_nodes[:, 1] if u_nodes.shape[1] > 1 else np.ones(len(alpha))
    return np.column_stack([throttle * np.cos(alpha), throttle * np.sin(alpha),
                            np.zeros(len(alpha))])


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The manoeuvre in the ground plane (this mission has no view options)."""
    v = sol.values
    start, target = (v["x0"], v["y0"], 0.0), (v["xf"], v["yf"], 0.0)
    path = plane(sol.x)
    ref = sol.references.get(REFERENCE)
    pts = np.vstack([path[:, :2], [start[:2]], [target[:2]]])
    lo = np.floor(pts.min(axis=0)) - 1
    hi = np.ceil(pts.max(axis=0)) + 1
    curves = [Curve("1 m grid", grid(lo, hi), palette.GRID),
              Curve("bounds x ≥ 0, y ≥ 0",
                    np.array([[hi[0], 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, hi[1], 0.0]]),
                    palette.BOUND)]
    if ref is not None:
        curves.append(Curve("maximum-principle optimum", plane(ref.values[:, :2]),
                            palette.REFERENCE, dashed=True))
    return Presentation(
        frame="ground plane (x east, y north)",
        path=path,
        nodes=plane(sol.node_x),
        thrust=thrust_arrows(sol.node_u),
        curves=curves,
        markers=[Marker("start", start, palette.START), Marker("target", target, palette.TARGET)],
        plots=plots(sol, ref),
        iterates=[(it.iteration, plane(it.x)) for it in sol.history],
        vehicle=sol.mission,
    )


def grid(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """A 1 m grid as one serpentine polyline (its joins run along the border)."""
    pts = []
    for i, gx in enumerate(np.arange(lo[0], hi[0] + 0.5)):
        ys = (lo[1], hi[1]) if i % 2 == 0 else (hi[1], lo[1])
        pts += [(gx, ys[0]), (gx, ys[1])]
    corner = pts[-1]
    ys = np.arange(lo[1], hi[1] + 0.5)
    for i, gy in enumerate(ys if corner[1] == lo[1] else ys[::-1]):
        xs = (corner[0], lo[0]) if i % 2 == 0 else (lo[0], corner[0])
        pts += [(xs[0], gy), (xs[1], gy)]
    pts = np.array(pts, float)
    return np.column_stack([pts, np.zeros(len(pts))])


def plots(sol: Solution, ref: Series | None) -> list[PlotSeries]:
    """The four states and the thrust angle, the maximum principle's angle beside them."""
    t, X, tn, Xn = sol.t, sol.x, sol.node_t, sol.node_x
    out = [PlotSeries(name, unit, t, X[:, i], tn, Xn[:, i])
           for i, (name, unit) in enumerate(zip(sol.state_names, sol.state_units, strict=True))]
    out.append(PlotSeries("thrust angle α", "deg", t, sol.u[:, 0] / DEG, tn,
                          sol.node_u[:, 0] / DEG, group="control"))
    if ref is not None:
        out.append(PlotSeries("α, maximum principle", "deg", ref.t,
                              ref.column("alpha") / DEG, group="control"))
    return out
