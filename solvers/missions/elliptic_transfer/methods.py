"""The methods of paper 001: its two closed-form laws (the STM law, eq. 10; the SEQ law,
eq. 16, `laws.py`) and the same LGL collocation handed to IPOPT as a general NLP, which must
agree with the SEQ law; and the deferred re-propagation check every method shares."""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...context import SolveContext
from ...dynamics.tschauner_hempel import th_rhs, true_anomaly_clock
from ...dynamics.two_body import propagate_relative
from ...lgl import lgl_differentiation, lgl_nodes, lgl_weights
from ...nlp.cache import built_once
from ...nlp.casadi_nlp import NLP, status_of
from ...problem import Method, Param
from ...solution import Iterate, Quantity, Series, Solution, WarmStart
from ...verify import repropagate
from .laws import LawResult, boundary_vector, evaluate_law, plan, solve_law
from .model import (
    CONTROL_UNITS,
    CONTROLS,
    STATE_UNITS,
    STATES,
    Case,
    gramian_cost,
    linear_function,
    polynomial,
)
from .problem import COST_LABEL, COST_UNIT, PAPER, quantities

NODES = (8, 64, 128)
NLP_KIND = "lgl-nlp"
METHODS = (
    Method(
        "stm-law", "STM law (closed form, eq. 10)", PAPER,
        "Yamanaka–Ankersen STM maps the control at the LGL nodes to the final state by LGL "
        "quadrature; Lagrange multipliers give the node controls in closed form. Only the "
        "initial and final states constrain the control.",
        nodes=NODES, nodes_label="LGL degree N",
    ),
    Method(
        "seq-law", "SEQ law (collocation + KKT, eq. 16)", PAPER,
        "The TH state equations are collocated at all N+1 LGL nodes, the boundary states "
        "are fixed and the equality-constrained QP is solved from its KKT system.",
        nodes=NODES, nodes_label="LGL degree N",
        params=(
            Param("variable", "independent variable", "", 0, 0, 1, 1, group="Method",
                  options=("true anomaly f (paper)", "time t"),
                  help="Time as independent variable needs more nodes for e = 0.3 over "
                       "three revolutions: the perigee passes are short in time."),
        ),
    ),
    Method(
        NLP_KIND, "LGL collocation as a general NLP (IPOPT)", "paper 001, solved by IPOPT",
        "The same collocation as the SEQ law written as an NLP (states and controls at the "
        "nodes, defects as constraints) and solved by IPOPT: it must agree with the SEQ law.",
        nodes=NODES, nodes_label="LGL degree N", backends=("ipopt",),
    ),
)

LAW_OF_METHOD = {"stm-law": "stm-f", "seq-law": "seq-f", NLP_KIND: "seq-f"}


def solve_method(case: Case, values: dict[str, float], method: Method, nodes: int, *,
                 backend: str, warm: Solution | None, ctx: SolveContext) -> Solution:
    """One of the three methods on a checked case; the re-propagation check deferred."""
    if method.key == NLP_KIND:
        sol, res = _solve_nlp(case, values, nodes, backend, warm, ctx)
    else:
        law = "seq-t" if method.key == "seq-law" and values["variable"] == 1 else \
            LAW_OF_METHOD[method.key]
        res = solve_law(case, law, nodes)
        sol = _solution(case, values, res, method=method.key, nodes=nodes, backend=backend,
                        status="optimal", message="closed form")
        # No iteration count: a closed form has none ("0 iterations" on the status line
        # read as a solver that did not run).
        sol.stats.update(nlp_variables=res.plan.n_unknowns, nlp_constraints=res.plan.n_equations)
    sol.checker = lambda: check(sol, case, res)
    return sol


def _solution(case: Case, values: dict[str, float], res: LawResult, *, method: str,
              nodes: int, backend: str, status: str, message: str) -> Solution:
    """The numeric record of a law's result (SI, LVLH)."""
    return Solution(
        mission="elliptic-transfer", method=method, nodes=nodes, backend=backend,
        status=status, message=message, cost=Quantity(res.J, COST_LABEL, COST_UNIT),
        values=values, quantities=quantities(case, res), state_names=STATES,
        state_units=STATE_UNITS, control_names=CONTROLS, control_units=CONTROL_UNITS,
        node_t=res.t_nodes, node_x=res.X, node_u=res.U, arcs=[(0.0, case.duration, "burn")],
        t=res.t, x=res.Xd, u=res.Ud,
        # The control is the LGL polynomial in the law's variable: in time only for "t".
        control_interpolation="polynomial" if res.plan.variable == "t" else "dense",
    )


@built_once
def lgl_nlp(N: int, backend: str) -> NLP:
    """The SEQ collocation as an NLP in variables (X, U) at the nodes, built once per N.

    Parameters p = (e, f0, fT, X_0, X_N) with boundary states divided by a scale so the
    variables are O(1). Cost: paper eq. 8 (without the constant k^8).
    """
    tau, w, D = lgl_nodes(N), lgl_weights(N), lgl_differentiation(N)
    X = ca.MX.sym("X", 6, N + 1)
    U = ca.MX.sym("U", 3, N + 1)
    p = ca.MX.sym("p", 15)
    e, f0, fT = p[0], p[1], p[2]
    f = f0 + 0.5 * (ca.DM(tau).T + 1) * (fT - f0)
    defects = ca.mtimes(X, ca.DM(D).T) * (2 / (fT - f0)) - th_rhs(X, U, f, e)
    rho = 1 + e * ca.cos(f)
    cost = 0.25 * (fT - f0) * ca.dot(ca.DM(w).T / rho**2, ca.sum1(U**2))
    g = ca.vertcat(ca.vec(defects), X[:, 0] - p[3:9], X[:, N] - p[9:15])
    return NLP(ca.vertcat(ca.vec(X), ca.vec(U)), cost, g, p, backend, name=f"lgl_nlp_{N}")


def _solve_nlp(case: Case, values: dict[str, float], N: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> tuple[Solution, LawResult]:
    """IPOPT on the SEQ collocation; restarts from the same NLP's optimum (rescaled to the
    new boundary states) or from states linear between the boundary states."""
    p_plan = plan("seq-f", N, case.orbit.e, case.f0, case.fT)
    b = boundary_vector(case, p_plan)
    scale = max(float(np.max(np.abs(b))), 1.0)
    nlp = lgl_nlp(N, backend)
    params = np.concatenate([[case.orbit.e, case.f0, case.fT], b / scale])
    start = warm.warm if warm is not None and warm.converged else None
    lam_x0 = lam_g0 = None
    if (start is not None and start.kind == NLP_KIND and start.n_intervals == N
            and len(start.z) == nlp.n_x):
        ratio = start.data["scale"] / scale
        x0, lam_x0, lam_g0 = start.z * ratio, start.lam_x * ratio, start.lam_g * ratio
    else:
        alpha = 0.5 * (lgl_nodes(N) + 1.0)
        Xg = np.outer(b[:6], 1 - alpha) + np.outer(b[6:], alpha)
        x0 = np.concatenate([Xg.T.ravel() / scale, np.zeros(3 * (N + 1))])
    zeros_g = np.zeros(nlp.n_g)
    inf = np.full(nlp.n_x, np.inf)
    out = nlp.solve(x0, params, -inf, inf, zeros_g, zeros_g, lam_x0, lam_g0, ctx)
    status, message = status_of(out)
    nx = 6 * (N + 1)

    def unpack(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return (z[:nx].reshape(N + 1, 6) * scale, z[nx:].reshape(N + 1, 3) * scale)

    res = evaluate_law(case, p_plan, *unpack(out.x))
    sol = _solution(case, values, res, method=NLP_KIND, nodes=N, backend=backend,
                    status=status, message=message)
    sol.stats.update(iterations=out.iterations, nlp_variables=nlp.n_x, nlp_constraints=nlp.n_g,
                     constraint_violation=out.max_violation)
    sol.history = [Iterate(k, res.t_nodes, case.orbit.from_scaled(p_plan.f_nodes, unpack(z)[0]))
                   for k, z in out.history]
    sol.warm = WarmStart(NLP_KIND, N, (res.t_nodes - res.t_nodes[0]) / case.duration, res.X,
                         res.U, case.duration, z=out.x, lam_x=out.lam_x, lam_g=out.lam_g,
                         data={"scale": scale})
    return sol, res


def check(sol: Solution, case: Case, res: LawResult) -> dict[str, float]:
    """Re-propagate the law's control (its LGL polynomial) through the time-domain linear
    model and the nonlinear two-body model; compare J with the Gramian's. Adds the misses
    as quantities and the nonlinear trajectory as the reference "nonlinear model"."""
    o = case.orbit
    p = res.plan
    u_of_s = polynomial(p.s_nodes, res.U)
    s_of_t = true_anomaly_clock(o.e, o.n, case.f0) if p.variable == "f" else \
        (lambda t: o.n * t)
    x0 = np.concatenate([case.x0, [case.f0]])
    control_lin = (lambda t, x: u_of_s(x[6])) if p.variable == "f" else \
        (lambda t, x: u_of_s(o.n * t))
    _, X_lin = repropagate(linear_function(), np.array([o.e, o.k2]), x0, control_lin,
                           res.t_nodes, atol=np.array([1e-6] * 3 + [1e-9] * 3 + [1e-12]))
    r_t0, v_t0 = case.target_state(case.f0)
    t_nl, X_nl, _ = propagate_relative(r_t0, v_t0, case.x0, lambda t: u_of_s(s_of_t(t)),
                                       res.t_nodes, o.mu, samples_per_piece=3)
    miss_lin, miss_nl = X_lin[-1, :6] - case.xT, X_nl[-1] - case.xT
    J_gram = gramian_cost(case)
    out = {
        "position_m": float(np.linalg.norm(miss_lin[:3])),
        "velocity_m_s": float(np.linalg.norm(miss_lin[3:])),
        "nonlinear_position_m": float(np.linalg.norm(miss_nl[:3])),
        "nonlinear_velocity_m_s": float(np.linalg.norm(miss_nl[3:])),
        "J_gramian_m2_s3": J_gram,
        # J - J_gram relative to J_gram (absolute when the transfer needs no control).
        "J_relative_difference": (res.J - J_gram) / J_gram if J_gram > 0 else res.J,
    }
    sol.quantities.update(
        linear_miss_position=Quantity(out["position_m"], "linear-model miss", "m"),
        linear_miss_velocity=Quantity(out["velocity_m_s"], "linear-model miss", "m/s"),
        nonlinear_miss_position=Quantity(out["nonlinear_position_m"],
                                         "nonlinear-model miss", "m"),
        nonlinear_miss_velocity=Quantity(out["nonlinear_velocity_m_s"],
                                         "nonlinear-model miss", "m/s"),
        J_gramian=Quantity(J_gram, "J (Gramian, exact)", "m^2/s^3"),
    )
    sol.references["nonlinear model"] = Series(t_nl, X_nl, STATES, STATE_UNITS)
    return out
