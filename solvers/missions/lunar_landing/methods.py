"""The paper's own method for the lunar landing (paper 002): the integral transformation
solved by the generalised multiplier method with BFGS; and the quantities every method
reports."""

from __future__ import annotations

import numpy as np

from ...mission import SolveContext
from ...problem import Method, Param
from ...solution import Iterate, Quantity, Solution, WarmStart
from ...verify import repropagate
from .integral_transform import solve_integral_transform
from .model import MU_MOON, R_MOON, STATE_UNITS, STATES
from .problem import DEG, P_C, P_F, P_M0, P_R0, P_W0, PAPER, ocp, touchdown_miss

PAPER_METHOD = Method(
    "paper", "Integral transform + Adams PC + multiplier method", PAPER,
    "ϖ = -ω as independent variable (free tf becomes a fixed end), ψ linear between N+1 "
    "nodes, 4th-order Adams-Bashforth-Moulton with RK4 start, augmented Lagrangian "
    "(generalised multiplier method) with a BFGS inner solver; exact gradients by AD.",
    nodes=(4, 30, 120), nodes_label="segments", backends=("multiplier-bfgs",),
    equations=(
        ("Integral transformation: ϖ = -ω as independent variable",
         r"\frac{d\varpi}{dt} = \frac{(F/m)\cos\psi + 2v\omega}{r},\qquad "
         r"\frac{dx}{d\varpi} = \frac{dx/dt}{d\varpi/dt},\qquad "
         r"\frac{dt}{d\varpi} = \left(\frac{d\varpi}{dt}\right)^{-1}"),
        ("Generalised multiplier method (augmented Lagrangian)",
         r"L(\psi) = J - \lambda^T h + \frac{\sigma}{2}\lVert h\rVert^2,\qquad "
         r"\lambda \leftarrow \lambda - \sigma h"),
    ),
    params=(
        Param("sigma0", "initial penalty factor σ", "", 20.0, 0.001, 1000.0, 0.001,
              group="Method", help="Paper: 20. Smaller σ widens the region of convergence.",
              guess=True),
        Param("psi_guess", "initial guess ψ (constant)", "rad", 0.0, -80 * DEG, 85 * DEG,
              DEG, group="Method", display_unit="deg", display_factor=1 / DEG, guess=True),
    ),
)


def landing_quantities(p: np.ndarray, t_nodes: np.ndarray, X: np.ndarray
                       ) -> dict[str, Quantity]:
    """Final time, fuel, the end state's altitude and speed, downrange (SI)."""
    r_f, v_f, theta_f, w_f, _ = X[-1]
    return {
        "tf": Quantity(float(t_nodes[-1]), "final time", "s"),
        "fuel": Quantity(float(p[P_M0] - X[-1, 4]), "fuel", "kg"),
        "final_altitude": Quantity(float(r_f - R_MOON), "final altitude", "m"),
        "final_speed": Quantity(float(np.hypot(v_f, r_f * w_f)), "final speed", "m/s"),
        "downrange": Quantity(float(R_MOON * theta_f), "downrange", "m"),
    }


def solve_paper(values: dict[str, float], p: np.ndarray, nodes: int, warm: Solution | None,
                ctx: SolveContext) -> Solution:
    """Paper 002's method; warm-started from a previous paper solution's ψ nodes."""
    warm_psi = None
    if warm is not None and warm.ok and warm.warm is not None and warm.warm.kind == "paper":
        warm_psi = warm.warm.U[:, 0]
    res = solve_integral_transform(
        r0=p[P_R0], omega0=p[P_W0], m0=p[P_M0], thrust=p[P_F], exhaust_speed=p[P_C],
        mu=MU_MOON, radius=R_MOON, n_segments=nodes, sigma0=values["sigma0"],
        psi_guess=values["psi_guess"], warm_psi=warm_psi, ctx=ctx,
    )
    fuel = float(p[P_M0] - res.x_nodes[-1, 4])
    sol = Solution(
        mission="lunar-landing", method="paper", nodes=nodes, backend="multiplier-bfgs",
        status="optimal" if res.converged else "failed", message=res.message,
        cost=Quantity(fuel, "fuel", "kg"), values=values,
        quantities=landing_quantities(p, res.t_nodes, res.x_nodes), state_names=STATES,
        state_units=STATE_UNITS, control_names=("psi",), control_units=("rad",),
        node_t=res.t_nodes, node_x=res.x_nodes, node_u=res.psi_nodes[:, None],
        arcs=[(0.0, float(res.t_nodes[-1]), "burn")], t=res.t_dense, x=res.x_dense,
        u=res.psi_dense[:, None], control_interpolation="dense",
        history=[Iterate(k, tk, xk) for k, tk, xk in res.history],
    )
    sol.stats.update(
        iterations=res.outer_iterations,
        inner_iterations=res.inner_iterations,
        function_evaluations=res.integrations,
        nlp_variables=res.n_variables,
        nlp_constraints=res.n_constraints,
        constraint_violation=res.constraint_violation,
    )
    tau = res.varpi_nodes - res.varpi_nodes[0]
    sol.warm = WarmStart("paper", nodes, tau / tau[-1], res.x_nodes, res.psi_nodes[:, None],
                         float(res.t_nodes[-1]))
    sol.check["max_defect"] = res.constraint_violation
    varpi, psi = res.varpi_nodes, res.psi_nodes
    sol.checker = lambda: check(p, res.t_nodes, lambda t, x: np.array([np.interp(-x[3], varpi,
                                                                                 psi)]))
    return sol


def check(p: np.ndarray, t_nodes: np.ndarray, control) -> dict[str, float]:
    """Re-propagate a control law in time (DOP853); miss of each terminal condition."""
    fn = ocp().functions()
    x0 = np.asarray(fn.x0(p)).ravel()
    _, X = repropagate(fn.f, p, x0, control, t_nodes,
                       atol=np.array([1e-6, 1e-9, 1e-12, 1e-14, 1e-9]))
    return touchdown_miss(X[-1])
