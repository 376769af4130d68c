"""The hovercraft's solve with any general transcription (paper 004, example 1): the thrust
vector first, then the paper's thrust angle; and the maximum-principle reference.

From the paper's guess α ≡ 0 the angle form is degenerate (∂v̇x/∂α = -(A/m) sin α = 0), so a
cold start first solves the thrust-vector form (|u| ≤ 1, exact for minimum time) and then
re-solves the angle form from there, with its 2π window of directions centred on the
solution; warm re-solves go straight to the chosen form. LGL keeps the thrust vector.
Every optimal solution is compared with the minimum-time extremal of the maximum principle
(`model.solve_min_time`), stored as `Solution.references["maximum principle"]`.
"""

from __future__ import annotations

import numpy as np

from ... import interval_error
from ...context import SolveContext
from ...ocp import OCPResult
from ...optimality import PMP_COSTATES, record_costate_error, too_few_nodes
from ...problem import Method
from ...solution import Iterate, Quantity, Series, Solution, WarmStart, costate_units
from ...transcription import direct_transcription
from ...verify import repropagate
from . import problem
from .model import STATE_UNITS, STATES, X_LB, X_UB, guess_from_steering, solve_min_time
from .problem import ANGLE_ONLY, ANGLE_VIA_VECTOR, P_A, P_AC, P_X0, P_XF, REFERENCE, VECTOR

REFERENCE_SAMPLES = 201


def _converted(warm: WarmStart, U: np.ndarray) -> WarmStart:
    """A start in the other control form: primal nodes only, re-interpolated by the
    transcription (its own kind never matches "converted", so no stale duals are used)."""
    return WarmStart("converted", warm.n_intervals, warm.tau, warm.X, U, warm.T)


def _as_angle(warm: WarmStart) -> WarmStart:
    return _converted(warm, np.unwrap(np.arctan2(warm.U[:, 1], warm.U[:, 0]))[:, None])


def _as_vector(warm: WarmStart) -> WarmStart:
    return _converted(warm, np.column_stack([np.cos(warm.U[:, 0]), np.sin(warm.U[:, 0])]))


def _stage(method: Method, nodes: int, backend: str, vector: bool, p: np.ndarray, *,
           start: WarmStart | None, ctx: SolveContext) -> OCPResult:
    """One solve of the thrust-vector (`vector`) or the angle form."""
    transcription = direct_transcription(method.transcription, problem.stage_ocp(vector), nodes,
                                         backend, **dict(method.options))
    return transcription.solve(p, start, ctx)


def solve_two_stage(values: dict[str, float], method: Method, nodes: int, backend: str,
                    warm: Solution | None, ctx: SolveContext) -> Solution:
    """Solve with `method`'s transcription in the control form that `steering` selects."""
    p = problem.parameter_vector(values)
    problem.precheck(p)
    mode = int(values["steering"])
    if mode == ANGLE_VIA_VECTOR and method.key == "lgl":
        # LGL collocates only at its nodes, where |u| = 1 holds exactly: there is no chord
        # loss to polish away, and the angle form's end-node controls admit spurious KKT
        # points (one node jumps to ±π at N = 40).
        mode = VECTOR
    prev = warm.warm if warm is not None and warm.converged and warm.warm is not None else None
    stages: list[OCPResult] = []
    if mode == VECTOR:
        start = _as_vector(prev) if prev is not None and prev.U.shape[1] == 1 else prev
        stages.append(_stage(method, nodes, backend, True, p, start=start, ctx=ctx))
    else:
        shown_vector = prev is not None and prev.U.shape[1] == 2
        start = _as_angle(prev) if shown_vector else prev
        if mode == ANGLE_VIA_VECTOR and (start is None or shown_vector):
            # Cold, or warm from a thrust-vector answer (the angle form could not follow it,
            # e.g. a throttled arc along an active bound): the vector form first again, so
            # that a re-solve on another mesh can fall back as the first solve did.
            first = _stage(method, nodes, backend, True, p, start=prev if shown_vector else None,
                           ctx=ctx)
            stages.append(first)
            start = _as_angle(first.warm) if first.status == "optimal" else None
        if mode == ANGLE_ONLY or start is not None:
            p_angle = p.copy()
            if mode == ANGLE_VIA_VECTOR:
                # The same 2π of directions as the paper's -π <= α <= π, centred on the start
                # so that a turn through 180° stays continuous.
                p_angle[P_AC] = float(np.mean(start.U[:, 0]))
            stages.append(_stage(method, nodes, backend, False, p_angle, start=start, ctx=ctx))
    res = stages[-1]
    if res.status != "optimal" and len(stages) == 2 and stages[0].status == "optimal":
        res = stages[0]
        throttle = float(np.min(np.hypot(res.U[:, 0], res.U[:, 1])))
        res.message += (" (the angle form, always at full thrust, did not converge from the "
                        "thrust-vector solution, whose thrust falls to "
                        f"|u| = {throttle:.2f}: showing the thrust-vector solution)")
    if res.status != "optimal" and nodes < method.nodes[1]:
        res.message = too_few_nodes(method, nodes, res.message)
    return _record(values, method.key, nodes, backend, p, stages=stages, res=res)


def angles(U: np.ndarray) -> np.ndarray:
    """Thrust angles from either control form, continuous along the trajectory."""
    if U.shape[1] == 2:
        return np.unwrap(np.arctan2(U[:, 1], U[:, 0]))
    return U[:, 0].copy()


def _controls(U: np.ndarray) -> np.ndarray:
    """The reported control: α, and for the thrust-vector form also the throttle |u|."""
    if U.shape[1] == 2:
        return np.column_stack([angles(U), np.hypot(U[:, 0], U[:, 1])])
    return U.copy()


def _record(values: dict[str, float], method: str, nodes: int, backend: str, p: np.ndarray,
            *, stages: list[OCPResult], res: OCPResult) -> Solution:
    """The numeric solution of the stage shown, with the iterates of every stage."""
    vector = res.U.shape[1] == 2
    form = "thrust vector" if vector else "angle α"
    message = res.message + f" [{form}" + (", after a thrust-vector start]"
                                           if len(stages) == 2 and not vector else "]")
    sol = Solution(
        mission="hovercraft", method=method, nodes=nodes, backend=backend, status=res.status,
        message=message, cost=Quantity(res.T, "final time", "s"), values=values,
        quantities={"T": Quantity(res.T, "final time", "s")}, state_names=STATES,
        state_units=STATE_UNITS,
        control_names=("alpha", "throttle") if vector else ("alpha",),
        control_units=("rad", "") if vector else ("rad",),
        node_t=res.t_nodes, node_x=res.X, node_u=_controls(res.U), arcs=[(0.0, res.T, "burn")],
        t=res.t_dense, x=res.X_dense, u=_controls(res.U_dense),
    )
    res.record_nlp(sol)
    offset = 0
    for stage in stages:
        sol.history += [Iterate(offset + it.iteration, it.t, it.x) for it in stage.history]
        offset += stage.iterations + 1
    sol.stats.update(iterations=sum(s.iterations for s in stages), stages=len(stages))
    if res.status == "optimal":
        sol.checker = lambda: check(sol, p, res, vector)
    return sol


def _costate_guess(sol: Solution, p: np.ndarray) -> np.ndarray:
    """The shooting unknowns (lam, c, T) from the estimated costates (p_r = lam constant,
    p_v(0) = c), or fitted to the steering when the method gave none."""
    if sol.costates is None:
        return guess_from_steering(sol.node_t, sol.node_u[:, 0], p[P_X0], p[P_A])
    lam = np.asarray(sol.costates.values)
    return np.concatenate([lam[:, :2].mean(axis=0), lam[0, 2:] + lam[0, :2] * sol.costates.t[0],
                           [sol.cost.value]])


def _add_reference(sol: Solution, p: np.ndarray) -> None:
    """The maximum-principle extremal started from this solution's costate estimate:
    T_pontryagin, T_error, the reference states and angle and its costates, and their
    agreement with the estimate; unless the extremal leaves the state box (a bound is active
    at the optimum, so it is no reference for the bounded problem)."""
    ext = solve_min_time(p[P_X0], p[P_XF], p[P_A], _costate_guess(sol, p))
    if not ext.converged:
        ext = solve_min_time(p[P_X0], p[P_XF], p[P_A], guess_from_steering(
            sol.node_t, sol.node_u[:, 0], p[P_X0], p[P_A]))
    if not ext.converged:
        return
    t = np.linspace(0.0, ext.T, REFERENCE_SAMPLES)
    X = ext.states(t, p[P_X0], p[P_A])
    if np.any(X < np.array(X_LB) - 1e-9) or np.any(X > np.array(X_UB) + 1e-9):
        sol.message += (" (the unconstrained maximum-principle extremal leaves the state box "
                        "here, so it is not shown as a reference)")
        return
    T = sol.cost.value
    sol.quantities["T_pontryagin"] = Quantity(ext.T, "T (maximum principle)", "s")
    sol.quantities["T_error"] = Quantity(T - ext.T, "T − T(maximum principle)", "s")
    sol.references[REFERENCE] = Series(
        t, np.column_stack([X, np.unwrap(ext.alpha(t))]), (*STATES, "alpha"),
        (*STATE_UNITS, "rad"))
    sol.references[PMP_COSTATES] = Series(t, ext.costates(t), STATES,
                                          costate_units("s", STATE_UNITS))
    record_costate_error(sol)


def check(sol: Solution, p: np.ndarray, res: OCPResult, vector: bool) -> dict[str, float]:
    """Re-propagate the method's own control (in the form it was solved in) with DOP853 and
    report the terminal miss; the local error of every interval (position, m) and the
    state box between nodes; then the maximum-principle reference (`_add_reference`: here,
    in the deferred check, it was more than half of a warm re-solve's time)."""
    ocp = problem.stage_ocp(vector)
    _, X = repropagate(ocp.functions().f, p, p[P_X0], res.control, res.t_nodes, atol=1e-12)
    errors, box = interval_error.box_check(sol, ocp, p, res, 1e-12)
    interval_error.record(sol, interval_error.error_series(
        res.t_nodes, np.hypot(errors[:, 0], errors[:, 1]), "error", "m"))
    miss = {**problem.end_miss(p, X[-1]), **box}
    _add_reference(sol, p)
    return miss
