"""A declarative optimal control problem that any general transcription can solve.

Bolza form on t in [t0, t0 + T]:

    min  mayer(x(tf), T, p) + integral of lagrange(x, u, p) dt
    s.t. x' = f(x, u, p),  x(t0) = x0(p) (or free),  terminal(x(tf), p) = 0,
         boundary_lb <= boundary(x(t0), x(tf), t0, T, s, p) <= boundary_ub,
         bounds on x, u, T, t0 and the static variables s,
         path_lb <= path(x, u, p) <= path_ub at the nodes.

Where every path row is a second-order cone, `path_cones` states it: a list of (v, t), row j
of `path` being |v_j|² - t_j² <= 0 with t_j >= 0, i.e. |v_j| <= t_j, v_j and t_j affine in
(x, u). The NLP methods ignore it; successive convexification keeps those cones exact in its
convex subproblems instead of linearising the rows (Mao, Szmuk & Açıkmeşe 2016 linearise only
the nonconvex constraints; a linearised cone is degenerate at its apex, where a coast sits).

The initial time t0 is 0 unless `free_initial_time` (e.g. a launch date); `statics` name
decision variables that do not depend on time (e.g. a departure v-infinity). The dynamics are
autonomous: t0 enters only through the boundary functions.

Symbolic functions take and return CasADi expressions in the problem's units (SI for our
missions); `*_scale`/`x_offset` say how the transcriptions nondimensionalise the NLP variables
(value = offset + scale * z). Numeric callables (`bounds`, `guess`) take the numeric parameter
vector, so bounds and guesses follow the sliders without rebuilding the NLP.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from .lgl import interpolate
from .solution import Iterate, Series, Solution, WarmStart, costate_units

Expr = ca.SX


def _none() -> np.ndarray:
    return np.zeros(0)


@dataclass(frozen=True)
class Bounds:
    """Numeric box bounds in the problem's units."""

    x_lb: np.ndarray
    x_ub: np.ndarray
    u_lb: np.ndarray
    u_ub: np.ndarray
    T_lb: float
    T_ub: float
    t0_lb: float = 0.0
    t0_ub: float = 0.0
    s_lb: np.ndarray = field(default_factory=_none)
    s_ub: np.ndarray = field(default_factory=_none)


@dataclass(frozen=True)
class Guess:
    """A cold-start guess: states linear from x(0) to `x_final` (from `x_initial` when the
    initial state is free), controls constant `u`; `x_path` / `u_path`, when given, give the
    states / controls at normalised times tau in [0, 1] instead (rows: times), so a guess
    may vary in time (a ramp, a thrust angle that turns through the flight)."""

    x_final: np.ndarray
    u: np.ndarray
    T: float
    x_initial: np.ndarray | None = None
    t0: float = 0.0
    statics: np.ndarray = field(default_factory=_none)
    x_path: Callable[[np.ndarray], np.ndarray] | None = None
    u_path: Callable[[np.ndarray], np.ndarray] | None = None

    def states(self, tau: np.ndarray, x0: np.ndarray) -> np.ndarray:
        """(len(tau), nx) states at normalised times tau; `x0` starts the straight line."""
        if self.x_path is not None:
            return np.asarray(self.x_path(tau), float).reshape(len(tau), -1)
        return x0 + np.outer(tau, np.asarray(self.x_final, float) - x0)

    def controls(self, tau: np.ndarray) -> np.ndarray:
        """(len(tau), nu) controls at normalised times tau."""
        if self.u_path is not None:
            return np.asarray(self.u_path(tau), float).reshape(len(tau), -1)
        return np.tile(np.asarray(self.u, float), (len(tau), 1))


@dataclass(frozen=True)
class BoundaryPoint:
    """The symbolic end points handed to `OCP.boundary`."""

    x0: Expr
    xf: Expr
    t0: Expr
    T: Expr
    s: Expr


@dataclass(frozen=True, eq=False)
class OCP:
    """The problem; frozen and hashed by identity so transcriptions can be cached per OCP."""

    states: tuple[str, ...]
    controls: tuple[str, ...]
    n_params: int
    dynamics: Callable[[Expr, Expr, Expr], Expr]
    bounds: Callable[[np.ndarray], Bounds]
    guess: Callable[[np.ndarray], Guess]
    x_scale: np.ndarray
    u_scale: np.ndarray
    T_scale: float
    state_units: tuple[str, ...] = ()
    control_units: tuple[str, ...] = ()
    initial_state: Callable[[Expr], Expr] | None = None
    terminal: Callable[[Expr, Expr], Expr] | None = None
    terminal_scale: np.ndarray = field(default_factory=_none)
    terminal_names: tuple[str, ...] = ()
    cost_scale: float = 1.0
    x_offset: np.ndarray | None = None
    mayer: Callable[[Expr, Expr, Expr], Expr] | None = None
    lagrange: Callable[[Expr, Expr, Expr], Expr] | None = None
    fixed_final_time: Callable[[Expr], Expr] | None = None
    path: Callable[[Expr, Expr, Expr], Expr] | None = None
    path_lb: np.ndarray = field(default_factory=_none)
    path_ub: np.ndarray = field(default_factory=_none)
    path_cones: Callable[[Expr, Expr, Expr], list[tuple[Expr, Expr]]] | None = None
    free_initial_time: bool = False
    t0_scale: float = 1.0
    statics: tuple[str, ...] = ()
    s_scale: np.ndarray | None = None
    boundary: Callable[[BoundaryPoint, Expr], Expr] | None = None
    boundary_lb: np.ndarray = field(default_factory=_none)
    boundary_ub: np.ndarray = field(default_factory=_none)
    boundary_scale: np.ndarray | None = None
    nlp_options: Mapping[str, Any] = field(default_factory=dict)
    # The controls from the ones a solution shows (rows of `Solution.u`), where the OCP adds
    # some (an L1 slack): so that a paper's answer can seed it (`continuation`).
    controls_from_shown: Callable[[np.ndarray], np.ndarray] | None = None

    @property
    def nx(self) -> int:
        return len(self.states)

    @property
    def nu(self) -> int:
        return len(self.controls)

    @property
    def ns(self) -> int:
        return len(self.statics)

    @property
    def offset(self) -> np.ndarray:
        return np.zeros(self.nx) if self.x_offset is None else np.asarray(self.x_offset, float)

    @property
    def static_scale(self) -> np.ndarray:
        return np.ones(self.ns) if self.s_scale is None else np.asarray(self.s_scale, float)

    def functions(self) -> OCPFunctions:
        return _functions(self)


@dataclass(frozen=True)
class OCPFunctions:
    """Numeric CasADi Functions of an OCP (for guesses, dense output and verification)."""

    f: ca.Function
    x0: ca.Function | None
    lagrange: ca.Function | None
    fixed_T: ca.Function | None
    terminal: ca.Function | None


# Keyed by the OCP object itself, weakly: an id() key was reused by a later OCP of another
# size after the first was garbage collected, handing it the wrong functions.
_FUNCTION_CACHE: weakref.WeakKeyDictionary[OCP, OCPFunctions] = weakref.WeakKeyDictionary()


def _functions(ocp: OCP) -> OCPFunctions:
    if ocp not in _FUNCTION_CACHE:
        x = ca.SX.sym("x", ocp.nx)
        u = ca.SX.sym("u", ocp.nu)
        p = ca.SX.sym("p", ocp.n_params)

        def fn(name: str, args: list, expr: Callable[..., Expr] | None) -> ca.Function | None:
            return None if expr is None else ca.Function(name, args, [expr(*args)])

        _FUNCTION_CACHE[ocp] = OCPFunctions(
            f=ca.Function("f", [x, u, p], [ocp.dynamics(x, u, p)]),
            x0=fn("x0", [p], ocp.initial_state),
            lagrange=fn("L", [x, u, p], ocp.lagrange),
            fixed_T=fn("T", [p], ocp.fixed_final_time),
            terminal=fn("terminal", [x, p], ocp.terminal),
        )
    return _FUNCTION_CACHE[ocp]


@dataclass
class OCPResult:
    """What a general transcription returns, in the problem's units."""

    T: float
    t_nodes: np.ndarray
    X: np.ndarray
    U: np.ndarray
    t_dense: np.ndarray
    X_dense: np.ndarray
    U_dense: np.ndarray
    cost: float
    status: str
    message: str
    iterations: int
    n_variables: int
    n_constraints: int
    max_violation: float
    history: list[Iterate]
    warm: WarmStart
    control_interpolation: str = "linear"
    t0: float = 0.0
    statics: np.ndarray = field(default_factory=_none)
    costates: Series | None = None
    hamiltonian: Series | None = None
    # (max H - min H) / the largest term of H: 0 for an exact extremal (constant H).
    hamiltonian_variation: float = float("nan")
    # The dynamics constraints at the last point (times, rows in the states' units).
    defects: tuple[np.ndarray, np.ndarray] | None = None

    def record_nlp(self, sol: Solution) -> None:
        """Put this solve's NLP statistics, warm start, own defect and optimality estimates
        into `sol`."""
        sol.stats.update(iterations=self.iterations, nlp_variables=self.n_variables,
                         nlp_constraints=self.n_constraints,
                         constraint_violation=self.max_violation)
        sol.warm = self.warm
        sol.check["max_defect"] = self.max_violation
        sol.control_interpolation = self.control_interpolation
        if self.costates is not None and self.hamiltonian is not None:
            cost_unit = sol.cost.unit
            sol.costates = Series(self.costates.t, self.costates.values, self.costates.names,
                                  costate_units(cost_unit, sol.state_units))
            sol.hamiltonian = Series(self.hamiltonian.t, self.hamiltonian.values, ("value",),
                                     (f"{cost_unit or '1'}/s",))
            sol.stats["hamiltonian_variation"] = self.hamiltonian_variation

    def controls(self, t: np.ndarray) -> np.ndarray:
        """`control` at many times at once: (len(t), nu)."""
        t = np.asarray(t, float)
        if self.control_interpolation == "polynomial":
            return interpolate(self.t_nodes, self.U, t)
        return np.column_stack([np.interp(t, self.t_nodes, col) for col in self.U.T])

    def control(self, t: float, x: np.ndarray | None = None) -> np.ndarray:
        """The control between nodes exactly as the transcription defines it: piecewise
        linear, or the polynomial through all nodes (pseudospectral methods); `t` counts from
        the initial time."""
        if self.control_interpolation == "polynomial":
            return interpolate(self.t_nodes, self.U, np.array([t]))[0]
        return np.array([np.interp(t, self.t_nodes, self.U[:, j]) for j in range(self.U.shape[1])])
