"""Mission `apollo-reentry`: Stoer & Bulirsch's Apollo-type lifting reentry with minimum
convective heating (paper 004, example 2; SPEC M5 case 2).

The three general methods solve the OCP of `problem.py` in the model's published units
(1e5 ft, s; `model.py`), so the cost J is the number the paper prints; the solution is
converted to SI at the interface (`problem.record`). An indirect multiple-shooting solution
on the maximum principle (`model.solve_indirect`, started from a direct solution by
`indirect_solution`) is the independent reference of the published numbers.
"""

from __future__ import annotations

import numpy as np

from ...context import SolveContext
from ...methods import HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING
from ...mission import Mission
from ...ocp import OCP, OCPResult
from ...optimality import PMP_COSTATES, PMP_TRAJECTORY, record_costate_error
from ...problem import Method
from ...solution import Quantity, Series, Solution, costate_units
from ...verify import repropagate
from . import problem, view
from .model import (
    LENGTH_UNIT,
    R_EARTH,
    STATE_UNITS,
    STATES,
    ReentryExtremal,
    solve_indirect,
    to_model,
    to_si,
)
from .problem import COST_UNIT, P_V0, P_VF, P_XI0, P_XIF

__all__ = ["MISSION", "R_EARTH", "ApolloReentry", "indirect_solution"]

# Model units per SI unit of each state: costates in model units are SI costates times this.
SI_PER_MODEL = np.array([LENGTH_UNIT, 1.0, R_EARTH])


class ApolloReentry(Mission, records=problem):
    key = "apollo-reentry"
    title = "Apollo reentry, minimum heating"
    summary = "Steer the lift of an Apollo-type capsule to minimise the convective heat load."
    methods = (
        MULTIPLE_SHOOTING.replace(
            nodes=(4, 40, 60), backends=("ipopt", "sqp"),
            summary=MULTIPLE_SHOOTING.summary + " RK4 steps of about 3 s. IPOPT is the "
            "default: CasADi's SQP with a BFGS Hessian (the paper's kind of solver) leaves "
            "the atmosphere from the paper's guess and stalls even when started at the "
            "optimum."),
        HERMITE_SIMPSON.replace(nodes=(4, 40, 300), backends=("ipopt", "fatrop")),
        LGL.replace(nodes=(10, 40, 80), backends=("ipopt",),
                    summary=LGL.summary + " The sharp dip into the dense air needs about 40 "
                    "nodes for 0.01 % (a global polynomial's weak spot)."),
    )
    # A slider move re-solves in 13 ms by Hermite–Simpson, 55 ms by multiple shooting (both
    # `optimal` at their defaults, bench_missions 2026-12-07): the explorer opens with it.
    live_method = "hermite-simpson"
    cost_label = "heat load J"

    def solve_direct(self, values: dict[str, float], method: Method, nodes: int, backend: str,
                     warm: Solution | None, ctx: SolveContext) -> Solution:
        """The general path, with multiple shooting's RK4 steps kept near 3 s whatever the
        node count."""
        if method.transcription == "multiple-shooting":
            method = method.replace(options=(("substeps", problem.substeps(nodes)),))
        return super().solve_direct(values, method, nodes, backend, warm, ctx)

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        problem.record(sol, res)

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        return problem.terminal_miss(p, x_final)

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str]:
        """Local error in altitude (the headline: the end altitude), m."""
        return np.abs(dx[:, 2]) * R_EARTH, "m"

    def check_direct(self, ocp: OCP, p: np.ndarray, res: OCPResult) -> dict[str, float]:
        """Re-propagate the method's own control (linear between nodes, or the LGL
        polynomial) with DOP853 together with the heat load; the terminal miss in SI and the
        relative mismatch of J."""
        x0 = np.concatenate([p[P_V0 : P_XI0 + 1], [0.0]])
        _, X = repropagate(problem.augmented(), p, x0, res.control, res.t_nodes,
                           atol=np.array([1e-12, 1e-12, 1e-14, 1e-14]))
        miss = self.terminal_miss(p, X[-1, :3])
        miss["J_repropagated_rel_error"] = float(X[-1, 3] / res.cost - 1)
        return miss

    def indirect_reference(self, sol: Solution, p: np.ndarray) -> None:
        """Indirect multiple shooting (`model.solve_indirect`) started from the costate
        estimate: the extremal, its J and T and the costate agreement."""
        if sol.costates is None:
            return
        try:
            ext = indirect_solution(sol)
        except FloatingPointError:
            ext = None
        if ext is None or not ext.converged:
            sol.message += " (indirect shooting did not converge from the costate estimate)"
            return
        store_extremal(sol, ext)

    _present = staticmethod(view.present)


def indirect_solution(sol: Solution, n_segments: int = 10) -> ReentryExtremal:
    """The maximum-principle extremal started from a direct solution of this mission (its
    dense SI samples converted back to the model's units, and its costate estimate when it
    has one); J and T in S&B units and s."""
    p = problem.parameter_vector(sol.values)
    lam = None
    if sol.costates is not None:
        est = sol.costates
        lam = np.column_stack([np.interp(sol.t, est.t, col) for col in np.asarray(est.values).T])
        lam = lam * SI_PER_MODEL
    return solve_indirect(sol.t, to_model(sol.x), sol.u[:, 0], p[P_V0 : P_XI0 + 1],
                          p[P_VF : P_XIF + 1], n_segments=n_segments, lam=lam)


def store_extremal(sol: Solution, ext: ReentryExtremal) -> None:
    """The extremal in SI as `sol.references` (trajectory and costates), its J and T, and
    the costate agreement."""
    sol.references[PMP_TRAJECTORY] = Series(
        ext.t, np.column_stack([to_si(ext.Y[:, :3]), ext.u]), (*STATES, "u"),
        (*STATE_UNITS, "rad"))
    sol.references[PMP_COSTATES] = Series(
        ext.t, ext.Y[:, 3:] / SI_PER_MODEL, STATES, costate_units(COST_UNIT, STATE_UNITS))
    sol.quantities["J_pontryagin"] = Quantity(ext.cost, "J (maximum principle)", COST_UNIT)
    sol.quantities["T_pontryagin"] = Quantity(ext.T, "T (maximum principle)", "s")
    record_costate_error(sol)


MISSION = ApolloReentry()
