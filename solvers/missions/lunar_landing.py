"""Mission `lunar-landing`: minimum-fuel powered descent from perilune (paper 002, SPEC M3).

Three methods solve the same problem: the paper's integral transformation with an
Adams predictor-corrector and the generalised multiplier method, and two modern direct
transcriptions (Hermite-Simpson collocation, multiple shooting) solved by IPOPT or SQP.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from ..dynamics.lunar import (
    MU_MOON,
    R_MOON,
    STATE_UNITS,
    STATES,
    conic_points,
    descent_rhs,
    perilune_rate,
)
from ..mission import Infeasible, Mission, SolveContext
from ..ocp import OCP, Bounds, Guess
from ..problem import Method, Param, Preset, Published
from ..solution import Body, Curve, Marker, PlotSeries, Quantity, Scene, Solution
from ..transcription import direct_transcription
from ..verify import repropagate

DEG = np.pi / 180
# Parameter vector of the OCP: initial radius, initial angular rate, initial mass, thrust,
# exhaust speed.
P_R0, P_W0, P_M0, P_F, P_C = range(5)

PAPER = "Zhao & Gu 2008, Science & Technology Review 26(20) (paper 002)"

PARAMS = (
    Param("altitude0", "initial altitude (perilune)", "m", 15e3, 1e3, 100e3, 500,
          group="Initial orbit", display_unit="km", display_factor=1e-3,
          help="Altitude above the mean lunar radius where the engine ignites."),
    Param("omega_source", "initial angular rate from", "", 0, 0, 1, 1, group="Initial orbit",
          options=("given ω0", "vis-viva from apolune"),
          help="Use ω0 as given, or compute it as the perilune rate of an orbit whose apolune "
               "altitude is set below."),
    Param("omega0", "initial angular rate ω0", "rad/s", 9.65e-4, 1e-4, 1.4e-3, 1e-6,
          group="Initial orbit", display_unit="mrad/s", display_factor=1e3,
          help="The paper's 9.65e-4 rad/s is the 100 x 15 km perilune rate (9.6522e-4) rounded."),
    Param("apolune_altitude", "apolune altitude", "m", 100e3, 1e3, 2000e3, 1e3,
          group="Initial orbit", display_unit="km", display_factor=1e-3,
          help="Used when ω0 comes from vis-viva."),
    Param("mass0", "initial mass", "kg", 600.0, 50.0, 5000.0, 10.0, group="Vehicle"),
    Param("thrust", "thrust F", "N", 2000.0, 10.0, 20000.0, 10.0, group="Vehicle",
          help="Constant braking thrust (the paper's constant-thrust assumption)."),
    Param("exhaust_speed", "exhaust speed Isp·g0", "m/s", 2940.0, 500.0, 5000.0, 10.0,
          group="Vehicle", help="Isp = 300 s with g0 = 9.8 m/s² gives the paper's 2940 m/s."),
)

METHODS = (
    Method(
        "paper", "Integral transform + Adams PC + multiplier method", PAPER,
        "ϖ = -ω as independent variable (free tf becomes a fixed end), ψ linear between N+1 "
        "nodes, 4th-order Adams-Bashforth-Moulton with RK4 start, augmented Lagrangian "
        "(generalised multiplier method) with a BFGS inner solver; exact gradients by AD.",
        nodes=(4, 30, 120), nodes_label="segments",
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
                  group="Method", help="Paper: 20. Smaller σ widens the region of convergence."),
            Param("psi_guess", "initial guess ψ (constant)", "rad", 0.0, -80 * DEG, 85 * DEG,
                  DEG, group="Method", display_unit="deg", display_factor=1 / DEG),
        ),
    ),
    Method(
        "hermite-simpson", "Hermite-Simpson collocation (IPOPT)", "direct collocation",
        "Time-domain collocation with free final time: cubic Hermite state, linear control, "
        "midpoint defects; the NLP is built once and re-solved warm.",
        nodes=(5, 30, 200), nodes_label="intervals", backends=("ipopt", "sqp"),
        equations=(("Hermite–Simpson defect",
                    r"x_{k+1} - x_k - \frac{h}{6}\left(f_k + 4 f_{k+\frac12} + f_{k+1}\right)"
                    r" = 0"),),
    ),
    Method(
        "multiple-shooting", "Direct multiple shooting (paper 004)", "paper 004",
        "τ ∈ [0, 1] with t = Tτ, T a parameter; control linear between nodes; RK4 on each "
        "interval; continuity of the node states.",
        nodes=(5, 30, 200), nodes_label="intervals", backends=("ipopt", "sqp"),
        equations=(("Continuity of the shooting intervals (paper 004)",
                    r"x\left(S_i, \tau_{i+1}\right) - S_{i+1} = 0,\qquad t = T\tau"),),
    ),
)

PUBLISHED = (
    Published("tf", 398.03868, "s", "paper 002, table 1 (multiplier method)"),
    Published("fuel", 270.77461, "kg", "paper 002, table 1 (multiplier method)"),
    Published("tf", 398.03873, "s", "paper 002, Pontryagin (indirect) reference"),
    Published("fuel", 270.77465, "kg", "paper 002, Pontryagin (indirect) reference"),
)

HELP = """\
**Powered descent from a 100 × 15 km lunar orbit** (paper 002). The engine fires at full
thrust from perilune until the lander touches down with zero radial and horizontal speed;
the only control is the thrust angle ψ above the local horizontal. Fuel is F·tf/c, so the
minimum-fuel descent is the minimum-time one.

*Published (paper 002):* tf = 398.03868 s, fuel = 270.77461 kg (Pontryagin reference
398.03873 s, 270.77465 kg). All three methods here reproduce them to better than 0.01 %.
"""


@cache
def _ocp() -> OCP:
    def dynamics(x, u, p):
        return descent_rhs(x, u[0], p[P_F], p[P_C])

    def initial_state(p):
        return ca.vertcat(p[P_R0], 0, 0, p[P_W0], p[P_M0])

    def terminal(xf, p):
        return ca.vertcat(xf[0] - R_MOON, xf[1], xf[3])

    def bounds(p):
        return Bounds(
            x_lb=np.array([R_MOON, -2e3, -1.0, -0.01, 1.0]),
            x_ub=np.array([R_MOON + 300e3, 2e3, 3.0, 0.01, p[P_M0]]),
            u_lb=np.array([-np.pi / 2]),
            u_ub=np.array([np.pi / 2]),
            T_lb=1.0,
            T_ub=p[P_M0] * p[P_C] / p[P_F],
        )

    def guess(p):
        T = _time_guess(p)
        return Guess(
            x_final=np.array([R_MOON, 0.0, 0.5 * p[P_W0] * T, 0.0, p[P_M0] - p[P_F] * T / p[P_C]]),
            u=np.array([0.0]),
            T=T,
        )

    return OCP(
        states=STATES,
        controls=("psi",),
        n_params=5,
        dynamics=dynamics,
        initial_state=initial_state,
        terminal=terminal,
        bounds=bounds,
        guess=guess,
        x_scale=np.array([1e4, 100.0, 0.1, 1e-3, 100.0]),
        x_offset=np.array([R_MOON, 0.0, 0.0, 0.0, 0.0]),
        u_scale=np.array([1.0]),
        T_scale=100.0,
        terminal_scale=np.array([1e3, 10.0, 1e-4]),
        cost_scale=100.0,
        mayer=lambda xf, T, p: p[P_M0] - xf[4],
    )


def _time_guess(p: np.ndarray) -> float:
    """Burn time to cancel the orbital speed by the rocket equation (a cold-start guess)."""
    dv = 1.05 * p[P_R0] * p[P_W0]
    return float(p[P_M0] * p[P_C] / p[P_F] * (1 - np.exp(-dv / p[P_C])))


class LunarLanding(Mission):
    key = "lunar-landing"
    title = "Lunar soft landing"
    summary = "Minimum-fuel powered descent from a 100 × 15 km orbit to a soft touchdown."
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "fuel"
    cost_unit = "kg"
    equations = (
        ("Equations of motion (paper 002, eq. 1)",
         r"\dot r = v,\quad \dot v = \frac{F}{m}\sin\psi - \frac{\mu}{r^2} + r\omega^2,"
         r"\quad \dot\omega = -\frac{(F/m)\cos\psi + 2v\omega}{r},\quad \dot\theta = \omega,"
         r"\quad \dot m = -\frac{F}{I_{sp} g_0}"),
        ("Cost (eq. 2) and terminal conditions",
         r"J = m(0) - m(t_f) = \frac{F t_f}{I_{sp} g_0},\qquad r(t_f) = R,\ v(t_f) = 0,\ "
         r"\omega(t_f) = 0"),
    )
    presets = (
        Preset("Paper 002 case", {}, note="The published case: tf = 398.039 s, fuel 270.775 kg."),
        Preset("From the 100 × 15 km orbit (vis-viva ω0)", {"omega_source": 1}),
        Preset("Heavy lander, 3 kN", {"mass0": 1200.0, "thrust": 3000.0}),
        Preset("Paper method, bad guess ψ = 60°", {"psi_guess": 60 * DEG}, method="paper"),
        Preset("Paper method, bad guess, small σ", {"psi_guess": 60 * DEG, "sigma0": 0.2},
               method="paper"),
        Preset("Coarse mesh (6 intervals)", {}, method="hermite-simpson", nodes=6),
    )

    def check_values(self, values: dict[str, float]) -> None:
        if values["omega_source"] == 1 and values["apolune_altitude"] < values["altitude0"]:
            raise ValueError(
                f"perilune altitude {values['altitude0'] / 1e3:g} km is above the apolune "
                f"altitude {values['apolune_altitude'] / 1e3:g} km"
            )

    @staticmethod
    def parameter_vector(values: dict[str, float]) -> np.ndarray:
        """The OCP's numeric parameters (SI) from validated mission values."""
        r0 = R_MOON + values["altitude0"]
        if values["omega_source"] == 1:
            omega0 = perilune_rate(r0, R_MOON + values["apolune_altitude"])
        else:
            omega0 = values["omega0"]
        return np.array([r0, omega0, values["mass0"], values["thrust"], values["exhaust_speed"]])

    def _solve(
        self,
        values: dict[str, float],
        method: Method,
        nodes: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        p = self.parameter_vector(values)
        _precheck(p)
        if method.key == "paper":
            return self._solve_paper(values, p, nodes, warm, ctx)
        transcription = direct_transcription(method.key, _ocp(), nodes, backend)
        warm_start = warm.warm if warm is not None and warm.ok else None
        res = transcription.solve(p, warm_start, ctx)
        sol = self._record(values, method.key, nodes, backend, p, res.status, res.message,
                           res.t_nodes, res.X, res.U[:, 0], res.t_dense, res.X_dense,
                           res.U_dense[:, 0], res.history)
        res.record_nlp(sol)
        sol.checker = lambda: self._check(p, res.t_nodes, res.control)
        return sol

    def _solve_paper(
        self, values: dict[str, float], p: np.ndarray, nodes: int, warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        from ..transcription.integral_transform import solve_integral_transform

        warm_psi = None
        if warm is not None and warm.ok and warm.method == "paper":
            warm_psi = warm.warm
        res = solve_integral_transform(
            r0=p[P_R0], omega0=p[P_W0], m0=p[P_M0], thrust=p[P_F], exhaust_speed=p[P_C],
            mu=MU_MOON, radius=R_MOON, n_segments=nodes, sigma0=values["sigma0"],
            psi_guess=values["psi_guess"], warm_psi=warm_psi, ctx=ctx,
        )
        status = "optimal" if res.converged else "failed"
        sol = self._record(values, "paper", nodes, "multiplier-bfgs", p, status, res.message,
                           res.t_nodes, res.x_nodes, res.psi_nodes, res.t_dense, res.x_dense,
                           res.psi_dense, res.history)
        sol.stats.update(
            iterations=res.outer_iterations,
            inner_iterations=res.inner_iterations,
            function_evaluations=res.integrations,
            nlp_variables=res.n_variables,
            nlp_constraints=res.n_constraints,
            constraint_violation=res.constraint_violation,
        )
        sol.warm = res.psi_nodes
        varpi, psi = res.varpi_nodes, res.psi_nodes
        sol.check["max_defect"] = res.constraint_violation
        sol.checker = lambda: self._check(
            p, res.t_nodes, lambda t, x: np.array([np.interp(-x[3], varpi, psi)])
        )
        return sol

    def _check(self, p: np.ndarray, t_nodes: np.ndarray, control) -> dict[str, float]:
        """Re-propagate the method's own control in time; miss of each terminal condition."""
        fn = _ocp().functions()
        x0 = np.asarray(fn.x0(p)).ravel()
        _, X = repropagate(fn.f, p, x0, control, t_nodes,
                           atol=np.array([1e-6, 1e-9, 1e-12, 1e-14, 1e-9]))
        r, v, _, w, _ = X[-1]
        return {
            "altitude_m": r - R_MOON,
            "radial_speed_m_s": v,
            "horizontal_speed_m_s": r * w,
            "speed_m_s": float(np.hypot(v, r * w)),
        }

    def _record(
        self, values, method, nodes, backend, p, status, message, t_nodes, X, psi, t, Xd, psid,
        history,
    ) -> Solution:
        tf = float(t_nodes[-1])
        fuel = float(p[P_M0] - X[-1, 4])
        r_f, v_f, theta_f, w_f, _ = X[-1]
        quantities = {
            "tf": Quantity(tf, "final time", "s"),
            "fuel": Quantity(fuel, "fuel", "kg"),
            "final_altitude": Quantity(float(r_f - R_MOON), "final altitude", "m"),
            "final_speed": Quantity(float(np.hypot(v_f, r_f * w_f)), "final speed", "m/s"),
            "downrange": Quantity(float(R_MOON * theta_f), "downrange", "m"),
        }
        sol = Solution(
            mission=self.key, method=method, nodes=nodes, backend=backend, status=status,
            message=message, cost=Quantity(fuel, "fuel", "kg"), values=values,
            quantities=quantities, state_names=STATES, state_units=STATE_UNITS,
            control_names=("psi",), control_units=("rad",), node_t=t_nodes, node_x=X,
            node_u=psi[:, None], arcs=[(0.0, tf, "burn")], t=t, x=Xd, u=psid[:, None],
        )
        sol.positions = _plane_to_3d(Xd[:, 0], Xd[:, 2])
        sol.node_positions = _plane_to_3d(X[:, 0], X[:, 2])
        sol.thrust = _thrust_directions(X[:, 2], psi)
        sol.history = [
            {"iteration": k, "positions": _plane_to_3d(Xk[:, 0], Xk[:, 2])}
            for k, _, Xk in history
        ]
        sol.scene = _scene(p, sol.positions)
        sol.plots = _plots(t, Xd, psid, t_nodes, X, psi)
        return sol


def _precheck(p: np.ndarray) -> None:
    """Requests that cannot land at all get a clear reason before any solve."""
    accel = p[P_F] / p[P_M0]
    gravity = MU_MOON / p[P_R0] ** 2
    if accel <= gravity:
        raise Infeasible(
            f"thrust-to-weight below 1: F/m0 = {accel:.3f} m/s² does not exceed lunar gravity "
            f"{gravity:.3f} m/s² at ignition, so the lander cannot stop its descent"
        )
    burn_limit = p[P_M0] * p[P_C] / p[P_F]
    if _time_guess(p) > 0.98 * burn_limit:
        raise Infeasible(
            "the propellant cannot cancel the orbital speed: the rocket equation needs more "
            "than the whole initial mass"
        )


def _plane_to_3d(r: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Orbit-plane polar coordinates to the display frame (Moon-centred, plane z = 0)."""
    return np.column_stack([r * np.cos(theta), r * np.sin(theta), np.zeros_like(r)])


def _thrust_directions(theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Braking thrust: up by ψ from the local horizontal, against the motion (+θ)."""
    e_r = np.column_stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)])
    e_t = np.column_stack([-np.sin(theta), np.cos(theta), np.zeros_like(theta)])
    return np.sin(psi)[:, None] * e_r - np.cos(psi)[:, None] * e_t


def _scene(p: np.ndarray, positions: np.ndarray) -> Scene:
    orbit = conic_points(p[P_R0], 0.0, p[P_W0])
    orbit3 = np.column_stack([orbit, np.zeros(len(orbit))])
    landing = tuple(positions[-1]) if len(positions) else (R_MOON, 0.0, 0.0)
    return Scene(
        frame="Moon-centred, descent plane",
        display_unit="km",
        display_scale=1e-3,
        bodies=[Body("Moon", (0.0, 0.0, 0.0), R_MOON, (170, 170, 165))],
        curves=[Curve("descent orbit", orbit3, (120, 160, 255), dashed=True)],
        markers=[
            Marker("ignition", tuple(_plane_to_3d(np.array([p[P_R0]]), np.zeros(1))[0]),
                   (255, 200, 80)),
            Marker("touchdown", landing, (120, 255, 120)),
        ],
    )


def _plots(t, Xd, psid, t_nodes, X, psi) -> list[PlotSeries]:
    def series(title, unit, y, y_nodes, group="state"):
        return PlotSeries(title, unit, t, y, t_nodes, y_nodes, group)

    return [
        series("altitude", "km", (Xd[:, 0] - R_MOON) / 1e3, (X[:, 0] - R_MOON) / 1e3),
        series("radial speed", "m/s", Xd[:, 1], X[:, 1]),
        series("angular rate ω", "mrad/s", Xd[:, 3] * 1e3, X[:, 3] * 1e3),
        series("thrust angle ψ", "deg", psid / DEG, psi / DEG, group="control"),
        series("mass", "kg", Xd[:, 4], X[:, 4]),
    ]


MISSION = LunarLanding()
