"""Draw a `Geometry` into one viser scene (a client's, or the server's in shared mode).

Objects are created once and then updated in place through their handles (new points and
colours on the same line-segment batch, point cloud and arrow batch), so a slider move sends
a few arrays and the page rebuilds no scene objects; the context (bodies, curves, markers) is
re-sent only when it changed, the vehicle mesh only when the mission changes (its size is a
scale on the same mesh). Layers: the solution, a failed attempt, comparison overlays, iterate
ghosts and the vehicle.

A node that is removed is never re-created under the same name (`SceneView._name`): viser
merges a remove still waiting to be sent with a create of the same name, and the page then
keeps the removed node's pose; a pose equal to the fresh handle's default (the origin) is
not sent at all, so a label at the origin stayed where the last mission had put its label.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import viser

from .asset_files import asset_bytes, vehicle_mesh
from .camera import scale_bar
from .geometry import (
    ARROW,
    BACKGROUNDS,
    NODE,
    NODE_LIGHT,
    Geometry,
    line_colors,
    node_size,
    steady,
)
from .player import Pose

VEHICLE_FRACTION = 0.035  # vehicle length as a fraction of the trajectory extent


def _in_place(store: dict, name: str, count: int) -> tuple[bool, Any]:
    """(anything to draw, the handle `name` to update in place or None to add it anew); with
    nothing to draw the old handle is hidden, never removed (it comes back in place)."""
    handle = store.get(name)
    if not count:
        if handle is not None and handle.visible:
            handle.visible = False
        return False, None
    return True, None if handle is None or _removed(handle) else handle


def _removed(handle: Any) -> bool:
    """Whether a handle's node is gone (replaced by another object of the same name)."""
    return bool(getattr(getattr(handle, "_impl", None), "removed", False))


class SceneView:
    """One scene's drawn objects, kept by name and updated in place."""

    def __init__(self, scene: viser.SceneApi, dark: bool = True, root: str = "") -> None:
        """`root` prefixes every node name (several views sharing one scene, in tests and
        benchmarks, keep their objects apart)."""
        self.scene = scene
        self.root = root
        self._context_key: bytes | None = None
        self._context_shape: tuple | None = None
        self._context: list[viser.SceneNodeHandle] = []
        self._solution: dict[str, Any] = {}
        self._layers: dict[str, Any] = {}
        self._vehicle: dict[str, Any] = {}
        self._vehicle_name: str | None = None
        self._vehicle_size = 1.0
        self._moving: list[tuple[viser.SceneNodeHandle, np.ndarray, np.ndarray]] = []
        self._markers: list[tuple[Any | None, Any | None]] = []
        self._marker_kinds: list[tuple[str, bool, str]] = []
        self._names: dict[str, int] = {}  # times each node name was used
        self._sizes: dict[str, float] = {}  # drawn sizes by role, kept while they fit
        self.updates = 0  # in-place updates sent (a test counts them)
        scene.configure_environment_map(None)
        scene.configure_default_lights(cast_shadow=False)
        self.set_dark(dark)

    def set_dark(self, dark: bool) -> None:
        self.dark = dark
        self.scene.set_background_image(np.full((1, 1, 3), BACKGROUNDS[dark], np.uint8))
        nodes = self._solution.get(f"{self.root}/nodes")
        if nodes is not None:
            nodes.colors = np.array(NODE if dark else NODE_LIGHT, np.uint8)

    def _steady(self, role: str, size: float) -> float:
        """`steady(size)`, keeping the size drawn for `role` while the new one is close."""
        self._sizes[role] = steady(size, self._sizes.get(role))
        return self._sizes[role]

    def _name(self, base: str) -> str:
        """A node name never used before in this view: `base`, then `base~1`, `base~2`...
        (see the module's note: a re-used name keeps a removed node's pose in the page)."""
        uses = self._names.get(base, 0)
        self._names[base] = uses + 1
        return base if uses == 0 else f"{base}~{uses}"

    @property
    def node_count(self) -> int:
        """Scene nodes this view holds (constant over re-solves: nothing accumulates)."""
        return (len(self._context) + len(self._solution) + len(self._layers)
                + len(self._vehicle) + sum((p is not None) + (lab is not None)
                                           for p, lab in self._markers))

    def draw(self, g: Geometry) -> None:
        """Show `g`: the context if it changed, then path, nodes and arrows in place."""
        self._draw_context(g)
        size = self._steady("arrows", 0.006 * g.extent)  # world units: scale with the view
        self._segments(f"{self.root}/trajectory", self._solution, g.segments, g.segment_colors,
                       4.0)
        self._points(f"{self.root}/nodes", g.nodes, self._steady("nodes", node_size(g)))
        self._arrows(f"{self.root}/thrust", g.arrows, size)
        self._scale_bar(g)

    def _scale_bar(self, g: Geometry) -> None:
        """A bar of round length with its unit above the path (the 3D view's scale); none
        on a 2-D plot, whose axes carry ticks."""
        start, end, text = scale_bar(g)
        segment = np.array([[start, end]], np.float32)[:0 if g.plan else 1]
        color = np.array([[[200, 200, 200], [200, 200, 200]]], np.uint8)
        self._segments(f"{self.root}/scale", self._solution, segment, color, 2.0)
        label = self._solution.get(f"{self.root}/scale_label")
        middle = tuple(0.5 * (start + end))
        if label is not None and label.visible == g.plan:
            label.visible = not g.plan
        if g.plan:
            return
        if label is None or _removed(label):
            self._solution[f"{self.root}/scale_label"] = self.scene.add_label(
                self._name(f"{self.root}/scale_label"), text, position=middle,
                font_screen_scale=0.8, anchor="bottom-center")
        else:
            label.text, label.position = text, middle

    def _segments(self, name: str, store: dict, segments: np.ndarray, colors: np.ndarray,
                  thickness: float) -> None:
        draw, handle = _in_place(store, name, len(segments))
        if not draw:
            return
        pts = np.asarray(segments, np.float32)
        cols = line_colors(colors)
        if handle is None:
            store[name] = self.scene.add_line_segments(self._name(name), pts, cols,
                                                       thickness=thickness,
                                                       thickness_units="screen")
            return
        if not (np.array_equal(handle.points, pts) and np.array_equal(handle.colors, cols)):
            handle.points, handle.colors = pts, cols
            self.updates += 1
        if not handle.visible:
            handle.visible = True

    def _points(self, name: str, points: np.ndarray, size: float) -> None:
        draw, handle = _in_place(self._solution, name, len(points))
        if not draw:
            return
        color = np.array(NODE if self.dark else NODE_LIGHT, np.uint8)
        pts = np.asarray(points, np.float32)
        if handle is None:
            self._solution[name] = self.scene.add_point_cloud(
                self._name(name), pts, color, point_size=size, point_shape="circle",
                precision="float32")
            return
        handle.points, handle.point_size = pts, size
        handle.visible = True
        self.updates += 1

    def _arrows(self, name: str, arrows: np.ndarray, size: float) -> None:
        draw, handle = _in_place(self._solution, name, len(arrows))
        if not draw:
            return
        pts = np.asarray(arrows, np.float32)
        if handle is None:
            self._solution[name] = self.scene.add_arrows(
                self._name(name), pts, ARROW, shaft_radius=0.25 * size, head_radius=0.8 * size,
                head_length=2.0 * size)
            return
        handle.points = pts
        handle.shaft_radius, handle.head_radius, handle.head_length = (
            0.25 * size, 0.8 * size, 2.0 * size)
        handle.visible = True
        self.updates += 1

    def show_solution(self, visible: bool) -> None:
        """Hide the solution layer (a comparison shows its own paths) or show it again."""
        for handle in self._solution.values():
            handle.visible = visible

    def set_layer(self, name: str, segments: np.ndarray, colors: np.ndarray,
                  thickness: float = 3.0) -> None:
        """Draw (or, given no segments, hide) a named batch of segments coloured by
        `colors`, (N, 2, 3) sRGB."""
        self._segments(f"{self.root}/layers/{name}", self._layers, segments, colors, thickness)

    def clear_layers(self, prefix: str = "") -> None:
        for path in [p for p in self._layers if p.startswith(f"{self.root}/layers/{prefix}")]:
            self._layers.pop(path).remove()

    # ---- vehicle ------------------------------------------------------------------------
    def set_vehicle(self, vehicle: str, extent: float) -> None:
        """The vehicle mesh (loaded once per vehicle), scaled to the view's extent."""
        size = self._steady("vehicle", VEHICLE_FRACTION * extent)
        if vehicle != self._vehicle_name:
            self.remove_vehicle()
            self._load_vehicle(vehicle)
        if size != self._vehicle_size:
            # A viser frame's scale sizes only its own axes, not its children: the body and
            # the plume are scaled themselves (the plume again per throttle in move_vehicle).
            self._vehicle["body"].scale = size
            plume = self._vehicle.get("plume")
            if plume is not None:
                plume.position = (0.0, 0.0, -0.5 * size)
            force = self._vehicle["force"]
            force.shaft_radius, force.head_radius, force.head_length = (
                0.06 * size, 0.18 * size, 0.4 * size)
            self._vehicle_size = size

    def _load_vehicle(self, vehicle: str) -> None:
        body = vehicle_mesh(vehicle)
        frame = self.scene.add_frame(self._name(f"{self.root}/vehicle"), show_axes=False,
                                     visible=False)
        self._vehicle = {"frame": frame}
        if body is not None:
            self._vehicle["body"] = self.scene.add_glb(f"{frame.name}/body", body, scale=1.0)
            plume = asset_bytes("plume.glb")
            if plume is not None:
                self._vehicle["plume"] = self.scene.add_glb(
                    f"{frame.name}/plume", plume, scale=(1.0, 1.0, 1.0),
                    position=(0.0, 0.0, -0.5), visible=False)
        else:  # no assets: a plain box still shows where the vehicle is
            self._vehicle["body"] = self.scene.add_box(f"{frame.name}/body", (255, 255, 255),
                                                       dimensions=(1.0, 1.0, 1.0))
        self._vehicle["force"] = self.scene.add_arrows(
            self._name(f"{self.root}/vehicle_force"), np.zeros((1, 2, 3), np.float32), ARROW,
            shaft_radius=0.06, head_radius=0.18, head_length=0.4, visible=False)
        self._vehicle_name = vehicle
        self._vehicle_size = 1.0

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
        self._vehicle, self._vehicle_name = {}, None

    def clear(self) -> None:
        """Remove everything drawn (a mission change)."""
        for handle in [*self._context, *self._solution.values(), *self._layers.values(),
                       *(h for pair in self._markers for h in pair if h is not None)]:
            handle.remove()
        self.remove_vehicle()
        self._context, self._solution, self._layers, self._context_key = [], {}, {}, None
        self._context_shape = None
        self._moving, self._markers, self._marker_kinds = [], [], []
        self._sizes = {}

    def _draw_context(self, g: Geometry) -> None:
        """Bodies and reference curves, re-sent only when they changed, and then in place
        when only positions moved (the asteroid's bodies and orbits follow the launch date:
        a position and a line's points, not a new sphere); markers moved in place."""
        key = repr([(s.name, s.center.tolist(), s.radius, s.color, s.subdivisions)
                    for s in g.spheres]).encode()
        key += g.curve_segments.tobytes() + g.curve_colors.tobytes()
        key += b"".join(s.track.tobytes() for s in g.spheres if s.track is not None)
        if key == self._context_key:
            self._draw_markers(g)
            return
        shape = _context_shape(g)
        if shape == self._context_shape and not any(_removed(h) for h in self._context):
            self._move_context(g)
        else:
            self._add_context(g)
        self._context_key, self._context_shape = key, shape
        self._draw_markers(g)

    def _add_context(self, g: Geometry) -> None:
        """New bodies and curves (their set or look changed): remove the old nodes."""
        for handle in self._context:
            handle.remove()
        self._context, self._moving = [], []
        add = self._context.append
        for s in g.spheres:
            add(self.scene.add_icosphere(self._name(f"{self.root}/bodies/{s.name}"),
                                         s.radius, s.color,
                                         subdivisions=s.subdivisions, position=s.center,
                                         cast_shadow=False, receive_shadow=False))
            if s.track is not None:
                self._moving.append((self._context[-1], g.times, s.track))
        if len(g.curve_segments):
            add(self.scene.add_line_segments(self._name(f"{self.root}/curves"),
                                             g.curve_segments.astype(np.float32),
                                             line_colors(g.curve_colors),
                                             thickness=1.5, thickness_units="screen"))

    def _move_context(self, g: Geometry) -> None:
        """The same bodies, and curves or none as on screen: move and resize them in place
        (viser sends only the properties that changed)."""
        self._moving = []
        for handle, s in zip(self._context[:len(g.spheres)], g.spheres, strict=True):
            handle.position = tuple(s.center)
            handle.radius, handle.subdivisions, handle.color = (
                float(s.radius), int(s.subdivisions), tuple(s.color))
            if s.track is not None:
                self._moving.append((handle, g.times, s.track))
        if len(g.curve_segments):
            curves = self._context[-1]
            curves.points = g.curve_segments.astype(np.float32)
            curves.colors = line_colors(g.curve_colors)

    def _draw_markers(self, g: Geometry) -> None:
        """Marker points and labels: made again when their kinds change, else moved in
        place, each label with its point (and its text, when only that changed)."""
        kinds = [(bool(m[0]), m[3], m[4]) for m in g.markers]
        if kinds != self._marker_kinds:
            for handle in (h for pair in self._markers for h in pair if h is not None):
                handle.remove()
            self._markers = [self._add_marker(i, marker, g.extent)
                             for i, marker in enumerate(g.markers)]
            self._marker_kinds = kinds
            return
        for (point, label), (name, position, _, _, _) in zip(self._markers, g.markers,
                                                             strict=True):
            if point is not None:
                point.points = position[None].astype(np.float32)
                point.point_size = self._steady("markers", 0.015 * g.extent)
            if label is not None:
                label.position = tuple(position)
                if label.text != name:
                    label.text = name

    def _add_marker(self, i: int, marker: tuple, extent: float
                    ) -> tuple[Any | None, Any | None]:
        """A marker's point (if it has one) and label (if it has a name)."""
        name, position, color, has_point, anchor = marker
        point = None
        if has_point:
            point = self.scene.add_point_cloud(
                self._name(f"{self.root}/markers/{i}"), position[None].astype(np.float32),
                color, point_size=self._steady("markers", 0.015 * extent), point_shape="circle",
                precision="float32")
        label = None if not name else self.scene.add_label(
            self._name(f"{self.root}/labels/{i}"), name, position=tuple(position),
            font_screen_scale=0.8, anchor=anchor)
        return point, label


def _context_shape(g: Geometry) -> tuple:
    """What of the bodies and curves only new scene nodes can show: which bodies, and
    whether there are curves (a body's size, colour and mesh and the curves' points, of
    any count, are set in place: the elliptic transfer's orbit curves change their sample
    count with every solve, and made it re-create its bodies and curves each time)."""
    return tuple(s.name for s in g.spheres), bool(len(g.curve_segments))
