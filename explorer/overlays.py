"""What a view draws over its solution: a method comparison (each method's path in its colour,
the plots overlaid) and the replay of the solver's iterates (ghosts added one at a time,
fading into the optimum)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from contextlib import AbstractContextManager

import numpy as np

from solvers.mission import Mission
from solvers.presentation import Presentation
from solvers.solution import Solution

from .geometry import PALETTE, ghost_geometry, path_segments
from .page_figures import PageFigure
from .panels.compare import comparison_html
from .panels.side import SidePanel
from .plots import figure_tree
from .scene import SceneView

REPLAY_STEP_S = 0.45  # s per iterate in the iteration replay

Figure = Callable[..., None]


Color = tuple[int, int, int]


class ComparisonOverlay:
    """The solutions of one comparison drawn together: each path a scene layer in its colour
    over the hidden solution, their plots overlaid in one figure, their table in the Compare
    tab."""

    def __init__(self, scene: SceneView, lock: AbstractContextManager, side: SidePanel,
                 show_table: Callable[[str], None],
                 present: Callable[[Solution], Presentation]) -> None:
        self.solutions: list[Solution] = []
        self._scene, self._lock, self._side = scene, lock, side
        self._show_table = show_table
        self._present = present

    def show(self, mission: Mission, solutions: list[Solution], labels: list[str],
             dark: bool) -> list[tuple[str, Color]]:
        """Draw the comparison; returns the legend's (label, colour) entries."""
        self.solutions = solutions
        presentations = [self._present(s) if s.has_trajectory else None for s in solutions]
        colors = comparison_layers(self._scene, self._lock, presentations)
        with self._lock:
            self._side.show_figure(PageFigure(comparison_figure(
                labels, colors, presentations, dark), 0))
        self._show_table(comparison_html(mission, solutions, colors, labels))
        return list(zip(labels, colors, strict=True))

    def clear(self) -> None:
        """Back to the solution alone."""
        self.solutions = []
        self._show_table("")
        with self._lock:
            self._scene.clear_layers("compare")
            self._scene.show_solution(True)


def comparison_layers(scene: SceneView, lock: AbstractContextManager,
                      presentations: list[Presentation | None]) -> list[Color]:
    """Draw each presentation's path in its comparison colour over a hidden solution;
    returns the colours."""
    colors = [PALETTE[i % len(PALETTE)] for i in range(len(presentations))]
    with lock:
        scene.show_solution(False)
        scene.clear_layers("compare")
        for i, (pres, color) in enumerate(zip(presentations, colors, strict=True)):
            if pres is not None:
                segs = path_segments(pres)
                scene.set_layer(f"compare/{i}", segs,
                                np.broadcast_to(np.array(color, np.uint8), segs.shape),
                                thickness=3.5)
    return colors


def comparison_figure(labels: list[str], colors: list[Color],
                      presentations: list[Presentation | None], dark: bool) -> dict:
    """The plots of every compared solution overlaid, in their colours (a plotly tree)."""
    first = next((p for p in presentations if p is not None), None)
    return figure_tree([], dark=dark, overlays=[
        (label, color, pres.plots) for label, color, pres
        in zip(labels, colors, presentations, strict=True) if pres is not None],
        time_unit=first.time_unit if first else "s",
        time_scale=first.time_scale if first else 1.0)


class IterationReplay:
    """Hide the optimum, add the iterates one at a time (older ones fading), then show the
    optimum again; `shown()` gives the presentation on screen (the replay stops when it
    changes) and `say(text)` reports progress."""

    def __init__(self, scene: SceneView, lock: AbstractContextManager,
                 shown: Callable[[], Presentation | None], say: Callable[[str], None],
                 finish: Callable[[], None]) -> None:
        self.scene, self.lock, self.shown, self.say, self.finish = (scene, lock, shown, say,
                                                                    finish)
        self._thread: threading.Thread | None = None
        self.closed = threading.Event()

    def start(self, dark: bool) -> None:
        pres = self.shown()
        if pres is None or not pres.iterates:
            self.say("_this method records no iterates_")
            return
        if self._thread is not None and self._thread.is_alive():
            return
        self._thread = threading.Thread(target=self._run, args=(pres, dark), daemon=True,
                                        name="explorer-replay")
        self._thread.start()

    def _run(self, pres: Presentation, dark: bool) -> None:
        with self.lock:
            self.scene.show_solution(False)
        n = len(pres.iterates)
        for k in range(1, n + 1):
            if self.closed.is_set() or self.shown() is not pres:
                break
            segs, cols = ghost_geometry(pres, upto=k, dark=dark)
            with self.lock:
                self.scene.set_layer("ghosts", segs, cols, thickness=2.0)
            self.say(f"iterate {k} of {n} (solver iteration {pres.iterates[k - 1][0]})")
            time.sleep(REPLAY_STEP_S)
        self.say(f"{n} iterates recorded; the optimum is drawn in colour")
        self.finish()
