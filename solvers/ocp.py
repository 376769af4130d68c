"""A declarative optimal control problem that any general transcription can solve.

Bolza form on t in [0, T]:

    min  mayer(x(T), T, p) + integral of lagrange(x, u, p) dt
    s.t. x' = f(x, u, p),  x(0) = x0(p),  terminal(x(T), p) = 0,
         bounds on x, u and T,  path_lb <= path(x, u, p) <= path_ub at the nodes.

Symbolic functions take and return CasADi expressions in SI units; `scale`/`offset` fields
say how the transcriptions nondimensionalise the NLP variables (value = offset + scale * z).
Numeric callables (`bounds`, `guess`) take the numeric parameter vector, so bounds and
guesses may follow the sliders without rebuilding the NLP.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from .solution import Solution

Expr = ca.SX


@dataclass(frozen=True)
class Bounds:
    """Numeric box bounds in SI units."""

    x_lb: np.ndarray
    x_ub: np.ndarray
    u_lb: np.ndarray
    u_ub: np.ndarray
    T_lb: float
    T_ub: float


@dataclass(frozen=True)
class Guess:
    """A cold-start guess: states linear from x(0) to `x_final`, constant control."""

    x_final: np.ndarray
    u: np.ndarray
    T: float


@dataclass(frozen=True, eq=False)
class OCP:
    """The problem; frozen and hashed by identity so transcriptions can be cached per OCP."""

    states: tuple[str, ...]
    controls: tuple[str, ...]
    n_params: int
    dynamics: Callable[[Expr, Expr, Expr], Expr]
    initial_state: Callable[[Expr], Expr]
    terminal: Callable[[Expr, Expr], Expr]
    bounds: Callable[[np.ndarray], Bounds]
    guess: Callable[[np.ndarray], Guess]
    x_scale: np.ndarray
    u_scale: np.ndarray
    T_scale: float
    terminal_scale: np.ndarray
    cost_scale: float = 1.0
    x_offset: np.ndarray | None = None
    mayer: Callable[[Expr, Expr, Expr], Expr] | None = None
    lagrange: Callable[[Expr, Expr, Expr], Expr] | None = None
    fixed_final_time: Callable[[Expr], Expr] | None = None
    path: Callable[[Expr, Expr, Expr], Expr] | None = None
    path_lb: np.ndarray = field(default_factory=lambda: np.zeros(0))
    path_ub: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def nx(self) -> int:
        return len(self.states)

    @property
    def nu(self) -> int:
        return len(self.controls)

    @property
    def offset(self) -> np.ndarray:
        return np.zeros(self.nx) if self.x_offset is None else np.asarray(self.x_offset, float)

    def functions(self) -> OCPFunctions:
        return _functions(self)


@dataclass(frozen=True)
class OCPFunctions:
    """Numeric CasADi Functions of an OCP (for guesses, dense output and verification)."""

    f: ca.Function
    x0: ca.Function
    lagrange: ca.Function | None
    fixed_T: ca.Function | None


# Keyed by the OCP object itself, weakly: an id() key was reused by a later OCP of another
# size after the first was garbage collected, handing it the wrong functions.
_FUNCTION_CACHE: weakref.WeakKeyDictionary[OCP, OCPFunctions] = weakref.WeakKeyDictionary()


def _functions(ocp: OCP) -> OCPFunctions:
    key = ocp
    if key not in _FUNCTION_CACHE:
        x = ca.SX.sym("x", ocp.nx)
        u = ca.SX.sym("u", ocp.nu)
        p = ca.SX.sym("p", ocp.n_params)
        lag = None
        if ocp.lagrange is not None:
            lag = ca.Function("L", [x, u, p], [ocp.lagrange(x, u, p)])
        fixed = None
        if ocp.fixed_final_time is not None:
            fixed = ca.Function("T", [p], [ocp.fixed_final_time(p)])
        _FUNCTION_CACHE[key] = OCPFunctions(
            f=ca.Function("f", [x, u, p], [ocp.dynamics(x, u, p)]),
            x0=ca.Function("x0", [p], [ocp.initial_state(p)]),
            lagrange=lag,
            fixed_T=fixed,
        )
    return _FUNCTION_CACHE[key]


@dataclass
class OCPResult:
    """What a general transcription returns, in SI units."""

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
    history: list[tuple[int, np.ndarray, np.ndarray]]
    warm: WarmStart
    control_interpolation: str = "linear"

    def record_nlp(self, sol: Solution) -> None:
        """Put this solve's NLP statistics, warm start and own defect into `sol`."""
        sol.stats.update(iterations=self.iterations, nlp_variables=self.n_variables,
                         nlp_constraints=self.n_constraints,
                         constraint_violation=self.max_violation)
        sol.warm = self.warm
        sol.check["max_defect"] = self.max_violation

    def control(self, t: float, x: np.ndarray | None = None) -> np.ndarray:
        """The control between nodes exactly as the transcription defines it: piecewise
        linear, or the polynomial through all nodes (pseudospectral methods)."""
        if self.control_interpolation == "polynomial":
            from .transcription.lgl import interpolate

            return interpolate(self.t_nodes, self.U, np.array([t]))[0]
        return np.array([np.interp(t, self.t_nodes, self.U[:, j]) for j in range(self.U.shape[1])])


@dataclass
class WarmStart:
    """Primal and dual values of an NLP solve, tagged with what produced them."""

    kind: str
    n_intervals: int
    tau: np.ndarray
    X: np.ndarray
    U: np.ndarray
    T: float
    z: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
