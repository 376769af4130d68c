"""How far the hovercraft can travel along one axis: the necessary conditions of its precheck
(issue 17).

Along an axis the acceleration is at most the thrust acceleration a = A/m in size, whatever
the steering (|u| <= 1 in both control forms), and the speed stays within the state box
[lo, hi]. So in a manoeuvre of duration T from speed v0 to speed vf the speed v(t) lies
under the ceiling min(hi, v0 + a t, vf + a (T - t)) and above the floor
max(lo, v0 - a t, vf - a (T - t)), and the distance travelled lies between the floor's
area and the ceiling's. Each area is exact (the envelopes are piecewise linear, integrated
between their breakpoints); the ceiling's area is convex in T and the floor's concave (the
slope of each is its end value plus a times a length that grows with T), so over an interval
of durations the extremes are at its ends. Stopping is the same bound: moving toward an
edge at speed v takes v²/(2a) to stop (or as much of it as the manoeuvre surely lasts), and
time reversed, arriving at speed v from the other side needs as much room behind.
"""

from __future__ import annotations

import numpy as np


def ceiling_area(v0: float, vf: float, hi: float, a: float, T: float) -> float:
    """The area under min(hi, v0 + a t, vf + a (T - t)) on [0, T]: the farthest an axis can
    travel in T (v0, vf <= hi and |vf - v0| <= a T)."""
    def ceiling(t: np.ndarray) -> np.ndarray:
        return np.minimum(np.minimum(hi, v0 + a * t), vf + a * (T - t))

    corners = [0.0, T, (hi - v0) / a, T - (hi - vf) / a, (vf - v0 + a * T) / (2 * a)]
    t = np.unique(np.clip(corners, 0.0, T))
    return float(np.trapezoid(ceiling(t), t))


def floor_area(v0: float, vf: float, lo: float, a: float, T: float) -> float:
    """The area under max(lo, v0 - a t, vf - a (T - t)): the least an axis can travel."""
    return -ceiling_area(-v0, -vf, -lo, a, T)


def travel_range(v0: float, vf: float, lo: float, hi: float, a: float,
                 durations: tuple[float, float]) -> tuple[float, float]:
    """The least and the most an axis can travel in a duration within `durations`."""
    return (min(floor_area(v0, vf, lo, a, T) for T in durations),
            max(ceiling_area(v0, vf, hi, a, T) for T in durations))


def overshoot(p: float, v: float, lo: float, hi: float, a: float, horizon: float) -> float:
    """How far beyond the edge of [lo, hi] that a point at p moving at v toward it goes
    within `horizon` (a time the manoeuvre surely lasts) at the least (<= 0: none): braking
    at a, it travels |v| t - a t²/2 toward the edge until it stops at t = |v|/a."""
    t = min(abs(v) / a, horizon)
    reach = abs(v) * t - a * t * t / 2
    return p + reach - hi if v > 0 else lo - (p - reach) if v < 0 else -1.0
