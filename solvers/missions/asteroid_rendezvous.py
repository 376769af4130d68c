"""Mission `asteroid-rendezvous`: fuel-optimal low-thrust rendezvous with the near-Earth
asteroid 469219 Kamoʻoalewa (2016 HO3), paper 003 / SPEC M4.

Two stages as in the paper: a particle swarm searches one of three kinds of impulsive
transfer (`asteroid_guess`), which seeds a Hermite–Simpson transcription with free launch and
arrival dates (`transcription.low_thrust`). The `impulsive` method shows the first stage
alone.

Conventions: dates (launch window, seeded launch) and durations in this mission's params and
quantities are days ("d"); dates count days from 2022-01-01 0h TDB (MJD 59580), the start of
the paper's window ("day 147" is 2022-05-28), and the ISO dates are in the quantities'
labels and the message.
Solution arrays are SI (s from launch, m, m/s, kg, N); the display frame is heliocentric
ecliptic J2000 in metres, drawn in AU.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from ..dynamics.ephemeris import (
    AU,
    DAY,
    ELEMENT_SETS,
    GM_SUN,
    MJD_2022,
    asteroid_state,
    earth_state,
    iso_from_mjd,
)
from ..dynamics.kepler import state_to_elements
from ..mission import Infeasible, Mission, SolveContext
from ..problem import Method, Param, Preset, Published
from ..solution import (
    Body,
    ColorBy,
    Curve,
    GridMap,
    Marker,
    PlotSeries,
    Quantity,
    Scene,
    Solution,
)
from ..transcription.low_thrust import (
    EPHEMERIS_FIRST,
    EPHEMERIS_LAST,
    G0,
    LowThrustGuess,
    LowThrustProblem,
    LowThrustResult,
    hermite_dense,
    rhs_si,
    transcription,
)
from ..verify import repropagate
from .asteroid_guess import KINDS, ImpulsiveTransfer, Window, lowest_c3_transfer, pso_search

PAPER = ("Wang, Shi, Wang & Peng, low-thrust transfer to near-Earth asteroid 2016 HO3 with "
         "PSO + SQP (paper 003)")
GUESS_OPTIONS = (*KINDS, "Lambert arc at chosen dates (lowest C3, 0-1 rev)")
CHOSEN_DATES = len(KINDS)
BURN_FRACTION = 0.05  # a node/sample burns when |U| > 5 % of Fmax
DEG = np.pi / 180
FIRST_DAY = EPHEMERIS_FIRST - MJD_2022
LAST_DAY = EPHEMERIS_LAST - MJD_2022
SUN_RADIUS_DRAWN = 0.03 * AU  # ~6.5 solar radii: enlarged so the Sun is visible at 1 AU
PLANET_RADIUS_DRAWN = 0.008 * AU  # Earth and asteroid drawn ~190x Earth's radius

PARAMS = (
    Param("launch_start", "launch window opens [days since 2022-01-01]", "d", 0.0, FIRST_DAY,
          LAST_DAY - 1, 1.0, group="Window",
          help="Paper 003: 2022-01-01 (0). Days from 2022-01-01 0h TDB."),
    Param("launch_end", "launch window closes [days since 2022-01-01]", "d", 730.0,
          FIRST_DAY + 1, LAST_DAY, 1.0, group="Window",
          help="Paper 003: 2024-01-01 (730)."),
    Param("max_flight_time", "maximum flight time", "d", 700.0, 60.0, 1000.0, 1.0,
          group="Window", help="Paper 003: 700 d."),
    Param("c3_max", "maximum launch C3", "m²/s²", 20e6, 0.0, 100e6, 0.5e6, group="Window",
          display_unit="km²/s²", display_factor=1e-6,
          help="Launch energy the launcher gives: the departure v∞ is free with |v∞|² <= C3. "
               "0 reproduces the paper's eq. 13 read literally (departure at Earth's "
               "velocity), which the 120 mN engine cannot fly within 700 d."),
    Param("mass0", "initial mass m0", "kg", 1500.0, 100.0, 5000.0, 10.0, group="Vehicle"),
    Param("thrust", "maximum thrust Fmax", "N", 0.12, 0.01, 1.0, 0.001, group="Vehicle",
          display_unit="mN", display_factor=1e3),
    Param("isp", "specific impulse Isp", "s", 3500.0, 500.0, 10000.0, 10.0, group="Vehicle"),
    Param("guess_kind", "first guess", "", 1.0, 0, len(GUESS_OPTIONS) - 1, 1, group="Guess",
          options=GUESS_OPTIONS,
          help="The paper's three impulsive kinds (PSO), or the Lambert arc between the two "
               "dates below (a cell of the launch map)."),
    Param("seed_launch", "chosen launch date [days since 2022-01-01]", "d", 147.0, FIRST_DAY,
          LAST_DAY, 1.0, group="Guess", help="Used by 'Lambert at chosen dates'."),
    Param("seed_flight_time", "chosen flight time", "d", 400.0, 20.0, 1000.0, 1.0,
          group="Guess", help="Used by 'Lambert at chosen dates'."),
    Param("elements", "asteroid elements", "", 0.0, 0, 1, 1, group="Guess",
          options=tuple(s.name for s in ELEMENT_SETS),
          help="Osculating element sets of reference/asteroid.md, two-body propagated."),
    Param("pso_seed", "PSO random seed", "", 0.0, 0.0, 1000.0, 1.0, group="Guess",
          integer=True),
    Param("pso_particles", "PSO particles", "", 100.0, 10.0, 400.0, 10.0, group="Guess",
          integer=True),
    Param("pso_generations", "PSO generations", "", 200.0, 10.0, 1000.0, 10.0, group="Guess",
          integer=True),
)

METHODS = (
    Method(
        "hermite-simpson", "PSO guess + Hermite–Simpson collocation (paper 003)", PAPER,
        "N equal segments, cubic Hermite states, linear thrust vector, midpoint collocation; "
        "free launch and arrival dates; |U| <= Fmax at the nodes; maximum final mass. IPOPT "
        "(default, adaptive barrier) or CasADi SQP (slow, often unconverged here: use a time "
        "limit); a 30-segment pre-solve warms the N-segment NLP.",
        nodes=(10, 150, 300), nodes_label="segments", backends=("ipopt", "sqp"),
        params=(
            Param("presolve_segments", "pre-solve segments (0: none)", "", 30.0, 0.0, 100.0,
                  5.0, group="Method", integer=True,
                  help="Solve a coarse mesh first and interpolate it (faster and surer); 0 "
                       "seeds the N-segment NLP with the impulsive guess itself, as the "
                       "paper does."),
        ),
    ),
    Method(
        "impulsive", "Impulsive transfer (PSO + Lambert)", PAPER,
        "The first stage alone: the particle swarm's best impulsive transfer of the chosen "
        "kind; cost is the spacecraft Δv after launch (launch v∞ within the C3 bound).",
        nodes=(20, 200, 2000), nodes_label="drawing samples",
    ),
)

PUBLISHED = (
    Published("launch_date", 147.0, "d", "paper 003 §4: launch window 2022-05-28",
              "days since 2022-01-01"),
    Published("launch_date", 332.0, "d", "paper 003 §4: launch window 2022-11-29",
              "days since 2022-01-01"),
    Published("fuel_spread", 6.0, "%", "paper 003 §4: the three optimised fuels differ < 6 %"),
    Published("impulsive_dv_spread", 58.0, "%",
              "paper 003 §4: the three impulsive guesses differ by up to 58 % in Δv"),
    Published("windows_per_year", 4.0, "", "paper 003 fig. 2: four launch-C3 troughs a year "
              "(long transfers 380–550 d, short 50–200 d)"),
    Published("main_burns", 2.0, "", "paper 003 fig. 3: bang–bang thrust, two main burns"),
)

HELP = """\
**Low-thrust rendezvous with asteroid Kamoʻoalewa (2016 HO3)** (paper 003). A 1500 kg
spacecraft with a 120 mN, Isp 3500 s engine leaves Earth with a launch C3 of at most
20 km²/s² and must match the asteroid's position and velocity, burning as little propellant
as possible. A particle swarm first finds an impulsive transfer (three kinds); it seeds the
Hermite–Simpson collocation, which moves the launch and arrival dates freely in the window.
Dates are counted in days from 2022-01-01 (TDB); the ISO dates are in the results.

*Paper 003:* launch windows 2022-05-28 and 2022-11-29; impulsive Δv of the three guesses
differ by up to 58 %, optimised fuels by under 6 %; bang–bang thrust with two main burns,
"long then short" in November, "short then long" in May.

*Here (150 segments, elements B):* the swarms land on the two node-crossing dates the paper
reports (Earth at the asteroid's line of nodes, where the launcher's v∞ makes the 7.8° plane
change); the optimised transfers launch 2022-05-28 (34.27 kg) or 2022-11-30 (34.58 kg),
bang–bang with two burns in the paper's order. Differences: the paper's table of fuels and
flight times did not survive the scan, so those cannot be compared; the multi-revolution
guess (670 d) runs to the 700 d limit and uses 26.3 kg, so the spread of the three fuels is
31 %, not < 6 %; the impulsive Δv differ by 71 % (paper 58 %). The launch map shows the
paper's short (50–200 d) and long (380–550 d, one revolution) windows, four a year each.
SQP (CasADi sqpmethod as configured in the core) does not converge on this NLP within
minutes here; IPOPT is the default.
"""


@dataclass(frozen=True)
class _GuessKey:
    kind: int
    window: Window
    particles: int
    generations: int
    seed: int


GUESS_CACHE_SIZE = 64
_GUESS_CACHE: dict[_GuessKey, ImpulsiveTransfer] = {}
_CACHE_LOCK = threading.Lock()


def window_of(values: dict[str, float]) -> Window:
    """The search window of a validated value set (dates as MJD TDB)."""
    return Window(MJD_2022 + values["launch_start"], MJD_2022 + values["launch_end"],
                  values["max_flight_time"], values["c3_max"],
                  ELEMENT_SETS[int(values["elements"])])


def impulsive_guess(values: dict[str, float], ctx: SolveContext | None = None) -> ImpulsiveTransfer:
    """The first-stage impulsive transfer of a value set (PSO results cached: they are
    deterministic for a fixed seed, and a thrust change needs no new search)."""
    window = window_of(values)
    kind = int(values["guess_kind"])
    if kind == CHOSEN_DATES:
        launch = MJD_2022 + values["seed_launch"]
        try:
            return lowest_c3_transfer(launch, values["seed_flight_time"], window)
        except ValueError as exc:
            raise Infeasible(str(exc)) from None
    key = _GuessKey(kind, window, int(values["pso_particles"]), int(values["pso_generations"]),
                    int(values["pso_seed"]))
    with _CACHE_LOCK:
        cached = _GUESS_CACHE.get(key)
    if cached is not None:
        return cached
    stop = None if ctx is None else (lambda gen, best: ctx.should_stop())
    try:
        transfer = pso_search(kind, window, key.particles, key.generations, key.seed, stop)
    except ValueError as exc:
        raise Infeasible(str(exc)) from None
    if ctx is not None:
        ctx.checkpoint()
    with _CACHE_LOCK:
        if len(_GUESS_CACHE) >= GUESS_CACHE_SIZE:
            _GUESS_CACHE.pop(next(iter(_GUESS_CACHE)))
        _GUESS_CACHE[key] = transfer
    return transfer


def problem_of(values: dict[str, float]) -> LowThrustProblem:
    w = window_of(values)
    return LowThrustProblem(
        m0=values["mass0"], thrust=values["thrust"], exhaust_speed=values["isp"] * G0,
        launch_first=w.launch_start, launch_last=w.launch_end, min_flight_days=20.0,
        max_flight_days=w.max_tof_days, c3_max=w.c3_max, elements=w.elements)


def low_thrust_guess(
    transfer: ImpulsiveTransfer, prob: LowThrustProblem, segments: int
) -> LowThrustGuess:
    """Paper 003 §3.1 step 5: node states from the impulsive arcs, masses falling linearly
    (to the rocket-equation final mass of the impulsive Δv), thrust Fmax·(0.5, 0.5, 0.5)."""
    mjd = transfer.launch_mjd + np.linspace(0.0, transfer.flight_days, segments + 1)
    r, v = transfer.states(mjd)
    m_final = prob.m0 * np.exp(-transfer.total_dv / prob.exhaust_speed)
    X = np.column_stack([r, v, np.linspace(prob.m0, m_final, segments + 1)])
    U = np.tile(prob.thrust * np.array([0.5, 0.5, 0.5]), (segments + 1, 1))
    vinf = transfer.v_inf
    vmax = np.sqrt(max(prob.c3_max, 0.0))
    speed = float(np.linalg.norm(vinf))
    if speed > vmax:
        vinf = vinf * (vmax / speed)
    return LowThrustGuess(X, U, transfer.launch_mjd, transfer.flight_days * DAY, vinf)


def _resample(coarse_tau: np.ndarray, res: LowThrustResult, segments: int) -> LowThrustGuess:
    """A solved mesh re-interpolated (linearly) onto `segments` equal segments."""
    tau = np.linspace(0.0, 1.0, segments + 1)
    X = np.column_stack([np.interp(tau, coarse_tau, c) for c in res.X.T])
    U = np.column_stack([np.interp(tau, coarse_tau, c) for c in res.U.T])
    return LowThrustGuess(X, U, res.launch_mjd, res.flight_time, res.v_inf)


# Values that define the first guess and the search window: a warm start from a solution
# made with other values would silently replace the guess being studied.
_GUESS_KEYS = ("launch_start", "launch_end", "max_flight_time", "c3_max", "guess_kind",
               "seed_launch", "seed_flight_time", "elements", "pso_seed", "pso_particles",
               "pso_generations")


def _same_guess(a: dict[str, float], b: dict[str, float]) -> bool:
    return all(a.get(k) == b.get(k) for k in _GUESS_KEYS)


def _guess_from_solution(sol: Solution, segments: int) -> LowThrustGuess:
    """Another segment count's optimum re-interpolated onto this mesh."""
    launch = MJD_2022 + sol.quantities["launch_date"].value
    tau_from = np.asarray(sol.node_t) / sol.node_t[-1]
    tau = np.linspace(0.0, 1.0, segments + 1)
    X = np.column_stack([np.interp(tau, tau_from, c) for c in sol.node_x.T])
    U = np.column_stack([np.interp(tau, tau_from, c) for c in sol.node_u.T])
    v_inf = sol.node_x[0, 3:6] - earth_state(launch)[1]
    return LowThrustGuess(X, U, launch, float(sol.node_t[-1]), v_inf)


class AsteroidRendezvous(Mission):
    key = "asteroid-rendezvous"
    title = "Low-thrust asteroid rendezvous"
    summary = ("Fuel-optimal electric-propulsion transfer from Earth to asteroid Kamoʻoalewa "
               "with free launch and arrival dates.")
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "fuel"
    cost_unit = "kg"
    equations = (
        ("Heliocentric two-body motion with thrust (paper 003)",
         r"\dot r = v,\quad \dot v = -\frac{\mu r}{\lVert r\rVert^3} + \frac{U}{m},\quad "
         r"\dot m = -\frac{\lVert U\rVert}{I_{sp} g_0},\qquad \lVert U(t_i)\rVert \le F_{max}"),
        ("Cost and boundary conditions",
         r"\max\ m(t_f),\quad r(t_0) = r_E(t_0),\ v(t_0) = v_E(t_0) + v_\infty,\ "
         r"\lVert v_\infty\rVert^2 \le C_{3,max},\quad (r, v)(t_f) = (r_A, v_A)(t_f)"),
    )
    presets = (
        Preset("Paper 003 case (three-impulse guess)", {}),
        Preset("Two-impulse single-revolution guess", {"guess_kind": 0}),
        Preset("Two-impulse multi-revolution guess", {"guess_kind": 2}),
        Preset("May window (three-impulse, launch before 2022-09-01)", {"launch_end": 243.0},
               note="The three-impulse fitness's other minimum: launch 2022-05-28 (the full "
                    "window's swarm finds 2022-11-29, within 0.4 % in Δv)."),
        Preset("Lambert seed 2022-11-29, 370 d", {"guess_kind": CHOSEN_DATES,
                                                  "seed_launch": 332, "seed_flight_time": 370}),
        Preset("Impulsive transfers only", {}, method="impulsive"),
        Preset("Coarse mesh (40 segments)", {}, method="hermite-simpson", nodes=40),
        Preset("Paper eq. 13 literally: no launch v∞ (C3 = 0)", {"c3_max": 0.0},
               note="The 120 mN engine cannot make the 7.8° plane change in 700 d: "
                    "infeasible."),
        Preset("Element set A (Horizons 2017)", {"elements": 1}),
    )

    def check_values(self, values: dict[str, float]) -> None:
        if values["launch_end"] <= values["launch_start"]:
            raise ValueError(
                f"the launch window closes (day {values['launch_end']:g}) before it opens "
                f"(day {values['launch_start']:g})")

    def _solve(
        self,
        values: dict[str, float],
        method: Method,
        nodes: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        transfer = impulsive_guess(values, ctx)
        if method.key == "impulsive":
            return self._impulsive_solution(values, transfer, nodes)
        prob = problem_of(values)
        tx = transcription(nodes, backend)
        warm_start, guess = None, None
        if warm is not None and warm.ok and _same_guess(warm.values, values):
            if getattr(warm.warm, "n_segments", None) == nodes:
                warm_start = warm.warm
            else:
                guess = _guess_from_solution(warm, nodes)
        presolve = int(values.get("presolve_segments", 0))
        if warm_start is None and guess is None:
            if 0 < presolve < nodes:
                coarse = transcription(presolve, backend).solve(
                    prob, low_thrust_guess(transfer, prob, presolve), ctx=ctx)
                if coarse.status == "optimal":
                    guess = _resample(np.linspace(0, 1, presolve + 1), coarse, nodes)
            if guess is None:
                guess = low_thrust_guess(transfer, prob, nodes)
        res = tx.solve(prob, guess, warm_start, ctx)
        if res.status == "infeasible" and prob.c3_max < 1e6:
            res.message += (f"; with launch C3 <= {prob.c3_max / 1e6:g} km²/s² the engine must "
                            "do the 7.8° plane change (about 4 km/s) itself")
        return self._low_thrust_solution(values, nodes, backend, prob, transfer, res)

    # ---- solutions -------------------------------------------------------------------
    def _low_thrust_solution(self, values, nodes, backend, prob, transfer, res) -> Solution:
        fmax = prob.thrust
        t_nodes = res.t_nodes
        F = rhs_si(res.X, res.U, res.gamma, prob.exhaust_speed)
        t, X = hermite_dense(t_nodes, res.X, F, per_segment=8)
        U = np.column_stack([np.interp(t, t_nodes, c) for c in res.U.T])
        fuel = float(prob.m0 - res.X[-1, 6])
        arcs = _arcs(t, np.linalg.norm(U, axis=1) > BURN_FRACTION * fmax)
        burns = sum(1 for a in arcs if a[2] == "burn")
        arrival = res.arrival_mjd
        quantities = _date_quantities(res.launch_mjd, arrival)
        quantities.update(
            fuel=Quantity(fuel, "fuel", "kg"),
            final_mass=Quantity(float(res.X[-1, 6]), "final mass", "kg"),
            impulsive_dv=Quantity(transfer.total_dv, "impulsive Δv of the guess", "m/s"),
            burn_arcs=Quantity(float(burns), "burn arcs", ""),
            launch_c3=Quantity(float(res.v_inf @ res.v_inf) / 1e6, "launch C3", "km²/s²"),
            guess_launch=Quantity(transfer.launch_mjd - MJD_2022,
                                  f"guess launch ({iso_from_mjd(transfer.launch_mjd)}) day", "d"),
            guess_flight_time=Quantity(transfer.flight_days, "guess flight time", "d"),
        )
        message = (f"{res.message}; launch {iso_from_mjd(res.launch_mjd)}, arrival "
                   f"{iso_from_mjd(arrival)}, {burns} burn arcs; guess: "
                   f"{GUESS_OPTIONS[int(values['guess_kind'])]} from "
                   f"{iso_from_mjd(transfer.launch_mjd)}, Δv {transfer.total_dv:.0f} m/s")
        sol = Solution(
            mission=self.key, method="hermite-simpson", nodes=nodes, backend=backend,
            status=res.status, message=message, cost=Quantity(fuel, "fuel", "kg"),
            values=values, quantities=quantities,
            state_names=("x", "y", "z", "vx", "vy", "vz", "m"),
            state_units=("m",) * 3 + ("m/s",) * 3 + ("kg",),
            control_names=("Fx", "Fy", "Fz"), control_units=("N", "N", "N"),
            node_t=t_nodes, node_x=res.X, node_u=res.U, arcs=arcs, t=t, x=X, u=U,
        )
        sol.positions = X[:, 0:3]
        sol.node_positions = res.X[:, 0:3]
        sol.thrust = res.U / fmax
        sol.history = [{"iteration": k, "positions": pos} for k, pos in res.history]
        sol.scene = _scene(res.launch_mjd, arrival, values)
        _attach_tracks(sol)
        _attach_launch_map(sol, res.launch_mjd, arrival - res.launch_mjd)
        sol.color_by = ColorBy("thrust magnitude", "mN", np.linalg.norm(U, axis=1) * 1e3)
        sol.plots = _plots(t, X, U, t_nodes, res.X, res.U, fmax)
        sol.stats.update(
            iterations=res.iterations, nlp_variables=res.n_variables,
            nlp_constraints=res.n_constraints, constraint_violation=res.max_violation,
            pso_evaluations=transfer.evaluations,
            max_mass_flow_slack_N=float(np.max(res.gamma - np.linalg.norm(res.U, axis=1))),
        )
        sol.warm = res.warm
        sol.check["max_defect"] = res.max_violation
        sol.checker = lambda: _check_low_thrust(prob, res)
        return sol

    def _impulsive_solution(self, values, transfer: ImpulsiveTransfer, samples: int) -> Solution:
        c = values["isp"] * G0
        m0 = values["mass0"]
        mjd = transfer.launch_mjd + np.linspace(0.0, transfer.flight_days, samples + 1)
        mjd = np.union1d(mjd, transfer.impulse_mjd)
        r, v = transfer.states(mjd)
        t = (mjd - transfer.launch_mjd) * DAY
        dv = transfer.total_dv
        quantities = _date_quantities(transfer.launch_mjd, transfer.arrival_mjd)
        quantities.update(
            impulsive_dv=Quantity(dv, "impulsive Δv", "m/s"),
            launch_c3=Quantity(transfer.c3 / 1e6, "launch C3", "km²/s²"),
            fuel=Quantity(m0 * (1 - np.exp(-dv / c)), "fuel (rocket equation)", "kg"),
            final_mass=Quantity(m0 * np.exp(-dv / c), "final mass", "kg"),
            impulses=Quantity(float(len(transfer.impulses)), "impulses (with launch)", ""),
        )
        impulse_t = (transfer.impulse_mjd - transfer.launch_mjd) * DAY
        r_imp, _ = transfer.states(transfer.impulse_mjd)
        sizes = np.linalg.norm(transfer.impulses, axis=1)
        message = (f"{GUESS_OPTIONS[int(values['guess_kind'])]}: launch "
                   f"{iso_from_mjd(transfer.launch_mjd)}, arrival "
                   f"{iso_from_mjd(transfer.arrival_mjd)}, impulses "
                   + ", ".join(f"{s:.0f}" for s in sizes) + " m/s (first: launch v∞)")
        sol = Solution(
            mission=self.key, method="impulsive", nodes=samples, backend="pso",
            status="optimal", message=message, cost=Quantity(dv, "Δv", "m/s"), values=values,
            quantities=quantities, state_names=("x", "y", "z", "vx", "vy", "vz"),
            state_units=("m",) * 3 + ("m/s",) * 3, control_names=("dvx", "dvy", "dvz"),
            control_units=("m/s",) * 3, node_t=impulse_t,
            node_x=np.column_stack(transfer.states(transfer.impulse_mjd)),
            node_u=transfer.impulses, arcs=[(0.0, float(t[-1]), "coast")], t=t,
            x=np.column_stack([r, v]), u=np.zeros((len(t), 3)),
        )
        sol.positions = r
        sol.node_positions = r_imp
        sol.thrust = transfer.impulses / max(float(sizes.max()), 1e-9)
        sol.scene = _scene(transfer.launch_mjd, transfer.arrival_mjd, values)
        _attach_tracks(sol)
        _attach_launch_map(sol, transfer.launch_mjd, transfer.arrival_mjd - transfer.launch_mjd)
        speed = np.linalg.norm(v, axis=1)
        sol.plots = [
            PlotSeries("heliocentric speed", "km/s", t, speed / 1e3, impulse_t, None),
            PlotSeries("impulse size", "m/s", impulse_t, sizes, impulse_t, sizes, "control"),
            *_element_plots(t, r, v, impulse_t, r_imp, transfer.states(transfer.impulse_mjd)[1]),
        ]
        sol.stats.update(pso_evaluations=transfer.evaluations,
                         pso_generations=float(len(transfer.history)))
        elements = ELEMENT_SETS[int(values["elements"])]
        sol.checker = lambda: _check_impulsive(transfer, elements)
        return sol


def _date_quantities(launch_mjd: float, arrival_mjd: float) -> dict[str, Quantity]:
    return {
        "launch_date": Quantity(launch_mjd - MJD_2022,
                                f"launch ({iso_from_mjd(launch_mjd)}) day", "d"),
        "arrival_date": Quantity(arrival_mjd - MJD_2022,
                                 f"arrival ({iso_from_mjd(arrival_mjd)}) day", "d"),
        "flight_time": Quantity(arrival_mjd - launch_mjd, "flight time", "d"),
    }


def _arcs(t: np.ndarray, burning: np.ndarray) -> list[tuple[float, float, str]]:
    """Maximal runs of burning / coasting samples as (t0, t1, kind)."""
    arcs: list[tuple[float, float, str]] = []
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or burning[i] != burning[start]:
            end = min(i, len(t) - 1)
            arcs.append((float(t[start]), float(t[end]), "burn" if burning[start] else "coast"))
            start = i
    return arcs


def body_tracks(sol: Solution) -> dict[str, np.ndarray]:
    """Earth's and the asteroid's positions [m] at the Solution's dense times `sol.t`, for an
    animation moving both bodies with the spacecraft (the Scene has no moving bodies yet)."""
    launch = MJD_2022 + sol.quantities["launch_date"].value
    dates = launch + np.asarray(sol.t) / DAY
    elements = ELEMENT_SETS[int(sol.values["elements"])]
    return {"Earth": earth_state(dates)[0], "Kamoʻoalewa": asteroid_state(dates, elements)[0]}


@cache
def _launch_map(elements: int):
    """Paper 003 fig. 2 on a display grid (3-day launch steps, 10-day flight steps): about
    0.1 s once per element set."""
    from ..launch_map import compute_launch_map

    return compute_launch_map(elements=ELEMENT_SETS[elements], tof=(50.0, 700.0, 66),
                              workers=1, step_days=3.0)


def _attach_launch_map(sol: Solution, launch_mjd: float, flight_days: float) -> None:
    """The launch-C3 map with this solution's (launch date, flight time) marked."""
    m = _launch_map(int(sol.values["elements"]))
    sol.maps = [GridMap(
        "launch C3 (paper 003 fig. 2): set a date pair with 'first guess: Lambert arc at "
        "chosen dates'", "launch date [days since 2022-01-01]", m.launch_mjd - MJD_2022,
        "flight time [d]", m.tof_days, "C3 [km²/s²]", m.c3, sol.values["c3_max"] / 1e6,
        marker=(launch_mjd - MJD_2022, flight_days),
    )]


def _attach_tracks(sol: Solution) -> None:
    """Let Earth and the asteroid move with the spacecraft in the animation."""
    tracks = body_tracks(sol)
    for body in sol.scene.bodies:
        for name, track in tracks.items():
            if body.name.startswith(name):
                body.track = track


def _scene(launch_mjd: float, arrival_mjd: float, values: dict) -> Scene:
    """Sun, both orbits (one revolution from launch), Earth (drawn at launch) and the asteroid
    at arrival (enlarged spheres that move with the spacecraft in the animation), and markers
    labelled with the dates."""
    elements = ELEMENT_SETS[int(values["elements"])]
    year = launch_mjd + np.linspace(0.0, 365.25, 367)
    r_earth_orbit, _ = earth_state(year)
    period = 2 * np.pi * np.sqrt((elements.a_au * AU) ** 3 / GM_SUN) / DAY
    r_ast_orbit, _ = asteroid_state(launch_mjd + np.linspace(0.0, period, 367), elements)
    r_launch, _ = earth_state(launch_mjd)
    r_arrival, _ = asteroid_state(arrival_mjd, elements)
    return Scene(
        frame="heliocentric ecliptic J2000",
        display_unit="AU",
        display_scale=1.0 / AU,
        bodies=[
            Body("Sun (enlarged)", (0.0, 0.0, 0.0), SUN_RADIUS_DRAWN, (255, 210, 60)),
            Body("Earth (enlarged)", tuple(r_launch), PLANET_RADIUS_DRAWN, (70, 130, 255)),
            Body("Kamoʻoalewa (enlarged)", tuple(r_arrival),
                 0.6 * PLANET_RADIUS_DRAWN, (200, 160, 120)),
        ],
        curves=[
            Curve("Earth's orbit", r_earth_orbit, (70, 130, 255), dashed=True),
            Curve("Kamoʻoalewa's orbit", r_ast_orbit, (200, 160, 120), dashed=True),
        ],
        markers=[
            Marker(f"launch {iso_from_mjd(launch_mjd)}", tuple(r_launch), (120, 200, 255)),
            Marker(f"arrival {iso_from_mjd(arrival_mjd)}", tuple(r_arrival), (255, 200, 120)),
        ],
    )


def _element_plots(t, r, v, t_nodes, r_nodes, v_nodes) -> list[PlotSeries]:
    """Semi-major axis, eccentricity and inclination along the transfer (paper 003 fig. 4)."""
    el = state_to_elements(r, v, GM_SUN)
    eln = state_to_elements(r_nodes, v_nodes, GM_SUN)
    return [
        PlotSeries("semi-major axis", "AU", t, el[:, 0] / AU, t_nodes, eln[:, 0] / AU),
        PlotSeries("eccentricity", "", t, el[:, 1], t_nodes, eln[:, 1]),
        PlotSeries("inclination", "deg", t, el[:, 2] / DEG, t_nodes, eln[:, 2] / DEG),
    ]


def _thrust_angles(U: np.ndarray, fmax: float) -> tuple[np.ndarray, np.ndarray]:
    """Ecliptic longitude [0, 360) and latitude of the thrust [deg]; NaN on coasts."""
    mag = np.linalg.norm(U, axis=1)
    on = mag > BURN_FRACTION * fmax
    lon = np.where(on, np.remainder(np.arctan2(U[:, 1], U[:, 0]) / DEG, 360.0), np.nan)
    lat = np.where(on, np.arcsin(np.clip(U[:, 2] / np.maximum(mag, 1e-30), -1, 1)) / DEG,
                   np.nan)
    return lon, lat


def _plots(t, X, U, t_nodes, Xn, Un, fmax) -> list[PlotSeries]:
    lon, lat = _thrust_angles(U, fmax)
    lon_n, lat_n = _thrust_angles(Un, fmax)
    return [
        PlotSeries("thrust magnitude", "mN", t, np.linalg.norm(U, axis=1) * 1e3, t_nodes,
                   np.linalg.norm(Un, axis=1) * 1e3, "control"),
        PlotSeries("thrust ecliptic longitude", "deg", t, lon, t_nodes, lon_n, "control"),
        PlotSeries("thrust ecliptic latitude", "deg", t, lat, t_nodes, lat_n, "control"),
        PlotSeries("mass", "kg", t, X[:, 6], t_nodes, Xn[:, 6]),
        *_element_plots(t, X[:, 0:3], X[:, 3:6], t_nodes, Xn[:, 0:3], Xn[:, 3:6]),
    ]


_SI_RHS: ca.Function | None = None


def _si_rhs() -> ca.Function:
    """f(x, u, p) in SI for the re-propagation: x = (r, v, m), u = (U, Γ), p = (GM, c)."""
    global _SI_RHS
    if _SI_RHS is None:
        x, u, p = ca.SX.sym("x", 7), ca.SX.sym("u", 4), ca.SX.sym("p", 2)
        r, v, m = x[0:3], x[3:6], x[6]
        acc = -p[0] * r / ca.norm_2(r) ** 3 + u[0:3] / m
        _SI_RHS = ca.Function("asteroid_rhs", [x, u, p], [ca.vertcat(v, acc, -u[3] / p[1])])
    return _SI_RHS


def _check_low_thrust(prob: LowThrustProblem, res: LowThrustResult) -> dict[str, float]:
    """Re-propagate the optimal control (solve_ivp, rtol 1e-10) from Earth's epv00 state plus
    the v∞ and measure the miss against the asteroid's Kepler state at arrival."""
    r0, v0 = earth_state(res.launch_mjd)
    x0 = np.concatenate([r0, v0 + res.v_inf, [prob.m0]])
    controls = np.column_stack([res.U, res.gamma])

    def control(t: float, x: np.ndarray) -> np.ndarray:
        return np.array([np.interp(t, res.t_nodes, c) for c in controls.T])

    _, X = repropagate(_si_rhs(), np.array([GM_SUN, prob.exhaust_speed]), x0, control,
                       res.t_nodes, atol=np.array([1.0] * 3 + [1e-6] * 3 + [1e-9]))
    ra, va = asteroid_state(res.arrival_mjd, prob.elements)
    return {
        "arrival_position_miss_m": float(np.linalg.norm(X[-1, 0:3] - ra)),
        "arrival_velocity_miss_m_s": float(np.linalg.norm(X[-1, 3:6] - va)),
        "final_mass_difference_kg": float(X[-1, 6] - res.X[-1, 6]),
    }


def _check_impulsive(transfer: ImpulsiveTransfer, elements) -> dict[str, float]:
    """Integrate each coast arc (solve_ivp, rtol 1e-10) and compare with the asteroid before
    the arrival impulse: an independent check of the Lambert and Kepler solutions."""
    from scipy.integrate import solve_ivp

    def rhs(_t, y):
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


MISSION = AsteroidRendezvous()
