"""Particle swarm optimisation with the schedules of paper 003 (section 3.1), numpy-vectorised.

Velocity and position updates (paper 003 eqs. 17-18):
    v <- w v + c1 r1 (pbest - p) + c2 r2 (gbest - p),   v clamped to [-vmax, vmax],
    p <- p + v,   clamped to the box;
with the inertia weight w and the local (cognitive) factor c1 decreasing linearly and the
global (social) factor c2 increasing linearly over the generations (eqs. 19-21). The scan
prints the social term as c2 r (gb - pb); we read it as the standard (gb - p), since with
(gb - pb) a particle's position would not pull it towards the swarm's best at all. The
paper's table 1 (the numbers of the schedules) did not survive the scan: the defaults below
are the usual time-varying coefficients (Ratnaweera et al. 2004).

The fitness is called once per generation with all particles, shape (n_particles, dim), so
it can be vectorised too. A fixed seed makes runs repeatable.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

Fitness = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Schedule:
    """Linear schedules of w, c1, c2 from their first to their last generation values."""

    w: tuple[float, float] = (0.9, 0.4)
    c1: tuple[float, float] = (2.5, 0.5)
    c2: tuple[float, float] = (0.5, 2.5)
    vmax_fraction: float = 0.2

    def at(self, generation: int, generations: int) -> tuple[float, float, float]:
        """(w, c1, c2) at a generation (paper 003 eqs. 19-21: linear in c / cmax)."""
        s = generation / max(generations - 1, 1)
        return tuple(a + (b - a) * s for a, b in (self.w, self.c1, self.c2))  # type: ignore[return-value]


@dataclass
class SwarmResult:
    """Best position and fitness, and the best fitness after every generation."""

    x: np.ndarray
    f: float
    history: np.ndarray
    evaluations: int
    generations: int
    final_positions: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 0)))


def particle_swarm(
    fitness: Fitness,
    lower: np.ndarray,
    upper: np.ndarray,
    particles: int = 60,
    generations: int = 200,
    seed: int = 0,
    schedule: Schedule | None = None,
    initial: np.ndarray | None = None,
    stop: Callable[[int, float], bool] | None = None,
) -> SwarmResult:
    """Minimise `fitness` over the box [lower, upper].

    `initial` optionally places the first particles (e.g. a previous optimum); `stop(gen,
    best)` may end the run early (cancellation). Non-finite fitness counts as +inf.
    """
    sched = schedule or Schedule()
    lower = np.asarray(lower, float)
    upper = np.asarray(upper, float)
    span = upper - lower
    vmax = sched.vmax_fraction * span
    rng = np.random.default_rng(seed)
    pos = lower + rng.random((particles, lower.size)) * span
    if initial is not None:
        init = np.atleast_2d(np.asarray(initial, float))[:particles]
        pos[: len(init)] = np.clip(init, lower, upper)
    vel = (rng.random(pos.shape) * 2.0 - 1.0) * vmax
    f = _evaluate(fitness, pos)
    best_pos, best_f = pos.copy(), f.copy()
    g = int(np.argmin(best_f))
    history = np.empty(generations)
    evaluations = particles
    done = 0
    for gen in range(generations):
        w, c1, c2 = sched.at(gen, generations)
        r1 = rng.random(pos.shape)
        r2 = rng.random(pos.shape)
        vel = w * vel + c1 * r1 * (best_pos - pos) + c2 * r2 * (best_pos[g] - pos)
        vel = np.clip(vel, -vmax, vmax)
        pos = np.clip(pos + vel, lower, upper)
        f = _evaluate(fitness, pos)
        evaluations += particles
        improved = f < best_f
        best_pos[improved] = pos[improved]
        best_f[improved] = f[improved]
        g = int(np.argmin(best_f))
        history[gen] = best_f[g]
        done = gen + 1
        if stop is not None and stop(gen, float(best_f[g])):
            break
    return SwarmResult(best_pos[g].copy(), float(best_f[g]), history[:done], evaluations, done,
                       pos)


def _evaluate(fitness: Fitness, pos: np.ndarray) -> np.ndarray:
    f = np.asarray(fitness(pos), float).reshape(len(pos))
    return np.where(np.isfinite(f), f, np.inf)
