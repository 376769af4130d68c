"""The asteroid's live method: the burn/coast structure of a Hermite–Simpson optimum, solved
again with free switch times (`burn_coast.py`). A cold solve runs the swarm and the
400-segment Hermite–Simpson NLP to find the structure (seconds; a coarser one led the
fixed-structure solve into another local optimum, a 700 d transfer); a slider move re-solves
the fixed-structure NLP from the last answer (tens of ms). Where the structure no longer holds (a
phase shrinks to nothing, or the warm solve fails) the structure is found again.

Solution arrays are SI (s from launch, m, m/s, kg, N), as the Hermite–Simpson method's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ...context import SolveContext
from ...dynamics.ephemeris import (
    TU,
    VU,
    iso_from_mjd,
)
from ...nlp.casadi_nlp import NLPResult, status_of
from ...problem import Method
from ...solution import Quantity, Solution, WarmStart
from ...verify import repropagate
from .burn_coast import BurnCoastNLP, Layout, built, direction, state
from .guess import impulsive_guess, same_guess
from .methods import (
    ATOL,
    LOW_THRUST,
    arrival_misses,
    departure_state,
    guess_quantities,
    rhs_parameters,
    solve_low_thrust,
    transfer_quantities,
)
from .model import SI_UNITS, si_rhs, to_mjd, to_si
from .problem import PAPER, parameter_vector

if TYPE_CHECKING:
    from ...mission import Mission

WARM_KIND = "asteroid-burn-coast"
MIN_SHARE = 1e-3  # a phase shorter than this share of the flight has vanished
BLIP = 1e-3  # a Hermite–Simpson arc shorter than this share of its flight is merged away
SAMPLES = 12  # drawn samples per interval

BURN_COAST = Method(
    "burn-coast", "Burn/coast phases with free switch times (Gauss–Legendre)", PAPER,
    "The burn/coast sequence of the Hermite–Simpson optimum (paper 003's swarm seeds it), "
    "solved again with each phase's duration free: full thrust along a unit "
    "direction on burns, no thrust on coasts, degree-5 Gauss–Legendre collocation on equal "
    "intervals per phase, the flight ending at the last burn. A slider move re-solves it in "
    "a few Newton steps; where a phase vanishes the structure is found again.",
    nodes=(8, 24, 60), nodes_label="intervals", backends=("ipopt",),
)


def solve_burn_coast(mission: Mission, values: dict[str, float], nodes: int, backend: str,
                     warm: Solution | None, ctx: SolveContext) -> Solution:
    """From the last answer's structure when it has one (and the same first guess), else
    from a Hermite–Simpson optimum's."""
    p = parameter_vector(values)
    found = None
    if _continues(warm, values):
        nlp, z0, lam = _from_answer(warm.warm, nodes, backend)
        found = _solve(nlp, p, z0, lam, ctx)
    if found is None:
        hs = solve_low_thrust(mission, values, LOW_THRUST.nodes[1], backend, None, ctx)
        if not hs.converged:
            hs.method, hs.nodes, hs.checker = BURN_COAST.key, nodes, None
            hs.message = (f"the Hermite–Simpson solve that finds the burn/coast structure "
                          f"ended {hs.status}: {hs.message}")
            return hs
        nlp, z0 = _from_hermite_simpson(hs, nodes, backend)
        found = _solve(nlp, p, z0, None, ctx, keep=True)
    nlp, res = found
    return record(values, nlp, res, nodes, backend, ctx)


def _continues(warm: Solution | None, values: dict[str, float]) -> bool:
    return (warm is not None and warm.converged and warm.warm is not None
            and warm.warm.kind == WARM_KIND and same_guess(warm.values, values))


def _solve(nlp: BurnCoastNLP, p: np.ndarray, z0: np.ndarray,
           lam: tuple[np.ndarray, np.ndarray] | None, ctx: SolveContext, keep: bool = False
           ) -> tuple[BurnCoastNLP, NLPResult] | None:
    """The solve, or None where the structure did not hold (unless `keep`)."""
    res = nlp.solve(p, z0, lam, ctx)
    _, _, durations = nlp.times(res.x)
    held = status_of(res)[0] == "optimal" and durations.min() > MIN_SHARE * durations.sum()
    return (nlp, res) if held or keep else None


def _from_answer(answer: WarmStart, nodes: int, backend: str
                 ) -> tuple[BurnCoastNLP, np.ndarray, tuple[np.ndarray, np.ndarray] | None]:
    """The last answer's NLP and point (with multipliers), or its trajectory on `nodes`."""
    kinds, durations = tuple(answer.data["kinds"]), np.asarray(answer.data["durations"])
    if answer.n_intervals == nodes and answer.data["backend"] == backend:
        nlp = built(Layout(kinds, tuple(answer.data["intervals"])), backend)
        return nlp, answer.z, (answer.lam_x, answer.lam_g)
    nlp = built(Layout.share(kinds, durations, nodes), backend)
    z0 = nlp.seed(answer.t0, answer.statics, durations, answer.tau * answer.T, answer.X,
                  answer.U)
    return nlp, z0, None


def _from_hermite_simpson(hs: Solution, nodes: int, backend: str
                          ) -> tuple[BurnCoastNLP, np.ndarray]:
    """The NLP of the Hermite–Simpson optimum's structure (a final coast dropped, short
    blips merged) and a start from its nodes."""
    arcs: list[list] = []
    for start, end, kind in hs.arcs:
        if end - start <= BLIP * hs.t[-1]:
            continue
        if arcs and arcs[-1][2] == kind:
            arcs[-1][1] = end
        else:
            arcs.append([start, end, kind])
    if arcs and arcs[-1][2] == "coast":
        arcs.pop()
    kinds = tuple(a[2] for a in arcs)
    durations = np.array([a[1] - a[0] for a in arcs]) / TU
    if arcs:  # the phases tile [0, last burn's end]
        durations[0] += arcs[0][0] / TU
    nlp = built(Layout.share(kinds, durations, nodes), backend)
    w = hs.warm
    z0 = nlp.seed(w.t0, w.statics, durations, w.tau * w.T, w.X, w.U[:, 0:3])
    return nlp, z0


def record(values: dict[str, float], nlp: BurnCoastNLP, res: NLPResult, nodes: int,
           backend: str, ctx: SolveContext) -> Solution:
    """The SI solution of one fixed-structure solve."""
    status, message = status_of(res)
    m0, fmax = values["mass0"], values["thrust"]
    t0, vinf, durations = nlp.times(res.x)
    pieces = nlp.pieces(res.x)
    end_state = res.x[nlp.i_xf:nlp.i_xf + 7]
    flight = float(durations.sum())
    node_t = np.array([a for a, *_ in pieces] + [flight])
    node_x = np.array([states[0] for _, _, states, _ in pieces] + [end_state])
    node_dirs = np.array([np.zeros(3) if d is None else direction(d, 0.0)[0]
                          for *_, d in pieces] + [np.zeros(3)])
    s = np.linspace(0.0, 1.0, SAMPLES, endpoint=False)
    t = np.concatenate([a + h * s for a, h, _, _ in pieces] + [[flight]])
    x = np.vstack([state(states, s) for _, _, states, _ in pieces] + [end_state[None]])
    u = np.vstack([np.zeros((SAMPLES, 3)) if d is None else direction(d, s)
                   for *_, d in pieces] + [np.zeros((1, 3))])
    launch, arrival = float(to_mjd(t0)), float(to_mjd(t0 + flight))
    fuel = float(m0 * (1.0 - end_state[6]))
    bounds = np.concatenate([[0.0], np.cumsum(durations)]) * TU
    arcs = [(float(a), float(b), kind) for a, b, kind
            in zip(bounds[:-1], bounds[1:], nlp.layout.kinds, strict=True) if b > a]
    burns = sum(1 for *_, kind in arcs if kind == "burn")
    sol = Solution(
        mission="asteroid-rendezvous", method=BURN_COAST.key, nodes=nodes, backend=backend,
        status=status, message=(f"{message}; {'–'.join(nlp.layout.kinds)}, launch "
                                f"{iso_from_mjd(launch)}, arrival {iso_from_mjd(arrival)}"),
        cost=Quantity(fuel, "fuel", "kg"), values=values,
        state_names=("x", "y", "z", "vx", "vy", "vz", "m"), state_units=SI_UNITS,
        control_names=("Fx", "Fy", "Fz"), control_units=("N",) * 3,
        node_t=node_t * TU, node_x=to_si(node_x, m0), node_u=node_dirs * fmax, arcs=arcs,
        t=t * TU, x=to_si(x, m0), u=u * fmax, control_interpolation="dense",
    )
    sol.quantities = transfer_quantities(launch, arrival, fuel, m0 - fuel, burns, vinf * VU)
    guess_quantities(sol, impulsive_guess(values, ctx))
    sol.stats.update(iterations=float(res.iterations), nlp_variables=float(nlp.n_x),
                     constraint_violation=res.max_violation)
    sol.warm = WarmStart(WARM_KIND, nodes, node_t / flight, node_x, node_dirs, flight,
                         z=res.x, lam_x=res.lam_x, lam_g=res.lam_g, t0=t0, statics=vinf,
                         data={"kinds": nlp.layout.kinds, "intervals": nlp.layout.intervals,
                               "durations": durations.tolist(), "backend": backend})
    if status == "optimal":
        sol.checker = lambda: check(values, pieces, t0, vinf, flight, m0 - fuel)
    return sol


def check(values: dict[str, float], pieces: list, t0: float, vinf: np.ndarray,
          flight: float, final_mass: float) -> dict[str, float]:
    """Re-propagate (DOP853, rtol 1e-10) in SI from Earth's epv00 state at launch plus the
    v∞, interval by interval with that interval's own control (full thrust along its
    interpolated direction, or none: exact at the switches), and measure the miss against
    the asteroid's Kepler state at arrival."""
    fmax = values["thrust"]
    x = departure_state(values, t0, vinf)
    f, p = si_rhs(), rhs_parameters(values)
    for a, h, _, dirs in pieces:
        if h <= 0.0:
            continue

        def control(t: float, _x: np.ndarray, a: float = a, h: float = h,
                    dirs: np.ndarray | None = dirs) -> np.ndarray:
            if dirs is None:
                return np.zeros(4)
            return np.append(fmax * direction(dirs, (t / TU - a) / h)[0], fmax)

        _, X = repropagate(f, p, x, control, np.array([a, a + h]) * TU, atol=ATOL)
        x = X[-1]
    return arrival_misses(values, t0 + flight, x, final_mass)
