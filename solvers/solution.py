"""The numeric record every method returns, so nothing downstream asks which method made it.

A `Solution` holds numbers only (SI units): status and message, cost and quantities, node and
dense trajectories, solver statistics, iterate snapshots, the re-propagation check, costate and
error estimates and a typed warm start. It pickles (the solve service sends it between
processes) and serialises to JSON and CSV. What the explorer draws is built from it by the
mission's view (`solvers.presentation`).
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

# "optimal": converged and the re-propagated miss meets the mission's accuracy targets;
# "inaccurate": converged, but the re-propagation misses a target (refine the mesh);
# "infeasible": a named physical bound proves the request impossible.
STATUSES = ("optimal", "inaccurate", "infeasible", "iteration-limit", "time-limit",
            "cancelled", "failed")


def _empty(*shape: int) -> Callable[[], np.ndarray]:
    return lambda: np.zeros(shape)


@dataclass
class Quantity:
    """A labelled scalar in SI units."""

    value: float
    label: str
    unit: str
    # The estimated absolute error of `value` (its unit; the cost's: `solvers.cost_error`).
    error_estimate: float | None = None

    def to_dict(self) -> dict[str, Any]:
        out = {"value": _num(self.value), "label": self.label, "unit": self.unit}
        if self.error_estimate is not None:
            out["error_estimate"] = _num(self.error_estimate)
        return out


@dataclass(frozen=True)
class Label:
    """How a state, control or check entry is named on screen: words and the SI unit of
    its value (missions give them in `Mission.labels`, keyed by name)."""

    text: str
    unit: str = ""


# The check entries and statistics the methods report (missions add their own states,
# controls and checks in `Mission.labels`, which come first).
COMMON_LABELS = {
    "max_defect": Label("largest constraint violation (scaled)"),
    "error": Label("re-propagation check failed"),
    "iterations": Label("iterations"),
    "inner_iterations": Label("inner iterations"),
    "function_evaluations": Label("function evaluations"),
    "nlp_variables": Label("NLP variables"),
    "nlp_constraints": Label("NLP constraints"),
    "constraint_violation": Label("largest constraint violation (scaled)"),
    "hamiltonian_variation": Label("Hamiltonian variation (relative)"),
    "worst_interval": Label("interval of the largest local error"),
    "worst_interval_t": Label("time of the largest local error", "s"),
    "worst_interval_error": Label("largest local error (relative)"),
    "steps_per_segment": Label("integration steps per segment"),
    "integration_error_m": Label("integration error, position", "m"),
    "integration_error_m_s": Label("integration error, speed", "m/s"),
    "stages": Label("solve stages"),
    "continuation_steps": Label("continuation steps"),
    "starts": Label("initial guesses"),
    "converged_starts": Label("converged guesses"),
    "distinct_optima": Label("distinct optima"),
    "pso_evaluations": Label("swarm evaluations"),
    "pso_generations": Label("swarm generations"),
    "cost_reference_nodes": Label("nodes of the cost error estimate's second solve"),
    "cost_error_s": Label("time of the cost error estimate", "s"),
}


@dataclass
class Series:
    """Named signals sampled over time: `values` has one row per `t` and one column per name
    (SI units)."""

    t: np.ndarray
    values: np.ndarray
    names: tuple[str, ...]
    units: tuple[str, ...] = ()

    def column(self, name: str) -> np.ndarray:
        return np.asarray(self.values)[:, self.names.index(name)]

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"t": _arr(self.t)}
        values = np.atleast_2d(np.asarray(self.values, float).reshape(len(self.t), -1))
        for i, name in enumerate(self.names):
            out[name] = _arr(values[:, i])
        return out


def costate_units(cost_unit: str, state_units: tuple[str, ...]) -> tuple[str, ...]:
    """Units of dJ/dx: the cost's unit per each state's unit."""
    def per(unit: str) -> str:
        if not unit:
            return cost_unit
        return f"{cost_unit or '1'}/({unit})" if "/" in unit else f"{cost_unit or '1'}/{unit}"

    return tuple(per(u) for u in state_units)


@dataclass
class Iterate:
    """One NLP iterate kept for the iteration replay: node times and states (SI)."""

    iteration: int
    t: np.ndarray
    x: np.ndarray


@dataclass
class WarmStart:
    """Primal (and dual) values of a solve, tagged with what made them.

    A later solve of the same NLP (`kind` and `n_intervals` equal) restarts from `z`,
    `lam_x`, `lam_g`; any other solve re-interpolates the node values `X`, `U` on `tau`
    (normalised time in [0, 1]) with final time `T`, initial time `t0` and static variables
    `statics`. `data` holds a method's own numeric extras (e.g. a scale)."""

    kind: str
    n_intervals: int
    tau: np.ndarray
    X: np.ndarray
    U: np.ndarray
    T: float
    z: np.ndarray = field(default_factory=_empty(0))
    lam_x: np.ndarray = field(default_factory=_empty(0))
    lam_g: np.ndarray = field(default_factory=_empty(0))
    t0: float = 0.0
    statics: np.ndarray = field(default_factory=_empty(0))
    data: dict[str, Any] = field(default_factory=dict)

    @property
    def has_duals(self) -> bool:
        return len(self.lam_g) > 0 or len(self.lam_x) > 0

    def primal_only(self, kind: str = "guess") -> WarmStart:
        """The same nodes as a plain guess (no NLP vector, no multipliers)."""
        return WarmStart(kind, self.n_intervals, self.tau, self.X, self.U, self.T, t0=self.t0,
                         statics=self.statics, data=dict(self.data))


def samples_guess(sol: Solution, controls: np.ndarray) -> WarmStart:
    """Any method's answer as a plain guess for a transcription of the same problem: its
    dense samples (`sol.t`, `sol.x`) on normalised time, with `controls` (the samples'
    controls in the OCP's columns). A mission's own method (a paper's) keeps its nodes on
    its own independent variable (lunar landing: ϖ), so its samples in time are what a
    transcription can re-interpolate."""
    t = np.asarray(sol.t, float)
    duration = float(t[-1] - t[0])
    return WarmStart("samples", len(t) - 1, (t - t[0]) / duration, np.asarray(sol.x, float),
                     np.asarray(controls, float), duration, t0=float(t[0]))


@dataclass
class Solution:
    """Result of `Mission.solve`, identical in shape for every mission and method.

    Times in s; states and controls in SI (`state_units`, `control_units`); `node_*` at the
    NLP nodes, `t`/`x`/`u` dense samples of the method's own interpolation
    (`control_interpolation`: "linear" between nodes, "polynomial" through all of them, or
    "dense" when the control is only known at the samples).
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
    node_t: np.ndarray = field(default_factory=_empty(0))
    node_x: np.ndarray = field(default_factory=_empty(0, 0))
    node_u: np.ndarray = field(default_factory=_empty(0, 0))
    arcs: list[tuple[float, float, str]] = field(default_factory=list)
    t: np.ndarray = field(default_factory=_empty(0))
    x: np.ndarray = field(default_factory=_empty(0, 0))
    u: np.ndarray = field(default_factory=_empty(0, 0))
    control_interpolation: str = "linear"
    stats: dict[str, float] = field(default_factory=dict)
    history: list[Iterate] = field(default_factory=list)
    check: dict[str, float] = field(default_factory=dict)
    references: dict[str, Series] = field(default_factory=dict)
    costates: Series | None = None
    hamiltonian: Series | None = None
    switching: Series | None = None
    interval_error: Series | None = None
    mesh: list[dict[str, float]] = field(default_factory=list)
    # Accuracy targets of the re-propagated miss (keys of `check`, SI): an "optimal" answer
    # that misses one becomes "inaccurate" when the check runs.
    targets: dict[str, float] = field(default_factory=dict)
    # Why a check entry misses its target, in words (by key of `check`; set by the check
    # that measured it where "k = value (target)" would not tell a user what happened).
    reasons: dict[str, str] = field(default_factory=dict)
    # The cold starts of a multi-start solve (`solvers.multistart`): cost, converged (0/1)
    # and the guess values of each.
    starts: list[dict[str, float]] = field(default_factory=list)
    # Screen names of the states, controls and check entries, by key (`Label`).
    labels: dict[str, Label] = field(default_factory=dict)
    warm: WarmStart | None = field(default=None, repr=False)
    # The deferred re-propagation check (see `Mission.solve(verify=False)`); it stays in the
    # process that solved: never pickled.
    checker: Callable[[], dict[str, float]] | None = field(default=None, repr=False)

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state["checker"] = None
        return state

    @property
    def ok(self) -> bool:
        return self.status == "optimal"

    @property
    def converged(self) -> bool:
        """The method converged (optimal, or inaccurate on re-propagation): usable as a warm
        start and as the start of a refinement."""
        return self.status in ("optimal", "inaccurate")

    def misses(self) -> dict[str, tuple[float, float]]:
        """The re-propagated misses beyond their targets: key -> (miss, target)."""
        return {k: (self.check[k], tol) for k, tol in self.targets.items()
                if k in self.check and not abs(self.check[k]) <= tol}

    def label(self, key: str, unit: str = "") -> Label:
        """The screen name of a state, control or check entry (`unit`: its SI unit when the
        mission gives no label; then the name is the key itself)."""
        return (self.labels.get(key) or COMMON_LABELS.get(key)
                or Label(key.replace("_", " "), unit))

    @property
    def has_trajectory(self) -> bool:
        return len(self.t) > 1

    def value(self, name: str) -> float:
        """A number by name: "cost", a quantity, a statistic or a check entry (SI)."""
        if name == "cost":
            return float(self.cost.value)
        if name in self.quantities:
            return float(self.quantities[name].value)
        for table in (self.stats, self.check):
            if name in table:
                return float(table[name])
        raise KeyError(f"{self.mission}/{self.method} reports no '{name}'")

    def run_check(self) -> dict[str, float]:
        """Run the deferred re-propagation check. A check that fails is reported in
        `message`, never raised: the solution stays usable."""
        if self.checker is not None:
            checker, self.checker = self.checker, None
            try:
                self.check.update(checker())
            except BaseException as exc:
                if not isinstance(exc, Exception):  # interrupted (or exiting): run it again
                    self.checker = checker
                    raise
                self.check["error"] = float("nan")  # a failed check is reported, not fatal
                self.message += f" (re-propagation check failed: {exc})"
            self.judge()
        return self.check

    def judge(self) -> None:
        """"optimal" becomes "inaccurate" when the re-propagated miss exceeds a target, or
        when the check could not measure it (its accuracy is then unknown)."""
        if self.status != "optimal":
            return
        if "error" in self.check:
            self.status = "inaccurate"
            self.message += " — its accuracy is unknown: the re-propagation check failed"
            return
        missed = self.misses()
        if not missed:
            return
        self.status = "inaccurate"
        cost = missed.pop("cost_error_estimate", None)
        why = [self.reasons[k] for k in list(missed) if k in self.reasons]
        missed = {k: v for k, v in missed.items() if k not in self.reasons}
        if missed:
            worst = ", ".join(f"{k} = {v:.3g} (target {tol:g})" for k, (v, tol) in missed.items())
            why.append(f"re-propagating the control misses {worst}")
        if cost is not None and not np.isfinite(cost[0]):
            why.append("the cost's error is unknown (its estimate did not come)")
        elif cost is not None:
            why.append(f"the cost's estimated error {cost[0]:.2g} {self.cost.unit} exceeds "
                       f"its target {cost[1]:.2g}".replace("  ", " "))
        self.message += (f" — inaccurate: {'; '.join(why)}; raise the node count or refine "
                         "(nodes='auto')")

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
            "mesh": {"nodes": self.nodes,
                     "steps": [{k: _num(v) for k, v in step.items()} for step in self.mesh]},
            "targets": {k: _num(v) for k, v in self.targets.items()},
        }
        if self.starts:
            out["starts"] = [{k: _num(v) for k, v in row.items()} for row in self.starts]
        for name in ("costates", "hamiltonian", "switching", "interval_error"):
            series = getattr(self, name)
            if series is not None:
                key = "switching_function" if name == "switching" else name
                out[key] = series.to_dict()
                if series.units:  # e.g. "costates_units": {"r": "kg/m", ...}
                    out[f"{key}_units"] = dict(zip(series.names, series.units, strict=False))
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
