"""How the elliptic transfer is drawn: in the target-centred LVLH frame or Earth-centred
inertially (view option `view`); the uncontrolled motion, the LGL nodes with thrust arrows,
the control and state plots of paper 001's figures, and, once the deferred check has run, the
control re-propagated in the nonlinear two-body model (`Solution.references`)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ... import palette
from ...dynamics.tschauner_hempel import R_EARTH, ya_stm
from ...dynamics.two_body import lvlh_basis
from ...presentation import Body, Curve, Marker, PlotSeries, Presentation
from ...solution import Solution
from .model import CONTROLS, STATES, Case, make_case

NONLINEAR = "nonlinear model"  # the reference the deferred check adds


class _Frame:
    """LVLH states at times t (from the start) to display positions and vectors (metres)."""

    def __init__(self, case: Case, inertial: bool) -> None:
        self.case = case
        self.inertial = inertial

    def positions(self, t: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Positions of LVLH states X at times t."""
        return self.at_anomaly(self._anomaly(t), X)

    def at_anomaly(self, f: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Positions of LVLH states X when the target is at true anomalies f."""
        if not self.inertial:
            return np.array(X[:, :3], float)
        r, v = self.case.target_state(f)
        return r + np.einsum("nij,nj->ni", lvlh_basis(r, v), X[:, :3])

    def vectors(self, t: np.ndarray, V: np.ndarray) -> np.ndarray:
        """LVLH vectors V at times t in the display axes."""
        if not self.inertial:
            return V
        r, v = self.case.target_state(self._anomaly(t))
        return np.einsum("nij,nj->ni", lvlh_basis(r, v), V)

    def _anomaly(self, t: np.ndarray) -> np.ndarray:
        return self.case.orbit.true_anomaly_after(np.asarray(t, float), self.case.f0)


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The transfer in the LVLH (view 0) or Earth-centred inertial (view 1) frame."""
    case = make_case(sol.values)
    frame = _Frame(case, view["view"] == 1)
    umax = max(float(np.max(np.linalg.norm(sol.node_u, axis=1), initial=0.0)), 1e-300)
    reference = sol.references.get(NONLINEAR)
    curves = [Curve("uncontrolled motion (linear model)", _free_motion(case, frame),
                    palette.FREE_MOTION, dashed=True)]
    if reference is not None:
        curves.append(Curve("nonlinear model (re-propagated)",
                            frame.positions(reference.t, reference.values), palette.NONLINEAR))
    pres = Presentation(
        frame="", path=frame.positions(sol.t, sol.x),
        nodes=frame.positions(sol.node_t, sol.node_x),
        thrust=frame.vectors(sol.node_t, sol.node_u / umax), display_unit="km",
        display_scale=1e-3, curves=curves, plots=plots(sol),
        iterates=[(it.iteration, frame.positions(it.t, it.x)) for it in sol.history],
    )
    if frame.inertial:
        _inertial_scene(pres, case)
    else:
        _lvlh_scene(pres, case)
    return pres


def _free_motion(case: Case, frame: _Frame) -> np.ndarray:
    """The chaser's uncontrolled motion in the linear model (YA STM), display frame."""
    o = case.orbit
    f = np.linspace(case.f0, case.fT, 400)
    X = o.from_scaled(f, ya_stm(f, case.f0, o.e) @ o.to_scaled(case.f0, case.x0))
    return frame.at_anomaly(f, X)


def _lvlh_scene(pres: Presentation, case: Case) -> None:
    pres.frame = "LVLH (target-centred): x radial, y along-track, z orbit normal"
    pres.up = "+x"
    pres.bodies = [Body("target", (0.0, 0.0, 0.0), 150.0, palette.HIGHLIGHT)]
    pres.markers = [Marker("chaser start", tuple(case.x0[:3]), palette.START),
                    Marker("target", (0.0, 0.0, 0.0), palette.TARGET)]


def _inertial_scene(pres: Presentation, case: Case) -> None:
    r_orbit, _ = case.target_state(np.linspace(0.0, 2 * np.pi, 361))
    r_t0, _ = case.target_state(case.f0)
    r_per, _ = case.target_state(0.0)
    pres.frame = "Earth-centred inertial"
    pres.up = "+z"
    pres.bodies = [Body("Earth", (0.0, 0.0, 0.0), R_EARTH, palette.EARTH)]
    pres.curves = [Curve("target orbit", r_orbit, palette.ORBIT, dashed=True), *pres.curves]
    pres.markers = [Marker("target at start", tuple(r_t0), palette.HIGHLIGHT),
                    Marker("perigee", tuple(r_per), palette.LABEL)]


def _state_plots(t: np.ndarray, X: np.ndarray, suffix: str, group: str,
                 t_nodes: np.ndarray | None = None, X_nodes: np.ndarray | None = None
                 ) -> list[PlotSeries]:
    out = []
    for k, name in enumerate(STATES):
        unit, factor = ("km", 1e-3) if k < 3 else ("m/s", 1.0)
        y_nodes = None if X_nodes is None else X_nodes[:, k] * factor
        out.append(PlotSeries(f"{name} {suffix}", unit, t, X[:, k] * factor, t_nodes, y_nodes,
                              group))
    return out


def plots(sol: Solution) -> list[PlotSeries]:
    """|u| and its components (paper figs. 1, 4), the states in the linear model (figs. 2,
    5) and, when the check has run, in the nonlinear model (figs. 3, 6)."""
    mm = 1e3  # m/s^2 -> mm/s^2
    out = [PlotSeries("|u| (paper figs. 1, 4)", "mm/s^2", sol.t,
                      np.linalg.norm(sol.u, axis=1) * mm, sol.node_t,
                      np.linalg.norm(sol.node_u, axis=1) * mm, group="control")]
    for k, name in enumerate(CONTROLS):
        out.append(PlotSeries(name, "mm/s^2", sol.t, sol.u[:, k] * mm, sol.node_t,
                              sol.node_u[:, k] * mm, group="control"))
    out += _state_plots(sol.t, sol.x, "(linear model)", "state", sol.node_t, sol.node_x)
    reference = sol.references.get(NONLINEAR)
    if reference is not None:
        out += _state_plots(reference.t, reference.values, "(nonlinear)", NONLINEAR)
    return out
