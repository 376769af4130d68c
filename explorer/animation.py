"""Where the vehicle is at time t, which way it points, and the read-outs shown there.

Pure numpy (tested without a browser): `Track` samples a `Solution` at any time of its
trajectory in display units; the view moves the vehicle mesh with it. Everything comes from
the Solution contract (positions, node thrust vectors, arcs, states), so every mission
animates without code of its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from solvers.solution import Solution

PLAY_SECONDS = 12.0  # wall-clock length of a whole run at speed 1x
SPEEDS = {"0.25x": 0.25, "0.5x": 0.5, "1x": 1.0, "2x": 2.0, "4x": 4.0, "real time": 0.0}
_AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0),
         "+z": (0, 0, 1), "-z": (0, 0, -1)}


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

    def __init__(self, sol: Solution) -> None:
        scene = sol.scene
        self.scale = scene.display_scale if scene is not None else 1.0
        self.unit = scene.display_unit if scene is not None else "m"
        self.up = np.asarray(_AXES.get(scene.up if scene else "+z", (0, 0, 1)), float)
        self.t = np.asarray(sol.t, float)
        self.positions = np.asarray(sol.positions, float) * self.scale
        self.t0, self.tf = float(self.t[0]), float(self.t[-1])
        self.arcs = list(sol.arcs)
        self.burns = [(a, b) for a, b, kind in self.arcs if kind == "burn"]
        node_t = np.asarray(sol.node_t, float)
        thrust = np.asarray(sol.thrust, float).reshape(-1, 3)
        self._thrust_t = node_t if len(node_t) == len(thrust) and len(thrust) else None
        self._thrust = thrust
        self._sol = sol
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


# ---- read-outs -----------------------------------------------------------------------------
def _fmt(value: float, unit: str) -> str:
    """A value in a readable unit: rad as deg, large metres as km."""
    if unit == "rad":
        return f"{math.degrees(value):.4g}°"
    if unit == "rad/s":
        return f"{1e3 * value:.4g} mrad/s"
    if unit == "m" and abs(value) >= 1e4:
        return f"{value / 1e3:.5g} km"
    if unit == "m/s" and abs(value) >= 1e4:
        return f"{value / 1e3:.4g} km/s"
    return f"{value:.4g} {unit}".rstrip()


def readouts(sol: Solution, track: Track, t: float) -> list[tuple[str, str]]:
    """(label, value) rows at animation time t: time, position, the velocity, mass and
    other states, thrust, controls and the range to the nearest body or target."""
    pose = track.pose(t)
    rows = [("time", f"{pose.t:.4g} s of {track.tf:.4g} s")]
    pos = pose.position
    rows.append((f"position [{track.unit}]", ", ".join(f"{c:.4g}" for c in pos)))
    x = np.asarray(sol.x, float)
    states = {}
    if x.ndim == 2 and x.shape[0] == len(track.t):
        states = {n: float(np.interp(pose.t, track.t, x[:, i]))
                  for i, n in enumerate(sol.state_names)}
    units = dict(zip(sol.state_names, sol.state_units, strict=False))
    vel = [n for n in ("vx", "vy", "vz") if n in states]
    if len(vel) >= 2:
        speed = math.sqrt(sum(states[n] ** 2 for n in vel))
        rows.append(("speed", f"{_fmt(speed, 'm/s')} ("
                     + ", ".join(f"{states[n]:.3g}" for n in vel) + " m/s)"))
    for name, value in states.items():
        if name in vel or name in ("x", "y", "z"):
            continue
        label = "mass" if name == "m" and units.get(name) == "kg" else name
        rows.append((label, _fmt(value, units.get(name, ""))))
    u = np.asarray(sol.u, float)
    if u.ndim == 2 and u.shape[0] == len(track.t):
        for i, (name, unit) in enumerate(zip(sol.control_names, sol.control_units,
                                             strict=False)):
            rows.append((f"control {name}", _fmt(float(np.interp(pose.t, track.t, u[:, i])),
                                                   unit)))
    if track.burns:
        rows.append(("thrust", f"burning, throttle {100 * pose.throttle:.0f} %"
                     if pose.burning else "coasting (engine off)"))
    rows.extend(_range_rows(sol, pos / track.scale, track))
    return rows


def _range_rows(sol: Solution, pos_m: np.ndarray, track: Track) -> list[tuple[str, str]]:
    """Distance to the surface of the nearest large body (one bigger than the path), else
    to the centre of a small one (a target), else to a marker named like a target, else to
    the origin of the (relative) frame. Distances are measured in the display frame: a
    frame drawn exaggerated or magnified says so, and the label then says "as drawn"."""
    scene = sol.scene
    rows = _ranges(sol, pos_m, track)
    frame = scene.frame.lower() if scene is not None else ""
    if any(word in frame for word in ("exaggerat", "magnif", "×")):
        rows = [(f"{label} (as drawn)", value) for label, value in rows]
    return rows


def _ranges(sol: Solution, pos_m: np.ndarray, track: Track) -> list[tuple[str, str]]:
    scene = sol.scene
    extent = float(np.ptp(track.positions, axis=0).max()) / track.scale if len(
        track.positions) else 0.0
    if scene is not None and scene.bodies:
        def gap(b):
            d = float(np.linalg.norm(pos_m - np.asarray(b.center, float)))
            return d - b.radius if b.radius > 0.5 * extent else d

        body = min(scene.bodies, key=gap)
        if body.radius > 0.5 * extent:
            return [(f"altitude above {body.name}", _fmt(gap(body), "m"))]
        return [(f"range to {body.name}", _fmt(gap(body), "m"))]
    if scene is not None:
        for m in scene.markers:
            if "target" in m.name.lower():
                d = float(np.linalg.norm(pos_m - np.asarray(m.position, float)))
                return [(f"range to {m.name}", _fmt(d, "m"))]
    return [("range to origin", _fmt(float(np.linalg.norm(pos_m)), "m"))]


def readout_markdown(rows: list[tuple[str, str]], frame: str = "") -> str:
    table = ["| at the vehicle | |", "|---|---|"] + [f"| {a} | {b} |" for a, b in rows]
    if frame:
        table.append(f"\n_display frame: {frame}_")
    return "\n".join(table)
