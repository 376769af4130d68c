"""Draw any `Solution` in the 3D view: bodies, reference curves, markers, the trajectory
(burn and coast arcs in different colours, or coloured by `Solution.color_by`), the NLP nodes
and thrust arrows; plus what the live view layers on top: a failed attempt in a warning
colour, a method comparison, the solver's iterates (ghosts) and the animated vehicle.

`build_geometry` is pure numpy (tested without a browser); `SceneView` sends it to one
client's scene. Everything is drawn in the scene's display unit (metres x
`Scene.display_scale`, e.g. km) so the WebGL float32 buffers keep their precision.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import viser
from plotly.colors import sample_colorscale

from solvers.solution import Solution

from .animation import Pose

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
ASSETS = Path(__file__).resolve().parent.parent / "assets"
VEHICLE_FRACTION = 0.06  # vehicle length as a fraction of the trajectory extent
BACKGROUNDS = {True: 8, False: 236}  # dark / light sky grey level
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
    track: np.ndarray | None = None  # display-unit positions at `Geometry.times`


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
    colorbar: ColorBar | None = None
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))  # Solution.t


@dataclass
class ColorBar:
    """What the path colours mean when it is coloured by value."""

    name: str
    unit: str
    lo: float
    hi: float


def colormap(values: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(N, 3) uint8 sRGB colours of `values` on `COLORSCALE` over [lo, hi]."""
    a, b = COLORSCALE_RANGE
    span = hi - lo if hi > lo else 1.0
    frac = a + (b - a) * np.clip((np.asarray(values, float) - lo) / span, 0.0, 1.0)
    rgb = sample_colorscale(COLORSCALE, list(frac), colortype="tuple")
    return np.round(255.0 * np.asarray(rgb, float)).astype(np.uint8).reshape(-1, 3)


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
    colorbar = None
    by = sol.color_by
    if by is not None and len(by.values) == len(pos) and len(pos) > 1:
        v = np.asarray(by.values, float)
        finite = v[np.isfinite(v)]
        if len(finite):
            colorbar = ColorBar(by.name, by.unit, float(finite.min()), float(finite.max()))
            mid = 0.5 * (v[:-1] + v[1:])
            colors = colormap(np.nan_to_num(mid, nan=colorbar.lo), colorbar.lo,
                              colorbar.hi).astype(float)
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
            track = None
            if body.track is not None and len(body.track) == len(sol.t):
                track = np.asarray(body.track, float) * scale
            spheres.append(Sphere(body.name, np.asarray(body.center, float) * scale, radius,
                                  body.color, sphere_subdivisions(radius, 0.003 * extent),
                                  track))
        markers = [(m.name, np.asarray(m.position, float) * scale, m.color)
                   for m in scene.markers]
    geometry = Geometry(
        segments=segments, segment_colors=seg_colors, nodes=nodes, arrows=arrows,
        curve_segments=np.concatenate(curves) if curves else np.zeros((0, 2, 3)),
        curve_colors=np.concatenate(curve_colors) if curves else np.zeros((0, 2, 3), np.uint8),
        spheres=spheres, markers=markers, center=center, extent=extent, points=pos,
        scene_up=np.asarray(_AXES.get(scene.up if scene else "+z", (0, 0, 1)), float),
        colorbar=colorbar, times=np.asarray(sol.t, float),
    )
    return geometry


def path_segments(sol: Solution, positions: np.ndarray | None = None) -> np.ndarray:
    """Display-unit segments of a solution's path (or of other positions in its frame,
    e.g. an iterate from `Solution.history`)."""
    scale = sol.scene.display_scale if sol.scene is not None else 1.0
    pos = np.asarray(sol.positions if positions is None else positions, float) * scale
    return polyline_segments(pos) if len(pos) > 1 else np.zeros((0, 2, 3))


def _view_up(g: Geometry) -> np.ndarray:
    """'Up' on screen: away from a large body the trajectory is close to (a landing is
    seen with the ground below), else the scene's up axis. Small bodies (a target drawn
    enlarged) do not count."""
    for s in g.spheres:
        offset = g.center - s.center
        if s.radius > 0.5 * g.extent and 0 < np.linalg.norm(offset) < s.radius + 2 * g.extent:
            return offset / np.linalg.norm(offset)
    return np.asarray(g.scene_up, float)


def _plane_axes(pts: np.ndarray) -> np.ndarray:
    """Rows: the path's main direction, second direction and best-fit plane normal."""
    if len(pts) >= 3:
        return np.linalg.svd(pts - pts.mean(axis=0), full_matrices=False)[2]
    return np.eye(3)


def top_view(g: Geometry) -> np.ndarray:
    """Direction from the path towards a camera looking straight at its plane (the plan
    view), from the side 'up' points to when the plane is vertical."""
    pts = g.points if len(g.points) else g.center[None]
    normal = _plane_axes(pts)[-1]
    ref = g.scene_up if abs(normal.dot(g.scene_up)) > 1e-6 else _view_up(g)
    return normal if normal.dot(ref) >= 0 else -normal


def fit_camera(g: Geometry, aspect: float = 1.0, bottom: float = 0.0,
               margin: float = 1.2, view: np.ndarray | None = None) -> Camera:
    """Look at the trajectory's centre obliquely from the side of its best-fit plane (from
    behind its start, `OBLIQUE` off the plane normal, `ELEVATION` above the plane), or from
    the direction `view` if given, just far enough that every point is inside a canvas of
    width/height `aspect` whose lowest `bottom` fraction is covered (by a floating panel).
    'Up' is `_view_up`, made perpendicular to the line of sight."""
    up = _view_up(g)
    pts = g.points if len(g.points) else g.center[None]
    framed = np.concatenate([pts, g.arrows.reshape(-1, 3)] + [m[1][None] for m in g.markers])
    axes = _plane_axes(pts)
    along, normal = axes[0], axes[-1]
    bottom = min(max(bottom, 0.0), 0.45)
    side = normal - normal.dot(up) * up
    if view is not None:
        view = np.asarray(view, float)
        up = up - up.dot(view) * view
        if np.linalg.norm(up) < 1e-6:  # looking along 'up': the path's direction is up
            up = along - along.dot(view) * view
        up /= np.linalg.norm(up)
    elif np.linalg.norm(side) < 0.3:
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
    view = view / np.linalg.norm(view)
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


def fade(rgb: np.ndarray | tuple[int, int, int], amount: float, dark: bool = True) -> np.ndarray:
    """`rgb` blended towards the sky by `amount` (0 = unchanged, 1 = invisible): lines have
    no alpha, so fading is a blend with the background."""
    sky = np.full(3, BACKGROUNDS[dark], float)
    return np.round((1.0 - amount) * np.asarray(rgb, float) + amount * sky).astype(np.uint8)


def ghost_geometry(sol: Solution, upto: int | None = None,
                   dark: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Segments and colours of the iterates in `sol.history` (the first `upto` of them):
    the earliest faintest, each later one brighter, the newest shown in full."""
    history = sol.history[:upto] if upto is not None else sol.history
    segs, cols = [], []
    n = len(history)
    for k, snap in enumerate(history):
        s = path_segments(sol, snap["positions"])
        if not len(s):
            continue
        amount = 0.6 * (1.0 - (k + 1) / n) + 0.05
        segs.append(s)
        cols.append(np.broadcast_to(fade(GHOST, amount, dark), s.shape))
    if not segs:
        return np.zeros((0, 2, 3)), np.zeros((0, 2, 3), np.uint8)
    return np.concatenate(segs), np.concatenate(cols).astype(np.uint8)


def vehicle_mesh(mission: str) -> bytes | None:
    """GLB bytes of the mission's vehicle from `assets/` (None if the assets are missing)."""
    try:
        table = json.loads((ASSETS / "vehicles.json").read_text())
        name = table.get(mission, table["default"])
        return (ASSETS / f"{name}.glb").read_bytes()
    except (OSError, KeyError, ValueError):
        return None


class SceneView:
    """Draws geometry into one scene (a client's, or the server's in shared mode),
    re-sending the context (bodies, curves, markers) only when it changed, so slider drags
    send just the trajectory. Layers: the solution, a failed attempt, comparison overlays,
    iterate ghosts and the vehicle, each replaced in place by name (no flicker)."""

    def __init__(self, scene: viser.SceneApi, dark: bool = True) -> None:
        self.scene = scene
        self._context_key: bytes | None = None
        self._context: list[viser.SceneNodeHandle] = []
        self._solution: dict[str, viser.SceneNodeHandle] = {}
        self._layers: dict[str, viser.SceneNodeHandle] = {}
        self._vehicle: dict[str, viser.SceneNodeHandle] = {}
        self._vehicle_key: tuple[str, float] | None = None
        self._vehicle_size = 1.0
        self._moving: list[tuple[viser.SceneNodeHandle, np.ndarray, np.ndarray]] = []
        scene.configure_environment_map(None)
        scene.configure_default_lights(cast_shadow=False)
        self.set_dark(dark)

    def set_dark(self, dark: bool) -> None:
        self.dark = dark
        self.scene.set_background_image(np.full((1, 1, 3), BACKGROUNDS[dark], np.uint8))

    @property
    def node_count(self) -> int:
        """Scene nodes this view holds (constant over re-solves: nothing accumulates)."""
        return (len(self._context) + len(self._solution) + len(self._layers)
                + len(self._vehicle))

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
                "/nodes", g.nodes.astype(np.float32), NODE if self.dark else NODE_LIGHT,
                point_size=size,
                point_shape="circle", precision="float32")
        if len(g.arrows):
            new["/thrust"] = self.scene.add_arrows(
                "/thrust", g.arrows, ARROW, shaft_radius=0.25 * size, head_radius=0.8 * size,
                head_length=2.0 * size)
        for name, handle in self._solution.items():
            if name not in new:
                handle.remove()
        self._solution = new

    def show_solution(self, visible: bool) -> None:
        """Hide the solution layer (a comparison shows its own paths) or show it again."""
        for handle in self._solution.values():
            handle.visible = visible

    def set_layer(self, name: str, segments: np.ndarray, colors: np.ndarray,
                  thickness: float = 3.0) -> None:
        """Draw (or, given no segments, remove) a named batch of segments coloured by
        `colors`, (N, 2, 3) sRGB."""
        path = f"/layers/{name}"
        if not len(segments):
            handle = self._layers.pop(path, None)
            if handle is not None:
                handle.remove()
            return
        self._layers[path] = self.scene.add_line_segments(
            path, segments, line_colors(colors), thickness=thickness, thickness_units="screen")

    def clear_layers(self, prefix: str = "") -> None:
        for path in [p for p in self._layers if p.startswith(f"/layers/{prefix}")]:
            self._layers.pop(path).remove()

    # ---- vehicle ------------------------------------------------------------------------
    def set_vehicle(self, mission: str, extent: float) -> None:
        """Load the mission's vehicle mesh sized to the view (once per mission and size)."""
        size = VEHICLE_FRACTION * extent
        key = (mission, round(size, 12))
        if key == self._vehicle_key:
            return
        self.remove_vehicle()
        body = vehicle_mesh(mission)
        frame = self.scene.add_frame("/vehicle", show_axes=False, visible=False)
        self._vehicle = {"frame": frame}
        if body is not None:
            self._vehicle["body"] = self.scene.add_glb("/vehicle/body", body, scale=size)
            self._vehicle["plume"] = self.scene.add_glb(
                "/vehicle/plume", (ASSETS / "plume.glb").read_bytes(),
                scale=(size, size, size), position=(0.0, 0.0, -0.5 * size), visible=False)
        else:  # no assets: a plain box still shows where the vehicle is
            self._vehicle["body"] = self.scene.add_box(
                "/vehicle/body", (255, 255, 255), dimensions=(size, size, size))
        self._vehicle["force"] = self.scene.add_arrows(
            "/vehicle_force", np.zeros((1, 2, 3)), ARROW, shaft_radius=0.06 * size,
            head_radius=0.18 * size, head_length=0.4 * size, visible=False)
        self._vehicle_size = size
        self._vehicle_key = key

    @property
    def vehicle_size(self) -> float:
        """Length of the drawn vehicle in display units."""
        return self._vehicle_size

    @property
    def vehicle_position(self) -> np.ndarray:
        """Where the vehicle is drawn (display units; the origin before any pose)."""
        frame = self._vehicle.get("frame")
        return np.array(frame.position if frame is not None else np.zeros(3), float)

    def move_vehicle(self, pose: Pose) -> None:
        """Place the vehicle at `pose`: attitude, plume length and the force arrow."""
        if not self._vehicle:
            return
        size = self._vehicle_size
        frame = self._vehicle["frame"]
        frame.position = tuple(pose.position)
        frame.wxyz = tuple(pose.wxyz)
        frame.visible = True
        plume = self._vehicle.get("plume")
        if plume is not None:
            plume.visible = pose.throttle > 1e-3
            if plume.visible:
                plume.scale = (size, size, size * (0.4 + 1.2 * pose.throttle))
        force = self._vehicle["force"]
        magnitude = float(np.linalg.norm(pose.force))
        force.visible = magnitude > 1e-3
        if force.visible:
            tip = pose.position + 2.5 * size * pose.force
            force.points = np.array([[pose.position, tip]], np.float32)

    def move_bodies(self, t: float) -> None:
        """Put every body that has a track where it is at time t."""
        for handle, times, track in self._moving:
            handle.position = tuple(np.interp(t, times, track[:, i]) for i in range(3))

    def remove_vehicle(self) -> None:
        """Remove the vehicle (its frame takes the body and plume with it)."""
        for key in ("frame", "force"):
            if key in self._vehicle:
                self._vehicle[key].remove()
        self._vehicle, self._vehicle_key = {}, None

    def clear(self) -> None:
        """Remove everything drawn (a mission change)."""
        for handle in [*self._context, *self._solution.values(), *self._layers.values()]:
            handle.remove()
        self.remove_vehicle()
        self._context, self._solution, self._layers, self._context_key = [], {}, {}, None
        self._moving = []

    def _draw_context(self, g: Geometry) -> None:
        key = repr([(s.name, s.center.tolist(), s.radius, s.color, s.subdivisions)
                    for s in g.spheres] + [(m[0], m[1].tolist()) for m in g.markers]).encode()
        key += g.curve_segments.tobytes()
        key += b"".join(s.track.tobytes() for s in g.spheres if s.track is not None)
        if key == self._context_key:
            return
        for handle in self._context:
            handle.remove()
        self._context, self._moving = [], []
        add = self._context.append
        for s in g.spheres:
            add(self.scene.add_icosphere(f"/bodies/{s.name}", s.radius, s.color,
                                         subdivisions=s.subdivisions, position=s.center,
                                         cast_shadow=False, receive_shadow=False))
            if s.track is not None:
                self._moving.append((self._context[-1], g.times, s.track))
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
