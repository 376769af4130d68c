"""Impulsive first guesses for the Earth–asteroid transfer (paper 003, section 3.1).

Three kinds, each a particle-swarm search over impulse times and impulse vectors:
- two-impulse single-revolution: launch date and flight time; the impulses are those of the
  zero-revolution Lambert arc;
- three-impulse: launch date, the launch v∞ vector, a mid-course impulse time and the flight
  time; the mid-course and arrival impulses come from a Lambert arc from the coasted state;
- two-impulse multi-revolution: launch date, flight time and Lambert branch, one revolution.

Fitness: total Δv of the spacecraft after launch (mid-course plus arrival impulses), with the
launch impulse — the v∞ the launcher delivers — bounded by C3 = |v∞|² <= C3max (a penalty for
the Lambert kinds, by construction for the three-impulse kind). The low-thrust problem has
the same structure: free v∞ within the C3 bound, fuel for everything after launch.

A fourth choice, "Lambert arc at chosen dates", takes the lowest-C3 Lambert arc between two
dates (a cell of the launch map). The chosen transfer seeds the low-thrust NLP
(`low_thrust_guess`, paper 003 section 3.1 step 5).

Numerics run in canonical units (AU, TU = sqrt(AU³/GM_sun) ≈ year/2π, GM_sun = 1); the
results are returned in SI with dates as MJD TDB.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from ...context import SolveContext
from ...dynamics.ephemeris import (
    AU,
    DAY,
    ELEMENT_SETS,
    MJD_2022,
    TU,
    VU,
    ElementSet,
    asteroid_state,
    earth_state_fast,
)
from ...dynamics.kepler import propagate
from ...dynamics.lambert import lambert
from ...nlp.particle_swarm import Schedule, particle_swarm
from ...solution import WarmStart
from .model import G0, to_tu

KINDS = ("two-impulse single-revolution", "three-impulse", "two-impulse multi-revolution")
SINGLE, THREE, MULTI = range(3)
GUESS_OPTIONS = (*KINDS, "Lambert arc at chosen dates (lowest C3, 0-1 rev)")
CHOSEN_DATES = len(KINDS)
DAY_TU = DAY / TU
MIN_TOF_DAYS = 20.0
PENALTY = 10.0  # Δv penalty per unit of v∞ above the C3 bound (both in VU)


@dataclass(frozen=True)
class Window:
    """The search box: launch dates (MJD TDB), flight times (days), launch C3 bound (m²/s²)."""

    launch_start: float
    launch_end: float
    max_tof_days: float
    c3_max: float
    elements: ElementSet

    @property
    def vinf_max(self) -> float:
        """Largest launch v∞ in VU."""
        return float(np.sqrt(max(self.c3_max, 0.0))) / VU


@dataclass
class ImpulsiveTransfer:
    """An impulsive transfer in SI (dates MJD TDB): its impulses and its Kepler arcs."""

    kind: int
    launch_mjd: float
    arrival_mjd: float
    impulse_mjd: np.ndarray  # (k,) launch, [mid-course], arrival
    arc_r: np.ndarray  # (k-1, 3) m: position at the start of each coast arc
    arc_v: np.ndarray  # (k-1, 3) m/s: velocity after the impulse starting each arc
    impulses: np.ndarray  # (k, 3) m/s: launch v∞, [mid-course Δv], arrival Δv
    revs: int = 0
    evaluations: int = 0
    history: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def flight_days(self) -> float:
        return self.arrival_mjd - self.launch_mjd

    @property
    def v_inf(self) -> np.ndarray:
        return self.impulses[0]

    @property
    def c3(self) -> float:
        return float(self.impulses[0] @ self.impulses[0])

    @property
    def total_dv(self) -> float:
        """Spacecraft Δv after launch [m/s] (the PSO fitness without penalty)."""
        return float(np.sum(np.linalg.norm(self.impulses[1:], axis=-1)))

    def states(self, mjd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Position [m] and velocity [m/s] along the coast arcs at dates within the transfer
        (the velocity just after an impulse at an impulse date, before it at arrival)."""
        mjd = np.asarray(mjd, float)
        arc = np.clip(np.searchsorted(self.impulse_mjd, mjd, side="right") - 1, 0,
                      len(self.arc_r) - 1)
        dt = (mjd - self.impulse_mjd[arc]) * DAY_TU
        r, v = propagate(self.arc_r[arc] / AU, self.arc_v[arc] / VU, dt, 1.0)
        return r * AU, v * VU


def earth_canonical(mjd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r, v = earth_state_fast(mjd)
    return r / AU, v / VU


def asteroid_canonical(mjd: np.ndarray, elements: ElementSet) -> tuple[np.ndarray, np.ndarray]:
    r, v = asteroid_state(mjd, elements)
    return r / AU, v / VU


def _penalty(vinf: np.ndarray, window: Window) -> np.ndarray:
    return PENALTY * np.maximum(np.linalg.norm(vinf, axis=-1) - window.vinf_max, 0.0)


def _fitness_lambert(window: Window, revs: int) -> Callable[[np.ndarray], np.ndarray]:
    """Fitness of the two-impulse kinds: particle = (launch MJD, flight days[, branch])."""

    def fitness(x: np.ndarray) -> np.ndarray:
        t0, tof = x[:, 0], x[:, 1]
        rE, vE = earth_canonical(t0)
        rA, vA = asteroid_canonical(t0 + tof, window.elements)
        if revs == 0:
            v1, v2, ok = lambert(rE, rA, tof * DAY_TU, 1.0)
        else:
            v1, v2, ok = lambert(rE, rA, tof * DAY_TU, 1.0, revs, x[:, 2] < 0.5)
        vinf = v1 - vE
        f = np.linalg.norm(vA - v2, axis=-1) + _penalty(vinf, window)
        return np.where(ok, f, np.inf)

    return fitness


def _vinf_vector(rE: np.ndarray, vE: np.ndarray, p: np.ndarray, window: Window) -> np.ndarray:
    """Launch v∞ from (fraction of the C3 bound's speed, azimuth from Earth's velocity in
    the orbit plane, elevation out of it): the three-impulse particle's launch impulse."""
    t_hat = vE / np.linalg.norm(vE, axis=-1, keepdims=True)
    h = np.cross(rE, vE)
    z_hat = h / np.linalg.norm(h, axis=-1, keepdims=True)
    n_hat = np.cross(z_hat, t_hat)
    mag, az, el = p[:, 0] * window.vinf_max, p[:, 1], p[:, 2]
    return mag[:, None] * (np.cos(el)[:, None] * (np.cos(az)[:, None] * t_hat
                                                  + np.sin(az)[:, None] * n_hat)
                           + np.sin(el)[:, None] * z_hat)


def _three_impulse_arcs(x: np.ndarray, window: Window) -> tuple[np.ndarray, ...]:
    """Coast from launch to the mid-course impulse, then the Lambert arc to the asteroid.
    Particle = (launch MJD, |v∞| fraction, azimuth, elevation, mid-course fraction, days)."""
    t0, frac, tof = x[:, 0], x[:, 4], x[:, 5]
    rE, vE = earth_canonical(t0)
    vinf = _vinf_vector(rE, vE, x[:, 1:4], window)
    t_mid = frac * tof
    r_mid, v_mid = propagate(rE, vE + vinf, t_mid * DAY_TU, 1.0)
    rA, vA = asteroid_canonical(t0 + tof, window.elements)
    v1, v2, ok = lambert(r_mid, rA, (tof - t_mid) * DAY_TU, 1.0)
    return rE, vE, vinf, r_mid, v_mid, v1, v2, rA, vA, ok


def _fitness_three(window: Window) -> Callable[[np.ndarray], np.ndarray]:
    def fitness(x: np.ndarray) -> np.ndarray:
        _, _, _, _, v_mid, v1, v2, _, vA, ok = _three_impulse_arcs(x, window)
        f = np.linalg.norm(v1 - v_mid, axis=-1) + np.linalg.norm(vA - v2, axis=-1)
        return np.where(ok, f, np.inf)

    return fitness


def search_box(kind: int, window: Window) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of a kind's particle."""
    t_lo, t_hi, tof_hi = window.launch_start, window.launch_end, window.max_tof_days
    if kind == SINGLE:
        return np.array([t_lo, MIN_TOF_DAYS]), np.array([t_hi, tof_hi])
    if kind == MULTI:
        return np.array([t_lo, MIN_TOF_DAYS, 0.0]), np.array([t_hi, tof_hi, 1.0])
    return (np.array([t_lo, 0.0, -np.pi, -np.pi / 2, 0.05, MIN_TOF_DAYS]),
            np.array([t_hi, 1.0, np.pi, np.pi / 2, 0.95, tof_hi]))


def pso_search(
    kind: int,
    window: Window,
    particles: int = 80,
    generations: int = 150,
    seed: int = 0,
    stop: Callable[[int, float], bool] | None = None,
) -> ImpulsiveTransfer:
    """Particle-swarm search of one kind of impulsive transfer (paper 003 section 3.1)."""
    if kind == SINGLE:
        fitness = _fitness_lambert(window, 0)
    elif kind == MULTI:
        fitness = _fitness_lambert(window, 1)
    elif kind == THREE:
        fitness = _fitness_three(window)
    else:
        raise ValueError(f"unknown guess kind {kind} (kinds: {', '.join(KINDS)})")
    lo, hi = search_box(kind, window)
    res = particle_swarm(fitness, lo, hi, particles, generations, seed, Schedule(), stop=stop)
    if not np.isfinite(res.f):
        raise ValueError("the particle swarm found no feasible impulsive transfer in the window")
    x = res.x[None, :]
    if kind == THREE:
        transfer = _three_impulse_transfer(x, window)
    else:
        branch = "left" if kind == SINGLE or x[0, 2] < 0.5 else "right"
        transfer = lambert_transfer(float(x[0, 0]), float(x[0, 1]), window,
                                    1 if kind == MULTI else 0, branch)
    transfer.kind = kind
    transfer.evaluations = res.evaluations
    transfer.history = res.history * VU
    return transfer


def lambert_transfer(
    launch_mjd: float, tof_days: float, window: Window, revs: int = 0, branch: str = "left"
) -> ImpulsiveTransfer:
    """The two-impulse Lambert transfer for one (launch date, flight time) pair."""
    t = np.array([launch_mjd])
    rE, vE = earth_canonical(t)
    rA, vA = asteroid_canonical(t + tof_days, window.elements)
    v1, v2, ok = lambert(rE, rA, tof_days * DAY_TU, 1.0, revs, branch)
    if not ok[0]:
        raise ValueError(f"no {revs}-revolution Lambert arc for a {tof_days:.1f} d flight")
    return ImpulsiveTransfer(
        kind=MULTI if revs else SINGLE,
        launch_mjd=float(launch_mjd),
        arrival_mjd=float(launch_mjd + tof_days),
        impulse_mjd=np.array([launch_mjd, launch_mjd + tof_days]),
        arc_r=rE * AU,
        arc_v=v1 * VU,
        impulses=np.vstack([v1 - vE, vA - v2]) * VU,
        revs=revs,
    )


def lowest_c3_transfer(
    launch_mjd: float, tof_days: float, window: Window, max_revs: int = 1
) -> ImpulsiveTransfer:
    """The Lambert transfer with the lowest launch C3 over 0..`max_revs` revolutions and both
    branches: the arc a cell of the launch map stands for (`launch_c3_rows`)."""
    best = None
    for revs in range(max_revs + 1):
        for branch in ("left", "right") if revs else ("left",):
            try:
                transfer = lambert_transfer(launch_mjd, tof_days, window, revs, branch)
            except ValueError:
                continue
            if best is None or transfer.c3 < best.c3:
                best = transfer
    if best is None:
        raise ValueError(f"no Lambert arc for a {tof_days:.1f} d flight")
    return best


def _three_impulse_transfer(x: np.ndarray, window: Window) -> ImpulsiveTransfer:
    rE, vE, vinf, r_mid, v_mid, v1, v2, rA, vA, _ = _three_impulse_arcs(x, window)
    t0, frac, tof = float(x[0, 0]), float(x[0, 4]), float(x[0, 5])
    return ImpulsiveTransfer(
        kind=THREE,
        launch_mjd=t0,
        arrival_mjd=t0 + tof,
        impulse_mjd=np.array([t0, t0 + frac * tof, t0 + tof]),
        arc_r=np.vstack([rE, r_mid]) * AU,
        arc_v=np.vstack([vE + vinf, v1]) * VU,
        impulses=np.vstack([vinf, v1 - v_mid, vA - v2]) * VU,
    )


# ---- the request's first guess (cached) and the low-thrust seed ---------------------------
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

# Values that define the first guess and the search window: a warm start from a solution
# made with other values would silently replace the guess being studied.
GUESS_KEYS = ("launch_start", "launch_end", "max_flight_time", "c3_max", "guess_kind",
              "seed_launch", "seed_flight_time", "elements", "pso_seed", "pso_particles",
              "pso_generations")


def same_guess(a: Mapping[str, float], b: Mapping[str, float]) -> bool:
    """Whether two value sets define the same first guess and window."""
    return all(a.get(k) == b.get(k) for k in GUESS_KEYS)


def window_of(values: Mapping[str, float]) -> Window:
    """The search window of a validated value set (dates as MJD TDB)."""
    return Window(MJD_2022 + values["launch_start"], MJD_2022 + values["launch_end"],
                  values["max_flight_time"], values["c3_max"],
                  ELEMENT_SETS[int(values["elements"])])


def impulsive_guess(values: Mapping[str, float], ctx: SolveContext | None = None
                    ) -> ImpulsiveTransfer:
    """The first-stage impulsive transfer of a value set (PSO results cached: they are
    deterministic for a fixed seed, and a thrust change needs no new search)."""
    window = window_of(values)
    kind = int(values["guess_kind"])
    if kind == CHOSEN_DATES:
        try:
            return lowest_c3_transfer(MJD_2022 + values["seed_launch"],
                                      values["seed_flight_time"], window)
        except ValueError as exc:  # a guess that does not exist proves nothing of the problem
            raise RuntimeError(f"{exc} at the chosen dates: choose other seed dates or "
                               "another guess kind") from None
    key = _GuessKey(kind, window, int(values["pso_particles"]), int(values["pso_generations"]),
                    int(values["pso_seed"]))
    with _CACHE_LOCK:
        cached = _GUESS_CACHE.get(key)
    if cached is not None:
        return cached
    stop = None if ctx is None else (lambda gen, best: ctx.should_stop())
    try:
        transfer = pso_search(kind, window, key.particles, key.generations, key.seed, stop)
    except ValueError:  # no arc of this kind: the guess, not the problem, is impossible
        hint = (" (one revolution takes about a year here)" if kind == MULTI else "")
        raise RuntimeError(
            f"no {KINDS[kind]} transfer fits the window: none of the particle swarm's "
            f"candidates has an arc of that kind within the {window.max_tof_days:g} d allowed"
            f"{hint}; choose another guess kind, a longer maximum flight time or a wider "
            "launch window") from None
    if ctx is not None:
        ctx.checkpoint()
    with _CACHE_LOCK:
        if len(_GUESS_CACHE) >= GUESS_CACHE_SIZE:
            _GUESS_CACHE.pop(next(iter(_GUESS_CACHE)))
        _GUESS_CACHE[key] = transfer
    return transfer


def low_thrust_guess(transfer: ImpulsiveTransfer, values: Mapping[str, float], segments: int
                     ) -> WarmStart:
    """Paper 003 §3.1 step 5, canonical units: node states from the impulsive arcs, masses
    falling linearly to the rocket-equation final mass of the impulsive Δv, thrust
    Fmax·(0.5, 0.5, 0.5) with Γ = |U|, the launch v∞ (shortened to the C3 bound) as the
    static variables; a primal-only guess the transcription re-interpolates."""
    tau = np.linspace(0.0, 1.0, segments + 1)
    r, v = transfer.states(transfer.launch_mjd + tau * transfer.flight_days)
    m_final = np.exp(-transfer.total_dv / (values["isp"] * G0))
    X = np.column_stack([r / AU, v / VU, np.linspace(1.0, m_final, segments + 1)])
    thrust = np.array([0.5, 0.5, 0.5])
    U = np.tile([*thrust, np.linalg.norm(thrust)], (segments + 1, 1))
    vinf = transfer.v_inf
    vmax = np.sqrt(max(values["c3_max"], 0.0))
    speed = float(np.linalg.norm(vinf))
    if speed > vmax:
        vinf = vinf * (vmax / speed)
    return WarmStart("guess", segments, tau, X, U, transfer.flight_days * DAY_TU,
                     t0=float(to_tu(transfer.launch_mjd)), statics=vinf / VU)
