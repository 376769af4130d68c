"""What the explorer shows about optimality and accuracy, from the numeric Solution alone:
the costates estimated from the NLP multipliers (with the maximum principle's dashed over
them when the mission has an indirect solution), the Hamiltonian, the switching function of
a bang–bang mission, and the path coloured by the local error of each interval with the worst
one marked."""

from __future__ import annotations

import numpy as np

from solvers import palette
from solvers.presentation import ColorBy, Marker, PlotSeries, Presentation
from solvers.solution import Solution

REFERENCE = "maximum principle costates"


def optimality_plots(sol: Solution) -> list[PlotSeries]:
    """Costates (and their maximum-principle reference), H and S over time."""
    plots: list[PlotSeries] = []
    lam = sol.costates
    if lam is not None and len(lam.t):
        values = np.asarray(lam.values, float).reshape(len(lam.t), -1)
        ref = sol.references.get(REFERENCE)
        for i, name in enumerate(lam.names):
            unit = lam.units[i] if i < len(lam.units) else ""
            title = f"costate λ {name}"
            plots.append(PlotSeries(title, unit, lam.t, values[:, i], lam.t, values[:, i],
                                    group="costate"))
            if ref is not None and name in ref.names:
                plots.append(PlotSeries(title, unit, ref.t, ref.column(name),
                                        group="reference"))
    for series, title in ((sol.hamiltonian, "Hamiltonian H"),
                          (sol.switching, "switching function S (> 0: burn)")):
        if series is not None and len(series.t):
            unit = series.units[0] if series.units else ""
            y = np.asarray(series.values, float).reshape(len(series.t), -1)[:, 0]
            plots.append(PlotSeries(title, unit, series.t, y, group="costate"))
    return plots


def color_by_error(sol: Solution, pres: Presentation) -> None:
    """Colour `pres`'s path by the local error of the interval each sample lies in, and mark
    the worst interval (a failed answer carries its constraint violation instead)."""
    err = sol.interval_error
    if err is None or not len(err.t) or not len(sol.t):
        return
    values = np.abs(np.asarray(err.values, float).reshape(len(err.t), -1)[:, 0])
    edges = np.asarray(sol.node_t, float)
    if len(edges) == len(values) + 1:  # one value per interval between nodes
        index = np.clip(np.searchsorted(edges, sol.t, side="right") - 1, 0, len(values) - 1)
        along = values[index]
    else:
        along = np.interp(sol.t, err.t, values)
    unit = err.units[0] if err.units else ""
    name = "local error" if err.names[0] != "defect" else "constraint violation"
    pres.color_by = ColorBy(name, unit, along)
    worst = int(np.argmax(values))
    at = float(err.t[worst])
    position = tuple(float(np.interp(at, sol.t, pres.path[:, k])) for k in range(3))
    pres.markers.append(Marker(f"worst interval ({values[worst]:.2g} {unit})".strip(),
                               position, palette.NONLINEAR))
