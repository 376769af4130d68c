"""The viser app: one server, one `View` per browser tab (or one shared by every tab with
`shared=True`: a slider moved in any tab moves in all of them; or, with `classroom=True`, a
`RoomView` per tab in one `Room`: the tab opened with the teacher's key drives and the others
follow, explore on their own and rejoin), every solve on the solve service's worker
processes."""

from __future__ import annotations

import secrets
import threading
from pathlib import Path

import viser

from solvers import list_missions
from solvers.cluster import connect
from solvers.mission import Mission
from solvers.registry import is_user_mission, mission_file_of
from solvers.service import SolveService

from .reload import MissionFiles
from .room import Room
from .room_view import RoomView
from .runners import ClusterRunner, Runner, ServiceRunner
from .session import DEFAULT_TIME_LIMIT, Session
from .view import View
from .view_drawing import apply_theme
from .viser_threads import make_pushes_thread_safe

make_pushes_thread_safe()  # before any server: the views push from worker and relay threads

START_LIMIT = 60.0  # s: the classroom's start-up solve


class ExplorerApp:
    """The viser server; `views` maps client ids to the `View` each browser watches."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, mission: str | None = None,
                 method: str | None = None, nodes: int | None = None,
                 verbose: bool = False, shared: bool = False,
                 time_limit: float | None = DEFAULT_TIME_LIMIT,
                 runner: Runner | None = None, workers: int | None = None,
                 prebuild: bool = True, mission_files: tuple[str, ...] = (),
                 classroom: bool = False, teacher_secret: str | None = None,
                 scheduler: str | None = None) -> None:
        """`workers` solve processes (default one per core) run every solve, unless a
        `runner` is given (tests of missions that live only in the test) or a dask
        `scheduler` address (every solve on that cluster: `RuntimeError` when it cannot be
        reached). `mission_files`
        (files or folders) add users' missions, reloaded when saved. `classroom`: the
        presenter mode, driven from `teacher_url` (`teacher_secret`, default a random
        one)."""
        if classroom and shared:
            raise ValueError("--classroom and --shared are two different modes: choose one")
        self.views: dict[int, View] = {}
        self._lock = threading.Condition()
        self.files = MissionFiles(mission_files, self._reloaded, self._file_error)
        # Missions registered in this process before (another app's files, a library user's)
        # are offered only where the solves can find them: from their file in the workers.
        self.missions = [m for m in list_missions() if runner is not None
                         or not is_user_mission(m.key) or mission_file_of(m.key)]
        by_key = {m.key: m for m in self.missions}
        if mission is not None and mission not in by_key:
            raise ValueError(f"unknown mission '{mission}' (missions: {', '.join(by_key)})")
        self.mission = by_key[mission] if mission else self.missions[0]
        if method is not None:
            self.mission.method(method)  # raises ValueError naming the known methods
        self.method, self.nodes, self.time_limit = method, nodes, time_limit
        self.service: SolveService | None = None
        self.cluster: ClusterRunner | None = None
        if runner is None and scheduler:
            runner = self.cluster = ClusterRunner(connect(scheduler), self._worker_files())
        if runner is None:
            self.service = SolveService(workers, prebuild=prebuild,
                                        first_mission=self.mission.key,
                                        mission_files=self._worker_files())
            runner = ServiceRunner(self.service)
        self.runner = runner
        self.shared = shared
        self.room: Room | None = None
        self.teacher_secret = (teacher_secret or secrets.token_urlsafe(16)) if classroom \
            else None
        if classroom:  # the start-up case, solved once for the room (workers may still be
            # building their first NLP: a longer limit than a slider move's)
            start = Session(self.mission, method=method, nodes=nodes, runner=self.runner,
                            time_limit=None if time_limit is None
                            else max(time_limit, START_LIMIT))
            self.room = Room(start)
            start.submit()
        self.server = viser.ViserServer(host=host, port=port, label="Trajectory explorer",
                                        verbose=verbose)
        apply_theme(self.server.gui, dark=True)
        self.server.gui.main_panel.dock_left()
        self.shared_view = (self._view(self.server.gui, self.server.scene, self.server.atomic)
                            if shared else None)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    def _view(self, gui, scene, atomic) -> View:
        return View(gui, scene, atomic, self.missions, self.mission, self.method, self.nodes,
                    self.time_limit, runner=self.runner)

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    @property
    def teacher_url(self) -> str:
        """The link that drives a classroom (empty outside the presenter mode)."""
        return f"{self.url}/?teacher={self.teacher_secret}" if self.teacher_secret else ""

    def _room_view(self, client: viser.ClientHandle) -> RoomView:
        assert self.room is not None
        return RoomView(client.gui, client.scene, client.atomic, self.missions, self.mission,
                        self.method, self.nodes, self.time_limit, self.runner, room=self.room,
                        member_id=client.client_id, room_url=f"{self.url}/",
                        claim=self._claim)

    def _claim(self, view: RoomView, key: str) -> None:
        """A page says it was opened with the teacher's key: it drives if the key is right."""
        secret = self.teacher_secret
        if self.room is None or secret is None or len(key) > 4 * len(secret) \
                or not secrets.compare_digest(key.encode(), secret.encode()):
            view.refuse("this is not the teacher's link", "you follow the room as a student")
            return
        self.room.promote(view.member_id)

    def _connect(self, client: viser.ClientHandle) -> None:
        if self.room is not None:
            view: View = self._room_view(client)
        else:
            view = self.shared_view or self._view(client.gui, client.scene, client.atomic)
        view.attach(client)
        for path, message in self.files.errors.items():
            client.add_notification(f"mission file {Path(path).name}", message, color="red")
        with self._lock:
            self.views[client.client_id] = view
            self._lock.notify_all()

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._lock:
            view = self.views.pop(client.client_id, None)
        if view is None:
            return
        if self.room is not None:
            self.room.leave(client.client_id)
        view.detach(client)
        if view is not self.shared_view:
            view.close()
            if self.service is not None:
                self.service.forget(view.session.id)

    def _all_views(self) -> list[View]:
        with self._lock:
            views = set(self.views.values())
        if getattr(self, "shared_view", None) is not None:
            views.add(self.shared_view)
        return list(views)

    def _worker_files(self) -> list[str]:
        """The mission files the solve workers load: this app's and those every other user
        mission on offer came from."""
        listed = [f for m in self.missions if (f := mission_file_of(m.key))]
        return list(dict.fromkeys(self.files.files + listed))

    def _reloaded(self, mission: Mission, path: str) -> None:
        """A mission file was saved and loads: workers and tabs take the new mission."""
        keys = [m.key for m in self.missions]
        if mission.key in keys:
            self.missions[keys.index(mission.key)] = mission
        else:
            self.missions.append(mission)
        if self.service is not None:
            self.service.reload_mission_files(self._worker_files())
        for view in self._all_views():
            view.file_loaded(path)
            view.mission_reloaded(mission, self.missions)

    def _file_error(self, path: str, message: str) -> None:
        """A mission file failed to load: every tab hears it; the old mission stays."""
        for view in self._all_views():
            view.file_broken(path, f"mission file {Path(path).name} not loaded", message)

    def stop(self) -> None:
        with self._lock:
            views = set(self.views.values())
        if self.shared_view is not None:
            views.add(self.shared_view)
        for view in views:
            view.close()
        if self.room is not None:
            self.room.close()
        self.files.stop()
        self.server.stop()
        if self.service is not None:
            self.service.close()
        if self.cluster is not None:
            self.cluster.close()
