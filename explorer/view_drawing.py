"""How a `View` draws: a solution becomes the mission's presentation, then geometry in the
scene, the plots' page figure, the legend and the animation track; the vehicle moves along it.
Split from `view.py` so that the view keeps the wiring (panels, session events) and this
module the picture."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any

import numpy as np
import viser

from solvers.presentation import PlotSeries, Presentation
from solvers.solution import Solution

from .geometry import WARNING, Geometry, build_geometry, ghost_geometry, path_segments
from .handles import Handles
from .legend import legend_html
from .optimality import color_by_error, optimality_plots
from .overlays import ComparisonOverlay
from .page_figures import SHARED, PageFigure
from .panels.play import PlayPanel
from .panels.side import SidePanel
from .panels.status import StatusPanel
from .panels.trust import TrustPanel
from .player import Track
from .plots import figure_tree
from .readouts import readout_markdown, readouts
from .scene import SceneView
from .session import Session
from .view_camera import ViewCamera

MARKER_S = 1.0  # s between the plots' time-marker updates while playing


def apply_theme(gui: viser.GuiApi, dark: bool) -> None:
    """Classroom theme: no share button (it needs the internet), panel docked left."""
    gui.configure_theme(dark_mode=dark, show_share_button=False, control_width="medium",
                        brand_color=(255, 140, 0))


class ViewDrawing:
    """The drawing half of `View` (a base class: `View` builds every attribute below)."""

    gui: viser.GuiApi
    atomic: Callable[[], AbstractContextManager[Any]]
    send_now: Callable[[bool], None]
    session: Session
    dark: bool
    drawn: int
    scene: SceneView
    camera: ViewCamera
    handles: Handles
    overlay: ComparisonOverlay
    play: PlayPanel
    side: SidePanel
    status: StatusPanel
    trust: TrustPanel
    _lock: threading.RLock
    _failed: bool
    _geometry: Geometry | None
    _shown: tuple[Solution, Presentation, bool] | None
    _drawn: tuple
    _marker_at: float

    @property
    def presentation(self) -> Presentation | None:
        return self._shown[1] if self._shown is not None else None

    # ---- drawing ----------------------------------------------------------------------
    def present(self, sol: Solution) -> Presentation:
        """The mission's presentation of `sol`, coloured by the local error if asked."""
        pres = self.session.mission.present(sol, self.session.view)
        if self.trust.error_colors_on:
            color_by_error(sol, pres)
        return pres

    def _draw(self, sol: Solution, dim: bool) -> None:
        if not sol.has_trajectory:
            return
        pres = self.present(sol)
        geometry = build_geometry(pres, sol.t, sol.arcs, dim=dim)
        plots = self.side.page_of(pres.plots, optimality_plots(sol))
        figure = self._figure(sol, pres, plots, dim)
        with self._lock, self.atomic():
            self._shown = (sol, pres, dim)
            self._drawn = drawn_signature(pres, sol)
            self.handles.place(pres, geometry)
            self.handles.annotate(geometry)
            self.scene.draw(geometry)
            self._geometry = geometry
            if not dim:
                self._new_track(sol, pres, geometry)
            self.side.post_figure(figure, lambda: self.play.t * pres.time_scale
                                  if self.play.track else None, self.dark)
            self.side.show_map(pres.maps[0] if pres.maps else None, self.dark)
            self._draw_ghosts()
        self.send_now(False)  # now, not after viser's window
        self.status.show_legend(legend_html(geometry, dim=dim, failed=self._failed,
                                            dark=self.dark))
        if not self.handles.in_hand:  # never under a hand: the point held would slip
            self.camera.frame_if_needed()
        self.drawn += 1

    def _figure(self, sol: Solution, pres: Presentation, plots: list[PlotSeries],
                dim: bool) -> PageFigure:
        """The plots' page figure, shared with every view drawing this answer alike (a
        classroom's followers: one figure per teacher answer, not one per tab)."""
        look = (tuple(sorted(self.session.view.items())), self.trust.error_colors_on,
                tuple((p.title, p.group) for p in plots), dim, self.dark)
        subplots = sum(p.group != "reference" for p in plots)
        return SHARED.get(sol, look, lambda: PageFigure(figure_tree(
            plots, dim=dim, dark=self.dark, time_unit=pres.time_unit,
            time_scale=pres.time_scale), subplots))

    def _redraw(self) -> None:
        """Draw what is on screen again (another page of plots was chosen)."""
        if self._shown is not None:
            sol, _, dim = self._shown
            self._draw(sol, dim)

    def _set_failed(self, sol: Solution | None) -> None:
        """Show a failed attempt's trajectory in the warning colour (or remove it)."""
        self._failed = sol is not None
        segments = path_segments(self.present(sol)) if sol is not None else np.zeros((0, 2, 3))
        colors = np.broadcast_to(np.array(WARNING, np.uint8), segments.shape)
        with self._lock:
            self.scene.set_layer("failed", segments, colors, thickness=3.0)
        if self._geometry is not None:
            self.status.show_legend(legend_html(self._geometry, dim=self._failed,
                                                failed=self._failed, dark=self.dark))

    def _draw_ghosts(self) -> None:
        pres = self.presentation
        with self._lock:
            if self.play.ghosts_on and pres is not None and pres.iterates:
                segs, cols = ghost_geometry(pres, dark=self.dark)
                self.scene.set_layer("ghosts", segs, cols, thickness=1.5)
            else:
                self.scene.clear_layers("ghosts")

    def set_dark(self, dark: bool) -> None:
        self.dark = dark
        apply_theme(self.gui, dark)
        with self._lock:
            self.scene.set_dark(dark)
        if self._shown is not None:
            sol, _, dim = self._shown
            self._draw(sol, dim)

    # ---- animation ----------------------------------------------------------------------
    def _new_track(self, sol: Solution, pres: Presentation, geometry: Geometry) -> None:
        track = Track(sol, pres)
        self.play.set_track(track, pres.time_unit, pres.time_scale)
        self.scene.set_vehicle(pres.vehicle, geometry.extent)
        self.show_time(self.play.t, slow=True, marker=False)  # the new figure has it

    def show_time(self, t: float, slow: bool, marker: bool = True) -> None:
        """Move the vehicle (and a following camera) to time t; `slow` also updates the
        read-outs and (at most once a second while playing, `marker`) the plots' time
        marker: every figure sent is a whole plotly redraw in the page."""
        track, shown = self.play.track, self._shown
        if track is None or shown is None:
            return
        sol, pres, _ = shown
        pose = track.pose(t)
        with self._lock:
            self.scene.move_vehicle(pose)
            self.scene.move_bodies(t)
        self.camera.follow(pose.position)
        if not slow:
            return
        self.play.show_readout(readout_markdown(readouts(sol, pres, track, t), pres.frame))
        now = time.monotonic()
        if not marker or (self.play.playing and now - self._marker_at < MARKER_S):
            return
        self._marker_at = now
        with self._lock:
            if not self.overlay.solutions:
                self.side.move_marker(t * pres.time_scale, self.dark)



def drawn_signature(pres: Presentation, sol: Solution) -> tuple:
    """What of a presentation a check can change: its curves, markers, plots and colours."""
    return (tuple(c.name for c in pres.curves), tuple(m.name for m in pres.markers),
            tuple((p.title, len(p.t)) for p in pres.plots),
            None if pres.color_by is None else pres.color_by.name,
            tuple(sorted(sol.references)))
