"""Particle swarm with paper 003's schedules (eqs. 17-21), numpy-vectorised, seeded."""

from __future__ import annotations

import numpy as np
import pytest

from solvers.nlp.particle_swarm import Schedule, particle_swarm


def _rastrigin(x: np.ndarray) -> np.ndarray:
    return 10 * x.shape[1] + np.sum(x**2 - 10 * np.cos(2 * np.pi * x), axis=1)


def test_schedules_are_linear_with_the_papers_directions():
    s = Schedule()
    w0, c10, c20 = s.at(0, 101)
    w1, c11, c21 = s.at(100, 101)
    wm, c1m, c2m = s.at(50, 101)
    assert w0 > w1 and c10 > c11 and c20 < c21  # w, c1 decrease; c2 increases
    assert wm == pytest.approx((w0 + w1) / 2) and c1m == pytest.approx((c10 + c11) / 2)
    assert c2m == pytest.approx((c20 + c21) / 2)


def test_finds_the_global_minimum_of_a_multimodal_function():
    res = particle_swarm(_rastrigin, -5.12 * np.ones(3), 5.12 * np.ones(3), particles=60,
                         generations=300, seed=0)
    assert res.f < 1e-6 and np.abs(res.x).max() < 1e-3
    assert np.all(np.diff(res.history) <= 0)  # the best never gets worse
    assert res.evaluations == 60 * 301


def test_fixed_seed_repeats_and_other_seeds_differ():
    args = (_rastrigin, -5.12 * np.ones(4), 5.12 * np.ones(4))
    a = particle_swarm(*args, particles=20, generations=30, seed=7)
    b = particle_swarm(*args, particles=20, generations=30, seed=7)
    c = particle_swarm(*args, particles=20, generations=30, seed=8)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.history, b.history)
    assert not np.array_equal(a.history, c.history)


def test_particles_stay_in_the_box_and_velocity_is_clamped():
    seen = []

    def fitness(x):
        seen.append(x.copy())
        return np.sum((x - 10.0) ** 2, axis=1)  # optimum outside the box: presses on a bound

    lo, hi = np.zeros(2), np.ones(2)
    res = particle_swarm(fitness, lo, hi, particles=15, generations=40, seed=1,
                         schedule=Schedule(vmax_fraction=0.1))
    pos = np.stack(seen)
    assert pos.min() >= 0.0 and pos.max() <= 1.0
    # |step| <= vmax = 0.1 of the span for every particle and generation.
    assert np.abs(np.diff(pos, axis=0)).max() <= 0.1 + 1e-12
    assert res.x == pytest.approx([1.0, 1.0])


def test_infeasible_particles_and_early_stop():
    def fitness(x):
        return np.where(x[:, 0] > 0.5, np.nan, x[:, 0])

    res = particle_swarm(fitness, np.zeros(1), np.ones(1), particles=10, generations=50,
                         seed=2, stop=lambda gen, best: gen >= 4)
    assert res.generations == 5 and res.f <= 0.5
