"""The viser app: one server, one `View` per browser tab (or one shared by every tab with
`shared=True`: the teacher drives, the room watches, and a slider moved in any tab moves in
all of them), every solve on the solve service's worker processes."""

from __future__ import annotations

import threading

import viser

from solvers import list_missions
from solvers.service import SolveService

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
                 prebuild: bool = True) -> None:
        """`workers` solve processes (default one per core) run every solve, unless a
        `runner` is given (tests of missions that live only in the test)."""
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
                                        first_mission=self.mission.key)
            runner = ServiceRunner(self.service)
        self.runner = runner
        self.shared = shared
        self.views: dict[int, View] = {}
        self._lock = threading.Condition()
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
        self.server.stop()
        if self.service is not None:
            self.service.close()
