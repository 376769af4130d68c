"""The status panel: what the last solve returned (status, cost, quantities, solver line,
re-propagation check), progress while a solve runs, the legend of the 3D view, a details
table, and error notifications that close when the next answer arrives."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from functools import lru_cache

import viser
from markdown_it import MarkdownIt

from solvers.solution import Solution

KEPT = "_showing the last good trajectory (dimmed)_"
NEW_CASE = "**solving…** the new case"
UNCHECKED = "converged · checking…"  # "optimal" before the re-propagation check has judged it
SHOWN = 3  # quantities and check items in the status; all of them are in the details
# Below these a number is below what anyone would measure: shown as "< limit", not as noise
# like "2.24131e-28 m/s".
NOISE = {"m": (1e-3, "< 1 mm"), "m/s": (1e-3, "< 1 mm/s"), "kg": (1e-3, "< 1 g"),
         "rad": (1e-6, "< 1 µrad"), "rad/s": (1e-6, "< 1 µrad/s"), "s": (1e-6, "< 1 µs"),
         "deg": (1e-4, "< 0.0001°")}
LARGE = {"m": (1e4, 1e3, "km"), "m/s": (1e4, 1e3, "km/s")}  # from, factor, unit shown
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def unit_text(unit: str) -> str:
    """A unit as it is printed: "m^2/s^3" -> "m²/s³"."""
    return re.sub(r"\^(-?\d+)", lambda m: m.group(1).translate(_SUPERSCRIPT), unit)


def number(value: float, digits: int = 6) -> str:
    """`digits` significant digits; a power of ten as "1.12×10⁻²⁶", never "1.12e-26"."""
    text = f"{value:.{digits}g}"
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def fmt(value: float | None, unit: str = "", digits: int = 6) -> str:
    """A value for a person: "n/a" when undefined, "< 1 mm" when below what matters,
    large distances in km, else `digits` significant digits and the unit as printed."""
    if value is None or not math.isfinite(value):
        return "n/a"
    floor = NOISE.get(unit)
    if floor is not None and abs(value) < floor[0]:
        return floor[1]
    large = LARGE.get(unit)
    if large is not None and abs(value) >= large[0]:
        value, unit = value / large[1], large[2]
    return f"{number(value, digits)} {unit_text(unit)}".rstrip()


def headline(sol: Solution, checking: bool = False) -> str:
    """Status, cost (when the answer is good) and the mission's quantities of interest; an
    optimum whose re-propagation check is still running is only "converged" (the check may
    find it inaccurate)."""
    parts = [f"**{UNCHECKED if checking and sol.ok else sol.status}**"]
    if sol.converged and math.isfinite(sol.cost.value):
        est = sol.cost.error_estimate  # the cost error estimate, once the check has run
        pm = f" ± {fmt(est, sol.cost.unit, 2)}" if est is not None and math.isfinite(est) else ""
        parts.append(f"{sol.cost.label} **{fmt(sol.cost.value, sol.cost.unit)}**{pm}")
    if sol.converged:
        parts += [f"{q.label} {fmt(q.value, q.unit)}" for q in sol.quantities.values()
                  if q.label != sol.cost.label][:SHOWN]
    return " · ".join(parts)


def wall_time(seconds: float) -> str:
    """A solve's wall time as a person reads it: "< 1 ms" for a closed form (not "0 ms",
    as if nothing ran), milliseconds below 10 s, seconds above."""
    if seconds < 1e-3:
        return "< 1 ms"
    return f"{1e3 * seconds:.0f} ms" if seconds < 10.0 else f"{seconds:.1f} s"


def solver_line(sol: Solution, nodes_label: str = "nodes") -> str:
    """Method, mesh (in the words of the method's node slider), iterations and wall time."""
    method = f"{sol.method}/{sol.backend}" if sol.backend else sol.method
    parts = [f"{method}, {nodes_label} {sol.nodes}"]
    if "iterations" in sol.stats:
        parts.append(f"{int(sol.stats['iterations'])} iterations")
    if "wall_s" in sol.stats:
        parts.append(wall_time(sol.stats["wall_s"]))
    return " · ".join(parts)


def check_line(sol: Solution) -> str:
    """Re-propagation miss by its labels (empty until the deferred check has run)."""
    items = []
    for key, value in list(sol.check.items())[:SHOWN]:
        label = sol.label(key)
        items.append(f"{label.text} {fmt(value, label.unit, 3)}")
    if not items:
        return ""
    more = " · …" if len(sol.check) > SHOWN else ""
    return "re-propagation check: " + " · ".join(items) + more


def details_markdown(sol: Solution) -> str:
    """Every quantity, statistic and check of a solution as a table (the status shows only
    the first few)."""
    rows = [f"| {sol.cost.label} (the cost) | {fmt(sol.cost.value, sol.cost.unit, 8)} |"]
    rows += [f"| {q.label} | {fmt(q.value, q.unit, 8)} |" for q in sol.quantities.values()
             if q.label != sol.cost.label]
    for key, v in sol.stats.items():
        if key == "wall_s":
            rows.append(f"| solve time | {wall_time(v)} |")
        else:
            label = sol.label(key)
            rows.append(f"| {label.text} | {fmt(v, label.unit, 6)} |")
    for key, value in sol.check.items():
        label = sol.label(key)
        rows.append(f"| check: {label.text} | {fmt(value, label.unit, 3)} |")
    return "\n".join(["| | |", "|---|---|", *rows])


# What to try, by status, in the explorer's words (the message says what happened).
HINTS = {
    "inaccurate": "What to try: refine the mesh to the accuracy target (Setup › accuracy "
                  "and optimality › refine), or more nodes.",
    "time-limit": "What to try: raise the limit (Export tab › Settings › solve time limit), "
                  "fewer nodes, or another method.",
    "iteration-limit": "What to try: solve from the initial guess (Setup), fewer or more "
                       "nodes, or another method.",
    "failed": "What to try: solve from the initial guess (Setup), another method or node "
              "count.",
}


def mesh_line(sol: Solution) -> str:
    """The refinement steps of an "auto" solve: node counts and the miss at each."""
    steps = [step for step in sol.mesh if "nodes" in step]
    if not steps:
        return ""
    unit = sol.label(next(iter(sol.targets))).unit if sol.targets else ""
    cells = [f"{int(s['nodes'])}" + (f" (miss {fmt(s['miss'], unit, 2)})" if "miss" in s
                                     else "") for s in steps]
    return "refined: " + " → ".join(cells)


def result_markdown(sol: Solution, checking: bool = False, kept: bool = False,
                    nodes_label: str = "nodes") -> str:
    """The full status; `kept` notes that an older good trajectory stays on screen."""
    lines = [headline(sol, checking), solver_line(sol, nodes_label), mesh_line(sol)]
    if not sol.ok:
        lines.append(f"_{sol.message}_")
        if sol.status in HINTS:
            lines.append(HINTS[sol.status])
        if kept:
            lines.append(KEPT)
    check = check_line(sol)
    lines.append(check if check else "re-propagation check running…" if checking else "")
    return "  \n".join(line for line in lines if line)


def progress_markdown(iteration: int, previous: str, elapsed: float | None = None,
                      limit: float | None = None, message: str = "") -> str:
    """'solving… iteration k (t s of the limit)' above the previous result, which stays
    readable; `message` is the solver's (or the comparison's) progress note."""
    head = f"**solving… iteration {iteration}**"
    if elapsed is not None:
        head += f" ({elapsed:.1f} s" + (f" of {limit:g} s limit)" if limit else ")")
    if message:
        head += f"  \n_{message}_"
    return f"{head}  \n{previous}" if previous else head


def rejected_markdown(message: str, kept: bool) -> str:
    return f"**request rejected**  \n{message}" + (f"  \n{KEPT}" if kept else "")


_MD = MarkdownIt("commonmark")


@lru_cache(maxsize=64)
def status_html(markdown: str) -> str:
    """The status markdown as HTML in the element `#explorer-status` (tests and the browser
    benchmark find it by that id); cached, as a classroom's followers show the same text."""
    return f'<div id="explorer-status">{_MD.render(markdown)}</div>'


class _StatusLine:
    """The status element; `content` takes markdown (kept, for tests) and shows HTML."""

    def __init__(self, gui: viser.GuiApi, markdown: str) -> None:
        self._markdown = markdown
        self.handle = gui.add_html(status_html(markdown), order=0)

    @property
    def content(self) -> str:
        return self._markdown

    @content.setter
    def content(self, markdown: str) -> None:
        if markdown != self._markdown:
            self._markdown = markdown
            self.handle.content = status_html(markdown)


class StatusPanel:
    """Status line, progress bar, legend and details of one view."""

    def __init__(self, gui: viser.GuiApi) -> None:
        self.status = _StatusLine(gui, "**starting…** the first solve is on its way")
        self.progress = gui.add_progress_bar(0.0, animated=True, visible=False, order=1)
        self.legend = gui.add_html("", order=2)
        with gui.add_folder("Result details", order=3, expand_by_default=False):
            self.details = gui.add_markdown("")
        self.result_md = ""
        self._notices: list[viser.NotificationHandle] = []
        self._file_notices: dict[str, list[viser.NotificationHandle]] = {}

    def show_legend(self, html: str) -> None:
        self.legend.content = html

    def show_progress(self, iteration: int, elapsed: float, limit: float | None,
                      message: str) -> None:
        self.progress.visible = True
        self.progress.value = min(100.0, 100.0 * elapsed / limit) if limit else 100.0
        self.status.content = progress_markdown(iteration, self.result_md, elapsed, limit,
                                                message)

    def show_result(self, sol: Solution, checking: bool, kept: bool,
                    nodes_label: str = "nodes") -> None:
        self.progress.visible = False
        self.result_md = result_markdown(sol, checking=checking, kept=kept,
                                         nodes_label=nodes_label)
        self.status.content = self.result_md
        self.details.content = details_markdown(sol)

    def show_rejected(self, message: str, kept: bool) -> None:
        self.progress.visible = False
        self.result_md = rejected_markdown(message, kept)
        self.status.content = self.result_md

    def restore(self) -> None:
        """Back to the last result (a comparison's progress is over)."""
        self.progress.visible = False
        self.status.content = self.result_md

    def clear(self) -> None:
        """Nothing of the previous case: the status waits for the new one."""
        self.result_md = ""
        self.status.content = NEW_CASE
        self.legend.content = self.details.content = ""

    def notify(self, clients: Iterable[viser.ClientHandle], title: str, body: str) -> None:
        """One error notification per browser at a time: a newer one replaces the older,
        and the next answer closes it (`clear_notices`)."""
        self.clear_notices()
        self._notices = [c.add_notification(title, body, color="red", auto_close_seconds=8.0)
                         for c in list(clients)]

    def notify_one(self, client: viser.ClientHandle, title: str, body: str) -> None:
        """A note for one browser only (what it tried is refused to it alone)."""
        client.add_notification(title, body, color="yellow", auto_close_seconds=6.0)

    def notify_kept(self, clients: Iterable[viser.ClientHandle], title: str, body: str) -> None:
        """A notification that stays until closed (no answer replaces it): why the case a
        link asked for is not the one on screen."""
        for client in list(clients):
            client.add_notification(title, body, color="yellow", auto_close_seconds=None)

    def clear_notices(self) -> None:
        for notice in self._notices:
            notice.remove()
        self._notices = []

    def notify_file(self, clients: Iterable[viser.ClientHandle], path: str, title: str,
                    body: str) -> None:
        """A mission file that does not load: the notice stays (no answer closes it, the
        file is still broken) until the file loads again (`clear_file_notice`)."""
        self.clear_file_notice(path)
        self._file_notices[path] = [
            c.add_notification(title, body, color="red", auto_close_seconds=None)
            for c in list(clients)]

    def clear_file_notice(self, path: str) -> None:
        for notice in self._file_notices.pop(path, []):
            notice.remove()
