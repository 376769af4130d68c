"""A `View` is a `Session` shown through one GUI and one scene: it builds the panels, listens
to the session, and turns each solution into a presentation (the mission's view), geometry
and plots. By default each browser tab has its own view (`client.gui`/`client.scene`); in
shared mode one view is built on the server-wide GUI and scene, mirrored to every tab.

Everything is generated from the mission contract: no mission has GUI code of its own.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager
from typing import Any

import viser

from solvers.mission import Mission
from solvers.presentation import Presentation
from solvers.solution import Solution

from . import style
from .about import about_html
from .geometry import Geometry
from .handles import Handles
from .help import KeyHelp, Welcome
from .legend import legend_html
from .link import CaseLink, case_query, parse_case
from .overlays import ComparisonOverlay, IterationReplay
from .page_figures import PageFigure
from .panels.compare import ComparePanel
from .panels.export import ExportPanel
from .panels.play import PlayPanel
from .panels.setup import Controls
from .panels.side import SidePanel
from .panels.status import StatusPanel
from .panels.trust import TrustPanel
from .plots import figure_tree
from .runners import Runner
from .scene import SceneView
from .sending import sender
from .session import DEFAULT_TIME_LIMIT, Request, Session
from .view_camera import ViewCamera
from .view_drawing import ViewDrawing, drawn_signature

PROGRESS_INTERVAL = 0.1  # s between "solving… iteration k" updates
DIM_AFTER = 0.25  # s: a solve slower than this dims the old trajectory while it runs
DRAG_PATIENCE = 0.5  # s: a newer slider value lets a younger running solve finish and show
BUILD_WAIT = 60.0  # s: a link that arrives while the view is built waits at most this long


class View(ViewDrawing):
    """One session shown through one GUI and scene; `attach` the browsers that watch it
    (one per tab, or every tab in shared mode). Implements `SessionListener`."""

    session_class: type[Session] = Session  # a classroom's views use a Session subclass

    def __init__(self, gui: viser.GuiApi, scene: viser.SceneApi,
                 atomic: Callable[[], AbstractContextManager[Any]], missions: Sequence[Mission],
                 mission: Mission, method: str | None = None, nodes: int | None = None,
                 time_limit: float | None = DEFAULT_TIME_LIMIT,
                 runner: Runner | None = None, scene_root: str = "") -> None:
        """`scene_root` prefixes this view's scene nodes (views sharing one scene)."""
        self.gui = gui
        self.atomic = atomic  # groups one update into one browser frame
        self.send_now = sender(atomic)  # the words of an answer leave before its picture
        self.session = self.session_class(mission, method=method, nodes=nodes, auto=False,
                                          time_limit=time_limit, runner=runner,
                                          patience=DRAG_PATIENCE)
        self.dark = True
        self.drawn = 0  # solutions drawn so far (capture waits on this)
        self._lock = threading.RLock()  # scene and figure updates come from several threads
        self._closed = threading.Event()
        self._last_progress = 0.0
        self._dimmed = False
        self._failed = False
        self._geometry: Geometry | None = None
        self._shown: tuple[Solution, Presentation, bool] | None = None
        self._drawn: tuple = ()  # what the check could change of the drawing on screen
        self._marker_at = 0.0
        # A link can arrive (from the page, on another thread) before this view is built.
        self._built = threading.Event()

        style.install(gui)
        self.missions = {m.key: m for m in missions}
        self.link = CaseLink(gui, self.restore_link)
        self.welcome = Welcome(gui)
        self.status = StatusPanel(gui)
        self._build_tabs(gui, missions)
        self.side = SidePanel(gui, self._redraw)
        self._build_commands()
        self.scene = SceneView(scene, dark=self.dark, root=scene_root)
        self.camera = ViewCamera(self.play, self._lock, self._drawn_geometry,
                                 lambda: self.scene.vehicle_size)
        self.handles = Handles(scene, self.session, self.controls, self.refuse, scene_root,
                               released=self.camera.frame_if_needed, may_drag=self.drives,
                               tell=self.status.notify_one)
        self.overlay = ComparisonOverlay(self.scene, self._lock, self.side,
                                         self.compare.show_table, self.present)
        self.replay = IterationReplay(self.scene, self._lock, lambda: self.presentation,
                                      self._say_replay, self._replay_done)
        self.session.listeners.append(self)
        self.on_config(self.session)
        self.session.auto = True
        self.session.submit()
        self._built.set()

    def _build_tabs(self, gui: viser.GuiApi, missions: Sequence[Mission]) -> None:
        """The Setup, Play, Compare and Export tabs and their panels."""
        tabs = gui.add_tab_group(order=5)
        tab_setup = tabs.add_tab("Setup", viser.Icon.ADJUSTMENTS)
        self.controls = Controls(gui, self.session, missions, order=10, container=tab_setup,
                                 report=self.refuse)
        with tab_setup:
            self.trust = TrustPanel(gui, self.session, self._redraw, order=10.5)
        with tabs.add_tab("Play", viser.Icon.PLAYER_PLAY):
            self.play = PlayPanel(gui, self.show_time, lambda: self.camera.apply(),
                                  lambda: self.camera.reset(), self._draw_ghosts,
                                  self.replay_iterations)
        with tabs.add_tab("Compare", viser.Icon.LAYOUT_COLUMNS):
            self.compare = ComparePanel(gui, self.session.compare,
                                        lambda: self.clear_comparison(redraw=True))
        with tabs.add_tab("Export", viser.Icon.DOWNLOAD):
            self.export = ExportPanel(gui, self.current, self.session.time_limit,
                                      self.session.set_time_limit, self.set_dark,
                                      lambda aspect: self.camera.shot(aspect), self.refuse)

    def _build_commands(self) -> None:
        play = self.gui.add_command("Play / pause animation", hotkey="space",
                                    icon=viser.Icon.PLAYER_PLAY)
        play.on_trigger(lambda _: self.play.toggle())
        reset = self.gui.add_command("Reset camera", hotkey="R", icon=viser.Icon.FOCUS_CENTERED)
        reset.on_trigger(lambda _: self.camera.reset())
        self.key_help = KeyHelp(self.gui)

    def mission_reloaded(self, mission: Mission, missions: Sequence[Mission]) -> None:
        """A mission file was reloaded: the mission list follows, and a tab showing that
        mission takes the new one (same values where they still exist) and solves again."""
        self.missions = {m.key: m for m in missions}
        self.controls.missions = {m.title: m for m in missions}
        if self.session.mission.key == mission.key:
            self.session.reload_mission(mission)
        else:
            self.controls.rebuild()

    def restore_link(self, query: str) -> None:
        """The page was opened with a case in its address: set that case (once the view is
        built: on a busy server the page's address came in while it was still being built,
        and a malformed link's notice found no camera to name the tab by)."""
        if not self._built.wait(BUILD_WAIT):
            return
        try:
            mission, method, nodes, backend, values, view = parse_case(query, self.missions)
            self.session.restore(mission, method, nodes, values, view, backend)
        except ValueError as exc:  # the default case stays; the notice says why
            self.status.notify_kept(self.camera.clients.values(),
                                    "this link's case cannot be restored", str(exc))

    def _say_replay(self, text: str) -> None:
        self.play.show_replay(text)

    def file_broken(self, path: str, title: str, message: str) -> None:
        """A mission file failed to load: a notice that stays until the file loads again."""
        self.status.notify_file(self.camera.clients.values(), path, title, message)

    def file_loaded(self, path: str) -> None:
        self.status.clear_file_notice(path)

    def refuse(self, title: str, message: str) -> None:
        """A typed value was refused: say why in every watching browser."""
        self.status.notify(self.camera.clients.values(), title, message)

    # ---- what is on screen ------------------------------------------------------------------
    @property
    def geometry(self) -> Geometry | None:
        """What the scene shows now (display units), None before the first solution."""
        return self._geometry

    @property
    def comparison(self) -> list[Solution]:
        """The solutions of the comparison on screen (empty when none)."""
        return self.overlay.solutions

    def _drawn_geometry(self) -> tuple[str, Geometry] | None:
        """(mission key, geometry) of the drawing on screen, for the cameras."""
        shown, geometry = self._shown, self._geometry
        return None if shown is None or geometry is None else (shown[0].mission, geometry)

    def current(self) -> tuple[Solution | None, Presentation | None]:
        """The good solution on screen and its presentation."""
        good = self.session.last_good
        if good is None or self._shown is None or self._shown[0] is not good:
            return good, self.present(good) if good is not None else None
        return good, self._shown[1]

    # ---- browsers watching this view ----------------------------------------------------
    def attach(self, client: viser.ClientHandle) -> None:
        """A browser starts watching: frame the current solution in its camera."""
        self.camera.attach(client)

    def detach(self, client: viser.ClientHandle) -> None:
        self.camera.detach(client)

    def drives(self, client_id: int | None) -> bool:
        """Whether the browser `client_id` drives this view's handles: the one that opened
        first of those watching (only shared mode has several; None: the server itself)."""
        watching = list(self.camera.clients)
        return client_id is None or not watching or client_id == watching[0]

    def close(self) -> None:
        self._closed.set()
        self.replay.closed.set()
        self.play.close()
        self.side.later.close()
        self.session.close()

    # ---- SessionListener ----------------------------------------------------------------
    def on_config(self, session: Session) -> None:
        self.link.show(case_query(session))
        self.controls.rebuild()
        self.compare.rebuild(session.mission)
        self.side.show_about(about_html(session.mission, session.method))
        self.clear_comparison(redraw=False)
        self.compare.show_table("")  # also "solving…" or "tick at least two methods"
        self.trust.clear()  # a verdict belongs to the case it checked
        self.play.show_replay("")
        shown = self._shown[0].mission if self._shown is not None else None
        if shown is not None and shown != session.mission.key:
            with self._lock:  # another mission: its first solve may fail, show nothing old
                self.scene.clear()
                self._geometry, self._shown = None, None
                self.camera.forget_frame()
                self.play.set_track(None)
                self.side.show_figure(PageFigure(figure_tree([], dark=self.dark), 0))
            self.status.clear()
            self.play.show_readout("")
            self.play.t = 0.0

    def on_view(self, session: Session) -> None:
        """A view option changed: redraw what is on screen from the same solution."""
        self.link.show(case_query(session))
        if self._shown is not None:
            sol, _, dim = self._shown
            self._draw(sol, dim)

    def on_submit(self, request: Request) -> None:
        self._dimmed = False
        self.link.show(case_query(self.session))

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        now = time.monotonic()
        if now - self._last_progress < PROGRESS_INTERVAL:
            return
        self._last_progress = now
        elapsed = now - request.started
        if elapsed < DIM_AFTER:
            return
        if not self._dimmed and not request.compare:
            self._dimmed = True
            good = self.session.last_good
            if good is not None and good.mission == request.mission.key:
                self._draw(good, dim=True)
        self.status.show_progress(iteration, elapsed, request.solve.time_limit, message)

    def on_result(self, request: Request, solution: Solution) -> None:
        good = self.session.last_good
        self.clear_comparison(redraw=False)
        self.trust.clear()
        self.status.clear_notices()
        if request.refine and solution.converged:
            self.controls.fields["nodes"].show(solution.nodes)
        self.link.show(case_query(self.session))  # a refinement changed the node count
        # The words first, the picture after: a batch of GUI messages alone is applied by
        # the page at once, while one that touches the scene waits for the next 3D frame
        # (and its text for the frame after that). Sent apart, the new numbers are painted
        # in the same frame as the new scene, one software frame (~85 ms) sooner.
        self.status.show_result(solution, checking=solution.ok and solution.has_trajectory,
                                kept=good is not None and not solution.converged,
                                nodes_label=self._nodes_label(request, solution))
        self.send_now()
        if solution.converged:
            self._draw(solution, dim=False)
            self._set_failed(None)
        else:
            if good is not None:
                self._draw(good, dim=True)
            self._set_failed(solution if solution.has_trajectory else None)
            self.status.notify(self.camera.clients.values(),
                               f"{solution.status}: {solution.mission}", solution.message)

    @staticmethod
    def _nodes_label(request: Request, sol: Solution) -> str:
        """The word for the node count of `sol`'s method (as its slider says it)."""
        return request.mission.method(sol.method).nodes_label

    def on_check(self, request: Request, solution: Solution) -> None:
        self.status.show_result(solution, checking=False, kept=False,
                                nodes_label=self._nodes_label(request, solution))
        if self._shown is None or self._shown[0] is not solution:
            return
        # Draw again only if the check changed what is on screen (a reference curve, the
        # error colours, the optimality plots): every redraw costs the page a 3D frame.
        changed = self._drawn != drawn_signature(self.present(solution), solution)
        if changed or self.trust.error_colors_on \
                or self.side.page_name.startswith(("costate", "Hamiltonian")):
            self._draw(solution, dim=False)

    def on_error(self, request: Request, message: str) -> None:
        good = self.session.last_good
        if good is not None:
            self._draw(good, dim=True)
        self.status.notify(self.camera.clients.values(), "request rejected", message)
        self.status.show_rejected(message, kept=good is not None)

    def on_compare(self, request: Request, solutions: list[Solution]) -> None:
        self.status.restore()
        good = self.session.last_good
        if len(request.compare) == 1 and good is not None:  # check from cold
            cold = solutions[0]
            self.show_comparison([good, cold], ["on screen", "from the initial guess"])
            self.trust.report_cold(good, cold)
            return
        self.show_comparison(solutions)

    # ---- comparison and replay -----------------------------------------------------------
    def show_comparison(self, solutions: list[Solution],
                        names: list[str] | None = None) -> None:
        entries = self.overlay.show(self.session.mission, solutions,
                                    names or [s.method for s in solutions], self.dark)
        if self._geometry is not None:
            self.status.show_legend(legend_html(self._geometry, comparison=entries))

    def clear_comparison(self, redraw: bool) -> None:
        if not self.overlay.solutions and not redraw:
            return
        self.overlay.clear()
        good = self.session.last_good
        if redraw and good is not None:
            self._draw(good, dim=False)

    def replay_iterations(self) -> None:
        self.replay.start(self.dark)

    def _replay_done(self) -> None:
        with self._lock:
            self.scene.show_solution(not self.overlay.solutions)
        self._draw_ghosts()
