"""The View a classroom tab gets: a `View` on a `RoomSession` that joins the room, with the
Classroom folder, the hidden teacher-key box, and the Room folder while it is the teacher's."""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

import viser

from solvers.mission import Mission

from .panels.room import ClassroomBar, RoomPanel, TeacherKey
from .requests import Request
from .room import Room, Shot
from .room_session import RoomSession
from .runners import Runner
from .session import Session
from .view import View

REFRESH_S = 0.25  # s: the room's panels are redrawn at most this often


class RoomView(View):
    """A classroom tab: a `View` on a `RoomSession` that joins the room (following), with
    the Classroom folder, the hidden teacher-key box, and the Room folder while it is the
    teacher's. `claim(view, key)` hears the key its page's address carried."""

    session_class = RoomSession

    def __init__(self, gui: viser.GuiApi, scene: viser.SceneApi, atomic: Callable[[], Any],
                 missions: Sequence[Mission], mission: Mission, method: str | None,
                 nodes: int | None, time_limit: float | None, runner: Runner | None, *,
                 room: Room, member_id: int, room_url: str,
                 claim: Callable[[RoomView, str], None], scene_root: str = "") -> None:
        self.room, self.member_id = room, member_id
        self.panel: RoomPanel | None = None
        self._refresh_due = False
        self._refresh_lock = threading.Lock()
        self._panel_lock = threading.Lock()  # one `_refresh` at a time
        self._claim = claim
        self._early_key: str | None = None  # a key sent before the tab joined the room
        self._joined = False
        self.key = TeacherKey(gui, self._key_sent)  # before the case link rewrites the address
        super().__init__(gui, scene, atomic, missions, mission, method, nodes, time_limit,
                         runner, scene_root)
        self.room_session: RoomSession = self.session  # type: ignore[assignment]
        self.room_session.on_refused = self._refused
        self.room_session.on_shot = self._take_shot
        self.bar = ClassroomBar(gui, room, member_id, room_url)
        room.listeners.append(self.room_changed)
        self.member = room.join(member_id, self.room_session)
        with self._refresh_lock:
            self._joined, key = True, self._early_key
        if key is not None:
            claim(self, key)

    def _key_sent(self, key: str) -> None:
        with self._refresh_lock:
            if not self._joined:
                self._early_key = key
                return
        self._claim(self, key)

    def room_changed(self) -> None:
        """Redraw the classroom panels soon (many changes make one redraw)."""
        with self._refresh_lock:
            if self._refresh_due:
                return
            self._refresh_due = True
        timer = threading.Timer(REFRESH_S, self._refresh)
        timer.daemon = True
        timer.start()

    def _refresh(self) -> None:
        """One redraw at a time: a change heard while the Room folder is being built starts
        another timer, which must not build a second folder."""
        with self._refresh_lock:
            self._refresh_due = False
        with self._panel_lock:
            if self._closed.is_set():
                return
            if self.member.teacher and self.panel is None:
                self.panel = RoomPanel(self.gui, self.room)
            elif not self.member.teacher and self.panel is not None:
                self.panel.remove()
                self.panel = None
            self.bar.refresh()
            if self.panel is not None:
                self.panel.refresh()

    # ---- the teacher's camera and clock ----------------------------------------------
    def attach(self, client: viser.ClientHandle) -> None:
        super().attach(client)
        client.camera.on_update(lambda camera: self._share(camera))

    def _share(self, camera: viser.CameraHandle | None = None) -> None:
        """The teacher's tab moved its camera or clock: the room hears it."""
        member = getattr(self, "member", None)  # camera updates may come before joining
        if member is None or not member.teacher:
            return
        if camera is None:
            clients = list(self.camera.clients.values())
            if not clients:
                return
            camera = clients[0].camera
        self.room.share(Shot(tuple(map(float, camera.position)),
                             tuple(map(float, camera.look_at)),
                             tuple(map(float, camera.up_direction)), float(self.play.t)))

    def show_time(self, t: float, slow: bool, marker: bool = True) -> None:
        super().show_time(t, slow, marker)
        if slow and self.room.sharing:
            self._share()

    def _take_shot(self, shot: Shot) -> None:
        """A follower shows the teacher's camera and animation time."""
        for client in list(self.camera.clients.values()):
            with client.atomic():
                client.camera.up_direction = shot.up
                client.camera.position = shot.position
                client.camera.look_at = shot.look_at
        track = self.play.track
        if track is not None and not self.play.playing:
            self.play.t = min(max(shot.t, track.t0), track.tf)
            View.show_time(self, self.play.t, slow=True)
            self.play.follow_slider(self.play.t)

    def _refused(self, key: str, message: str) -> None:
        self.refuse("the challenge freezes this", message)
        field = self.controls.fields.get(key)
        if field is not None and key in self.session.values:
            field.show(self.session.values[key])

    def _show_values(self) -> None:
        """A follower's controls show the teacher's values (without applying them)."""
        s = self.session
        params = {p.key: p for p in (*s.mission.all_params(s.method), *s.mission.view_params)}
        for key, handle in list(self.controls.inputs.items()):
            if key == "nodes":
                self.controls.fields["nodes"].show(s.nodes)
            elif key == "backend" and s.backend:
                handle.value = s.backend
            elif key in params:
                value = s.values.get(key, s.view.get(key))
                if value is None:
                    continue
                if key in self.controls.fields:
                    self.controls.fields[key].show(value)
                elif params[key].options:
                    handle.value = params[key].options[int(value)]

    def on_submit(self, request: Request) -> None:
        super().on_submit(request)
        if self.room_session.following:
            self._show_values()

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        """A follower keeps the teacher's last picture while the teacher's solve runs (a
        dimmed redraw in every follower would cost as much as the answer's own)."""
        if not self.room_session.following:
            super().on_progress(request, iteration, message)

    def on_view(self, session: Session) -> None:
        super().on_view(session)
        if self.room_session.following:
            self._show_values()

    def close(self) -> None:
        if self.room_changed in self.room.listeners:
            self.room.listeners.remove(self.room_changed)
        super().close()
