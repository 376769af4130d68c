"""Where the vehicle is at time t and which way it points.

Pure numpy (tested without a browser): `Track` samples a solution's presentation at any time
of its trajectory in display units; the play panel moves the vehicle mesh with it. Everything
comes from the contracts (path and node thrust vectors of the Presentation, arcs and times of
the Solution), so every mission animates without code of its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from solvers.presentation import Presentation
from solvers.solution import Solution

from .geometry import up_axis

PLAY_SECONDS = 12.0  # wall-clock length of a whole run at speed 1x
SPEEDS = {"0.25x": 0.25, "0.5x": 0.5, "1x": 1.0, "2x": 2.0, "4x": 4.0, "real time": 0.0}


@dataclass
class Pose:
    """The vehicle at one time, in display units."""

    t: float
    position: np.ndarray  # (3,)
    wxyz: np.ndarray  # body +z (thrust axis) -> `axis`, body +y as close to 'up' as it goes
    axis: np.ndarray  # unit vector the vehicle points along
    throttle: float  # 0..1: plume length
    force: np.ndarray  # (3,) thrust/force vector at t (unit length x throttle), display frame
    burning: bool


def quaternion_from_axes(z_axis: np.ndarray, up: np.ndarray) -> np.ndarray:
    """wxyz of the rotation taking body z to `z_axis` and body y towards `up`."""
    z = z_axis / np.linalg.norm(z_axis)
    y = up - up.dot(z) * z
    if np.linalg.norm(y) < 1e-6:  # up along the axis: any perpendicular will do
        ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        y = ref - ref.dot(z) * z
    y /= np.linalg.norm(y)
    x = np.cross(y, z)
    m = np.column_stack([x, y, z])
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    xq = math.copysign(math.sqrt(max(0.0, 1.0 + m[0, 0] - m[1, 1] - m[2, 2])) / 2.0,
                       m[2, 1] - m[1, 2])
    yq = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] + m[1, 1] - m[2, 2])) / 2.0,
                       m[0, 2] - m[2, 0])
    zq = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] - m[1, 1] + m[2, 2])) / 2.0,
                       m[1, 0] - m[0, 1])
    q = np.array([w, xq, yq, zq])
    return q / np.linalg.norm(q)


class Track:
    """A solution sampled for animation: `pose(t)` for any t in [t0, tf]."""

    def __init__(self, sol: Solution, pres: Presentation) -> None:
        self.scale = pres.display_scale
        self.unit = pres.display_unit
        self.up = up_axis(pres.up)
        self.t = np.asarray(sol.t, float)
        self.positions = np.asarray(pres.path, float) * self.scale
        self.t0, self.tf = float(self.t[0]), float(self.t[-1])
        self.arcs = list(sol.arcs)
        self.burns = [(a, b) for a, b, kind in self.arcs if kind == "burn"]
        node_t = np.asarray(sol.node_t, float)
        thrust = np.asarray(pres.thrust, float).reshape(-1, 3)
        self._thrust_t = node_t if len(node_t) == len(thrust) and len(thrust) else None
        self._thrust = thrust
        self._last_axis: np.ndarray | None = None

    def burning(self, t: float) -> bool:
        return any(a <= t <= b for a, b in self.burns)

    def force(self, t: float) -> np.ndarray:
        """Node thrust vectors interpolated linearly in time; zero on coast arcs of a
        solution that has burns (a coast has no thrust, whatever the nodes around it say)."""
        if self._thrust_t is None or (self.burns and not self.burning(t)):
            return np.zeros(3)
        return np.array([np.interp(t, self._thrust_t, self._thrust[:, i]) for i in range(3)])

    def position(self, t: float) -> np.ndarray:
        return np.array([np.interp(t, self.t, self.positions[:, i]) for i in range(3)])

    def velocity_direction(self, t: float) -> np.ndarray:
        """Unit tangent of the drawn path at t (central difference on the dense samples)."""
        dt = 1e-3 * max(self.tf - self.t0, 1e-9)
        d = self.position(min(t + dt, self.tf)) - self.position(max(t - dt, self.t0))
        n = np.linalg.norm(d)
        return d / n if n > 0 else np.array([1.0, 0.0, 0.0])

    def pose(self, t: float) -> Pose:
        """The vehicle at t. It points along the thrust while burning, keeps its last burn
        attitude while coasting, and heads into the flow (body -z forward) when the
        solution has no burns at all (an entry capsule, heat shield first)."""
        t = min(max(t, self.t0), self.tf)
        force = self.force(t)
        throttle = float(min(np.linalg.norm(force), 1.0))
        burning = self.burning(t) if self.burns else False
        if burning and throttle > 1e-6:
            axis = force / np.linalg.norm(force)
        elif self.burns:
            axis = self._attitude_before(t)
        else:
            axis = -self.velocity_direction(t)
        return Pose(t, self.position(t), quaternion_from_axes(axis, self.up), axis,
                    throttle if burning else 0.0, force, burning)

    def _attitude_before(self, t: float) -> np.ndarray:
        """Thrust direction at the end of the latest burn before t (the first burn's start
        before any burn)."""
        ends = [b for _, b in self.burns if b <= t]
        at = max(ends) if ends else self.burns[0][0]
        f = self.force(at)
        if np.linalg.norm(f) < 1e-9:
            return -self.velocity_direction(t)
        return f / np.linalg.norm(f)

    def step(self, t: float, wall_dt: float, speed: float) -> float:
        """The animation time after `wall_dt` seconds of wall clock at `speed` (0 = real
        time); wraps to the start after the end."""
        rate = 1.0 if speed == 0.0 else speed * (self.tf - self.t0) / PLAY_SECONDS
        t_next = t + rate * wall_dt
        return self.t0 if t >= self.tf else min(t_next, self.tf)
