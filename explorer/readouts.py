"""The read-outs at the vehicle: time, position, speed, mass, controls, thrust and the range
to the nearest body or target, from the Solution's states and the Presentation's frame."""

from __future__ import annotations

import math

import numpy as np

from solvers.presentation import Presentation
from solvers.solution import Solution

from .panels.status import number, unit_text
from .player import Track


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
    return f"{number(value, 4)} {unit_text(unit)}".rstrip()


def readouts(sol: Solution, pres: Presentation, track: Track, t: float) -> list[tuple[str, str]]:
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
        unit = units.get(name, "")
        label = sol.labels.get(name)
        text = label.text if label else "mass" if name == "m" and unit == "kg" else name
        rows.append((text, _fmt(value, unit)))
    u = np.asarray(sol.u, float)
    if u.ndim == 2 and u.shape[0] == len(track.t):
        for i, (name, unit) in enumerate(zip(sol.control_names, sol.control_units,
                                             strict=False)):
            label = sol.labels.get(name)
            rows.append((label.text if label else f"control {name}",
                         _fmt(float(np.interp(pose.t, track.t, u[:, i])), unit)))
    if track.burns:
        rows.append(("thrust", f"burning, throttle {100 * pose.throttle:.0f} %"
                     if pose.burning else "coasting (engine off)"))
    rows.extend(_range_rows(pres, pos / track.scale, track))
    return rows


def _range_rows(pres: Presentation, pos_m: np.ndarray, track: Track
                ) -> list[tuple[str, str]]:
    """Distance to the surface of the nearest large body (one bigger than the path), else
    to the centre of a small one (a target), else to a marker named like a target, else to
    the origin of the (relative) frame. Distances are measured in the display frame: a
    frame drawn exaggerated or magnified says so, and the label then says "as drawn"."""
    rows = _ranges(pres, pos_m, track)
    frame = pres.frame.lower()
    if any(word in frame for word in ("exaggerat", "magnif", "×")):
        rows = [(f"{label} (as drawn)", value) for label, value in rows]
    return rows


def _ranges(pres: Presentation, pos_m: np.ndarray, track: Track) -> list[tuple[str, str]]:
    extent = float(np.ptp(track.positions, axis=0).max()) / track.scale if len(
        track.positions) else 0.0
    if pres.bodies:
        def gap(b):
            d = float(np.linalg.norm(pos_m - np.asarray(b.center, float)))
            return d - b.radius if b.radius > 0.5 * extent else d

        body = min(pres.bodies, key=gap)
        if body.radius > 0.5 * extent:
            return [(f"altitude above {body.name}", _fmt(gap(body), "m"))]
        return [(f"range to {body.name}", _fmt(gap(body), "m"))]
    for m in pres.markers:
        if "target" in m.name.lower():
            d = float(np.linalg.norm(pos_m - np.asarray(m.position, float)))
            return [(f"range to {m.name}", _fmt(d, "m"))]
    return [("range to origin", _fmt(float(np.linalg.norm(pos_m)), "m"))]


def readout_markdown(rows: list[tuple[str, str]], frame: str = "") -> str:
    table = ["| at the vehicle | |", "|---|---|"] + [f"| {a} | {b} |" for a, b in rows]
    if frame:
        table.append(f"\n_display frame: {frame}_")
    return "\n".join(table)
