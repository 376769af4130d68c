"""The viser app: one server, one `View` per browser tab (or one shared by every tab with
`shared=True`: the teacher drives, the room watches, and a slider moved in any tab moves in
all of them), every solve on the solve service's worker processes."""

from __future__ import annotations

import threading
from pathlib import Path

import viser

from solvers import list_missions
from solvers.mission import Mission
from solvers.service import SolveService

from .reload import MissionFiles
from .runners import Runner, ServiceRunner
from .session import DEFAULT_TIME_LIMIT
from .view import View, apply_theme


class ExplorerApp:
    """The viser server; `views` maps client ids to the `View` each browser watches."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, mission: str | None = None,
                 method: str | None = None, nodes: int | None = None,
                 verbose: bool = False, shared: bool = False,
                 time_limit: float | None = DEFAULT_TIME_LIMIT,
                 runner: Runner | None = None, workers: int | None = None,
                 prebuild: bool = True, mission_files: tuple[str, ...] = ()) -> None:
        """`workers` solve processes (default one per core) run every solve, unless a
        `runner` is given (tests of missions that live only in the test). `mission_files`
        (files or folders) add users' missions, reloaded when saved."""
        self.views: dict[int, View] = {}
        self._lock = threading.Condition()
        self.files = MissionFiles(mission_files, self._reloaded, self._file_error)
        self.missions = list_missions()
        by_key = {m.key: m for m in self.missions}
        if mission is not None and mission not in by_key:
            raise ValueError(f"unknown mission '{mission}' (missions: {', '.join(by_key)})")
        self.mission = by_key[mission] if mission else self.missions[0]
        if method is not None:
            self.mission.method(method)  # raises ValueError naming the known methods
        self.method, self.nodes, self.time_limit = method, nodes, time_limit
        self.service: SolveService | None = None
        if runner is None:
            self.service = SolveService(workers, prebuild=prebuild,
                                        first_mission=self.mission.key,
                                        mission_files=self.files.files)
            runner = ServiceRunner(self.service)
        self.runner = runner
        self.shared = shared
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

    def _connect(self, client: viser.ClientHandle) -> None:
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

    def _reloaded(self, mission: Mission, path: str) -> None:
        """A mission file was saved and loads: workers and tabs take the new mission."""
        keys = [m.key for m in self.missions]
        if mission.key in keys:
            self.missions[keys.index(mission.key)] = mission
        else:
            self.missions.append(mission)
        if self.service is not None:
            self.service.reload_mission_files(self.files.files)
        for view in self._all_views():
            view.mission_reloaded(mission, self.missions)

    def _file_error(self, path: str, message: str) -> None:
        """A mission file failed to load: every tab hears it; the old mission stays."""
        for view in self._all_views():
            view.refuse(f"mission file {Path(path).name} not loaded", message)

    def wait_for_view(self, timeout: float) -> View:
        """The first connected tab's view (waits for a browser to connect)."""
        with self._lock:
            if not self._lock.wait_for(lambda: self.views, timeout):
                raise TimeoutError(f"no browser connected within {timeout:g} s")
            return next(iter(self.views.values()))

    def stop(self) -> None:
        with self._lock:
            views = set(self.views.values())
        if self.shared_view is not None:
            views.add(self.shared_view)
        for view in views:
            view.close()
        self.files.stop()
        self.server.stop()
        if self.service is not None:
            self.service.close()
