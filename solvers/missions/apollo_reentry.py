"""Mission `apollo-reentry`: Stoer & Bulirsch's Apollo-type lifting reentry with minimum
convective heating (paper 004, example 2; SPEC M5 case 2).

The model stays in its published units (1e5 ft, s; `solvers/dynamics/reentry.py`) inside the
NLP, so the cost J is the number the paper prints; states, plots and the scene are converted
to SI here. An indirect multiple-shooting solution (`solvers/indirect/reentry.py`) is the
independent reference quoted in the help and checked by the tests.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ..dynamics import reentry as model
from ..indirect.reentry import ReentryExtremal, solve_indirect
from ..mission import Infeasible, Mission, SolveContext
from ..nlp.casadi_nlp import built_once
from ..ocp import OCP, Bounds, Guess, OCPResult
from ..problem import Method, Param, Preset, Published
from ..solution import Body, ColorBy, Marker, PlotSeries, Quantity, Scene, Solution
from ..transcription import direct_transcription
from ..transcription.direct import DirectTranscription
from ..verify import repropagate

DEG = np.pi / 180
G0 = 9.80665  # m/s^2, only to express decelerations in g
PAPER = "Wang, Cui & Hou 1988, Northwestern Polytechnical University (paper 004)"
LU = model.LENGTH_UNIT  # m per 1e5 ft
R_EARTH = model.R * LU  # m (R = 209e5 ft)
COST_UNIT = "(S&B units)"
# RK4 steps of about 3 s for multiple shooting whatever the node count (T is about 225 s).
RK4_STEPS_PER_RUN = 80

# OCP parameters, model units: boundary values, guesses, bounds.
(P_V0, P_G0, P_XI0, P_VF, P_GF, P_XIF, P_TG, P_UG, P_VLB, P_VUB, P_GLB, P_GUB, P_XIUB,
 P_UMAX, P_TLB, P_TUB) = range(16)
N_PARAMS = 16

PARAMS = (
    Param("v0", "entry speed v(0)", "m/s", 0.36 * LU, 6000.0, 12000.0, 10.0,
          group="Boundary values", display_unit="km/s", display_factor=1e-3,
          help="S&B: 0.36e5 ft/s."),
    Param("gamma0", "entry flight-path angle γ(0)", "rad", -8.1 * DEG, -20 * DEG, -1 * DEG,
          0.1 * DEG, group="Boundary values", display_unit="deg", display_factor=1 / DEG),
    Param("h0", "entry altitude h(0)", "m", 4.0 * LU, 60e3, 180e3, 100.0,
          group="Boundary values", display_unit="km", display_factor=1e-3,
          help="S&B: 4e5 ft (ξ(0) = 4/R)."),
    Param("vf", "final speed v(T)", "m/s", 0.27 * LU, 4000.0, 12000.0, 10.0,
          group="Boundary values", display_unit="km/s", display_factor=1e-3),
    Param("gammaf", "final flight-path angle γ(T)", "rad", 0.0, -10 * DEG, 10 * DEG,
          0.1 * DEG, group="Boundary values", display_unit="deg", display_factor=1 / DEG),
    Param("hf", "final altitude h(T)", "m", 2.5 * LU, 30e3, 180e3, 100.0,
          group="Boundary values", display_unit="km", display_factor=1e-3,
          help="S&B: 2.5e5 ft."),
    Param("u_max", "control bound |u| ≤", "rad", np.pi / 2, 10 * DEG, np.pi / 2, DEG,
          group="Bounds", display_unit="deg", display_factor=1 / DEG),
    Param("T_min", "final time ≥", "s", 200.0, 10.0, 1000.0, 1.0, group="Bounds"),
    Param("T_max", "final time ≤", "s", 500.0, 50.0, 2000.0, 1.0, group="Bounds"),
    Param("v_min", "speed ≥", "m/s", 0.1 * LU, 100.0, 8000.0, 10.0, group="Bounds",
          display_unit="km/s", display_factor=1e-3),
    Param("v_max", "speed ≤", "m/s", 0.5 * LU, 8000.0, 20000.0, 10.0, group="Bounds",
          display_unit="km/s", display_factor=1e-3),
    Param("gamma_min", "flight-path angle ≥", "rad", -0.2, -0.5, 0.0, 0.001, group="Bounds",
          display_unit="deg", display_factor=1 / DEG),
    Param("gamma_max", "flight-path angle ≤", "rad", 0.1, 0.0, 0.5, 0.001, group="Bounds",
          display_unit="deg", display_factor=1 / DEG),
    Param("h_max", "altitude ≤", "m", 0.03 * model.R * LU, 100e3, 400e3, 100.0,
          group="Bounds", display_unit="km", display_factor=1e-3,
          help="Paper: ξ ≤ 0.03 (and ξ ≥ 0)."),
    Param("T_guess", "initial guess T", "s", 230.0, 50.0, 1000.0, 1.0, group="Initial guess",
          help="Paper: 230 s; the paper found its method sensitive to this guess only."),
    Param("u_guess", "initial guess u (constant)", "rad", 0.0, -np.pi / 2, np.pi / 2, DEG,
          group="Initial guess", display_unit="deg", display_factor=1 / DEG),
    Param("exaggerate", "exaggerate altitude", "×", 20.0, 1.0, 100.0, 1.0, group="Display",
          help="Display only: altitudes are drawn this many times higher so the path "
               "stands off the Earth."),
)

METHODS = (
    Method(
        "multiple-shooting", "Direct multiple shooting (paper 004)", PAPER,
        "τ ∈ [0, 1], t = Tτ; control linear between nodes; RK4 (steps of about 3 s) on each "
        "interval; the heat load rides along as a state (the paper's Mayer form). IPOPT is "
        "the default: CasADi's SQP with a BFGS Hessian (the paper's kind of solver) leaves "
        "the atmosphere from the paper's guess and stalls even when started at the optimum.",
        nodes=(4, 20, 60), nodes_label="intervals", backends=("ipopt", "sqp"),
    ),
    Method(
        "hermite-simpson", "Hermite–Simpson collocation", "direct collocation",
        "Cubic Hermite state, control linear between nodes, Simpson quadrature of the heat "
        "load.",
        nodes=(4, 40, 300), nodes_label="intervals", backends=("ipopt",),
    ),
    Method(
        "lgl", "LGL pseudospectral collocation", "paper 001's LGL nodes",
        "One polynomial through N+1 LGL nodes; the sharp dip into the dense air needs about "
        "40 nodes for 0.01 % (a global polynomial's weak spot).",
        nodes=(10, 40, 80), nodes_label="LGL degree", backends=("ipopt",),
    ),
)

PUBLISHED = (
    Published("J", 2.4967e-2, COST_UNIT, "paper 004, example 2 (10 nodes, 20 iterations)",
              "not reproduced: with S&B's constants the optimum is J = 2.7782e-2"),
    Published("T", 226.3, "s", "paper 004, example 2"),
    Published("J", 2.53e-2, COST_UNIT, "paper 004, example 2, u fixed at 1.5 on τ ∈ [0, 0.1]"),
)

HELP = """\
**Apollo-type lifting reentry with minimum heating** (paper 004, example 2; Stoer &
Bulirsch §7.3.7). The capsule enters at 0.36e5 ft/s (11.0 km/s), γ = −8.1°, 4e5 ft
(121.9 km) and must leave the manoeuvre at 0.27e5 ft/s, γ = 0, 2.5e5 ft (76.2 km), steering
its trim angle u (C_D = 1.174 − 0.9 cos u, C_L = 0.6 sin u) to minimise the convective heat
load J = ∫ 10 v³ √ρ dt. The model and J are in S&B's units (1e5 ft, s); everything shown
is in SI except J, reported "(S&B units)" as the paper does.

*Our optimum, two independent ways:* J = 2.77824e-2, T = 224.901 s. Indirect multiple
shooting on the maximum principle (u* from tan u = 0.6 λγ / (0.9 v λv), `solvers/indirect/
reentry.py`) gives J = 2.7782409e-2, T = 224.90076 s; Hermite–Simpson with 160 intervals agrees to
3e-7 and LGL with 60 nodes to 2e-6. At their default node counts all three methods
agree within 0.05 % (multiple shooting 20 intervals, Hermite–Simpson 40, LGL 40). The paper's
10 intervals give J about 1 % high.

*The paper's numbers:* J = 2.4967e-2, T = 226.3 s. Our J is 11.3 % higher and our T 0.6 %
shorter. A direct method with an accurate integrator can only land *above* the true minimum,
so a J this far below ours means a different problem, not a better solution: the paper
states that it omits its constants ("有关参数值略"), and its scan garbles the boundary values
(v(0) reads 0.11), so we use S&B's constants (R = 209, β = 4.26, ρ0 = 2.704e-3,
g = 3.2172e-4, S/m = 53200) as in public teaching codes. The paper's own variant with u
fixed at 1.5 on the first tenth gives 2.53e-2, also below our unrestricted optimum, which
supports a difference in the model or its constants rather than in the method.

*Entry angle:* the heat load rises steeply with a steeper entry (J = 2.68e-2 at −8.0°,
2.95e-2 at −8.2°); from about −8.25° on, even full lift (C_L = 0.6) cannot pull the capsule
out to the end state and every method reports the request infeasible. Shallower than about
−7°, the trim angle saturates at ±90° and the methods may stop at different local optima.
LGL is the fragile one from the paper's cold guess (it fails at −8.0°, or from T guesses of
200 or 260 s); started from a neighbouring solution (a slider move) it converges.

The Earth is drawn to scale with the path's altitude exaggerated (Display group); arrows
show the direction of the aerodynamic force (drag back, lift up for u > 0) relative to the
drawn path at the nodes.
"""


@cache
def _ocp() -> OCP:
    def bounds(p):
        return Bounds(
            x_lb=np.array([p[P_VLB], p[P_GLB], 0.0]),
            x_ub=np.array([p[P_VUB], p[P_GUB], p[P_XIUB]]),
            u_lb=np.array([-p[P_UMAX]]),
            u_ub=np.array([p[P_UMAX]]),
            T_lb=float(p[P_TLB]),
            T_ub=float(p[P_TUB]),
        )

    def guess(p):
        return Guess(x_final=np.asarray(p[P_VF : P_XIF + 1]), u=np.array([p[P_UG]]),
                     T=float(p[P_TG]))

    return OCP(
        states=("v", "gamma", "xi"),
        controls=("u",),
        n_params=N_PARAMS,
        dynamics=lambda x, u, p: model.rhs(x, u[0]),
        initial_state=lambda p: p[P_V0 : P_XI0 + 1],
        terminal=lambda xf, p: xf - p[P_VF : P_XIF + 1],
        bounds=bounds,
        guess=guess,
        x_scale=np.array([0.1, 0.1, 0.01]),
        u_scale=np.ones(1),
        T_scale=100.0,
        terminal_scale=np.array([0.01, 0.01, 0.001]),
        lagrange=lambda x, u, p: model.heating_rate(x),
        cost_scale=0.01,
    )


def _transcription(kind: str, n: int, backend: str) -> DirectTranscription:
    if kind == "multiple-shooting":
        substeps = max(2, -(-RK4_STEPS_PER_RUN // n))
        return direct_transcription(kind, _ocp(), n, backend, substeps=substeps)
    return direct_transcription(kind, _ocp(), n, backend)


@built_once
def _augmented() -> ca.Function:
    """(x, heat)' = (f, L) for re-propagating the heat load with the state."""
    x = ca.SX.sym("x", 4)
    u = ca.SX.sym("u", 1)
    p = ca.SX.sym("p", N_PARAMS)
    return ca.Function("reentry_aug", [x, u, p],
                       [ca.vertcat(model.rhs(x[:3], u[0]), model.heating_rate(x[:3]))])


class ApolloReentry(Mission):
    key = "apollo-reentry"
    title = "Apollo reentry, minimum heating"
    summary = "Steer the lift of an Apollo-type capsule to minimise the convective heat load."
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "heat load J"
    cost_unit = COST_UNIT
    equations = (
        ("Apollo-type reentry (Stoer & Bulirsch; paper 004, example 2)",
         r"\dot v = -\frac{S\rho v^2 C_D(u)}{2m} - \frac{g\sin\gamma}{(1+\xi)^2},\quad "
         r"\dot\gamma = \frac{S\rho v C_L(u)}{2m} + \frac{v\cos\gamma}{R(1+\xi)} - "
         r"\frac{g\cos\gamma}{v(1+\xi)^2},\quad \dot\xi = \frac{v\sin\gamma}{R}"),
        ("Atmosphere, aerodynamics and the heating cost",
         r"\rho = \rho_0 e^{-\beta R\xi},\quad C_D = 1.174 - 0.9\cos u,\quad C_L = 0.6\sin u,"
         r"\qquad J = \int_0^T 10\, v^3\sqrt{\rho}\, dt"),
    )
    presets = (
        Preset("Paper 004 case: multiple shooting, 10 intervals", {},
               method="multiple-shooting", nodes=10,
               note="The paper's mesh: J about 1 % above the converged optimum."),
        Preset("Reference: Hermite–Simpson, 160 intervals", {}, method="hermite-simpson",
               nodes=160, note="Agrees with the indirect solution to 1e-6."),
        Preset("Reference: LGL, 60 nodes", {}, method="lgl", nodes=60),
        Preset("Shallower entry, γ(0) = −6.5°", {"gamma0": -6.5 * DEG},
               note="Bornemann's exercise. The trim angle saturates at ±90°: the optimum is "
                    "no longer smooth and the methods stop at different local optima."),
        Preset("Steepest feasible entry, γ(0) = −8.2°", {"gamma0": -8.2 * DEG},
               note="About −8.25° and steeper cannot reach the end state: infeasible."),
        Preset("Lift limited, |u| ≤ 60°", {"u_max": 60 * DEG}),
    )

    @staticmethod
    def parameter_vector(values: dict[str, float]) -> np.ndarray:
        """OCP parameters in the model's units (1e5 ft, s) from SI values."""
        xi = 1.0 / (model.R * LU)
        return np.array([
            values["v0"] / LU, values["gamma0"], values["h0"] * xi,
            values["vf"] / LU, values["gammaf"], values["hf"] * xi,
            values["T_guess"], values["u_guess"],
            values["v_min"] / LU, values["v_max"] / LU, values["gamma_min"],
            values["gamma_max"], values["h_max"] * xi, values["u_max"],
            values["T_min"], values["T_max"],
        ])

    def check_values(self, values: dict[str, float]) -> None:
        for lo, hi in (("v_min", "v_max"), ("gamma_min", "gamma_max"), ("T_min", "T_max")):
            if values[lo] >= values[hi]:
                raise ValueError(f"bound {lo} = {values[lo]:g} is not below {hi} = "
                                 f"{values[hi]:g}")

    def _solve(
        self, values: dict[str, float], method: Method, nodes: int, backend: str,
        warm: Solution | None, ctx: SolveContext,
    ) -> Solution:
        p = self.parameter_vector(values)
        _precheck(values)
        transcription = _transcription(method.key, nodes, backend)
        start = warm.warm if warm is not None and warm.ok else None
        res = transcription.solve(p, start, ctx)
        sol = self._record(values, method.key, nodes, backend, res)
        res.record_nlp(sol)
        if res.status == "optimal":
            sol.checker = lambda: _check(p, method.key, res)
        return sol

    def _record(
        self, values: dict[str, float], method: str, nodes: int, backend: str, res: OCPResult,
    ) -> Solution:
        t, X, U = res.t_dense, res.X_dense, res.U_dense[:, 0]
        Xs, Xns = _to_si(X), _to_si(res.X)
        # A diverged iterate (e.g. SQP leaving the atmosphere) may overflow exp(-beta R xi).
        with np.errstate(over="ignore", invalid="ignore"):
            heating = model.heating_rate(X)
            decel = _deceleration(X, U)
            theta = _downrange(t, X)
        theta_nodes = np.interp(res.t_nodes, t, theta)
        quantities = {
            "T": Quantity(res.T, "final time", "s"),
            "J": Quantity(res.cost, "heat load J", COST_UNIT),
            "peak_heating": Quantity(float(heating.max()), "peak heating rate 10 v³√ρ",
                                     COST_UNIT + "/s"),
            "peak_deceleration": Quantity(float(decel.max()), "peak deceleration", "m/s²"),
            "min_altitude": Quantity(float(Xs[:, 2].min()), "lowest altitude", "m"),
            "downrange": Quantity(float(theta[-1] * R_EARTH), "downrange", "m"),
        }
        sol = Solution(
            mission=self.key, method=method, nodes=nodes, backend=backend, status=res.status,
            message=res.message, cost=Quantity(res.cost, "heat load J", COST_UNIT),
            values=values, quantities=quantities, state_names=model.STATES,
            state_units=model.STATE_UNITS, control_names=("u",), control_units=("rad",),
            node_t=res.t_nodes, node_x=Xns, node_u=res.U, arcs=[(0.0, res.T, "coast")],
            t=t, x=Xs, u=res.U_dense,
        )
        k = values["exaggerate"]
        sol.positions = _display(theta, X[:, 2], k)
        sol.node_positions = _display(theta_nodes, res.X[:, 2], k)
        sol.thrust = _force_arrows(sol.node_positions, res.X, res.U[:, 0], theta_nodes, k)
        sol.history = []
        for it, tk, Xk in res.history:
            sol.history.append({"iteration": it,
                                "positions": _display(_downrange(tk, Xk), Xk[:, 2], k)})
        sol.scene = _scene(sol.positions)
        sol.plots = _plots(t, Xs, U, heating, decel, res.t_nodes, Xns, res.U[:, 0])
        sol.color_by = ColorBy("heating rate 10 v³√ρ", COST_UNIT + "/s", heating)
        return sol


def _precheck(values: dict[str, float]) -> None:
    """Boundary values outside the state bounds make the request impossible."""
    checks = (("v0", "v_min", "v_max"), ("vf", "v_min", "v_max"),
              ("gamma0", "gamma_min", "gamma_max"), ("gammaf", "gamma_min", "gamma_max"))
    for key, lo, hi in checks:
        if not values[lo] <= values[key] <= values[hi]:
            raise Infeasible(f"{key} = {values[key]:g} lies outside the bounds "
                             f"[{values[lo]:g}, {values[hi]:g}] ({lo}, {hi})")
    for key in ("h0", "hf"):
        if values[key] > values["h_max"]:
            raise Infeasible(f"{key} = {values[key]:g} m is above h_max = {values['h_max']:g} m")


def _to_si(X: np.ndarray) -> np.ndarray:
    """(v, gamma, xi) in model units to (v [m/s], gamma [rad], h [m])."""
    return np.column_stack([X[:, 0] * LU, X[:, 1], X[:, 2] * model.R * LU])


def _deceleration(X: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Drag deceleration (S/m) rho v^2 C_D / 2 in m/s^2."""
    rho = model.RHO0 * np.exp(-model.BETA * model.R * X[:, 2])
    cd = model.C1 - model.C2 * np.cos(u)
    return model.S_OVER_M * rho * X[:, 0] ** 2 * cd / 2 * LU


def _downrange(t: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Central angle travelled, ∫ v cos(gamma) / (R (1 + xi)) dt (trapezoid on samples)."""
    rate = model.downrange_rate(X)
    return np.concatenate([[0.0], np.cumsum(np.diff(t) * (rate[1:] + rate[:-1]) / 2)])


def _display(theta: np.ndarray, xi: np.ndarray, k: float) -> np.ndarray:
    """Earth-centred display frame (m), path in the z = 0 plane, altitude exaggerated k×."""
    r = R_EARTH * (1 + k * np.asarray(xi))
    return np.column_stack([r * np.cos(theta), r * np.sin(theta), np.zeros_like(r)])


def _force_arrows(P: np.ndarray, X: np.ndarray, u: np.ndarray, theta: np.ndarray,
                  k: float) -> np.ndarray:
    """Unit arrows along the aerodynamic force C_D (-v^) + C_L n^, with v^ the tangent of
    the *drawn* (exaggerated) path so the arrows read correctly against it."""
    gamma_drawn = np.arctan2(k * R_EARTH * (1 + X[:, 2]) * np.sin(X[:, 1]),
                             np.linalg.norm(P, axis=1) * np.cos(X[:, 1]))
    e_r = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    e_t = np.column_stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)])
    v_hat = np.cos(gamma_drawn)[:, None] * e_t + np.sin(gamma_drawn)[:, None] * e_r
    n_hat = -np.sin(gamma_drawn)[:, None] * e_t + np.cos(gamma_drawn)[:, None] * e_r
    cd = model.C1 - model.C2 * np.cos(u)
    cl = model.C3 * np.sin(u)
    force = -cd[:, None] * v_hat + cl[:, None] * n_hat
    return force / np.linalg.norm(force, axis=1, keepdims=True)


def _scene(positions: np.ndarray) -> Scene:
    return Scene(
        frame="Earth-centred, entry plane (altitude exaggerated)",
        display_unit="km",
        display_scale=1e-3,
        bodies=[Body("Earth", (0.0, 0.0, 0.0), R_EARTH, (70, 110, 190))],
        markers=[Marker("entry", tuple(positions[0]), (255, 200, 80)),
                 Marker("end of manoeuvre", tuple(positions[-1]), (120, 255, 120))],
    )


def _plots(t, Xs, u, heating, decel, t_nodes, Xns, u_nodes) -> list[PlotSeries]:
    heat_nodes = np.interp(t_nodes, t, heating)
    return [
        PlotSeries("speed v", "km/s", t, Xs[:, 0] / 1e3, t_nodes, Xns[:, 0] / 1e3),
        PlotSeries("flight-path angle γ", "deg", t, Xs[:, 1] / DEG, t_nodes, Xns[:, 1] / DEG),
        PlotSeries("altitude", "km", t, Xs[:, 2] / 1e3, t_nodes, Xns[:, 2] / 1e3),
        PlotSeries("trim angle u", "deg", t, u / DEG, t_nodes, u_nodes / DEG, group="control"),
        PlotSeries("heating rate 10 v³√ρ", COST_UNIT + "/s", t, heating, t_nodes, heat_nodes,
                   group="output"),
        PlotSeries("deceleration", "g", t, decel / G0, group="output"),
    ]


def _check(p: np.ndarray, method: str, res: OCPResult) -> dict[str, float]:
    """Re-propagate the method's own control (linear between nodes, or the LGL polynomial)
    with DOP853 together with the heat load; terminal miss in SI and the J mismatch."""
    x0 = np.concatenate([p[P_V0 : P_XI0 + 1], [0.0]])
    _, X = repropagate(_augmented(), p, x0, res.control, res.t_nodes,
                       atol=np.array([1e-12, 1e-12, 1e-14, 1e-14]))
    miss = X[-1, :3] - p[P_VF : P_XIF + 1]
    return {
        "speed_miss_m_s": float(miss[0] * LU),
        "gamma_miss_rad": float(miss[1]),
        "altitude_miss_m": float(miss[2] * model.R * LU),
        "J_repropagated_rel_error": float(X[-1, 3] / res.cost - 1),
    }


def indirect_solution(sol: Solution, n_segments: int = 10) -> ReentryExtremal:
    """The maximum-principle extremal started from a direct solution of this mission (its
    dense SI samples converted back to the model's units); J and T in S&B units and s."""
    p = ApolloReentry.parameter_vector(sol.values)
    X = np.column_stack([sol.x[:, 0] / LU, sol.x[:, 1], sol.x[:, 2] / (model.R * LU)])
    return solve_indirect(sol.t, X, sol.u[:, 0], p[P_V0 : P_XI0 + 1], p[P_VF : P_XIF + 1],
                          n_segments=n_segments)


MISSION = ApolloReentry()
