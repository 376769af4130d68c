"""Is this the optimum, and how accurate is it? Actions that answer it in class: refine the
mesh until the re-propagated miss meets the mission's accuracy targets, solve again from the
initial guess and set the answers side by side, start from several guesses and keep the best;
and colour the path by the local error of each interval."""

from __future__ import annotations

import math
from collections.abc import Callable

import viser

from solvers.solution import Solution

from ..session import Session
from .status import fmt

STARTS = 5  # initial guesses of a multi-start solve


class TrustPanel:
    """A folder of the Setup tab; `redraw()` draws the answer on screen again."""

    def __init__(self, gui: viser.GuiApi, session: Session, redraw: Callable[[], None],
                 order: float) -> None:
        self.session = session
        with gui.add_folder("Accuracy and optimality", order=order, expand_by_default=False):
            refine = gui.add_button(
                "refine to the accuracy target", icon=viser.Icon.ZOOM_IN,
                hint="Solve with more nodes, warm from the answer on screen, until the "
                     "re-propagated miss meets the mission's accuracy targets (or a node "
                     "cap): the steps show in the status.")
            refine.on_click(lambda _: session.submit(refine=True))
            cold = gui.add_button(
                "check from cold", icon=viser.Icon.SNOWFLAKE,
                hint="Solve this case again from the method's initial guess and set the two "
                     "answers side by side: did the path that led here change the optimum?")
            cold.on_click(lambda _: session.check_from_cold())
            multi = gui.add_button(
                f"multi-start ({STARTS} guesses)", icon=viser.Icon.ARROWS_SPLIT,
                hint="Solve from several initial guesses, keep the best and say how many "
                     "distinct optima were met.")
            multi.on_click(lambda _: session.submit(starts=STARTS))
            self.error_colors = gui.add_checkbox(
                "colour the path by the local error", False,
                hint="Each interval's error against a high-accuracy integration of that "
                     "interval with the method's own control; the worst one is marked.")
            self.error_colors.on_update(lambda _: redraw())
            self.report = gui.add_markdown("")

    def clear(self) -> None:
        """No verdict: the case on screen is not the one that was checked."""
        self.report.content = ""

    @property
    def error_colors_on(self) -> bool:
        """The path is to be coloured by each interval's local error."""
        return bool(self.error_colors.value)

    def report_cold(self, warm: Solution, cold: Solution) -> None:
        """Say whether the cold answer is the same optimum as the one on screen."""
        if not cold.converged:
            self.report.content = (f"From the initial guess: **{cold.status}** — "
                                   f"{cold.message}")
            return
        a, b = warm.cost.value, cold.cost.value
        unit = warm.cost.unit
        scale = max(abs(a), abs(b), 1e-300)
        if math.isfinite(a) and abs(a - b) <= 1e-6 * scale:
            verdict = "the same optimum (within 1e-6)"
        else:
            better = "lower" if b < a else "higher"
            verdict = (f"**a different local optimum**: {fmt(b, unit)} from the guess, "
                       f"{better} than the {fmt(a, unit)} on screen")
        self.report.content = f"Checked from the initial guess: {verdict}."
