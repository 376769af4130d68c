"""The Export panel: the solution on screen as JSON or CSV, its plots as PNG, a screenshot of
the view; settings (solve time limit, theme) and the keys."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import viser

from solvers.presentation import Presentation
from solvers.solution import Solution

from ..export import file_stem, plots_png, png_bytes, solution_csv, solution_figure, solution_json
from .value_input import TIME_LIMIT_RANGE, Report, TimeLimitField

Current = Callable[[], tuple[Solution | None, Presentation | None]]
# (width/height) -> (wxyz, position, fov) of a camera framing the path on the whole image
ShotCamera = Callable[[float], tuple[np.ndarray, np.ndarray, float] | None]
KEYS = ("Keys: **space** play/pause · **r** reset camera · **?** help · **ctrl-k** command "
        "palette. Offline copy of a case: `python -m explorer.export --mission KEY --out DIR`.")


class ExportPanel:
    """Download buttons and settings; `current()` gives the solution and presentation on
    screen."""

    def __init__(self, gui: viser.GuiApi, current: Current, time_limit: float | None,
                 on_time_limit: Callable[[float | None], None], on_dark: Callable[[bool], None],
                 shot_camera: ShotCamera, report: Report) -> None:
        self.current = current
        self.shot_camera = shot_camera
        with gui.add_folder("Download"):
            for label, kind in (("solution (JSON)", "json"), ("solution (CSV)", "csv"),
                                ("plots (PNG)", "plots"), ("screenshot of the view (PNG)",
                                                           "shot")):
                button = gui.add_button(label, icon=viser.Icon.DOWNLOAD)
                button.on_click(lambda event, kind=kind: self.download(kind, event.client))
        with gui.add_folder("Settings"):
            lo, hi = TIME_LIMIT_RANGE
            self.time_limit = TimeLimitField(
                gui, "solve time limit [s]", time_limit, on_time_limit, report,
                hint=f"A solve still running after this is stopped (status 'time-limit'); "
                     f"a cold start (new method, comparison) gets three times as long, or "
                     f"three times a slow mission's first solve (the asteroid's 10 s); "
                     f"{lo:g} to {hi:g} s, or 0: no limit.")
            self.dark = gui.add_checkbox("dark mode", True, hint="Dark or light theme.")
            self.dark.on_update(lambda _: on_dark(bool(self.dark.value)))
        gui.add_markdown(KEYS)

    def download(self, kind: str, client: viser.ClientHandle | None) -> None:
        """Send the current solution (JSON/CSV), its plots (PNG) or a screenshot of this
        client's view (PNG) to the browser that asked."""
        if client is None:
            return
        sol, pres = self.current()
        if (sol is None or pres is None) and kind != "shot":
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
                    png = plots_png(solution_figure(sol, pres), len(pres.plots))
                finally:
                    note.remove()
                client.send_file_download(f"{file_stem(sol)}-plots.png", png,
                                          save_immediately=True)
            else:
                camera = client.camera
                height, width = camera.image_height, camera.image_width
                pose = self.shot_camera(width / max(height, 1))
                if pose is None:
                    image = client.get_render(height, width, transport_format="png",
                                              timeout=30.0)
                else:  # framed for the whole image: no panel covers a screenshot
                    wxyz, position, fov = pose
                    image = client.get_render(height, width, wxyz=wxyz, position=position,
                                              fov=fov, transport_format="png", timeout=30.0)
                name = f"{file_stem(sol)}-view.png" if sol else "view.png"
                client.send_file_download(name, png_bytes(image), save_immediately=True)
        except (RuntimeError, TimeoutError) as exc:
            client.add_notification("export failed", str(exc), color="red",
                                    auto_close_seconds=15.0)
