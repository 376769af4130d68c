"""Draw any `Solution` in the 3D view: bodies, reference curves, markers, the trajectory
(burn and coast arcs in different colours), the NLP nodes and thrust arrows.

`build_geometry` is pure numpy (tested without a browser); `SceneView` sends it to one
client's scene. Everything is drawn in the scene's display unit (metres x
`Scene.display_scale`, e.g. km) so the WebGL float32 buffers keep their precision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import viser

from solvers.solution import Solution

BURN = (255, 140, 0)
COAST = (0, 200, 255)
NODE = (245, 245, 245)
ARROW = (255, 60, 200)
DIM_TO = np.array([90, 90, 90])
FOV = math.radians(50.0)
ARROW_FRACTION = 0.08  # thrust arrow length as a fraction of the trajectory extent
ELEVATION = 0.06  # how far above the trajectory's plane the camera looks from
OBLIQUE = math.radians(20.0)  # camera azimuth from the plane normal towards the start
_AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0),
         "+z": (0, 0, 1), "-z": (0, 0, -1)}


@dataclass
class Camera:
    """A camera pose in display units plus clipping distances."""

    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    near: float
    far: float


@dataclass
class Sphere:
    """A body in display units, with the mesh detail that keeps its faces near the sphere."""

    name: str
    center: np.ndarray
    radius: float
    color: tuple[int, int, int]
    subdivisions: int


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
    markers: list[tuple[str, np.ndarray, tuple[int, int, int]]] = field(default_factory=list)
    center: np.ndarray = field(default_factory=lambda: np.zeros(3))
    extent: float = 1.0
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))  # trajectory
    scene_up: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))


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


def sphere_subdivisions(radius: float, tolerance: float) -> int:
    """three.js icosahedron detail whose flat faces sag at most `tolerance` below the sphere
    (edge angle ~1.107 rad / (detail + 1); face-centre sag ~ R (1 - cos(edge / sqrt 3)))."""
    if tolerance >= radius:
        return 3
    edge = math.sqrt(3.0) * math.acos(1.0 - tolerance / radius)
    return int(np.clip(math.ceil(1.107 / edge) - 1, 3, 40))


def build_geometry(sol: Solution, dim: bool = False) -> Geometry:
    """Display-unit geometry of a solution; `dim` greys the trajectory (a stale result)."""
    scene = sol.scene
    scale = scene.display_scale if scene is not None else 1.0
    pos = np.asarray(sol.positions, float) * scale
    segments = polyline_segments(pos) if len(pos) > 1 else np.zeros((0, 2, 3))
    kinds = arc_kinds(np.asarray(sol.t, float), sol.arcs) if len(pos) > 1 else []
    colors = np.array([BURN if k == "burn" else COAST for k in kinds], float).reshape(-1, 3)
    if dim:
        colors = 0.35 * colors + 0.65 * DIM_TO
    seg_colors = np.repeat(colors[:, None, :], 2, axis=1).astype(np.uint8)

    if len(pos):
        lo, hi = pos.min(axis=0), pos.max(axis=0)
        center, extent = 0.5 * (lo + hi), float(np.linalg.norm(hi - lo))
    else:
        center, extent = np.zeros(3), 0.0
    if extent <= 0.0:
        extent = 1.0 if scene is None or not scene.bodies else 4.0 * scene.bodies[0].radius * scale

    nodes = np.asarray(sol.node_positions, float).reshape(-1, 3) * scale
    thrust = np.asarray(sol.thrust, float).reshape(-1, 3)
    arrows = np.zeros((0, 2, 3))
    if len(thrust) and len(thrust) == len(nodes):
        on = np.linalg.norm(thrust, axis=1) > 1e-9
        tips = nodes[on] + ARROW_FRACTION * extent * thrust[on]
        arrows = np.stack([nodes[on], tips], axis=1)

    curves, curve_colors, spheres, markers = [], [], [], []
    if scene is not None:
        for curve in scene.curves:
            segs = polyline_segments(np.asarray(curve.points, float) * scale)
            if curve.dashed and len(segs) >= 40:
                segs = segs[::2]
            curves.append(segs)
            curve_colors.append(np.broadcast_to(np.array(curve.color, np.uint8), segs.shape))
        for body in scene.bodies:
            radius = body.radius * scale
            spheres.append(Sphere(body.name, np.asarray(body.center, float) * scale, radius,
                                  body.color, sphere_subdivisions(radius, 0.003 * extent)))
        markers = [(m.name, np.asarray(m.position, float) * scale, m.color)
                   for m in scene.markers]
    geometry = Geometry(
        segments=segments, segment_colors=seg_colors, nodes=nodes, arrows=arrows,
        curve_segments=np.concatenate(curves) if curves else np.zeros((0, 2, 3)),
        curve_colors=np.concatenate(curve_colors) if curves else np.zeros((0, 2, 3), np.uint8),
        spheres=spheres, markers=markers, center=center, extent=extent, points=pos,
        scene_up=np.asarray(_AXES.get(scene.up if scene else "+z", (0, 0, 1)), float),
    )
    return geometry


def fit_camera(g: Geometry, aspect: float = 1.0, bottom: float = 0.0,
               margin: float = 1.2) -> Camera:
    """Look at the trajectory's centre obliquely from the side of its best-fit plane (from
    behind its start, `OBLIQUE` off the plane normal, `ELEVATION` above the plane), just far
    enough that every point is inside a canvas of width/height `aspect` whose lowest
    `bottom` fraction is covered (by a floating panel). 'Up' points away
    from a body the trajectory is close to (a landing is seen with the ground below), else
    along the scene's up axis."""
    up = np.asarray(g.scene_up, float)
    for s in g.spheres:
        offset = g.center - s.center
        if 0 < np.linalg.norm(offset) < s.radius + 2.0 * g.extent:
            up = offset / np.linalg.norm(offset)
            break
    pts = g.points if len(g.points) else g.center[None]
    framed = np.concatenate([pts, g.arrows.reshape(-1, 3)] + [m[1][None] for m in g.markers])
    axes = np.eye(3)
    if len(pts) >= 3:
        axes = np.linalg.svd(pts - pts.mean(axis=0), full_matrices=False)[2]
    along, normal = axes[0], axes[-1]
    bottom = min(max(bottom, 0.0), 0.45)
    side = normal - normal.dot(up) * up
    if np.linalg.norm(side) < 0.3:
        # The trajectory lies across 'up' (e.g. an orbit seen from above): look down at it.
        ref = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        side = ref - ref.dot(up) * up
        view = 0.55 * side / np.linalg.norm(side) + 0.85 * up
    else:
        side /= np.linalg.norm(side)
        side = side if side.dot(g.scene_up) >= 0 else -side
        back = along - along.dot(up) * up - along.dot(side) * side
        if np.linalg.norm(back) > 1e-9:
            back /= np.linalg.norm(back)
            back = back if back.dot(pts[0] - pts[-1]) >= 0 else -back
        view = math.cos(OBLIQUE) * side + math.sin(OBLIQUE) * back + ELEVATION * up
    view /= np.linalg.norm(view)
    right = np.cross(up, view)
    right /= np.linalg.norm(right)
    screen_up = np.cross(view, right)
    rel = framed - g.center
    tan_v = math.tan(FOV / 2)
    # Perspective: a point at depth z (towards the camera) fits when |x| <= tan (D - z).
    z = rel @ view
    need_w = z + margin * np.abs(rel @ right) / (tan_v * aspect)
    need_h = z + margin * np.abs(rel @ screen_up) / ((1.0 - bottom) * tan_v)
    distance = max(float(np.max(need_w)), float(np.max(need_h)), 1e-2 * g.extent)
    reach = max([np.linalg.norm(s.center - g.center) + s.radius for s in g.spheres] + [g.extent])
    # Aim below the centre so that it shows in the middle of the uncovered part.
    look_at = g.center - bottom * tan_v * distance * screen_up
    return Camera(g.center + distance * view, look_at, up,
                  near=1e-3 * distance, far=4.0 * (distance + reach))


def line_colors(srgb: np.ndarray) -> np.ndarray:
    """viser's line shader takes vertex colours as linear and encodes them to sRGB on output
    (measured: (255, 140, 0) is drawn as (231, 203, 68)); decode first so lines show the
    colour asked for, like meshes and points do."""
    c = np.asarray(srgb, float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return np.round(255.0 * lin).astype(np.uint8)


class SceneView:
    """Draws geometry into one client's scene, re-sending the context (bodies, curves,
    markers) only when it changed, so slider drags send just the trajectory."""

    def __init__(self, scene: viser.SceneApi) -> None:
        self.scene = scene
        self._context_key: bytes | None = None
        self._context: list[viser.SceneNodeHandle] = []
        self._solution: dict[str, viser.SceneNodeHandle] = {}
        scene.configure_environment_map(None)
        scene.configure_default_lights(cast_shadow=False)
        scene.set_background_image(np.full((1, 1, 3), 8, np.uint8))

    def draw(self, g: Geometry) -> None:
        """Replace the drawn solution by `g` (same names replace in place: no flicker)."""
        self._draw_context(g)
        size = 0.006 * g.extent  # world units: node points and arrows scale with the view
        new: dict[str, viser.SceneNodeHandle] = {}
        if len(g.segments):
            new["/trajectory"] = self.scene.add_line_segments(
                "/trajectory", g.segments, line_colors(g.segment_colors), thickness=4.0,
                thickness_units="screen")
        if len(g.nodes):
            new["/nodes"] = self.scene.add_point_cloud(
                "/nodes", g.nodes.astype(np.float32), NODE, point_size=size,
                point_shape="circle", precision="float32")
        if len(g.arrows):
            new["/thrust"] = self.scene.add_arrows(
                "/thrust", g.arrows, ARROW, shaft_radius=0.25 * size, head_radius=0.8 * size,
                head_length=2.0 * size)
        for name, handle in self._solution.items():
            if name not in new:
                handle.remove()
        self._solution = new

    def clear(self) -> None:
        """Remove everything drawn (a mission change)."""
        for handle in [*self._context, *self._solution.values()]:
            handle.remove()
        self._context, self._solution, self._context_key = [], {}, None

    def _draw_context(self, g: Geometry) -> None:
        key = repr([(s.name, s.center.tolist(), s.radius, s.color, s.subdivisions)
                    for s in g.spheres] + [(m[0], m[1].tolist()) for m in g.markers]).encode()
        key += g.curve_segments.tobytes()
        if key == self._context_key:
            return
        for handle in self._context:
            handle.remove()
        self._context = []
        add = self._context.append
        for s in g.spheres:
            add(self.scene.add_icosphere(f"/bodies/{s.name}", s.radius, s.color,
                                         subdivisions=s.subdivisions, position=s.center,
                                         cast_shadow=False, receive_shadow=False))
        if len(g.curve_segments):
            add(self.scene.add_line_segments("/curves", g.curve_segments,
                                             line_colors(g.curve_colors),
                                             thickness=1.5, thickness_units="screen"))
        for i, (name, position, color) in enumerate(g.markers):
            add(self.scene.add_point_cloud(f"/markers/{i}", position[None].astype(np.float32),
                                           color, point_size=0.015 * g.extent,
                                           point_shape="circle", precision="float32"))
            add(self.scene.add_label(f"/labels/{i}", name, position=position,
                                     font_screen_scale=0.8, anchor="bottom-left"))
        self._context_key = key
