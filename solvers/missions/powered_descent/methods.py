"""The `lossless` method (the papers' SOCP, `lossless.py`) as a mission method, and the
quantities every method of this mission reports."""

from __future__ import annotations

from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from ...context import Infeasible, SolveContext
from ...ocp import OCPResult
from ...problem import Method, Param
from ...solution import Quantity, Solution, WarmStart
from ...verify import repropagate
from .model import (
    CONTROL_UNITS,
    CONTROLS,
    P_C,
    P_G,
    P_MWET,
    P_RHO1,
    P_RHO2,
    STATE_UNITS,
    STATES,
)
from .problem import ocp, touchdown_miss
from .switch_mesh import switch_times

if TYPE_CHECKING:  # `lossless` imports cvxpy: loaded by the solves that use it (`_lossless`)
    from .lossless import LosslessResult, SOCPResult

OBJECTIVES = ("fuel", "landing-error")

LOSSLESS = Method(
    "lossless", "Lossless convexification (SOCP, Clarabel)",
    "Açıkmeşe & Ploen 2007; Blackmore, Açıkmeşe & Scharf 2010",
    "The slack Γ ≥ |T| with ρ1 ≤ Γ ≤ ρ2, z = ln m and σ = Γ/m make the problem a second-order "
    "cone program whose optimum has |T| = Γ; compiled once per node count with CVXPY "
    "parameters, re-solved by Clarabel; an outer golden-section search on the final time.",
    nodes=(10, 60, 200), nodes_label="intervals", backends=("clarabel",),
    params=(Param("objective", "problem", "", 0, 0, 1, 1, group="Method",
                  options=("minimum fuel", "minimum landing error"),
                  help="Minimum landing error (Blackmore et al. 2010): land as close to the "
                       "target as the fuel allows, then with the least fuel."),),
    equations=(
        ("Relaxation (lossless: |T| = Γ at the optimum)",
         r"\lVert u\rVert \le \sigma,\quad \mu_1(1 - \delta + \tfrac{\delta^2}{2}) \le \sigma "
         r"\le \mu_2 (1 - \delta),\quad \mu_i = \rho_i e^{-z_0},\ \delta = z - z_0"),
        ("Dynamics in the convex variables", r"\dot v = g + u,\quad \dot z = -\sigma / c,\quad "
         r"\min\ -z(t_f)"),
    ),
)


def descent_quantities(p: np.ndarray, t_nodes: np.ndarray, X: np.ndarray, U: np.ndarray
                       ) -> dict[str, Quantity]:
    """Fuel, flight time, touchdown distance and the thrust's margin over ρ1 (SI)."""
    thrust = np.linalg.norm(U, axis=1)
    return {
        "fuel": Quantity(float(p[P_MWET] - np.exp(X[-1, 6])), "fuel", "kg"),
        "tf": Quantity(float(t_nodes[-1]), "flight time", "s"),
        "landing_error": Quantity(float(np.linalg.norm(X[-1, :2])), "landing error", "m"),
        "min_thrust_margin": Quantity(float(np.min(thrust) - p[P_RHO1]), "min |T| − ρ1", "N"),
    }


def solve_method(values: dict[str, float], p: np.ndarray, nodes: int, warm: Solution | None,
                 ctx: SolveContext) -> Solution:
    """The lossless SOCP; a previous lossless answer's final time narrows the search."""
    objective = OBJECTIVES[int(values["objective"])]
    hint, switches = None, []
    if warm is not None and warm.warm is not None and warm.warm.kind == "lossless":
        w = warm.warm
        hint = w.T
        if w.n_intervals == nodes:
            switches = switch_times(w.tau * w.T, np.linalg.norm(w.U, axis=1), p[P_RHO1],
                                    p[P_RHO2])
    result = _lossless().solve_lossless(p, nodes, objective, hint, ctx,
                                        switches_hint=switches)
    return _solution(values, p, nodes, result)


def _lossless() -> ModuleType:
    """The SOCP module, imported on a convex solve's first use: it imports cvxpy, about a
    third of every process's start-up (CLI, solve workers) when imported with the missions."""
    from . import lossless

    return lossless


def _solution(values: dict[str, float], p: np.ndarray, nodes: int, result: LosslessResult
              ) -> Solution:
    best = result.best
    t_nodes = best.t
    mass = np.exp(best.z)
    X = np.column_stack([best.r, best.v, best.z])
    U = best.u * mass[:, None]
    t, X_dense, U_dense = dense(best, p)
    gap = best.sigma * mass - np.linalg.norm(U, axis=1)
    sol = Solution(
        mission="powered-descent", method="lossless", nodes=nodes, backend="clarabel",
        status="optimal", message=_message(result, gap, U, p), values=values,
        cost=Quantity(best.fuel, "fuel", "kg"),
        quantities=descent_quantities(p, t_nodes, X, U),
        state_names=STATES, state_units=STATE_UNITS, control_names=CONTROLS,
        control_units=CONTROL_UNITS, node_t=t_nodes, node_x=X, node_u=U,
        arcs=[(0.0, best.tf, "burn")], t=t, x=X_dense, u=U_dense,
    )
    sol.quantities["slack_gap"] = Quantity(float(np.max(np.abs(gap))), "max |Γ − |T||", "N")
    sol.stats.update(iterations=result.solves, socp_solves=result.solves,
                     relinearisations=result.relinearisations,
                     nlp_variables=13 * (nodes + 1))
    sol.warm = WarmStart("lossless", nodes, t_nodes / best.tf, X, U, best.tf)
    sol.check["max_defect"] = 0.0
    sol.checker = lambda: _check(p, best)
    return sol


def lossless_holds(gap: np.ndarray, U: np.ndarray, p: np.ndarray) -> bool:
    """Whether the relaxation was lossless: Γ = |T| and |T| ≥ ρ1 at every node (to 1e-5 of
    ρ1, the SOCP's accuracy)."""
    tol = 1e-5 * p[P_RHO1]
    return bool(np.max(np.abs(gap)) <= tol
                and np.min(np.linalg.norm(U, axis=1)) >= p[P_RHO1] - tol)


def _message(result: LosslessResult, gap: np.ndarray, U: np.ndarray, p: np.ndarray) -> str:
    verdict = "holds" if lossless_holds(gap, U, p) else "FAILS"
    text = (f"lossless: ‖T‖ ≥ ρ1 {verdict}, slack gap {np.max(np.abs(gap)):.1e} N; "
            f"{result.solves} SOCP solves (golden section on tf, {result.relinearisations} "
            "re-expansions of e^-z)")
    if result.landing_error > _lossless().REACHED:
        text += f"; target out of reach, touchdown {result.landing_error:.1f} m from it"
    return text


def dense(best: SOCPResult, p: np.ndarray, per_interval: int = 10
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The SOCP's own trajectory between nodes: u and σ linear, r and v exact, z by the
    same linear σ; thrust T = u e^z."""
    N = len(best.z) - 1
    g = np.array([0.0, 0.0, -p[P_G]])
    s = np.linspace(0.0, 1.0, per_interval + 1)[:-1]
    ts, xs, us = [], [], []
    for k in range(N):
        h = best.t[k + 1] - best.t[k]
        tau = (s * h)[:, None]
        du = (best.u[k + 1] - best.u[k]) / h
        v = best.v[k] + (g + best.u[k]) * tau + du * tau**2 / 2
        r = best.r[k] + best.v[k] * tau + (g + best.u[k]) * tau**2 / 2 + du * tau**3 / 6
        ds = (best.sigma[k + 1] - best.sigma[k]) / h
        z = best.z[k] - (best.sigma[k] * tau[:, 0] + ds * tau[:, 0] ** 2 / 2) / p[P_C]
        u = best.u[k] + du * tau
        ts.append(best.t[k] + s * h)
        xs.append(np.column_stack([r, v, z]))
        us.append(u * np.exp(z)[:, None])
    last = np.concatenate([best.r[-1], best.v[-1], [best.z[-1]]])
    return (np.concatenate([*ts, [best.tf]]), np.vstack([*xs, last]),
            np.vstack([*us, best.u[-1:] * np.exp(best.z[-1])]))


def _check(p: np.ndarray, best: SOCPResult) -> dict[str, float]:
    """Re-propagate the nonconvex dynamics (thrust T = u(t) m, u linear between nodes) with
    DOP853; the miss from the SOCP's own touchdown point."""
    t_nodes = best.t
    fn = ocp().functions()
    x0 = np.asarray(fn.x0(p)).ravel()

    def control(t: float, x: np.ndarray) -> np.ndarray:
        u = np.array([np.interp(t, t_nodes, best.u[:, j]) for j in range(3)])
        return u * np.exp(x[6])

    _, X = repropagate(fn.f, p, x0, control, t_nodes,
                       atol=np.array([1e-6] * 3 + [1e-8] * 3 + [1e-12]))
    return touchdown_miss(X[-1], best.r[-1])


def certify_infeasible(p: np.ndarray, ctx: SolveContext, nodes: int = 30) -> str:
    """Why no landing exists, from the lossless SOCP (its infeasibility is a certificate for
    the nonconvex problem); "" when it finds a landing (the failure was the solver's)."""
    try:
        _lossless().solve_lossless(p, nodes, "fuel", None, ctx)
    except Infeasible as exc:
        return str(exc)
    return ""


def record_direct(sol: Solution, res: OCPResult, p: np.ndarray) -> None:
    """The quantities of a general method's solution."""
    sol.quantities = descent_quantities(p, res.t_nodes, res.X, res.U)
