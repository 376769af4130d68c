"""Handles and shapes dragged in the 3D view: each mission's `Handle`s (a start, a target)
and shapes (a keep-out sphere, a glide-slope cone: `solvers.shapes`) drawn as viser
transform controls bound to parameters, each shape a unit mesh placed and scaled by them.

A drag event sets the bound values the way a slider does (clamped at the range's end, the
label saying so, never an exception) and asks the session for a solve: its newest request
wins, so intermediate optima show while the hand moves. The sliders and boxes follow every
submitted value (`on_submit`), the link follows through the view. Where a handle sits comes
from the parameters and the view options (magnification), so it stays where the hand left it
when the answer there is infeasible (the view keeps the last optimum dimmed and names the
bound). Sizes follow the drawn path's extent.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import viser

from solvers import palette
from solvers.handles import AnyHandle, values_at
from solvers.presentation import Presentation
from solvers.problem import Param
from solvers.shapes import Shape

from .geometry import MERGE_LABELS, Geometry, steady
from .panels.setup import Controls
from .panels.value_input import display_unit, shown_text, to_display
from .requests import Request
from .session import Session

GIZMO_FRACTION = 0.12  # gizmo arm length as a fraction of the path's extent
GIZMO_BAND = 0.5  # octaves the path's extent may drift before the gizmo is resized
# s after a hand's last drag event that the gizmo counts as let go even without an "end"
# (a page may miss the release): then the values place it again.
DRAG_IDLE = 1.0
Report = Callable[[str, str], None]
# Whether the browser of this client id may drag (shared mode: only the driver's), and how
# a refused browser is told (its own notification, not everyone's).
MayDrag = Callable[[int | None], bool]
TellClient = Callable[[Any, str, str], None]


@dataclass
class _Drawn:
    """One handle on screen: its record, gizmo, label and (for a shape) its mesh."""

    handle: AnyHandle
    gizmo: viser.TransformControlsHandle
    label: viser.LabelHandle
    shape: Shape | None = None
    mesh: Any = None
    shaft: Any = None  # an arrow's line from its tail to the gizmo
    held: tuple[str, ...] = ()
    in_hand: bool = False
    last_event: float = 0.0

    @property
    def dragging(self) -> bool:
        """In a hand: grabbed, not released, and moved within `DRAG_IDLE`."""
        return self.in_hand and time.monotonic() - self.last_event < DRAG_IDLE


def describe(handle: AnyHandle, values: Mapping[str, float], params: Mapping[str, Param],
             held: tuple[str, ...] = ()) -> str:
    """The short label beside a handle: its name and bound values in display units
    ("start point (2000, 0, 1500) m"; the parameters' names are on the sliders, and a long
    label would cover the path); a date for a day count ("launch window opens 2022-05-28");
    a value held at the end of its range says so."""
    shown = [(to_display(params[k], values[k]), display_unit(params[k])) for k in handle.params]
    units = {unit for _, unit in shown}
    dated = [params[k] for k in handle.params if params[k].epoch is not None]
    if len(handle.params) == 1 and dated:
        text = f"{handle.label} {shown_text(dated[0], values[dated[0].key])}"
    elif len(units) == 1:
        unit = units.pop()
        numbers = ", ".join(f"{v:.4g}" for v, _ in shown)
        text = f"{numbers}{' ' + unit if unit else ''}"
        text = f"{handle.label} {text}" if len(shown) == 1 else \
            f"{handle.label} ({numbers}){' ' + unit if unit else ''}"
    else:
        text = f"{handle.label} (" + ", ".join(
            f"{v:.4g}{' ' + u if u else ''}" for v, u in shown) + ")"
    if held:
        text += " · end of range: " + ", ".join(params[k].label for k in held)
    return text


class Handles:
    """The draggable handles and shapes of one view's mission (a `SessionListener`); the
    view calls `place` after every drawing."""

    def __init__(self, scene: viser.SceneApi, session: Session, controls: Controls,
                 report: Report, root: str = "",
                 released: Callable[[], None] = lambda: None,
                 may_drag: MayDrag = lambda _client_id: True,
                 tell: TellClient = lambda _client, _title, _body: None) -> None:
        """`may_drag(client_id)` says whether that browser's drags count (in shared mode
        only the driver's: two hands on one gizmo would fight); a refused drag puts the
        handle back and `tell`s that browser why."""
        self.scene, self.session, self.controls = scene, session, controls
        self.report, self.root, self.released = report, root, released
        self.may_drag, self.tell = may_drag, tell
        self.moves = 0  # drag events that set values (tests and benchmarks count them)
        self._drawn: dict[str, _Drawn] = {}
        self._scale = 1.0  # scene units per display metre (the presentation's display_scale)
        self._size = 1.0
        self._mission = ""
        self._lock = threading.RLock()
        session.listeners.append(self)

    @property
    def drawn(self) -> dict[str, _Drawn]:
        return self._drawn

    @property
    def in_hand(self) -> bool:
        """Whether a hand holds a handle now (the view keeps its camera still meanwhile, so
        the point under the mouse does not slip)."""
        return any(d.dragging for d in self._drawn.values())

    def _params(self) -> dict[str, Param]:
        return {p.key: p for p in self.session.mission.all_params(self.session.method)}

    # ---- what the view tells -------------------------------------------------------------
    def place(self, pres: Presentation, geometry: Geometry) -> None:
        """Show the mission's handles and shapes for these view options, sized by the path
        (after every drawing: a view change moves them)."""
        mission = self.session.mission
        with self._lock:
            if mission.key != self._mission:
                self.clear()
                self._mission = mission.key
            self._scale = pres.display_scale
            self._size = steady(GIZMO_FRACTION * geometry.extent, self._size if self._drawn
                                else None, GIZMO_BAND)
            view = self.session.view
            items = [(h, None) for h in mission.handles]
            items += [(s.handle, s) for s in mission.shapes]
            for handle, shape in items:
                drawn = self._drawn.get(handle.key)
                if drawn is None:
                    drawn = self._drawn[handle.key] = self._add(handle, shape)
                shown = handle.shown_in(view)
                drawn.gizmo.visible = shown and bool(handle.params)  # a fixed shape: no gizmo
                if drawn.mesh is not None:
                    drawn.mesh.visible = shown
                if drawn.gizmo.scale != self._size and not drawn.dragging:
                    drawn.gizmo.scale = self._size
            self._sync(self.session.values)

    def annotate(self, geometry: Geometry) -> None:
        """A marked point where a shown handle stands keeps its point, not its label: the
        handle's label says the same with its values ("chaser start" under "chaser start
        (15, -0.5, 0) km" would cover it). Every shown handle joins the markers as a bare
        position, so the camera frames it too (a velocity arrow's tip beyond the path)."""
        spots = [np.asarray(d.gizmo.position, float) for d in self._drawn.values()
                 if d.gizmo.visible]
        near = MERGE_LABELS * geometry.extent
        geometry.markers = [
            ("" if point and any(np.linalg.norm(position - s) < near for s in spots) else name,
             position, color, point, anchor)
            for name, position, color, point, anchor in geometry.markers]
        geometry.markers += [("", spot, palette.LABEL, False, "top-left") for spot in spots]

    def clear(self) -> None:
        """Remove every handle (another mission)."""
        with self._lock:
            for drawn in self._drawn.values():
                drawn.gizmo.remove()  # takes its label with it
                for beside in (drawn.shaft, drawn.mesh):
                    if beside is not None:
                        beside.remove()
            self._drawn.clear()
            self._mission = ""

    # ---- SessionListener -----------------------------------------------------------------
    def on_config(self, session: Session) -> None:
        if session.mission.key != self._mission:
            self.clear()

    def on_submit(self, request: Request) -> None:
        """New values went to the solver: sliders, boxes and handles follow them."""
        for key, field in list(self.controls.fields.items()):
            value = request.solve.values.get(key)
            if value is not None and field.value != value:
                field.show(value)
        with self._lock:
            self._sync(request.solve.values)

    # ---- drawing -------------------------------------------------------------------------
    def _add(self, handle: AnyHandle, shape: Shape | None) -> _Drawn:
        name = f"{self.root}/handles/{handle.key}"
        gizmo = self.scene.add_transform_controls(
            name, scale=self._size, active_axes=handle.active_axes, disable_rotations=True,
            depth_test=False, line_width=3.0)
        # Below and left of the point: the gizmo's arrows point up and right, free to grab;
        # an arrow's tip above and right (below and left is towards its tail's label).
        label = self.scene.add_label(f"{name}/label", handle.label, font_screen_scale=0.8,
                                     anchor="bottom-left" if handle.is_arrow else "top-right")
        drawn = _Drawn(handle, gizmo, label, shape)
        if handle.is_arrow:  # not under the gizmo: the tail stays while the tip moves
            drawn.shaft = self.scene.add_line_segments(
                f"{name}_shaft", np.zeros((1, 2, 3), np.float32), palette.LABEL,
                line_width=3.0)
        if shape is not None:  # beside the gizmo, not under it: a fixed shape has none shown
            vertices, faces = shape.unit_mesh()
            drawn.mesh = self.scene.add_mesh_simple(
                f"{name}_shape", vertices, faces, color=palette.BOUND, opacity=0.35,
                side="double", cast_shadow=False, receive_shadow=False)
        gizmo.on_update(lambda event: self._event(drawn, event))
        return drawn

    def _event(self, drawn: _Drawn, event: viser.TransformControlsEvent) -> None:
        """A browser moved a gizmo: a drag if that browser may drag, else put it back."""
        if self.may_drag(event.client_id):
            self._dragged(drawn, event.phase)
            return
        with self._lock:
            drawn.in_hand = False
            self._sync(self.session.values)
        if event.phase == "start" and event.client is not None:
            self.tell(event.client, "only the driver drags",
                      "Every tab shows one case here: the tab that opened first drives the "
                      "handles (sliders move for everyone).")

    def _sync(self, values: Mapping[str, float]) -> None:
        """Put every handle not in a hand where `values` place it, labels and shapes too."""
        view, params = self.session.view, self._params()
        for drawn in self._drawn.values():
            h = drawn.handle
            if any(k not in values for k in h.params):
                continue
            if not drawn.dragging:
                drawn.gizmo.position = tuple(self._scale * np.array(h.where(values, view)))
            if drawn.shaft is not None:
                drawn.shaft.points = np.array([[self._scale * np.array(h.tail(values, view)),
                                                drawn.gizmo.position]], np.float32)
            drawn.label.text = describe(h, values, params, drawn.held)
            if drawn.shape is not None:  # where the values put it (clamped), not the hand
                drawn.mesh.position = tuple(self._scale * np.array(h.where(values, view)))
                drawn.mesh.scale = tuple(self._scale * np.array(drawn.shape.scale(values, view)))

    # ---- dragging ------------------------------------------------------------------------
    def drag(self, key: str, position: tuple[float, float, float], phase: str = "update") -> None:
        """Move handle `key` to `position` (scene units) as a hand does (tests, benchmarks)."""
        drawn = self._drawn[key]
        drawn.gizmo.position = position
        self._dragged(drawn, phase)

    def _dragged(self, drawn: _Drawn, phase: str) -> None:
        """A drag event (threadpool: events may arrive out of order, so each reads the
        gizmo's latest pose): set the bound values, clamped, and solve."""
        with self._lock:
            drawn.in_hand, drawn.last_event = phase != "end", time.monotonic()
            position = np.array(drawn.gizmo.position, float) / self._scale
            moved = values_at(drawn.handle, position, tuple(self._params().values()),
                              self.session.view, self.session.values)
            drawn.held = moved.held
            self.moves += 1
        try:
            self.session.set_values(moved.values)
        except KeyError as exc:  # a drag racing a mission change: nothing to set
            self.report("handle", str(exc))
            return
        with self._lock:
            self._sync(self.session.values)
        if phase == "end":
            self.released()
        if phase == "end" and moved.held:
            params = self._params()
            ends = "; ".join(f"{params[k].label} {params[k].describe_range()}"
                             for k in moved.held)
            self.report(drawn.handle.label, f"held at the end of the range: {ends}")
