"""The floating side panel: the plots of the solution on screen, a map (e.g. the launch-C3
contour with the solution marked) and the About page (equations, paper, published numbers).
A figure is sent to the browser only when it changed."""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence

import plotly.graph_objects as go
import viser

from solvers.presentation import GridMap, PlotSeries

from ..deferred import Deferred
from ..page_figures import PageFigure
from ..plots import figure_aspect, figure_tree, map_figure

PLOT_PANEL = (620, 300)  # px: plots float in the canvas's bottom-right corner
PANEL_GAP = 10  # px from the canvas edges
PLOT_ASPECT = 0.37  # height/width of the figure inside that panel


PER_PAGE = 6  # plots on one page of the panel: more would squeeze or overflow it
# s an answer's plots follow its picture (two software-WebGL frames of viser's page: the
# frame that applies the scene and the one that draws it), and at most one plot redraw in
# that time while answers stream in (a drag).
FIGURE_DELAY = 0.25


class SidePanel:
    """Plots, Map and About tabs in a panel floating over the 3D view; more than
    `PER_PAGE` plots are shown a page at a time."""

    def __init__(self, gui: viser.GuiApi, on_page: Callable[[], None]) -> None:
        self.panel = gui.add_panel()
        self._choosing = False  # `page_of` is setting the page list
        with self.panel.add_tab("Plots", viser.Icon.CHART_LINE):
            self.page = gui.add_dropdown("plots", ("all",), visible=False,
                                         hint="This solution has more plots than fit: "
                                              "choose which to show.")
            # Only a person's choice redraws: setting the options from `page_of`, inside a
            # draw, would draw the previous answer again first (viser calls back at once).
            self.page.on_update(lambda _: None if self._choosing else on_page())
            self.plot = gui.add_plotly(go.Figure(), aspect=PLOT_ASPECT)
        with self.panel.add_tab("Map", viser.Icon.MAP):
            self.map_note = gui.add_markdown("This mission has no map.")
            self.map_plot = gui.add_plotly(go.Figure(), aspect=PLOT_ASPECT, visible=False)
        with self.panel.add_tab("About", viser.Icon.INFO_CIRCLE):
            self.about = gui.add_html("")
        self.panel.float(x=-PANEL_GAP, y=-PANEL_GAP, width=PLOT_PANEL[0], height=PLOT_PANEL[1])
        self.figure = PageFigure(figure_tree([]), 0)
        self.marker_t: float | None = None
        self._sending = threading.RLock()  # one figure at a time leaves (two threads send)
        self.later = Deferred(FIGURE_DELAY)
        self.show_figure(self.figure)
        self._map_key: tuple | None = None

    def show_about(self, html: str) -> None:
        self.about.content = html

    @property
    def page_name(self) -> str:
        """The plot page chosen (its series' names)."""
        return str(self.page.value)

    def page_of(self, series: Sequence[PlotSeries], extra: Sequence[PlotSeries] = ()
                ) -> list[PlotSeries]:
        """The series of the chosen page: the mission's plots a page at a time, then the
        `extra` ones (costates, H...) on pages of their own; the page list follows the
        titles. A "reference" series rides with the series of its title."""
        pages = _pages(list(series)) + _pages(list(extra))
        if len(pages) <= 1:
            self.page.visible = False
            return pages[0] if pages else []
        names = tuple(_page_name(chunk) for chunk in pages)
        if tuple(self.page.options) != names:
            chosen = self.page.value
            self._choosing = True
            try:
                self.page.options = names
                self.page.value = chosen if chosen in names else names[0]
            finally:
                self._choosing = False
        self.page.visible = True
        return pages[names.index(self.page.value)] if self.page.value in names else pages[0]

    def show_figure(self, figure: PageFigure, t: float | None = None, dark: bool = True,
                    subplots: int | None = None) -> None:
        """Show `figure` with the time marker at `t` now (a figure waiting to follow its
        picture is dropped); its height follows its `subplots` (default: those that carry
        the marker)."""
        self.later.cancel()
        with self._sending:
            self.figure = figure
            self.move_marker(t, dark)
            self.plot.aspect = figure_aspect(max(subplots or figure.n_series, 1),
                                             PLOT_ASPECT)

    def post_figure(self, figure: PageFigure, t: Callable[[], float | None],
                    dark: bool = True) -> None:
        """Show an answer's `figure` after its picture (`FIGURE_DELAY`), the newest of those
        posted meanwhile; `t` gives the time marker when it leaves."""
        def send() -> None:
            with self._sending:
                self.figure = figure
                self.move_marker(t(), dark)
                self.plot.aspect = figure_aspect(max(figure.n_series, 1), PLOT_ASPECT)
        self.later.post(send)

    def move_marker(self, t: float | None, dark: bool = True) -> None:
        """Send the figure again with its time marker at `t`."""
        with self._sending:
            self.marker_t = t
            # viser's own setter encodes a go.Figure (6 ms); the JSON is written once here
            # and set as the handle's synced property (viser 1.x: `_plotly_json_str`).
            self.plot._plotly_json_str = self.figure.text(t, dark)

    def show_map(self, grid_map: GridMap | None, dark: bool) -> None:
        """The first map of the presentation, re-sent only when it changed."""
        key = None if grid_map is None else (id(grid_map.z), grid_map.marker, dark)
        if key == self._map_key:
            return
        self._map_key = key
        self.map_note.visible = grid_map is None
        self.map_plot.visible = grid_map is not None
        if grid_map is not None:
            self.map_plot.figure = map_figure(grid_map, dark)


def _pages(series: list[PlotSeries]) -> list[list[PlotSeries]]:
    """Chunks of at most PER_PAGE subplots (a reference series stays with its own)."""
    pages: list[list[PlotSeries]] = []
    for s in series:
        if s.group == "reference" and pages:
            pages[-1].append(s)
        elif not pages or sum(x.group != "reference" for x in pages[-1]) >= PER_PAGE:
            pages.append([s])
        else:
            pages[-1].append(s)
    return pages


def _page_name(chunk: list[PlotSeries]) -> str:
    titles = [s.title for s in chunk if s.group != "reference"]
    return titles[0] if len(titles) == 1 else f"{titles[0]} … {titles[-1]}"
