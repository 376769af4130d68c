"""Paper 003's two stages: the particle swarm's impulsive transfer (`impulsive`), and that
transfer seeding the general Hermite–Simpson transcription of the OCP in `problem.py`
(`hermite-simpson`), through a coarse pre-solve by default; and the quantities, SI conversion
and re-propagation checks of both.

Solution arrays are SI: s from launch, m, m/s, kg, N (the impulsive method's controls are
the impulses in m/s at their dates).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ... import interval_error
from ...context import SolveContext
from ...dynamics.ephemeris import (
    AU,
    DAY,
    ELEMENT_SETS,
    GM_SUN,
    MJD_2022,
    TU,
    VU,
    ElementSet,
    asteroid_state,
    earth_state,
    iso_from_mjd,
)
from ...methods import HERMITE_SIMPSON
from ...ocp import OCPResult
from ...optimality import too_few_nodes
from ...problem import Method, Param
from ...solution import Iterate, Quantity, Series, Solution
from ...transcription import direct_transcription
from ...transcription.costates import rescale, rescale_hamiltonian
from ...verify import repropagate
from .guess import GUESS_OPTIONS, ImpulsiveTransfer, impulsive_guess, low_thrust_guess, same_guess
from .model import ACC, G0, SI_UNITS, si_rhs, to_mjd, to_si
from .problem import PAPER, ocp, parameter_vector

if TYPE_CHECKING:
    from ...mission import Mission

BURN_FRACTION = 0.05  # a node/sample burns when |U| > 5 % of Fmax
ATOL = np.array([1.0] * 3 + [1e-6] * 3 + [1e-9])  # re-propagation: m, m/s, kg
# Samples of the drawn path and plots, whatever the segment count: 8 per segment at 150, and
# 400 segments drawn 8 per segment tripled the page's bytes per update (121 -> 358 kB).
DENSE_SAMPLES = 1200

LOW_THRUST = HERMITE_SIMPSON.replace(
    label="PSO guess + Hermite–Simpson collocation (paper 003)", source=PAPER,
    summary="The general Hermite–Simpson transcription of the OCP: N equal segments, cubic "
            "Hermite states, linear thrust vector, midpoint collocation; free launch and "
            "arrival dates; |U| <= Fmax at the nodes; maximum final mass. Seeded by the "
            "particle swarm's impulsive transfer, through a 30-segment pre-solve. IPOPT "
            "(default, adaptive barrier) or CasADi SQP (slow, often unconverged here: use a "
            "time limit).",
    # 400 segments by default: the arrival miss is Hermite–Simpson's smooth 4th-order
    # truncation error, largest on the coast arc near 0.89 AU (not at the switches): 29.8 km
    # at 150, 2.0 km at 300, 0.59 km at 400 (target 1 km); a warm re-solve takes ~60 ms. The
    # cap is 450: from an interpolated start IPOPT stops converging above it (500 segments
    # from the 400 answer hit the 3000-iteration limit, 600 the time limit), so at 400 the
    # cost error estimate comes from a 266-segment solve (`cost_error.reference_nodes`).
    nodes=(10, 400, 450), nodes_label="segments",
    params=(
        Param("presolve_segments", "pre-solve segments (0: none)", "", 30.0, 0.0, 100.0,
              5.0, group="Method", integer=True,
              help="Solve a coarse mesh first and interpolate it (faster and surer); 0 seeds "
                   "the N-segment NLP with the impulsive guess itself, as the paper does."),
    ),
)

IMPULSIVE = Method(
    "impulsive", "Impulsive transfer (PSO + Lambert)", PAPER,
    "The first stage alone: the particle swarm's best impulsive transfer of the chosen kind; "
    "cost is the spacecraft Δv after launch (launch v∞ within the C3 bound).",
    nodes=(20, 200, 2000), nodes_label="drawing samples", backends=("pso",),
    other_problem=True,
)


# ---- the low-thrust method -----------------------------------------------------------------
def solve_low_thrust(mission: Mission, values: dict[str, float], nodes: int, backend: str,
                     warm: Solution | None, ctx: SolveContext) -> Solution:
    """Paper 003 §3: PSO guess, (coarse pre-solve,) Hermite–Simpson NLP. A previous optimum
    made with the same guess values warm-starts the NLP instead (its duals too on the same
    mesh)."""
    transfer = impulsive_guess(values, ctx)
    p = parameter_vector(values)
    problem = ocp()
    start = None
    if warm is not None and warm.converged and warm.warm is not None and same_guess(warm.values,
                                                                             values):
        start = warm.warm
    presolve = int(values.get("presolve_segments", 0))
    if start is None and 0 < presolve < nodes:
        coarse = direct_transcription(LOW_THRUST.transcription, problem, presolve, backend)
        pre = coarse.solve(p, low_thrust_guess(transfer, values, presolve), ctx)
        if pre.status == "optimal":
            start = pre.warm.primal_only()
    if start is None:
        start = low_thrust_guess(transfer, values, nodes)
    transcription = direct_transcription(LOW_THRUST.transcription, problem, nodes, backend)
    res = transcription.solve(p, start, ctx,
                              dense_per_interval=max(2, math.ceil(DENSE_SAMPLES / nodes)))
    if res.status != "optimal" and nodes < LOW_THRUST.nodes[1]:
        res.message = too_few_nodes(LOW_THRUST, nodes, res.message)
    sol = mission.direct_solution(values, LOW_THRUST, nodes, backend, problem, res)
    record_low_thrust(sol, res)
    guess_quantities(sol, transfer)
    sol.message += (f"; guess: {GUESS_OPTIONS[int(values['guess_kind'])]} from "
                    f"{iso_from_mjd(transfer.launch_mjd)}, Δv {transfer.total_dv:.0f} m/s")
    if res.status != "optimal" and values["c3_max"] < 1e6:
        sol.message += (f"; with launch C3 <= {values['c3_max'] / 1e6:g} km²/s² the engine "
                        "must do the 7.8° plane change (about 4 km/s) itself")
    if res.status == "optimal":
        sol.checker = lambda: verify_low_thrust(sol, values, res)
    return sol


def verify_low_thrust(sol: Solution, values: Mapping[str, float], res: OCPResult
                      ) -> dict[str, float]:
    """The deferred check: the re-propagated arrival miss, the local error of every
    segment (position, m) and the state box between nodes, in the NLP's canonical model."""
    miss = check_low_thrust(values, res)
    p = parameter_vector(values)
    errors, box = interval_error.box_check(sol, ocp(), p, res, 1e-12)
    interval_error.record(sol, interval_error.error_series(
        res.t_nodes * TU, np.linalg.norm(errors[:, 0:3], axis=1) * AU, "error", "m"))
    return {**miss, **box}


def record_low_thrust(sol: Solution, res: OCPResult) -> None:
    """The canonical NLP result in SI (s from launch, m, m/s, kg, N), its dates, fuel, burn
    arcs and bang–bang share."""
    m0, fmax = sol.values["mass0"], sol.values["thrust"]
    sol.node_t, sol.t = res.t_nodes * TU, res.t_dense * TU
    sol.node_x, sol.x = to_si(res.X, m0), to_si(res.X_dense, m0)
    sol.node_u, sol.u = res.U[:, 0:3] * fmax, res.U_dense[:, 0:3] * fmax
    sol.state_units = SI_UNITS
    sol.control_names, sol.control_units = ("Fx", "Fy", "Fz"), ("N", "N", "N")
    sol.history = [Iterate(it.iteration, it.t * TU, to_si(it.x, m0)) for it in res.history]
    sol.arcs = arcs_of(sol.t, np.linalg.norm(sol.u, axis=1) > BURN_FRACTION * fmax)
    burns = sum(1 for a in sol.arcs if a[2] == "burn")
    throttle = np.linalg.norm(sol.node_u, axis=1) / fmax
    fuel = float(m0 - sol.node_x[-1, 6])
    vinf = np.asarray(res.statics) * VU
    launch, arrival = float(to_mjd(res.t0)), float(to_mjd(res.t0 + res.T))
    sol.cost = Quantity(fuel, "fuel", "kg")
    sol.quantities = transfer_quantities(launch, arrival, fuel, float(sol.node_x[-1, 6]),
                                         burns, vinf)
    sol.quantities["bang_bang_fraction"] = Quantity(
        float(np.mean((throttle < BURN_FRACTION) | (throttle > 1 - BURN_FRACTION))),
        "nodes at zero or full thrust", "")
    _si_costates(sol, m0, float(sol.values["thrust"] / m0 / ACC), res)
    slack = res.U[:, 3] - np.linalg.norm(res.U[:, 0:3], axis=1)
    sol.stats["max_mass_flow_slack_N"] = float(np.max(slack) * fmax)
    sol.message = (f"{res.message}; launch {iso_from_mjd(launch)}, arrival "
                   f"{iso_from_mjd(arrival)}, {burns} burn arcs")


def _si_costates(sol: Solution, m0: float, accel: float, res: OCPResult) -> None:
    """Costates, Hamiltonian and switching function from canonical to SI (cost: fuel in kg,
    = m0 times the NLP's -m_f). With H = ... + lambda_v . a_F U/m - lambda_m k Gamma and
    |U| <= Gamma, H is least for U = -Gamma lambda_v/|lambda_v| and Gamma = 1 where the
    switching function S = a_F |lambda_v| / m + k lambda_m > 0 (burn), Gamma at its floor
    where S < 0 (coast): S is reported in kg/s per unit throttle."""
    est = sol.costates
    if est is None:
        return
    scale = np.array([AU] * 3 + [VU] * 3 + [m0])
    sol.costates = rescale(est, state_factor=scale, cost_factor=m0, time_factor=TU,
                           cost_unit="kg", state_units=SI_UNITS)
    sol.hamiltonian = rescale_hamiltonian(sol.hamiltonian, cost_factor=m0, time_factor=TU,
                                          cost_unit="kg")
    lam = np.asarray(est.values)
    m = np.interp(est.t, res.t_nodes, res.X[:, 6])
    flow = parameter_vector(sol.values)[1]
    S = accel * np.linalg.norm(lam[:, 3:6], axis=1) / m + flow * lam[:, 6]
    sol.switching = Series(np.asarray(est.t) * TU, (S * m0 / TU)[:, None], ("S",),
                           ("kg/s",))


def guess_quantities(sol: Solution, transfer: ImpulsiveTransfer) -> None:
    """What the first stage handed the NLP."""
    sol.quantities.update(
        impulsive_dv=Quantity(transfer.total_dv, "impulsive Δv of the guess", "m/s"),
        guess_launch=Quantity(transfer.launch_mjd - MJD_2022,
                              f"guess launch ({iso_from_mjd(transfer.launch_mjd)}) day", "d"),
        guess_flight_time=Quantity(transfer.flight_days, "guess flight time", "d"),
    )
    sol.stats["pso_evaluations"] = float(transfer.evaluations)


def check_low_thrust(values: Mapping[str, float], res: OCPResult) -> dict[str, float]:
    """Re-propagate the optimal control (DOP853, rtol 1e-10) in SI from Earth's epv00 state
    (not the NLP's spline) plus the v∞, and measure the miss against the asteroid's Kepler
    state at arrival."""
    t_nodes = res.t_nodes * TU
    controls = res.U * values["thrust"]

    def control(t: float, x: np.ndarray) -> np.ndarray:
        return np.array([np.interp(t, t_nodes, col) for col in controls.T])

    _, X = repropagate(si_rhs(), rhs_parameters(values),
                       departure_state(values, res.t0, np.asarray(res.statics)), control,
                       t_nodes, atol=ATOL)
    return arrival_misses(values, res.t0 + res.T, X[-1], res.X[-1, 6] * values["mass0"])


def departure_state(values: Mapping[str, float], t0: float, vinf: np.ndarray) -> np.ndarray:
    """The SI state at launch (canonical date `t0`): Earth's epv00 state (not the NLP's
    spline) plus the v∞ (canonical), and the initial mass."""
    r0, v0 = earth_state(float(to_mjd(t0)))
    return np.concatenate([r0, v0 + vinf * VU, [values["mass0"]]])


def rhs_parameters(values: Mapping[str, float]) -> np.ndarray:
    """The parameters of `si_rhs`: GM of the Sun and the exhaust speed."""
    return np.array([GM_SUN, values["isp"] * G0])


def arrival_misses(values: Mapping[str, float], arrival: float, x: np.ndarray,
                   final_mass: float) -> dict[str, float]:
    """A re-propagated arrival state `x` (SI) against the asteroid's Kepler state at the
    canonical date `arrival`, and its mass against the NLP's `final_mass` (kg)."""
    ra, va = asteroid_state(float(to_mjd(arrival)), ELEMENT_SETS[int(values["elements"])])
    return {
        "arrival_position_miss_m": float(np.linalg.norm(x[0:3] - ra)),
        "arrival_velocity_miss_m_s": float(np.linalg.norm(x[3:6] - va)),
        "final_mass_difference_kg": float(x[6] - final_mass),
    }


# ---- the impulsive method ------------------------------------------------------------------
def solve_impulsive(key: str, values: dict[str, float], samples: int, ctx: SolveContext
                    ) -> Solution:
    """The first stage alone, drawn with `samples` points along its Kepler arcs."""
    transfer = impulsive_guess(values, ctx)
    c, m0 = values["isp"] * G0, values["mass0"]
    mjd = transfer.launch_mjd + np.linspace(0.0, transfer.flight_days, samples + 1)
    mjd = np.union1d(mjd, transfer.impulse_mjd)
    r, v = transfer.states(mjd)
    dv = transfer.total_dv
    quantities = date_quantities(transfer.launch_mjd, transfer.arrival_mjd)
    quantities.update(
        impulsive_dv=Quantity(dv, "impulsive Δv", "m/s"),
        launch_c3=Quantity(transfer.c3 / 1e6, "launch C3", "km²/s²"),
        fuel=Quantity(m0 * (1 - np.exp(-dv / c)), "fuel (rocket equation)", "kg"),
        final_mass=Quantity(m0 * np.exp(-dv / c), "final mass", "kg"),
        impulses=Quantity(float(len(transfer.impulses)), "impulses (with launch)", ""),
    )
    t = (mjd - transfer.launch_mjd) * DAY
    sizes = np.linalg.norm(transfer.impulses, axis=1)
    message = (f"{GUESS_OPTIONS[int(values['guess_kind'])]}: launch "
               f"{iso_from_mjd(transfer.launch_mjd)}, arrival "
               f"{iso_from_mjd(transfer.arrival_mjd)}, impulses "
               + ", ".join(f"{s:.0f}" for s in sizes) + " m/s (first: launch v∞)")
    sol = Solution(
        mission=key, method=IMPULSIVE.key, nodes=samples, backend="pso", status="optimal",
        message=message, cost=Quantity(dv, "Δv", "m/s"), values=values, quantities=quantities,
        state_names=("x", "y", "z", "vx", "vy", "vz"), state_units=SI_UNITS[:6],
        control_names=("dvx", "dvy", "dvz"), control_units=("m/s",) * 3,
        node_t=(transfer.impulse_mjd - transfer.launch_mjd) * DAY,
        node_x=np.column_stack(transfer.states(transfer.impulse_mjd)),
        node_u=transfer.impulses, arcs=[(0.0, float(t[-1]), "coast")], t=t,
        x=np.column_stack([r, v]), u=np.zeros((len(t), 3)), control_interpolation="dense",
    )
    sol.stats.update(pso_evaluations=float(transfer.evaluations),
                     pso_generations=float(len(transfer.history)))
    elements = ELEMENT_SETS[int(values["elements"])]
    sol.checker = lambda: check_impulsive(transfer, elements)
    return sol


def check_impulsive(transfer: ImpulsiveTransfer, elements: ElementSet) -> dict[str, float]:
    """Integrate each coast arc (DOP853, rtol 1e-10) and compare with the asteroid before
    the arrival impulse: an independent check of the Lambert and Kepler solutions."""
    from scipy.integrate import solve_ivp

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([y[3:], -GM_SUN * y[:3] / np.linalg.norm(y[:3]) ** 3])

    y = np.zeros(6)
    for k in range(len(transfer.arc_r)):
        y0 = np.concatenate([transfer.arc_r[k], transfer.arc_v[k]])
        span = (transfer.impulse_mjd[k + 1] - transfer.impulse_mjd[k]) * DAY
        y = solve_ivp(rhs, (0.0, span), y0, method="DOP853", rtol=1e-10,
                      atol=[1.0] * 3 + [1e-6] * 3).y[:, -1]
    ra, va = asteroid_state(transfer.arrival_mjd, elements)
    return {
        "arrival_position_miss_m": float(np.linalg.norm(y[:3] - ra)),
        "arrival_velocity_miss_m_s": float(np.linalg.norm(y[3:] + transfer.impulses[-1] - va)),
    }


# ---- shared ----------------------------------------------------------------------------------
def transfer_quantities(launch_mjd: float, arrival_mjd: float, fuel: float, final_mass: float,
                        burns: int, vinf: np.ndarray) -> dict[str, Quantity]:
    """The dates, fuel, final mass, burn arcs and launch C3 (v∞ in m/s) of a low-thrust
    answer."""
    return {
        **date_quantities(launch_mjd, arrival_mjd),
        "fuel": Quantity(fuel, "fuel", "kg"),
        "final_mass": Quantity(final_mass, "final mass", "kg"),
        "burn_arcs": Quantity(float(burns), "burn arcs", ""),
        "launch_c3": Quantity(float(vinf @ vinf) / 1e6, "launch C3", "km²/s²"),
    }


def date_quantities(launch_mjd: float, arrival_mjd: float) -> dict[str, Quantity]:
    """Launch and arrival (days since 2022-01-01, the ISO date in the label), flight time."""
    return {
        "launch_date": Quantity(launch_mjd - MJD_2022,
                                f"launch ({iso_from_mjd(launch_mjd)}) day", "d"),
        "arrival_date": Quantity(arrival_mjd - MJD_2022,
                                 f"arrival ({iso_from_mjd(arrival_mjd)}) day", "d"),
        "flight_time": Quantity(arrival_mjd - launch_mjd, "flight time", "d"),
    }


def arcs_of(t: np.ndarray, burning: np.ndarray) -> list[tuple[float, float, str]]:
    """Maximal runs of burning / coasting samples as (t0, t1, kind)."""
    arcs: list[tuple[float, float, str]] = []
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or burning[i] != burning[start]:
            end = min(i, len(t) - 1)
            arcs.append((float(t[start]), float(t[end]), "burn" if burning[start] else "coast"))
            start = i
    return arcs
