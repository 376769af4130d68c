"""Exports: the solution as JSON/CSV, the plots as PNG (kaleido) or self-contained HTML, a
screenshot as PNG, and the offline classroom export, a folder that opens from file:// with
no server:

    python -m explorer.export --mission lunar-landing [--preset NAME] [--method KEY]
                              [--nodes N] --out DIR

writes DIR/scene.html (the 3D scene with the vehicle animation, viser's scene serializer),
DIR/plots.html (plotly.js inlined once), DIR/plots.png (if kaleido works here),
DIR/solution.json, DIR/solution.csv and DIR/index.html linking them.
"""

from __future__ import annotations

import argparse
import html
import io
import socket
from pathlib import Path

import numpy as np
import plotly.graph_objects as go

from solvers import get_mission
from solvers.mission import Mission
from solvers.presentation import Presentation
from solvers.problem import Preset
from solvers.solution import Solution

from .camera import FOV, fit_camera
from .geometry import build_geometry
from .player import PLAY_SECONDS, Track
from .plots import figure_aspect, make_figure
from .scene import SceneView

EXPORT_FPS = 12  # frames per second of the recorded vehicle animation
PLOT_WIDTH = 1200  # px of the exported plot image


def solution_json(sol: Solution) -> bytes:
    """The solution with its dense samples, as JSON (SI units)."""
    return sol.to_json(dense=True).encode()


def solution_csv(sol: Solution) -> bytes:
    return sol.to_csv().encode()


def file_stem(sol: Solution) -> str:
    return f"{sol.mission}-{sol.method}-{sol.nodes}"


def solution_figure(sol: Solution, pres: Presentation) -> go.Figure:
    """The plot panel's figure on a light background, titled with the case (for printing
    and slides)."""
    fig = make_figure(pres.plots, dark=False, time_unit=pres.time_unit,
                      time_scale=pres.time_scale)
    title = f"{sol.mission}: {sol.method}, {sol.nodes} nodes — {sol.summary()}"
    fig.update_layout(paper_bgcolor="white", title={"text": title, "font": {"size": 12}},
                      margin={"t": 60})
    return fig


def plots_png(fig: go.Figure, n_series: int, width: int = PLOT_WIDTH) -> bytes:
    """PNG of a plotly figure through kaleido; `RuntimeError` says why if it cannot."""
    try:
        import kaleido  # noqa: F401 - only to give a clear message when it is missing
    except ImportError as exc:
        raise RuntimeError("kaleido is not installed (pip install kaleido): use the camera "
                           "icon of the plot's toolbar to save it as PNG") from exc
    height = int(width * figure_aspect(n_series, 0.37))
    try:
        return fig.to_image(format="png", width=width, height=height)
    except Exception as exc:  # noqa: BLE001 - kaleido needs a working chromium
        raise RuntimeError(f"kaleido could not render the plots ({exc}): use the camera "
                           "icon of the plot's toolbar to save them as PNG") from exc


def plots_html(fig: go.Figure, title: str) -> str:
    """The figure as one HTML file with plotly.js inlined (works from file://)."""
    return fig.to_html(include_plotlyjs=True, full_html=True, default_width="100%",
                       default_height="90vh").replace("<head>", f"<head><title>"
                                                      f"{html.escape(title)}</title>", 1)


def png_bytes(image: np.ndarray) -> bytes:
    """Encode an (H, W, 3|4) uint8 image as PNG (imageio ships with viser)."""
    import imageio.v3 as iio

    buf = io.BytesIO()
    iio.imwrite(buf, np.asarray(image, np.uint8), extension=".png")
    return buf.getvalue()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def scene_html(sol: Solution, pres: Presentation, aspect: float = 16 / 9,
               dark: bool = True) -> str:
    """A self-contained HTML file of the solution's 3D scene with the vehicle flying the
    trajectory once (PLAY_SECONDS long), recorded from a server that has no GUI at all (so
    no plotly.js is embedded)."""
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=_free_port(), verbose=False)
    try:
        view = SceneView(server.scene, dark=dark)
        g = build_geometry(pres, sol.t, sol.arcs)
        view.draw(g)
        cam = fit_camera(g, aspect)
        server.initial_camera.fov = FOV
        server.initial_camera.near, server.initial_camera.far = cam.near, cam.far
        server.initial_camera.up = tuple(cam.up)
        server.initial_camera.position = tuple(cam.position)
        server.initial_camera.look_at = tuple(cam.look_at)
        track = Track(sol, pres)
        view.set_vehicle(pres.vehicle, g.extent)
        view.move_vehicle(track.pose(track.t0))
        view.move_bodies(track.t0)
        serializer = server.get_scene_serializer()
        frames = int(PLAY_SECONDS * EXPORT_FPS)
        for t in np.linspace(track.t0, track.tf, frames + 1):
            view.move_vehicle(track.pose(float(t)))
            view.move_bodies(float(t))
            serializer.insert_sleep(1.0 / EXPORT_FPS)
        serializer.insert_sleep(1.0)  # rest at the end before the loop restarts
        return serializer.as_html(dark_mode=dark)
    finally:
        server.stop()


def preset_by_name(mission: Mission, name: str) -> Preset:
    for p in mission.presets:
        if p.name == name:
            return p
    known = "; ".join(p.name for p in mission.presets) or "none"
    raise ValueError(f"mission '{mission.key}' has no preset '{name}' (presets: {known})")


def classroom_export(out: Path, mission_key: str, preset: str | None = None,
                     method: str | None = None, nodes: int | None = None) -> list[Path]:
    """Solve one case and write the offline folder; returns the files written."""
    mission = get_mission(mission_key)
    values: dict[str, float] = {}
    preset_view: dict[str, float] = {}
    if preset is not None:
        p = preset_by_name(mission, preset)
        values, method, nodes = dict(p.values), method or p.method, nodes or p.nodes
        preset_view = dict(p.view)
    sol = mission.solve(values, method, nodes)
    if not sol.has_trajectory:
        raise RuntimeError(f"{mission_key}: {sol.status}: {sol.message}")
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []

    def write(name: str, data: bytes | str) -> None:
        path = out / name
        path.write_bytes(data if isinstance(data, bytes) else data.encode())
        written.append(path)

    title = f"{mission.title}: {mission.method(sol.method).label}, {sol.nodes} nodes"
    pres = mission.present(sol, preset_view)
    write("scene.html", scene_html(sol, pres))
    fig = solution_figure(sol, pres)
    fig.update_layout(title={"text": title, "font": {"size": 14}})
    write("plots.html", plots_html(fig, title))
    png_note = "plots.png: the same plots as an image"
    try:
        write("plots.png", plots_png(fig, len(pres.plots)))
    except RuntimeError as exc:
        png_note = f"no plots.png: {exc}"
    write("solution.json", solution_json(sol))
    write("solution.csv", solution_csv(sol))
    write("index.html", _index(title, sol, png_note))
    return written


def _index(title: str, sol: Solution, png_note: str) -> str:
    items = ["<li><a href='scene.html'>3D scene with the animation</a> (drag to orbit, "
             "scroll to zoom; the vehicle flies the trajectory in a loop)</li>",
             "<li><a href='plots.html'>plots</a> (interactive)</li>",
             f"<li>{html.escape(png_note)}</li>" if "no plots" in png_note else
             "<li><a href='plots.png'>plots as an image</a></li>",
             "<li><a href='solution.json'>solution.json</a> and <a href='solution.csv'>"
             "solution.csv</a> (SI units)</li>"]
    return (f"<!doctype html><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<h2>{html.escape(title)}</h2><p>{html.escape(sol.summary())}</p>"
            f"<ul>{''.join(items)}</ul>")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m explorer.export", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mission", required=True)
    parser.add_argument("--preset", help="name of one of the mission's presets")
    parser.add_argument("--method")
    parser.add_argument("--nodes", type=int)
    parser.add_argument("--out", required=True, type=Path)
    args = parser.parse_args(argv)
    try:
        files = classroom_export(args.out, args.mission, args.preset, args.method, args.nodes)
    except (ValueError, RuntimeError) as exc:
        parser.error(str(exc))
    for path in files:
        print(f"{path} ({path.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
