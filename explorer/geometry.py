"""What the 3D view draws, in display units, built from a `Presentation` (pure numpy, tested
without a browser): the path as segments (burn and coast arcs in their colours, or coloured by
`Presentation.color_by`), the nodes, thrust arrows, reference curves (the throttle bounds'
rings around the arrows among them), bodies and markers; plus the iterate ghosts and a failed
attempt's path.

Everything is scaled to the presentation's display unit (metres x `display_scale`, e.g. km)
so the WebGL float32 buffers keep their precision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache

import numpy as np
from plotly.colors import convert_colors_to_same_type, get_colorscale

from solvers import palette
from solvers.presentation import Curve, Presentation

BURN = (255, 140, 0)
COAST = (0, 200, 255)
NODE = (245, 245, 245)
NODE_LIGHT = (40, 40, 40)  # nodes on the light theme's sky
ARROW = (255, 60, 200)
WARNING = (255, 45, 45)  # a failed/infeasible attempt drawn over the last good trajectory
DIM_TO = np.array([90, 90, 90])
COLORSCALE = "Plasma"
COLORSCALE_RANGE = (0.25, 1.0)  # skip Plasma's dark-blue end: it vanishes on a dark sky
# Comparison overlays: distinct from each other and from the warning red.
PALETTE = ((255, 200, 0), (0, 200, 255), (150, 240, 80), (240, 90, 220), (255, 120, 70),
           (170, 140, 255))
GHOST = np.array([185, 205, 255])  # iterates fade from the background towards this
BACKGROUNDS = {True: 8, False: 236}  # dark / light sky grey level
ARROW_FRACTION = 0.08  # thrust arrow length as a fraction of the trajectory extent
MAX_ARROWS = 120  # more nodes than this: every k-th thrust arrow (a fine mesh is a blur)
MAX_RINGS = 12  # arrows with throttle-bound rings (two circles each: more is a tangle)
RING_POINTS = 24  # segments per ring (software WebGL draws every one)
RING_NAME = "throttle bounds ρ1, ρ2"
MERGE_LABELS = 0.05  # markers closer than this fraction of the extent share one label
_AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0),
         "+z": (0, 0, 1), "-z": (0, 0, -1)}


def up_axis(name: str) -> np.ndarray:
    """The unit vector of an axis name such as "+z"."""
    return np.asarray(_AXES.get(name, (0, 0, 1)), float)


@dataclass
class Sphere:
    """A body in display units, with the mesh detail that keeps its faces near the sphere."""

    name: str
    center: np.ndarray
    radius: float
    color: tuple[int, int, int]
    subdivisions: int
    track: np.ndarray | None = None  # display-unit positions at `Geometry.times`


@dataclass
class ColorBar:
    """What the path colours mean when it is coloured by value."""

    name: str
    unit: str
    lo: float
    hi: float


@dataclass
class Geometry:
    """Everything `SceneView.draw` sends, in display units."""

    segments: np.ndarray  # (N, 2, 3) trajectory segments
    segment_colors: np.ndarray  # (N, 2, 3) uint8
    nodes: np.ndarray  # (M, 3)
    arrows: np.ndarray  # (K, 2, 3) start and tip of each thrust arrow
    curve_segments: np.ndarray  # (C, 2, 3) all reference curves in one batch
    curve_colors: np.ndarray  # (C, 2, 3) uint8
    spheres: list[Sphere] = field(default_factory=list)
    # (label, position, colour, whether a point is drawn, label anchor)
    markers: list[tuple[str, np.ndarray, tuple[int, int, int], bool, str]] = field(
        default_factory=list)
    center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    extent: float = 1.0
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # trajectory
    scene_up: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    colorbar: ColorBar | None = None
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))  # Solution.t
    unit: str = "m"
    curve_names: list[tuple[str, tuple[int, int, int], bool]] = field(default_factory=list)
    arrow_name: str = "thrust direction"
    arc_names: dict[str, str] = field(default_factory=dict)
    plan: bool = False  # the default camera looks straight at the path's plane


@cache
def _colorscale_stops() -> tuple[np.ndarray, np.ndarray]:
    """`COLORSCALE`'s stops: positions (K,) and sRGB colours (K, 3) in [0, 1]."""
    scale = get_colorscale(COLORSCALE)
    colors, _ = convert_colors_to_same_type([c for _, c in scale], colortype="tuple")
    return np.array([p for p, _ in scale], float), np.asarray(colors, float)


def colormap(values: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(N, 3) uint8 sRGB colours of `values` on `COLORSCALE` over [lo, hi]: linear in sRGB
    between its stops, as plotly's `sample_colorscale` (whose validation of every call was
    half of a reentry redraw's server time)."""
    a, b = COLORSCALE_RANGE
    span = hi - lo if hi > lo else 1.0
    frac = a + (b - a) * np.clip((np.asarray(values, float).ravel() - lo) / span, 0.0, 1.0)
    pos, rgb = _colorscale_stops()
    out = np.column_stack([np.interp(frac, pos, rgb[:, k]) for k in range(3)])
    return np.round(255.0 * out).astype(np.uint8).reshape(-1, 3)


def colorbar_css() -> str:
    """CSS linear-gradient of the colour map (for the legend)."""
    stops = colormap(np.linspace(0.0, 1.0, 9), 0.0, 1.0)
    return "linear-gradient(to right, " + ", ".join(
        f"rgb({r},{g},{b_}) {100 * i / 8:.0f}%" for i, (r, g, b_) in enumerate(stops)) + ")"


def arc_kinds(t: np.ndarray, arcs: list[tuple[float, float, str]]) -> list[str]:
    """Kind ("burn"/"coast") of each segment [t_i, t_i+1], judged at its midpoint."""
    mid = 0.5 * (t[:-1] + t[1:])
    kinds = ["coast"] * len(mid)
    for t0, t1, kind in arcs:
        for i in np.flatnonzero((mid >= t0) & (mid <= t1)):
            kinds[i] = kind
    return kinds


def polyline_segments(points: np.ndarray) -> np.ndarray:
    """(N, 3) polyline -> (N-1, 2, 3) segments."""
    return np.stack([points[:-1], points[1:]], axis=1)


# Icosphere details used: rounded up to one of these, so that a slider move that changes
# the path's size a little does not re-send the body (a new mesh in the page each time).
DETAIL_STEPS = (3, 5, 8, 12, 16, 20, 25, 32, 40)


def sphere_subdivisions(radius: float, tolerance: float) -> int:
    """three.js icosahedron detail whose flat faces sag at most `tolerance` below the sphere
    (edge angle ~1.107 rad / (detail + 1); face-centre sag ~ R (1 - cos(edge / sqrt 3))),
    rounded up to a `DETAIL_STEPS` step."""
    if tolerance >= radius:
        return DETAIL_STEPS[0]
    edge = math.sqrt(3.0) * math.acos(1.0 - tolerance / radius)
    needed = math.ceil(1.107 / edge) - 1
    return next((d for d in DETAIL_STEPS if d >= needed), DETAIL_STEPS[-1])


def _path_colors(pres: Presentation, t: np.ndarray, arcs: list, n: int
                 ) -> tuple[np.ndarray, ColorBar | None]:
    kinds = arc_kinds(np.asarray(t, float), arcs) if n > 1 else []
    colors = np.array([BURN if k == "burn" else COAST for k in kinds], float).reshape(-1, 3)
    by = pres.color_by
    if by is not None and len(by.values) == n and n > 1:
        v = np.asarray(by.values, float)
        finite = v[np.isfinite(v)]
        if len(finite):
            bar = ColorBar(by.name, by.unit, float(finite.min()), float(finite.max()))
            mid = 0.5 * (v[:-1] + v[1:])
            return colormap(np.nan_to_num(mid, nan=bar.lo), bar.lo, bar.hi).astype(float), bar
    return colors, None


def thrust_arrows(pres: Presentation, nodes: np.ndarray, extent: float) -> np.ndarray:
    """(K, 2, 3) base and tip of the thrust arrows at the nodes (display units): length
    `ARROW_FRACTION` of the extent times the throttle, every k-th beyond `MAX_ARROWS`."""
    thrust = np.asarray(pres.thrust, float).reshape(-1, 3)
    if not len(thrust) or len(thrust) != len(nodes):
        return np.zeros((0, 2, 3))
    on = np.flatnonzero(np.linalg.norm(thrust, axis=1) > 1e-9)
    on = on[::max(1, math.ceil(len(on) / MAX_ARROWS))]
    return np.stack([nodes[on], nodes[on] + ARROW_FRACTION * extent * thrust[on]], axis=1)


def throttle_rings(arrows: np.ndarray, bounds: tuple[float, float] | None, length: float,
                   up: np.ndarray) -> list[Curve]:
    """The throttle bounds (fractions of a full-length arrow, `length` display units) as
    two circles about the bases of at most `MAX_RINGS` arrows, evenly spread along the path
    (by distance: slow flight near the ground bunches the nodes), each in the plane of its
    arrow and the vertical: the tip lies between them, on the inner one where the lower
    bound (the nonconvex ρ1) is active. Display units, `RING_POINTS` a circle."""
    if bounds is None or not len(arrows):
        return []
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(arrows[:, 0], axis=0),
                                                            axis=1))])
    marks = np.linspace(0.0, along[-1], min(len(arrows), MAX_RINGS))
    pick = np.unique(np.argmin(np.abs(along[:, None] - marks), axis=0))
    theta = np.linspace(0.0, 2.0 * np.pi, RING_POINTS + 1)[:, None]
    fallback = np.cross(up, np.eye(3)[int(np.argmin(np.abs(up)))])
    rings = []
    for base, tip in arrows[pick]:
        side = (tip - base) - ((tip - base) @ up) * up  # the arrow's horizontal part
        norm = float(np.linalg.norm(side))
        side = side / norm if norm > 1e-9 * length else fallback / np.linalg.norm(fallback)
        circle = np.cos(theta) * up + np.sin(theta) * side
        rings += [Curve(RING_NAME, base + fraction * length * circle, palette.CONTROL_BOUND)
                  for fraction in bounds]
    return rings


def build_geometry(pres: Presentation, t: np.ndarray, arcs: list[tuple[float, float, str]],
                   dim: bool = False) -> Geometry:
    """Display-unit geometry of a presentation of a solution with dense times `t` and
    `arcs`; `dim` greys the trajectory (a stale result)."""
    scale = pres.display_scale
    pos = np.asarray(pres.path, float) * scale
    segments = polyline_segments(pos) if len(pos) > 1 else np.zeros((0, 2, 3))
    colors, colorbar = _path_colors(pres, t, arcs, len(pos))
    if dim:
        colors = 0.35 * colors + 0.65 * DIM_TO
    seg_colors = np.repeat(colors[:, None, :], 2, axis=1).astype(np.uint8)
    if len(pos):
        lo, hi = pos.min(axis=0), pos.max(axis=0)
        center, extent = 0.5 * (lo + hi), float(np.linalg.norm(hi - lo))
    else:
        center, extent = np.zeros(3), 0.0
    if extent <= 0.0:
        extent = 4.0 * pres.bodies[0].radius * scale if pres.bodies else 1.0
    nodes = np.asarray(pres.nodes, float).reshape(-1, 3) * scale
    arrows = thrust_arrows(pres, nodes, extent)
    rings = throttle_rings(arrows, pres.thrust_bounds, ARROW_FRACTION * extent,
                           up_axis(pres.up))
    curves, curve_colors, names = [], [], []
    for curve, k in [*((c, scale) for c in pres.curves), *((r, 1.0) for r in rings)]:
        segs = polyline_segments(np.asarray(curve.points, float) * k)
        if curve.dashed and len(segs) >= 40:
            segs = segs[::2]
        curves.append(segs)
        curve_colors.append(np.broadcast_to(np.array(curve.color, np.uint8), segs.shape))
        names.append((curve.name, tuple(curve.color), curve.dashed))
    spheres = []
    for body in pres.bodies:
        radius = body.radius * scale
        track = None
        if body.track is not None and len(body.track) == len(t):
            track = np.asarray(body.track, float) * scale
        spheres.append(Sphere(body.name, np.asarray(body.center, float) * scale, radius,
                              body.color, sphere_subdivisions(radius, 0.003 * extent), track))
    markers = merge_close([(m.name, np.asarray(m.position, float) * scale, m.color, m.point,
                            m.anchor) for m in pres.markers], MERGE_LABELS * extent)
    return Geometry(
        segments=segments, segment_colors=seg_colors, nodes=nodes, arrows=arrows,
        curve_segments=np.concatenate(curves) if curves else np.zeros((0, 2, 3)),
        curve_colors=np.concatenate(curve_colors) if curves else np.zeros((0, 2, 3), np.uint8),
        spheres=spheres, markers=markers, center=center, extent=extent, points=pos,
        scene_up=up_axis(pres.up), colorbar=colorbar, times=np.asarray(t, float),
        unit=pres.display_unit, curve_names=names, arrow_name=pres.arrow_name,
        arc_names=dict(pres.arc_names), plan=pres.plan,
    )


def steady(size: float, shown: float | None = None, band: float = 0.125) -> float:
    """A drawn size (a point's, an arrow's, the vehicle's, a handle's) on a grid of steps of
    1/8 octave (9 %): a re-solve that barely changes the path's extent leaves it as it was,
    and viser sends nothing for a property set to its own value (each size sent made the
    page rebuild that object: 11 of lunar landing's 32 messages per slider step). Given the
    size `shown` now, that size stays while `size` is within `band` octaves of it: a path
    whose extent sits on a grid line would otherwise flip between two sizes on every step
    (a handle's gizmo compiles a shader program in the page at each new size)."""
    if not np.isfinite(size) or size <= 0.0:
        return size
    if shown is not None and shown > 0.0 and abs(np.log2(size / shown)) <= band:
        return shown
    return float(2.0 ** (round(8.0 * np.log2(size)) / 8.0))


def node_size(g: Geometry) -> float:
    """Node points 0.6 % of the extent across, smaller where the nodes are closer than
    that (a fine mesh would draw a solid band), never below 0.2 %; `steady`."""
    size = 0.006 * g.extent
    if len(g.nodes) > 2:
        spacing = float(np.median(np.linalg.norm(np.diff(g.nodes, axis=0), axis=1)))
        size = min(size, max(0.6 * spacing, 0.002 * g.extent))
    return steady(size)


def merge_close(markers: list[tuple[str, np.ndarray, tuple[int, int, int], bool, str]],
                distance: float) -> list[tuple[str, np.ndarray, tuple[int, int, int], bool, str]]:
    """Marked points closer than `distance` to an earlier labelled one move their names into
    its label ("launch … · arrival …") and keep their points: two labels at one spot would
    cover each other. Labels alone (axis ticks) stay as they are."""
    merged: list[tuple[str, np.ndarray, tuple[int, int, int], bool, str]] = []
    for name, position, color, point, anchor in markers:
        near = None if not point else next(
            (i for i, m in enumerate(merged)
             if m[0] and m[3] and np.linalg.norm(m[1] - position) < distance), None)
        if near is not None and name:
            first = merged[near]
            merged[near] = (f"{first[0]} · {name}", *first[1:])
            name = ""
        if name or point:
            merged.append((name, position, color, point, anchor))
    return merged


def path_segments(pres: Presentation, positions: np.ndarray | None = None) -> np.ndarray:
    """Display-unit segments of a presentation's path (or of other positions in its frame,
    e.g. an iterate)."""
    pos = np.asarray(pres.path if positions is None else positions, float) * pres.display_scale
    return polyline_segments(pos) if len(pos) > 1 else np.zeros((0, 2, 3))


def _srgb_to_linear_table() -> np.ndarray:
    c = np.arange(256) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return np.round(255.0 * lin).astype(np.uint8)


_LINEAR = _srgb_to_linear_table()  # one entry per 8-bit sRGB level


def line_colors(srgb: np.ndarray) -> np.ndarray:
    """viser's line shader takes vertex colours as linear and encodes them to sRGB on output
    (measured: (255, 140, 0) is drawn as (231, 203, 68)); decode first so lines show the
    colour asked for, like meshes and points do. A table lookup per 8-bit level: every
    follower of a classroom decodes every path's colours on every answer."""
    levels = np.clip(np.rint(np.asarray(srgb, float)), 0, 255).astype(np.intp)
    return _LINEAR[levels]


def fade(rgb: np.ndarray | tuple[int, int, int], amount: float, dark: bool = True) -> np.ndarray:
    """`rgb` blended towards the sky by `amount` (0 = unchanged, 1 = invisible): lines have
    no alpha, so fading is a blend with the background."""
    sky = np.full(3, BACKGROUNDS[dark], float)
    return np.round((1.0 - amount) * np.asarray(rgb, float) + amount * sky).astype(np.uint8)


def ghost_geometry(pres: Presentation, upto: int | None = None,
                   dark: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Segments and colours of the iterates (the first `upto` of them): the earliest
    faintest, each later one brighter, the newest shown in full."""
    iterates = pres.iterates[:upto] if upto is not None else pres.iterates
    segs, cols = [], []
    n = len(iterates)
    for k, (_, positions) in enumerate(iterates):
        s = path_segments(pres, positions)
        if not len(s):
            continue
        amount = 0.6 * (1.0 - (k + 1) / n) + 0.05
        segs.append(s)
        cols.append(np.broadcast_to(fade(GHOST, amount, dark), s.shape))
    if not segs:
        return np.zeros((0, 2, 3)), np.zeros((0, 2, 3), np.uint8)
    return np.concatenate(segs), np.concatenate(cols).astype(np.uint8)
