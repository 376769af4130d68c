"""A mesh that follows the thrust switches of a bang–bang optimum.

With the slack σ linear between nodes (first-order hold), a switch of |T| between ρ1 and ρ2
becomes a ramp over the interval it falls in, and the fuel that ramp costs or saves grows
with the interval's length: on equal steps the fuel converges only at order 1 to 2 in N, and
not monotonically (where in its interval a switch falls changes with N). Here each switch
gets a short interval of its own (`SHORT` times the equal step) centred on it, and the other
intervals share the rest of [0, 1] by length: the nodes go where the control is not smooth
(Betts 2010, Practical Methods for Optimal Control, §4.7).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

SHORT = 0.05  # a switch's interval over the equal step 1/N
END_GRADING = 1.0
SATURATED = 0.02  # |T| within this fraction of ρ2 - ρ1 from a bound is on that bound


def switch_times(t: np.ndarray, thrust: np.ndarray, rho1: float, rho2: float) -> list[float]:
    """The times of the equivalent bang–bang switches: between a node on one thrust bound
    and the next node on the other, the step that gives the same impulse as the ramp the
    discrete answer draws (the integral of (|T| - ρ1) / (ρ2 - ρ1), trapezoidal as σ is
    linear between nodes)."""
    f = (np.asarray(thrust, float) - rho1) / (rho2 - rho1)
    level = np.where(f >= 1 - SATURATED, 1, np.where(f <= SATURATED, 0, -1))
    on_bound = np.flatnonzero(level >= 0)
    switches = []
    for a, b in zip(on_bound[:-1], on_bound[1:], strict=True):
        if level[a] == level[b]:
            continue
        impulse = float(np.sum((f[a:b] + f[a + 1:b + 1]) / 2 * np.diff(t[a:b + 1])))
        switches.append(t[a] + impulse if level[a] == 1 else t[b] - impulse)
    return switches


def switch_mesh(n_intervals: int, switches: Sequence[float], short: float = SHORT
                ) -> np.ndarray | None:
    """Node positions τ in [0, 1] with an interval of width `short / n_intervals` centred on
    each switch (fractions of t_f); None when the switches do not leave every other stretch
    at least one interval (too many, or too close to each other or to the ends)."""
    n = n_intervals
    width = short / n
    cuts = [0.0]
    for s in sorted(switches):
        lo, hi = s - width / 2, s + width / 2
        if lo <= cuts[-1] + width or hi >= 1.0 - width:
            return None
        cuts += [lo, hi]
    cuts.append(1.0)
    stretches = np.diff(cuts)[0::2]  # between the switches' intervals
    n_long = n - len(switches)
    if n_long < len(stretches):
        return None
    share = stretches / stretches.sum() * n_long
    counts = np.maximum(np.floor(share).astype(int), 1)
    while counts.sum() < n_long:  # largest remainders first
        counts[int(np.argmax(share - counts))] += 1
    while counts.sum() > n_long:
        counts[int(np.argmax(np.where(counts > 1, counts - share, -np.inf)))] -= 1
    tau = []
    for j, count in enumerate(counts):
        u = np.linspace(0.0, 1.0, count + 1)[:-1]
        if j == len(counts) - 1:
            u = 1.0 - (1.0 - u) ** END_GRADING
        tau.append(cuts[2 * j] + (cuts[2 * j + 1] - cuts[2 * j]) * u)
        if j < len(switches):
            tau.append([cuts[2 * j + 1]])
    return np.concatenate([*tau, [1.0]])


def equal_mesh(tf: float) -> None:
    """The mesh of equal steps at any final time."""
    return None


def anchored_mesh(n_intervals: int, switches: Sequence[float], ref: float
                  ) -> Callable[[float], np.ndarray | None]:
    """The switch mesh for switches found at final time `ref`, as a function of t_f: a
    switch in the first half of the flight keeps its time from the start, a later one its
    time before touchdown. (With the mesh fixed in τ instead, only `ref` would have its
    switches on their intervals, and a search over t_f could not leave it.)"""
    def mesh(tf: float) -> np.ndarray | None:
        return switch_mesh(n_intervals, [s / tf if s < ref / 2 else 1 - (ref - s) / tf
                                         for s in switches])
    return mesh
