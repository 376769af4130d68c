"""The viser app. A `View` is a `Session` plus the GUI and scene that show it. By default each
browser tab gets its own view (`client.gui`/`client.scene`), so ten students moving sliders
never see each other's state; with `shared=True` one view is built on the server-wide GUI and
scene (`server.gui`/`server.scene`), which viser mirrors to every tab: the teacher drives,
the room watches, and a slider moved in any tab moves in all of them.

Everything is generated from the mission contract: no mission has GUI code of its own.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Sequence
from contextlib import AbstractContextManager
from typing import Any

import numpy as np
import plotly.graph_objects as go
import viser

from solvers import list_missions
from solvers.mission import Mission
from solvers.solution import Solution

from . import status
from .about import about_html
from .animation import SPEEDS, Track, readout_markdown, readouts
from .compare import comparison_html
from .controls import Controls
from .export import file_stem, plots_png, png_bytes, solution_csv, solution_figure, solution_json
from .legend import legend_html
from .plots import figure_aspect, make_figure, map_figure, set_time_marker
from .scene import (
    FOV,
    PALETTE,
    WARNING,
    Geometry,
    SceneView,
    build_geometry,
    fit_camera,
    ghost_geometry,
    path_segments,
    top_view,
)
from .session import DEFAULT_TIME_LIMIT, Request, Session

PROGRESS_INTERVAL = 0.1  # s between "solving… iteration k" updates
DIM_AFTER = 0.25  # s: a solve slower than this dims the old trajectory while it runs
PLOT_PANEL = (620, 300)  # px: plots float in the canvas's bottom-right corner
PANEL_GAP = 10  # px from the canvas edges
PLOT_ASPECT = 0.37  # height/width of the figure inside that panel
FRAME_S = 1 / 20  # animation frame period (vehicle, follow camera)
SLOW_S = 1 / 3  # period of the slower animation updates (plot marker, read-outs, slider)
REPLAY_STEP_S = 0.45  # s per iterate in the iteration replay
CAMERAS = ("overview", "follow vehicle", "top view")
FOLLOW_DISTANCE = 8.0  # follow camera distance in vehicle lengths


def apply_theme(gui: viser.GuiApi, dark: bool) -> None:
    """Classroom theme: no share button (it needs the internet), panel docked left."""
    gui.configure_theme(dark_mode=dark, show_share_button=False, control_width="medium",
                        brand_color=(255, 140, 0))


class View:
    """One session shown through one GUI and scene; `attach` the browsers that watch it
    (one per tab, or every tab in shared mode). Implements `SessionListener`."""

    def __init__(self, gui: viser.GuiApi, scene: viser.SceneApi,
                 atomic: Callable[[], AbstractContextManager[Any]], missions: Sequence[Mission],
                 mission: Mission, method: str | None = None, nodes: int | None = None,
                 time_limit: float | None = DEFAULT_TIME_LIMIT) -> None:
        self.gui = gui
        self.atomic = atomic  # groups one update into one browser frame
        self.clients: dict[int, viser.ClientHandle] = {}
        self.session = Session(mission, method=method, nodes=nodes, auto=False,
                               time_limit=time_limit)
        self.dark = True
        self.drawn = 0  # solutions drawn so far (capture waits on this)
        self._lock = threading.RLock()  # scene and figure updates come from several threads
        self._closed = threading.Event()
        self._result_md = ""
        self._notices: list[viser.NotificationHandle] = []
        self._last_progress = 0.0
        self._request: Request | None = None
        self._dimmed = False
        self._failed = False
        self._geometry: Geometry | None = None
        self._mission_drawn: str | None = None
        self._fit_aspect: dict[int, float] = {}
        self._comparison: list[Solution] = []
        self._shown: tuple[Solution, bool] | None = None  # what _draw drew last
        # animation state
        self.track: Track | None = None
        self.t_anim = 0.0
        self.playing = False
        self._player: threading.Thread | None = None
        self._replay: threading.Thread | None = None
        self._slow_at = 0.0
        self._setting_time = False
        self._figure = make_figure([])
        self._n_series = 0

        self.status = gui.add_markdown("**starting…**", order=0)
        self.progress = gui.add_progress_bar(0.0, animated=True, visible=False, order=1)
        self.legend = gui.add_html("", order=2)
        with gui.add_folder("Result details", order=3, expand_by_default=False):
            self.details = gui.add_markdown("")
        tabs = gui.add_tab_group(order=5)
        self.tab_setup = tabs.add_tab("Setup", viser.Icon.ADJUSTMENTS)
        self.tab_play = tabs.add_tab("Play", viser.Icon.PLAYER_PLAY)
        self.tab_compare = tabs.add_tab("Compare", viser.Icon.LAYOUT_COLUMNS)
        self.tab_export = tabs.add_tab("Export", viser.Icon.DOWNLOAD)
        self.controls = Controls(gui, self.session, missions, order=10, container=self.tab_setup)
        with self.tab_play:
            self._build_play()
        with self.tab_compare:
            self._build_compare()
        with self.tab_export:
            self._build_export()
        self.panel = gui.add_panel()
        with self.panel.add_tab("Plots", viser.Icon.CHART_LINE):
            self.plot = gui.add_plotly(self._figure, aspect=PLOT_ASPECT)
        with self.panel.add_tab("Map", viser.Icon.MAP):
            self.map_note = gui.add_markdown("This mission has no map.")
            self.map_plot = gui.add_plotly(go.Figure(), aspect=PLOT_ASPECT, visible=False)
        self._map_key: tuple | None = None
        with self.panel.add_tab("About", viser.Icon.INFO_CIRCLE):
            self.about = gui.add_html("")
        self.panel.float(x=-PANEL_GAP, y=-PANEL_GAP, width=PLOT_PANEL[0], height=PLOT_PANEL[1])
        self._build_commands()
        self.scene = SceneView(scene, dark=self.dark)
        self.session.listeners.append(self)
        self.on_config(self.session)
        self.session.auto = True
        self.session.submit()

    # ---- GUI construction -----------------------------------------------------------------
    def _build_play(self) -> None:
        gui = self.gui
        self.play_button = gui.add_button("play", icon=viser.Icon.PLAYER_PLAY,
                                          hint="Play/pause the vehicle along the trajectory "
                                               "(key: space)")
        self.play_button.on_click(lambda _: self.toggle_play())
        self.time_slider = gui.add_slider("time [s]", 0.0, 1.0, 0.001, 0.0,
                                          hint="Animation time: drag to move the vehicle.")
        self.time_slider.on_update(self._time_moved)
        self.speed = gui.add_dropdown("speed", tuple(SPEEDS), initial_value="1x",
                                      hint="1x plays the whole trajectory in 12 s.")
        self.camera_mode = gui.add_dropdown("camera", CAMERAS, initial_value=CAMERAS[0],
                                            hint="overview: the whole path; follow: chase the "
                                                 "vehicle; top: look straight at the path's "
                                                 "plane.")
        self.camera_mode.on_update(lambda _: self.apply_camera())
        reset = gui.add_button("reset camera", icon=viser.Icon.FOCUS_CENTERED,
                               hint="Back to the overview (key: r)")
        reset.on_click(lambda _: self.reset_camera())
        self.readout = gui.add_markdown("")
        with gui.add_folder("Solver iterations", expand_by_default=True):
            self.ghosts = gui.add_checkbox(
                "show iterates", False,
                hint="Draw the solver's intermediate trajectories (Solution.history), the "
                     "earliest faintest.")
            self.ghosts.on_update(lambda _: self._draw_ghosts())
            self.replay_button = gui.add_button(
                "replay iterations", icon=viser.Icon.PLAYER_TRACK_NEXT,
                hint="Step through the iterates one by one, fading into the optimum.")
            self.replay_button.on_click(lambda _: self.replay_iterations())
            self.replay_text = gui.add_markdown("")

    def _build_compare(self) -> None:
        gui = self.gui
        self.compare_intro = gui.add_markdown(
            "Solve the same case with several methods and overlay the results.")
        self.compare_boxes: dict[str, Any] = {}
        self._compare_folder: Any = None
        self.compare_button = gui.add_button("solve and compare", icon=viser.Icon.SCALE,
                                             order=100)
        self.compare_button.on_click(lambda _: self.run_comparison())
        clear = gui.add_button("clear comparison", order=101)
        clear.on_click(lambda _: self.clear_comparison(redraw=True))
        self.compare_table = gui.add_html("", order=102)

    def _build_export(self) -> None:
        gui = self.gui
        with gui.add_folder("Download"):
            for label, kind in (("solution (JSON)", "json"), ("solution (CSV)", "csv"),
                                ("plots (PNG)", "plots"), ("screenshot of the view (PNG)",
                                                           "shot")):
                button = gui.add_button(label, icon=viser.Icon.DOWNLOAD)
                button.on_click(lambda event, kind=kind: self.download(kind, event.client))
        with gui.add_folder("Settings"):
            limit = self.session.time_limit or 0.0
            self.time_limit = gui.add_number(
                "solve time limit [s]", limit, min=0.0, max=600.0, step=0.5,
                hint="A solve still running after this is stopped (status 'time-limit'); "
                     "a cold start (new method, comparison) gets three times as long; "
                     "0: no limit.")
            self.time_limit.on_update(lambda _: self.session.set_time_limit(
                float(self.time_limit.value)))
            self.dark_box = gui.add_checkbox("dark mode", True, hint="Dark or light theme.")
            self.dark_box.on_update(lambda _: self.set_dark(bool(self.dark_box.value)))
        gui.add_markdown("Keys: **space** play/pause · **r** reset camera · **ctrl-k** "
                         "command palette. Offline copy of a case: `python -m explorer.export "
                         "--mission KEY --out DIR`.")

    def _build_commands(self) -> None:
        play = self.gui.add_command("Play / pause animation", hotkey="space",
                                    icon=viser.Icon.PLAYER_PLAY)
        play.on_trigger(lambda _: self.toggle_play())
        reset = self.gui.add_command("Reset camera", hotkey="R", icon=viser.Icon.FOCUS_CENTERED)
        reset.on_trigger(lambda _: self.reset_camera())

    def _rebuild_compare_boxes(self) -> None:
        if self._compare_folder is not None:
            self._compare_folder.remove()
        self.compare_boxes = {}
        with self.tab_compare:
            self._compare_folder = self.gui.add_folder("Methods", order=50)
            with self._compare_folder:
                for m in self.session.mission.methods:
                    self.compare_boxes[m.key] = self.gui.add_checkbox(m.label, True,
                                                                      hint=m.summary)

    @property
    def geometry(self) -> Geometry | None:
        """What the scene shows now (display units), None before the first solution."""
        return self._geometry

    @property
    def comparison(self) -> list[Solution]:
        """The solutions of the comparison on screen (empty when none)."""
        return self._comparison

    def scene_vehicle_position(self) -> np.ndarray:
        """Where the vehicle is drawn now (display units)."""
        return self.scene.vehicle_position

    # ---- browsers watching this view ----------------------------------------------------
    def attach(self, client: viser.ClientHandle) -> None:
        """A browser starts watching: frame the current solution in its camera."""
        self.clients[client.client_id] = client
        client.camera.on_update(self._camera_update)
        if self._geometry is not None:
            self.apply_camera([client])

    def detach(self, client: viser.ClientHandle) -> None:
        self.clients.pop(client.client_id, None)
        self._fit_aspect.pop(client.client_id, None)

    def close(self) -> None:
        self._closed.set()
        self.playing = False
        self.session.close()

    # ---- SessionListener ----------------------------------------------------------------
    def on_config(self, session: Session) -> None:
        self.controls.rebuild()
        self._rebuild_compare_boxes()
        self.about.content = about_html(session.mission, session.method)
        self.clear_comparison(redraw=False)
        if self._mission_drawn is not None and self._mission_drawn != session.mission.key:
            with self._lock:  # another mission: its first solve may fail, show nothing old
                self.scene.clear()
                self._geometry, self.track, self._mission_drawn = None, None, None
                self._figure, self._n_series = make_figure([], dark=self.dark), 0
                self.plot.figure = self._figure
            self.legend.content = self.readout.content = self.details.content = ""
            self.t_anim = 0.0

    def on_submit(self, request: Request) -> None:
        self._request = request
        self._dimmed = False

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        now = time.monotonic()
        if now - self._last_progress < PROGRESS_INTERVAL:
            return
        self._last_progress = now
        elapsed = now - request.started
        if elapsed < DIM_AFTER:
            return
        limit = request.time_limit
        self.progress.visible = True
        self.progress.value = min(100.0, 100.0 * elapsed / limit) if limit else 100.0
        if not self._dimmed and not request.compare:
            self._dimmed = True
            good = self.session.last_good
            if good is not None and good.mission == request.mission.key:
                self._draw(good, dim=True)
        self.status.content = status.progress_markdown(iteration, self._result_md, elapsed,
                                                       limit, message)

    def on_result(self, request: Request, solution: Solution) -> None:
        self.progress.visible = False
        good = self.session.last_good
        self.clear_comparison(redraw=False)
        if solution.ok:
            self._draw(solution, dim=False)
            self._set_failed(None)
        else:
            if good is not None:
                self._draw(good, dim=True)
            self._set_failed(solution if solution.has_trajectory else None)
            self._notify(f"{solution.status}: {solution.mission}", solution.message)
        self._result_md = status.result_markdown(solution, checking=solution.ok,
                                                 kept=good is not None and not solution.ok)
        self.status.content = self._result_md
        self.details.content = status.details_markdown(solution)

    def on_check(self, request: Request, solution: Solution) -> None:
        self._result_md = status.result_markdown(solution)
        self.status.content = self._result_md
        self.details.content = status.details_markdown(solution)

    def on_error(self, request: Request, message: str) -> None:
        self.progress.visible = False
        good = self.session.last_good
        if good is not None:
            self._draw(good, dim=True)
        self._notify("request rejected", message)
        self._result_md = status.rejected_markdown(message, kept=good is not None)
        self.status.content = self._result_md

    def on_compare(self, request: Request, solutions: list[Solution]) -> None:
        self.progress.visible = False
        self.status.content = self._result_md
        self.show_comparison(solutions)

    def _notify(self, title: str, body: str) -> None:
        """One error notification per browser at a time: a newer one replaces the older."""
        for notice in self._notices:
            notice.remove()
        self._notices = [c.add_notification(title, body, color="red", auto_close_seconds=10.0)
                         for c in list(self.clients.values())]

    # ---- drawing ----------------------------------------------------------------------
    def _draw(self, sol: Solution, dim: bool) -> None:
        if not sol.has_trajectory:
            return
        self._shown = (sol, dim)
        geometry = build_geometry(sol, dim=dim)
        figure = make_figure(sol.plots, dim=dim, dark=self.dark)
        with self._lock, self.atomic():
            self.scene.draw(geometry)
            self._geometry = geometry
            self._figure, self._n_series = figure, len(sol.plots)
            if not dim:
                self._new_track(sol, geometry)
            set_time_marker(self._figure, self._n_series,
                            self.t_anim if self.track else None, self.dark)
            self.plot.figure = self._figure
            self.plot.aspect = figure_aspect(len(sol.plots), PLOT_ASPECT)
            self._draw_map(sol)
            self._draw_ghosts()
        self.legend.content = legend_html(geometry, dim=dim, failed=self._failed)
        if self._mission_drawn != sol.mission:
            self._mission_drawn = sol.mission
            self.apply_camera()
        self.drawn += 1

    def _draw_map(self, sol: Solution) -> None:
        """The solution's first `GridMap` in the Map tab, re-sent only when it changed."""
        grid_map = sol.maps[0] if sol.maps else None
        key = None if grid_map is None else (id(grid_map.z), grid_map.marker, self.dark)
        if key == self._map_key:
            return
        self._map_key = key
        self.map_note.visible = grid_map is None
        self.map_plot.visible = grid_map is not None
        if grid_map is not None:
            self.map_plot.figure = map_figure(grid_map, self.dark)

    def _set_failed(self, sol: Solution | None) -> None:
        """Show a failed attempt's trajectory in the warning colour (or remove it)."""
        self._failed = sol is not None
        segments = path_segments(sol) if sol is not None else np.zeros((0, 2, 3))
        colors = np.broadcast_to(np.array(WARNING, np.uint8), segments.shape)
        with self._lock:
            self.scene.set_layer("failed", segments, colors, thickness=3.0)
        if self._geometry is not None:
            self.legend.content = legend_html(self._geometry, dim=self._failed,
                                              failed=self._failed)

    def _draw_ghosts(self) -> None:
        good = self.session.last_good
        with self._lock:
            if self.ghosts.value and good is not None and good.history:
                segs, cols = ghost_geometry(good, dark=self.dark)
                self.scene.set_layer("ghosts", segs, cols, thickness=1.5)
            else:
                self.scene.clear_layers("ghosts")

    def set_dark(self, dark: bool) -> None:
        self.dark = dark
        apply_theme(self.gui, dark)
        with self._lock:
            self.scene.set_dark(dark)
        if self._shown is not None:
            self._draw(*self._shown)

    # ---- comparison -------------------------------------------------------------------
    def run_comparison(self) -> None:
        methods = [k for k, box in self.compare_boxes.items() if box.value]
        if len(methods) < 2:
            self.compare_table.content = "<p><b>Tick at least two methods.</b></p>"
            return
        self.compare_table.content = "<p><em>solving…</em></p>"
        self.session.compare(methods)

    def show_comparison(self, solutions: list[Solution]) -> None:
        self._comparison = solutions
        colors = [PALETTE[i % len(PALETTE)] for i in range(len(solutions))]
        with self._lock:
            self.scene.show_solution(False)
            self.scene.clear_layers("compare")
            for i, (sol, color) in enumerate(zip(solutions, colors, strict=True)):
                if sol.has_trajectory:
                    segs = path_segments(sol)
                    self.scene.set_layer(f"compare/{i}", segs,
                                         np.broadcast_to(np.array(color, np.uint8), segs.shape),
                                         thickness=3.5)
            labels = [s.method for s in solutions]
            self._figure = make_figure([], dark=self.dark, overlays=[
                (label, color, sol.plots) for label, color, sol
                in zip(labels, colors, solutions, strict=True) if sol.has_trajectory])
            self.plot.figure = self._figure
        self.compare_table.content = comparison_html(self.session.mission, solutions, colors)
        self.legend.content = legend_html(self._geometry, comparison=list(zip(
            labels, colors, strict=True))) if self._geometry is not None else ""

    def clear_comparison(self, redraw: bool) -> None:
        if not self._comparison and not redraw:
            return
        self._comparison = []
        self.compare_table.content = ""
        with self._lock:
            self.scene.clear_layers("compare")
            self.scene.show_solution(True)
        good = self.session.last_good
        if redraw and good is not None:
            self._draw(good, dim=False)

    # ---- iteration replay ---------------------------------------------------------------
    def replay_iterations(self) -> None:
        sol = self.session.last_good
        if sol is None or not sol.history:
            self.replay_text.content = "_this method records no iterates_"
            return
        if self._replay is not None and self._replay.is_alive():
            return
        self._replay = threading.Thread(target=self._run_replay, args=(sol,), daemon=True,
                                        name="explorer-replay")
        self._replay.start()

    def _run_replay(self, sol: Solution) -> None:
        """Hide the optimum, add the iterates one at a time (older ones fading), then show
        the optimum again."""
        with self._lock:
            self.scene.show_solution(False)
        n = len(sol.history)
        for k in range(1, n + 1):
            if self._closed.is_set() or self.session.last_good is not sol:
                break
            segs, cols = ghost_geometry(sol, upto=k, dark=self.dark)
            with self._lock:
                self.scene.set_layer("ghosts", segs, cols, thickness=2.0)
            self.replay_text.content = (f"iterate {k} of {n} (solver iteration "
                                        f"{sol.history[k - 1]['iteration']})")
            time.sleep(REPLAY_STEP_S)
        self.replay_text.content = f"{n} iterates recorded; the optimum is drawn in colour"
        with self._lock:
            self.scene.show_solution(not self._comparison)
        self._draw_ghosts()

    # ---- animation ----------------------------------------------------------------------
    def _new_track(self, sol: Solution, geometry: Geometry) -> None:
        self.track = Track(sol)
        self.t_anim = min(max(self.t_anim, self.track.t0), self.track.tf)
        self.scene.set_vehicle(sol.mission, geometry.extent)
        self._setting_time = True
        try:
            span = self.track.tf - self.track.t0
            self.time_slider.min = self.track.t0
            self.time_slider.max = self.track.tf
            self.time_slider.step = float(f"{span / 500:.2g}") if span > 0 else 1.0
            self.time_slider.value = self.t_anim
        finally:
            self._setting_time = False
        self.show_time(self.t_anim, slow=True)

    def toggle_play(self) -> None:
        if self.playing:
            self.playing = False
            return
        if self.track is None:
            return
        self.playing = True
        self.play_button.label = "pause"
        self.play_button.icon = viser.Icon.PLAYER_PAUSE
        if self._player is None or not self._player.is_alive():
            self._player = threading.Thread(target=self._play, daemon=True,
                                            name="explorer-player")
            self._player.start()

    def _play(self) -> None:
        last = time.monotonic()
        while self.playing and not self._closed.is_set():
            time.sleep(FRAME_S)
            now = time.monotonic()
            track = self.track
            if track is None:
                break
            t = track.step(self.t_anim, now - last, SPEEDS[self.speed.value])
            last = now
            self.show_time(t, slow=now - self._slow_at >= SLOW_S or t >= track.tf)
            if t >= track.tf:
                break
        self.playing = False
        self.show_time(self.t_anim, slow=True)  # read-outs and marker at the paused time
        self.play_button.label = "play"
        self.play_button.icon = viser.Icon.PLAYER_PLAY

    def _time_moved(self, _: Any) -> None:
        if not self._setting_time:
            self.show_time(float(self.time_slider.value), slow=True, from_slider=True)

    def show_time(self, t: float, slow: bool, from_slider: bool = False) -> None:
        """Move the vehicle (and a following camera) to time t; `slow` also updates the
        slower views: time slider (unless it moved), read-outs and the plots' marker."""
        track = self.track
        if track is None:
            return
        self.t_anim = t
        pose = track.pose(t)
        with self._lock:
            self.scene.move_vehicle(pose)
            self.scene.move_bodies(t)
        if self.camera_mode.value == "follow vehicle":
            self._follow(pose.position)
        if not slow:
            return
        self._slow_at = time.monotonic()
        good = self.session.last_good
        if not from_slider:
            self._setting_time = True
            try:
                self.time_slider.value = float(min(max(t, track.t0), track.tf))
            finally:
                self._setting_time = False
        if good is not None:
            frame = good.scene.frame if good.scene is not None else ""
            self.readout.content = readout_markdown(readouts(good, track, t), frame)
        with self._lock:
            if not self._comparison:
                set_time_marker(self._figure, self._n_series, t, self.dark)
                self.plot.figure = self._figure

    # ---- camera -------------------------------------------------------------------------
    def reset_camera(self) -> None:
        if self.camera_mode.value != CAMERAS[0]:
            self.camera_mode.value = CAMERAS[0]  # runs apply_camera through its callback
        else:
            self.apply_camera()

    def apply_camera(self, clients: Iterable[viser.ClientHandle] | None = None) -> None:
        """Point the cameras (of `clients`, default all watching) by the camera mode."""
        g = self._geometry
        if g is None:
            return
        mode = self.camera_mode.value
        for client in list(self.clients.values()) if clients is None else clients:
            camera = client.camera
            covered = (PLOT_PANEL[1] + PANEL_GAP) / max(camera.image_height, 1)
            view = top_view(g) if mode == "top view" else None
            cam = fit_camera(g, camera.aspect, bottom=covered, view=view)
            self._fit_aspect[client.client_id] = camera.aspect
            with client.atomic():
                camera.fov = FOV
                camera.near, camera.far = cam.near, cam.far
                camera.max_orbit_distance = cam.far / 2
                camera.up_direction = tuple(cam.up)
                if mode == "follow vehicle" and self.track is not None:
                    self._follow(self.track.pose(self.t_anim).position, [client])
                else:
                    camera.position = tuple(cam.position)
                    camera.look_at = tuple(cam.look_at)

    def _follow(self, target: np.ndarray, clients: Iterable[viser.ClientHandle] | None = None
                ) -> None:
        """Chase camera: a few vehicle lengths behind the overview's line of sight."""
        g = self._geometry
        if g is None:
            return
        for client in list(self.clients.values()) if clients is None else clients:
            camera = client.camera
            cam = fit_camera(g, camera.aspect)
            back = cam.position - cam.look_at
            back /= np.linalg.norm(back)
            distance = FOLLOW_DISTANCE * self.scene.vehicle_size
            with client.atomic():
                camera.look_at = tuple(target)
                camera.position = tuple(target + distance * back)

    def _camera_update(self, camera: viser.CameraHandle) -> None:
        """Refit when the canvas changes shape (panels docking, window resized): viser does
        not say whether a camera message comes from the user, so a resize wins."""
        client = camera.client
        fitted = self._fit_aspect.get(client.client_id)
        if fitted is not None and abs(camera.aspect - fitted) > 0.01:
            self.apply_camera([client])

    # ---- export -------------------------------------------------------------------------
    def download(self, kind: str, client: viser.ClientHandle | None) -> None:
        """Send the current solution (JSON/CSV), its plots (PNG) or a screenshot of this
        client's view (PNG) to the browser that asked."""
        if client is None:
            return
        sol = self.session.last_good
        if sol is None and kind != "shot":
            client.add_notification("nothing to export", "no solution yet", color="yellow",
                                    auto_close_seconds=5.0)
            return
        try:
            if kind == "json":
                client.send_file_download(f"{file_stem(sol)}.json", solution_json(sol),
                                          save_immediately=True)
            elif kind == "csv":
                client.send_file_download(f"{file_stem(sol)}.csv", solution_csv(sol),
                                          save_immediately=True)
            elif kind == "plots":
                note = client.add_notification("rendering the plots…", "kaleido", loading=True,
                                               with_close_button=False)
                try:
                    png = plots_png(solution_figure(sol), len(sol.plots))
                finally:
                    note.remove()
                client.send_file_download(f"{file_stem(sol)}-plots.png", png,
                                          save_immediately=True)
            else:
                camera = client.camera
                image = client.get_render(camera.image_height, camera.image_width,
                                          transport_format="png", timeout=30.0)
                name = f"{file_stem(sol)}-view.png" if sol else "view.png"
                client.send_file_download(name, png_bytes(image), save_immediately=True)
        except (RuntimeError, TimeoutError) as exc:
            client.add_notification("export failed", str(exc), color="red",
                                    auto_close_seconds=15.0)


class ExplorerApp:
    """The viser server; `views` maps client ids to the `View` each browser watches (one
    per tab, or one shared by all with `shared=True`)."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, mission: str | None = None,
                 method: str | None = None, nodes: int | None = None,
                 verbose: bool = False, shared: bool = False,
                 time_limit: float | None = DEFAULT_TIME_LIMIT) -> None:
        self.missions = list_missions()
        by_key = {m.key: m for m in self.missions}
        if mission is not None and mission not in by_key:
            raise ValueError(f"unknown mission '{mission}' (missions: {', '.join(by_key)})")
        self.mission = by_key[mission] if mission else self.missions[0]
        if method is not None:
            self.mission.method(method)  # raises ValueError naming the known methods
        self.method, self.nodes, self.time_limit = method, nodes, time_limit
        self.shared = shared
        self.views: dict[int, View] = {}
        self._lock = threading.Condition()
        self.server = viser.ViserServer(host=host, port=port, label="Trajectory explorer",
                                        verbose=verbose)
        apply_theme(self.server.gui, dark=True)
        self.server.gui.main_panel.dock_left()
        self.shared_view = (View(self.server.gui, self.server.scene, self.server.atomic,
                                 self.missions, self.mission, method, nodes, time_limit)
                            if shared else None)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def _connect(self, client: viser.ClientHandle) -> None:
        view = self.shared_view or View(client.gui, client.scene, client.atomic, self.missions,
                                        self.mission, self.method, self.nodes, self.time_limit)
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
