"""The `OCP` of a declaration: scales (from the bounds when not given), bounds and the
cold-start guess (`guesses`) as functions of the parameter vector, boundary conditions and
the cost.

Fixed final states become the OCP's terminal conditions; an initial state fixed in full is
pinned by the variable bounds; a partly fixed initial state and the final constraints become
boundary rows. Values given as parameter keys follow the sliders without rebuilding.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial

import casadi as ca
import numpy as np

from ..ocp import OCP, BoundaryPoint, Bounds, Guess
from .declaration import Declaration, resolve
from .functions import Traced
from .guesses import ENDS, control_guess, state_guess
from .records import FreeTime, State, Value


def _values(decl: Declaration, p: np.ndarray) -> dict[str, float]:
    return dict(zip(decl.param_keys, np.asarray(p, float), strict=True))


def symbolic(value: Value, decl: Declaration, p: ca.SX | ca.MX) -> ca.SX | ca.MX | float:
    """A number, or the parameter it names as an entry of the symbolic vector `p`."""
    return p[decl.param_keys.index(value)] if isinstance(value, str) else float(value)


def _magnitude(values: Sequence[float]) -> float:
    finite = [abs(v) for v in values if math.isfinite(v) and v != 0]
    return max(finite) if finite else 1.0


def state_scaling(s: State, defaults: dict[str, float]) -> tuple[float, float]:
    """(offset, scale) of a state: its own scale, else the centre and half-width of finite
    bounds, else the largest of its values (1 when all are zero)."""
    if s.scale is not None:
        return 0.0, float(s.scale)
    lo, hi = (resolve(b, defaults) for b in s.bounds)
    if math.isfinite(lo) and math.isfinite(hi):
        return (lo + hi) / 2, (hi - lo) / 2
    ends = [resolve(v, defaults) for v in (s.initial, s.final) if v is not None]
    guess = [] if s.guess is None or callable(s.guess) else [s.guess]
    return 0.0, _magnitude([lo, hi, *ends, *guess])


def bound_scale(scale: float | None, lower: float, upper: float) -> float:
    """A control's or constraint's scale: its own, else the largest finite bound, else 1."""
    return float(scale) if scale is not None else _magnitude([lower, upper])


def final_time_guess(decl: Declaration, values: dict[str, float]) -> float:
    ft = decl.final_time
    return ft.guess if isinstance(ft, FreeTime) else resolve(ft, values)


def _bounds(decl: Declaration, p: np.ndarray) -> Bounds:
    """The states', controls' and final time's bounds at the parameter vector p."""
    v = _values(decl, p)
    x = np.array([[resolve(b, v) for b in s.bounds] for s in decl.states], float)
    u = np.array([[resolve(b, v) for b in c.bounds] for c in decl.controls], float)
    ft = decl.final_time
    T_lb, T_ub = (ft.lower, ft.upper) if isinstance(ft, FreeTime) else (0.0, math.inf)
    return Bounds(x_lb=x[:, 0], x_ub=x[:, 1], u_lb=u[:, 0], u_ub=u[:, 1], T_lb=T_lb, T_ub=T_ub)


def _guess(decl: Declaration, p: np.ndarray) -> Guess:
    """The cold start at p: the file's state and control guesses as functions of the
    normalised time, sampled on each method's grid."""
    v = _values(decl, p)
    X = state_guess(decl, v, ENDS)
    return Guess(x_final=X[-1], u=control_guess(decl, v, ENDS)[0],
                 T=final_time_guess(decl, v), x_initial=X[0],
                 x_path=partial(state_guess, decl, v), u_path=partial(control_guess, decl, v))


def _scales(decl: Declaration) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The states' offsets and scales and the controls' scales, from the defaults' bounds."""
    defaults = decl.defaults
    scaling = [state_scaling(s, defaults) for s in decl.states]
    u_scale = np.array([bound_scale(c.scale, *(resolve(b, defaults) for b in c.bounds))
                        for c in decl.controls])
    return np.array([o for o, _ in scaling]), np.array([s for _, s in scaling]), u_scale


def build_ocp(decl: Declaration, traced: Traced) -> OCP:
    """The OCP the general transcriptions solve (built once per declaration)."""
    x_offset, x_scale, u_scale = _scales(decl)
    sign = -1.0 if decl.maximize else 1.0
    fixed_start = [i for i, s in enumerate(decl.states) if s.initial is not None]
    fixed_end = [i for i, s in enumerate(decl.states) if s.final is not None]
    pinned = len(fixed_start) == len(decl.states)
    free_time = isinstance(decl.final_time, FreeTime)

    def initial_state(p: ca.SX) -> ca.SX:
        return ca.vertcat(*[symbolic(s.initial, decl, p) for s in decl.states])

    def terminal(xf: ca.SX, p: ca.SX) -> ca.SX:
        return ca.vertcat(*[xf[i] - symbolic(decl.states[i].final, decl, p) for i in fixed_end])

    rows_lb, rows_ub, rows_scale = _boundary_rows(decl, x_scale, [] if pinned else fixed_start)

    def boundary(point: BoundaryPoint, p: ca.SX) -> ca.SX:
        rows = [] if pinned else [point.x0[i] - symbolic(decl.states[i].initial, decl, p)
                                  for i in fixed_start]
        if traced.final is not None:
            rows.append(traced.final(point.xf, p))
        return ca.vertcat(*rows)

    def mayer(xf: ca.SX, T: ca.SX, p: ca.SX) -> ca.SX:
        value = traced.mayer(xf, p) if traced.mayer is not None else 0.0
        return sign * (value + (T if decl.minimum_time else 0.0))

    path_scale = np.array([bound_scale(c.scale, c.lower, c.upper) for c in decl.path])
    return OCP(
        states=decl.state_names,
        controls=decl.control_names,
        state_units=tuple(s.unit for s in decl.states),
        control_units=tuple(c.unit for c in decl.controls),
        n_params=len(decl.params),
        dynamics=lambda x, u, p: traced.f(x, u, p),
        bounds=partial(_bounds, decl),
        guess=partial(_guess, decl),
        x_scale=x_scale,
        x_offset=x_offset,
        u_scale=u_scale,
        T_scale=final_time_guess(decl, decl.defaults),
        initial_state=initial_state if pinned else None,
        terminal=terminal if fixed_end else None,
        terminal_scale=x_scale[fixed_end],
        terminal_names=tuple(decl.states[i].name for i in fixed_end),
        cost_scale=decl.cost_scale,
        mayer=mayer if (traced.mayer is not None or decl.minimum_time) else None,
        lagrange=(None if traced.lagrange is None
                  else lambda x, u, p: sign * traced.lagrange(x, u, p)),
        fixed_final_time=None if free_time else (lambda p: symbolic(decl.final_time, decl, p)),
        path=(None if traced.path is None
              else lambda x, u, p: traced.path(x, u, p) / ca.DM(path_scale)),
        path_lb=np.array([c.lower for c in decl.path]) / path_scale,
        path_ub=np.array([c.upper for c in decl.path]) / path_scale,
        boundary=boundary if len(rows_lb) else None,
        boundary_lb=rows_lb,
        boundary_ub=rows_ub,
        boundary_scale=rows_scale,
    )


def _boundary_rows(decl: Declaration, x_scale: np.ndarray, fixed_start: list[int]
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bounds and scales of the boundary rows: fixed initial states (when the initial state
    is only partly fixed), then the final constraints."""
    lb = [0.0] * len(fixed_start) + [c.lower for c in decl.final]
    ub = [0.0] * len(fixed_start) + [c.upper for c in decl.final]
    scale = [x_scale[i] for i in fixed_start] + [bound_scale(c.scale, c.lower, c.upper)
                                                 for c in decl.final]
    return np.array(lb, float), np.array(ub, float), np.array(scale, float)


def parameter_vector(decl: Declaration, values: dict[str, float]) -> np.ndarray:
    """The OCP's numeric parameters: the declared parameters' values in order."""
    return np.array([values[k] for k in decl.param_keys], float)
