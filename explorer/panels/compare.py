"""The Compare panel: tick methods, solve them all on the same values (each from its initial
guess, in parallel on the solve service), overlay them; and the comparison table: one column
per method (in its overlay colour), one row per figure of merit (status, cost, the mission's
quantities, iterations, solve time, the re-propagation miss). Transposed so that it fits the
narrow control panel."""

from __future__ import annotations

import html
import math
from collections.abc import Callable, Sequence
from typing import Any

import viser

from solvers.mission import Mission
from solvers.solution import Solution

from .status import fmt, number, wall_time

SCROLLBAR_PX = 12  # the control panel's scrollbar, drawn over its right edge


def _num(value: float, digits: int = 6) -> str:
    return "–" if value is None or not math.isfinite(value) else number(value, digits)


def comparison_rows(mission: Mission, solutions: Sequence[Solution]) -> list[list[str]]:
    """Rows of plain strings: [label, value per solution], each value with its unit (as
    the status prints it: "< 1 mm", "29.8 km"); the first row holds the method keys."""
    rows = [["", *[s.method for s in solutions]],
            ["status", *[s.status for s in solutions]]]
    cost = solutions[0].cost if solutions else None
    if cost is not None:
        rows.append([cost.label, *[fmt(s.cost.value, s.cost.unit) for s in solutions]])
    keys: list[str] = []
    for s in solutions:
        keys += [k for k, q in s.quantities.items() if k not in keys and q.label != s.cost.label]
    for key in keys:
        q = next(s.quantities[key] for s in solutions if key in s.quantities)
        rows.append([q.label, *[fmt(s.quantities[key].value, s.quantities[key].unit)
                                if key in s.quantities else "–" for s in solutions]])
    rows.append(["mesh", *[f"{mission.method(s.method).nodes_label} {s.nodes}"
                           for s in solutions]])
    rows.append(["iterations", *[_num(s.stats.get("iterations", math.nan), 4)
                                 for s in solutions]])
    rows.append(["solve time", *[wall_time(s.stats["wall_s"]) if "wall_s" in s.stats
                                 else "–" for s in solutions]])
    checks: list[str] = []
    for s in solutions:
        checks += [k for k in s.check if k not in checks]
    for key in checks:
        label = next(s.label(key) for s in solutions if key in s.check)
        rows.append([f"check: {label.text}", *[fmt(s.check[key], label.unit, 3)
                                               if key in s.check else "–" for s in solutions]])
    return rows


def comparison_html(mission: Mission, solutions: Sequence[Solution],
                    colors: Sequence[tuple[int, int, int]],
                    names: Sequence[str] | None = None) -> str:
    """The table as HTML, each method's header underlined in its overlay colour; failed
    solves say why below the table."""
    rows = comparison_rows(mission, solutions)
    head = "".join(
        f'<th style="border-bottom:4px solid rgb{tuple(c)}" '
        f'title="{html.escape(mission.method(s.method).label)}">{html.escape(name)}</th>'
        for s, c, name in zip(solutions, colors, names or [s.method for s in solutions],
                              strict=False))
    body = "".join("<tr>" + "".join(f"<td>{html.escape(v)}</td>" for v in row) + "</tr>"
                   for row in rows[1:])
    notes = "".join(f"<p><b>{html.escape(mission.method(s.method).label)}</b>: "
                    f"{html.escape(s.message)}</p>" for s in solutions if not s.converged)
    # A value never breaks inside (white-space: nowrap); a table wider than the panel
    # scrolls sideways in its own box, which stops short of the panel's scrollbar (drawn
    # over the panel's right edge) so that no column is hidden under it.
    return ('<style>.cmp{font-size:0.8em;border-collapse:collapse}'
            '.cmp td,.cmp th{padding:2px 4px;border-bottom:1px solid rgba(128,128,128,.3);'
            'text-align:right;vertical-align:top;white-space:nowrap}.cmp th{white-space:normal}'
            '.cmp td:first-child{text-align:left;white-space:normal;min-width:6em}'
            f'.cmp-box{{overflow-x:auto;margin-right:{SCROLLBAR_PX}px}}</style>'
            '<div class="cmp-box"><table class="cmp" id="comparison-table">'
            f'<tr><th></th>{head}</tr>{body}</table></div>'
            f'<div style="font-size:0.8em">{notes}</div>')


class ComparePanel:
    """Method check boxes, the solve/clear buttons and the table."""

    def __init__(self, gui: viser.GuiApi, on_compare: Callable[[list[str]], None],
                 on_clear: Callable[[], None]) -> None:
        self.gui = gui
        self.on_compare = on_compare
        gui.add_markdown("Solve the same case with several methods, each from its initial "
                         "guess, and overlay the results.")
        self.boxes: dict[str, Any] = {}
        self._folder: Any = None
        self._container = gui.add_folder("Methods", order=50)
        self.button = gui.add_button("solve and compare", icon=viser.Icon.SCALE, order=100)
        self.button.on_click(lambda _: self._compare())
        clear = gui.add_button("clear comparison", order=101)
        clear.on_click(lambda _: on_clear())
        self.table = gui.add_html("", order=102)

    def show_table(self, html: str) -> None:
        """The comparison's table ("" for none)."""
        self.table.content = html

    def rebuild(self, mission: Mission) -> None:
        """One check box per method of the mission."""
        if self._folder is not None:
            self._folder.remove()
        self.boxes = {}
        with self._container:
            self._folder = self.gui.add_folder(mission.title, expand_by_default=True)
            with self._folder:
                for m in mission.methods:
                    self.boxes[m.key] = self.gui.add_checkbox(m.label, True, hint=m.summary)

    def _compare(self) -> None:
        methods = [k for k, box in self.boxes.items() if box.value]
        if len(methods) < 2:
            self.show_table("<p><b>Tick at least two methods.</b></p>")
            return
        self.show_table("<p><em>solving…</em></p>")
        self.on_compare(methods)
