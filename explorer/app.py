"""The viser app: one `ClientView` (its own `Session`, controls, scene and plots) per browser
tab, so two tabs never see each other's state."""

from __future__ import annotations

import threading
import time
from collections.abc import Sequence

import viser

from solvers import list_missions
from solvers.mission import Mission
from solvers.solution import Solution

from . import status
from .controls import Controls
from .plots import figure_aspect, make_figure
from .scene import FOV, Geometry, SceneView, build_geometry, fit_camera
from .session import Request, Session

PROGRESS_INTERVAL = 0.1  # s between "solving… iteration k" updates
PLOT_PANEL = (620, 300)  # px: plots float in the canvas's bottom-right corner
PANEL_GAP = 10  # px from the canvas edges
PLOT_ASPECT = 0.37  # height/width of the figure inside that panel


class ClientView:
    """One browser tab: a session plus the GUI and scene that show it (a `SessionListener`).

    Extension points: animation and iteration replay draw `session.last_good` (and its
    `history`) through `self.scene`; a method comparison keeps several solutions; a shared
    mode subscribes several views to one session.
    """

    def __init__(self, client: viser.ClientHandle, missions: Sequence[Mission],
                 mission: Mission, method: str | None = None, nodes: int | None = None) -> None:
        self.client = client
        gui = client.gui
        self.session = Session(mission, method=method, nodes=nodes, auto=False)
        self.status = gui.add_markdown("**starting…**", order=0)
        self._result_md = ""
        self._notice: viser.NotificationHandle | None = None
        self._last_progress = 0.0
        self.drawn = 0  # solutions drawn so far (capture waits on this)
        self._fitted: str | None = None
        self._geometry: Geometry | None = None
        fit = gui.add_button("fit view to trajectory", order=1)
        fit.on_click(lambda _: self.fit_camera())
        self.controls = Controls(gui, self.session, missions, order=10)
        self.panel = gui.add_panel()
        with self.panel.add_tab("Plots"):
            self.plot = gui.add_plotly(make_figure([]), aspect=PLOT_ASPECT)
        with self.panel.add_tab("About"):
            self.help = gui.add_markdown("")
        self.panel.float(x=-PANEL_GAP, y=-PANEL_GAP, width=PLOT_PANEL[0], height=PLOT_PANEL[1])
        self.scene = SceneView(client.scene)
        self._fit_aspect: float | None = None  # canvas aspect of the last camera fit
        client.camera.on_update(self._camera_update)
        self.session.listeners.append(self)
        self.on_config(self.session)
        self.session.auto = True
        self.session.submit()

    def close(self) -> None:
        self.session.close()

    # ---- SessionListener ----------------------------------------------------------------
    def on_config(self, session: Session) -> None:
        self.controls.rebuild()
        self.help.content = help_markdown(session.mission, session.method)
        if self._fitted is not None and self._fitted != session.mission.key:
            self.scene.clear()  # another mission: its first solve may fail, show nothing old
            self._geometry = None

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        now = time.monotonic()
        if now - self._last_progress >= PROGRESS_INTERVAL:
            self._last_progress = now
            self.status.content = status.progress_markdown(iteration, self._result_md)

    def on_result(self, request: Request, solution: Solution) -> None:
        good = self.session.last_good
        if solution.ok:
            self._draw(solution, dim=False)
        else:
            if good is not None:
                self._draw(good, dim=True)
            self._notify(f"{solution.status}: {solution.mission}", solution.message)
        self._result_md = status.result_markdown(solution, checking=solution.ok,
                                                 kept=good is not None and not solution.ok)
        self.status.content = self._result_md

    def on_check(self, request: Request, solution: Solution) -> None:
        self._result_md = status.result_markdown(solution)
        self.status.content = self._result_md

    def on_error(self, request: Request, message: str) -> None:
        good = self.session.last_good
        if good is not None:
            self._draw(good, dim=True)
        self._notify("request rejected", message)
        self._result_md = status.rejected_markdown(message, kept=good is not None)
        self.status.content = self._result_md

    def _notify(self, title: str, body: str) -> None:
        """One error notification at a time: a newer problem replaces the older one."""
        if self._notice is not None:
            self._notice.remove()
        self._notice = self.client.add_notification(title, body, color="red",
                                                    auto_close_seconds=10.0)

    # ---- drawing ----------------------------------------------------------------------
    def _draw(self, sol: Solution, dim: bool) -> None:
        if not sol.has_trajectory:
            return
        geometry = build_geometry(sol, dim=dim)
        with self.client.atomic():
            self.scene.draw(geometry)
            self.plot.figure = make_figure(sol.plots, dim=dim)
            self.plot.aspect = figure_aspect(len(sol.plots), PLOT_ASPECT)
        self._geometry = geometry
        if self._fitted != sol.mission:
            self.fit_camera()
            self._fitted = sol.mission
        self.drawn += 1

    def fit_camera(self) -> None:
        """Point this tab's camera at the drawn trajectory (see `scene.fit_camera`)."""
        if self._geometry is None:
            return
        camera = self.client.camera
        covered = (PLOT_PANEL[1] + PANEL_GAP) / max(camera.image_height, 1)
        cam = fit_camera(self._geometry, camera.aspect, bottom=covered)
        self._fit_aspect = camera.aspect
        with self.client.atomic():
            camera.fov = FOV
            camera.near, camera.far = cam.near, cam.far
            camera.max_orbit_distance = cam.far / 2
            camera.up_direction = tuple(cam.up)
            camera.position = tuple(cam.position)
            camera.look_at = tuple(cam.look_at)

    def _camera_update(self, camera: viser.CameraHandle) -> None:
        """Refit when the canvas changes shape (panels docking, window resized): viser does
        not say whether a camera message comes from the user, so a resize wins."""
        if self._fit_aspect is not None and abs(camera.aspect - self._fit_aspect) > 0.01:
            self.fit_camera()


def help_markdown(mission: Mission, method_key: str) -> str:
    """The mission's help, the chosen method's summary and the published numbers."""
    method = mission.method(method_key)
    lines = [f"### {mission.title}", f"_{mission.source}_", "", mission.help.strip(), "",
             f"**Method — {method.label}** ({method.source}): {method.summary}"]
    if mission.published:
        lines += ["", "| published | value | source |", "|---|---|---|"]
        lines += [f"| {p.name} | {p.value:g} {p.unit} | {p.source} |" for p in mission.published]
    return "\n".join(lines)


class ExplorerApp:
    """The viser server; a `ClientView` per connected browser, in `views` by client id."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, mission: str | None = None,
                 method: str | None = None, nodes: int | None = None,
                 verbose: bool = False) -> None:
        self.missions = list_missions()
        by_key = {m.key: m for m in self.missions}
        if mission is not None and mission not in by_key:
            raise ValueError(f"unknown mission '{mission}' (missions: {', '.join(by_key)})")
        self.mission = by_key[mission] if mission else self.missions[0]
        if method is not None:
            self.mission.method(method)  # raises ValueError naming the known methods
        self.method, self.nodes = method, nodes
        self.views: dict[int, ClientView] = {}
        self._lock = threading.Condition()
        self.server = viser.ViserServer(host=host, port=port, label="Trajectory explorer",
                                        verbose=verbose)
        self.server.gui.configure_theme(show_share_button=False, dark_mode=True,
                                        control_width="medium", brand_color=(255, 140, 0))
        self.server.gui.main_panel.dock_left()
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def _connect(self, client: viser.ClientHandle) -> None:
        view = ClientView(client, self.missions, self.mission, self.method, self.nodes)
        with self._lock:
            self.views[client.client_id] = view
            self._lock.notify_all()

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._lock:
            view = self.views.pop(client.client_id, None)
        if view is not None:
            view.close()

    def wait_for_view(self, timeout: float) -> ClientView:
        """The first connected tab's view (waits for a browser to connect)."""
        with self._lock:
            if not self._lock.wait_for(lambda: self.views, timeout):
                raise TimeoutError(f"no browser connected within {timeout:g} s")
            return next(iter(self.views.values()))

    def stop(self) -> None:
        with self._lock:
            views = list(self.views.values())
        for view in views:
            view.close()
        self.server.stop()
