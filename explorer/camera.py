"""Where the camera looks from: framing a path obliquely from the side of its best-fit plane
(pure numpy on a `Geometry`, display units), the plan view, the chase camera, and the cameras
of the browsers that watch one view."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
import viser

from .geometry import Geometry
from .player import quaternion_from_axes

FOV = math.radians(50.0)
ELEVATION = 0.06  # how far above the trajectory's plane the camera looks from
OBLIQUE = math.radians(20.0)  # camera azimuth from the plane normal towards the start
# Of the canvas height, kept clear above the highest and below the lowest framed point: a
# label stands above or below its point in screen space (the hovercraft's target-velocity
# label ran off the top edge).
LABEL_ROOM = 0.08


@dataclass
class Camera:
    """A camera pose in display units plus clipping distances."""

    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    near: float
    far: float


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


def plot_view(g: Geometry) -> np.ndarray:
    """Direction towards a camera that sees a 2-D plot's plane as a plot: display x to the
    right and the scene's up (display y) up, i.e. from +z."""
    view = np.cross([1.0, 0.0, 0.0], g.scene_up)
    return view / np.linalg.norm(view) if np.linalg.norm(view) > 1e-9 else np.array([0, 0, 1.0])


def top_view(g: Geometry) -> np.ndarray:
    """Direction from the path towards a camera looking straight at its plane (the plan
    view), from the side 'up' points to when the plane is vertical; a 2-D plot's own
    (`plot_view`)."""
    if g.plan:
        return plot_view(g)
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
    'Up' is `_view_up`, made perpendicular to the line of sight. A 2-D plot (`Geometry.plan`)
    is seen straight on, x to the right and y up."""
    if view is None and g.plan:
        view = plot_view(g)
    up = _view_up(g)
    pts = g.points if len(g.points) else g.center[None]
    framed = np.concatenate([pts, g.arrows.reshape(-1, 3), np.stack(scale_bar(g)[:2])]
                            + [m[1][None] for m in g.markers])
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
        # The trajectory lies across 'up' (e.g. an orbit or a ground plane seen from above):
        # look down at it from the side that puts display x to the right (from -y when up
        # is +z, as a map is read: x right, y away).
        side = np.cross([1.0, 0.0, 0.0], up)
        if np.linalg.norm(side) < 0.3:
            side = np.array([0.0, 1.0, 0.0]) - up[1] * up
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
    need_h = z + margin * np.abs(rel @ screen_up) / ((1.0 - bottom - LABEL_ROOM) * tan_v)
    distance = max(float(np.max(need_w)), float(np.max(need_h)), 1e-2 * g.extent)
    reach = max([np.linalg.norm(s.center - g.center) + s.radius for s in g.spheres] + [g.extent])
    # Aim below the centre so that it shows in the middle of the uncovered part.
    look_at = g.center - bottom * tan_v * distance * screen_up
    return Camera(g.center + distance * view, look_at, up,
                  near=1e-3 * distance, far=4.0 * (distance + reach))


FOLLOW_DISTANCE = 8.0  # follow camera distance in vehicle lengths
# After a placement, a browser's camera messages are its pose from before (already on the way)
# until it echoes the placement; past this wait without an echo (a person took the camera
# while ours was on the way), its messages count as a person's again.
ECHO_WAIT_S = 2.0


class Cameras:
    """The cameras of the browsers watching one view: framed by `fit_camera` minding the
    floating panel over the bottom of the canvas, refitted when a canvas changes shape. A
    person who orbits the camera keeps their angle: later refits (a new scale) only move the
    camera along that direction, until the camera is reset."""

    def __init__(self, covered_px: float) -> None:
        self.covered_px = covered_px  # canvas pixels hidden under the floating plot panel
        self.clients: dict[int, viser.ClientHandle] = {}
        self._fit_aspect: dict[int, float] = {}
        self._placed: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # what we set last
        self._sent_at: dict[int, float] = {}  # when, until the browser echoes it
        self.user_view: dict[int, np.ndarray] = {}  # direction a person chose, per browser
        self._refit: Callable[[viser.ClientHandle], None] | None = None
        self.framed: tuple[str, np.ndarray, np.ndarray, float] | None = None

    def attach(self, client: viser.ClientHandle, refit: Callable[[viser.ClientHandle], None]
               ) -> None:
        self.clients[client.client_id] = client
        self._refit = refit
        client.camera.on_update(self._camera_update)

    def detach(self, client: viser.ClientHandle) -> None:
        self.clients.pop(client.client_id, None)
        self._fit_aspect.pop(client.client_id, None)
        self._placed.pop(client.client_id, None)
        self._sent_at.pop(client.client_id, None)
        self.user_view.pop(client.client_id, None)

    def needs_framing(self, mission: str, g: Geometry) -> bool:
        """Whether the cameras must frame the path again: a new mission, a path that left
        the framed box (by a quarter of its size) or shrank below 40 % of it. Records the
        new frame when they must."""
        lo, hi = g.points.min(axis=0), g.points.max(axis=0)
        old = self.framed
        if old is not None and old[0] == mission:
            _, old_lo, old_hi, old_extent = old
            margin = 0.25 * old_extent
            inside = bool(np.all(lo >= old_lo - margin) and np.all(hi <= old_hi + margin))
            if inside and g.extent >= 0.4 * old_extent:
                return False
        else:
            self.forget_user_views()
        self.framed = (mission, lo, hi, g.extent)
        return True

    def forget_user_views(self) -> None:
        """Back to the framed overview (reset camera, another mission)."""
        self.user_view.clear()

    def chosen(self, clients: Iterable[viser.ClientHandle] | None) -> list[viser.ClientHandle]:
        return list(self.clients.values()) if clients is None else list(clients)

    def frame(self, g: Geometry, view: np.ndarray | None,
              clients: Iterable[viser.ClientHandle] | None = None,
              follow: np.ndarray | None = None, vehicle_size: float = 1.0) -> None:
        """Point each camera at `g` (from direction `view` if given), or chase `follow`."""
        for client in self.chosen(clients):
            camera = client.camera
            covered = self.covered_px / max(camera.image_height, 1)
            chosen = view if view is not None else self.user_view.get(client.client_id)
            cam = fit_camera(g, camera.aspect, bottom=covered, view=chosen)
            self._fit_aspect[client.client_id] = camera.aspect
            with client.atomic():
                camera.fov = FOV
                camera.near, camera.far = cam.near, cam.far
                camera.max_orbit_distance = cam.far / 2
                camera.up_direction = tuple(cam.up)
                if follow is not None:
                    self._chase(client, g, follow, vehicle_size)
                else:
                    camera.position = tuple(cam.position)
                    camera.look_at = tuple(cam.look_at)
                    self._place(client, cam.position, cam.look_at)

    def chase(self, g: Geometry, target: np.ndarray, vehicle_size: float) -> None:
        for client in self.chosen(None):
            self._chase(client, g, target, vehicle_size)

    def _chase(self, client: viser.ClientHandle, g: Geometry, target: np.ndarray,
               vehicle_size: float) -> None:
        """Chase camera: a few vehicle lengths behind the overview's line of sight."""
        camera = client.camera
        cam = fit_camera(g, camera.aspect, view=self.user_view.get(client.client_id))
        back = cam.position - cam.look_at
        back /= np.linalg.norm(back)
        position = target + FOLLOW_DISTANCE * vehicle_size * back
        with client.atomic():
            camera.look_at = tuple(target)
            camera.position = tuple(position)
        self._place(client, position, np.asarray(target, float))

    def _place(self, client: viser.ClientHandle, position: np.ndarray, look_at: np.ndarray
               ) -> None:
        self._placed[client.client_id] = (np.asarray(position, float), look_at)
        self._sent_at[client.client_id] = time.monotonic()

    def _camera_update(self, camera: viser.CameraHandle) -> None:
        """Refit when the canvas changes shape (panels docking, window resized): viser does
        not say whether a camera message comes from the user, so a resize wins."""
        client = camera.client
        fitted = self._fit_aspect.get(client.client_id)
        if fitted is not None and abs(camera.aspect - fitted) > 0.01 and self._refit:
            self._refit(client)
            return
        placed = self._placed.get(client.client_id)
        if placed is None:
            return
        position, look_at = np.asarray(camera.position), np.asarray(camera.look_at)
        scale = max(float(np.linalg.norm(placed[0] - placed[1])), 1e-12)
        moved = (np.linalg.norm(position - placed[0]) + np.linalg.norm(look_at - placed[1]))
        ours = moved <= 1e-3 * scale  # our own placement coming back, not a person's move
        sent = self._sent_at.get(client.client_id)
        if sent is not None:
            if ours:  # our placement came back: later messages are a person's
                del self._sent_at[client.client_id]
                return
            if time.monotonic() - sent < ECHO_WAIT_S:  # the pose from before, on its way
                return
            del self._sent_at[client.client_id]
        if not ours:  # a person moved it
            direction = position - look_at
            if np.linalg.norm(direction) > 0:
                self.user_view[client.client_id] = direction / np.linalg.norm(direction)


def nice_length(x: float) -> float:
    """The largest 1, 2 or 5 times a power of ten not above x."""
    if x <= 0:
        return 1.0
    power = 10.0 ** math.floor(math.log10(x))
    return max(m for m in (1.0, 2.0, 5.0) if m * power <= x * (1 + 1e-9)) * power


def scale_bar(g: Geometry) -> tuple[np.ndarray, np.ndarray, str]:
    """A bar of a round length (about a quarter of the path's extent) beside the path, along
    its main direction, and its label with the display unit. Beside means 'above' where the
    path's plane holds the up direction (a landing, a reentry); where the plane is level (an
    orbit seen from above) it is the plane's other direction, so the bar never lies on the
    path in a plan view."""
    pts = g.points if len(g.points) else g.center[None]
    up = _view_up(g)
    axes = _plane_axes(pts)
    side = up - up.dot(axes[2]) * axes[2]
    if np.linalg.norm(side) < 0.5:
        side = np.cross(up, axes[0])
        side = side if np.linalg.norm(side) > 1e-9 else axes[1]
    side /= np.linalg.norm(side)
    along = axes[0] - axes[0].dot(side) * side
    if np.linalg.norm(along) < 1e-9:
        along = np.cross(side, [0.0, 0.0, 1.0]) if abs(side[2]) < 0.9 else np.array([1.0, 0, 0])
    along /= np.linalg.norm(along)
    length = nice_length(0.25 * g.extent)
    height = float(np.max((pts - g.center) @ side)) + 0.12 * g.extent
    middle = g.center + height * side
    return middle - 0.5 * length * along, middle + 0.5 * length * along, f"{length:g} {g.unit}"


def camera_wxyz(cam: Camera) -> np.ndarray:
    """The orientation of `cam` in viser's camera convention (+z forward, +y down)."""
    forward = np.asarray(cam.look_at, float) - np.asarray(cam.position, float)
    return quaternion_from_axes(forward / np.linalg.norm(forward), -np.asarray(cam.up, float))


def shot_pose(g: Geometry, aspect: float) -> tuple[np.ndarray, np.ndarray, float]:
    """(wxyz, position, fov) of a camera framing `g` on a whole image (no panel over it)."""
    cam = fit_camera(g, aspect)
    return camera_wxyz(cam), cam.position, FOV
