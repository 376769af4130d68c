"""Fast tests of the explorer's classroom features without a browser: animation poses and
read-outs, colour-by-value, iterate ghosts, the About panel's MathML, the comparison table,
time limits and comparisons in the session, exports, and a live view (server-side GUI and
scene, no browser) whose scene and memory stay bounded over many re-solves.

Reference: paper 002 (SPEC M3) publishes tf = 398.03868 s for the default lunar case.
"""

from __future__ import annotations

import json
import threading
import time

import numpy as np
import pytest

from explorer.geometry import BURN, build_geometry, colormap, ghost_geometry
from explorer.legend import legend_html
from explorer.page_figures import PageFigure
from explorer.panels.compare import comparison_rows
from explorer.player import Track, quaternion_from_axes
from explorer.plots import figure_tree
from explorer.readouts import readouts
from explorer.session import COLD_FACTOR, Session
from solvers.presentation import Body, ColorBy, Marker, PlotSeries, Presentation
from solvers.solution import Quantity, Solution

TF_PAPER = 398.03868  # s, paper 002 table 1


def _rotate(wxyz: np.ndarray, v: np.ndarray) -> np.ndarray:
    w, x, y, z = wxyz
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    return r @ v


def _burn_coast_burn() -> tuple[Solution, Presentation]:
    """A straight path along x at 1 km/s: burn 0-4 s (+x thrust), coast, burn 6-10 s (-x)."""
    t = np.linspace(0.0, 10.0, 101)
    pos = np.column_stack([1e3 * t, np.zeros_like(t), np.zeros_like(t)])
    node_t = np.array([0.0, 4.0, 6.0, 10.0])
    thrust = np.array([[1.0, 0, 0], [1.0, 0, 0], [-0.5, 0, 0], [-0.5, 0, 0]])
    x = np.column_stack([pos, np.full_like(t, 1e3), 0 * t, 0 * t, 500.0 - t])
    sol = Solution(
        mission="toy", method="m", nodes=3, status="optimal", message="",
        cost=Quantity(1.0, "cost", ""), t=t, node_t=node_t,
        arcs=[(0.0, 4.0, "burn"), (4.0, 6.0, "coast"), (6.0, 10.0, "burn")],
        x=x, state_names=("x", "y", "z", "vx", "vy", "vz", "m"),
        state_units=("m", "m", "m", "m/s", "m/s", "m/s", "kg"),
    )
    pres = Presentation("toy frame", path=pos, thrust=thrust, display_unit="km",
                        display_scale=1e-3,
                        bodies=[Body("target", (12e3, 0, 0), 10.0, (200, 200, 200))],
                        markers=[Marker("start", (0, 0, 0))])
    return sol, pres


def test_vehicle_pose_follows_thrust_and_keeps_its_attitude_while_coasting():
    track = Track(*_burn_coast_burn())
    burn = track.pose(2.0)
    assert burn.burning and burn.throttle == pytest.approx(1.0)
    assert burn.position == pytest.approx([2.0, 0.0, 0.0])  # km: display units
    assert _rotate(burn.wxyz, np.array([0, 0, 1.0])) == pytest.approx([1, 0, 0], abs=1e-9)
    coast = track.pose(5.0)
    assert not coast.burning and coast.throttle == 0.0 and np.all(coast.force == 0)
    assert coast.axis == pytest.approx([1, 0, 0])  # the attitude of the end of burn 1
    second = track.pose(8.0)
    assert second.throttle == pytest.approx(0.5)
    assert _rotate(second.wxyz, np.array([0, 0, 1.0])) == pytest.approx([-1, 0, 0], abs=1e-9)
    # Body +y stays as close to the scene's up (+z) as the attitude allows.
    assert _rotate(second.wxyz, np.array([0, 1.0, 0])) == pytest.approx([0, 0, 1], abs=1e-9)
    # 1x plays the run in 12 s of wall clock and stops at the end; then it wraps.
    assert track.step(0.0, 1.2, 1.0) == pytest.approx(1.0)
    assert track.step(9.9, 1.2, 1.0) == 10.0 and track.step(10.0, 0.1, 1.0) == 0.0
    assert track.step(3.0, 0.5, 0.0) == pytest.approx(3.5)  # real time


def test_quaternion_handles_an_axis_along_up():
    q = quaternion_from_axes(np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))
    assert np.linalg.norm(q) == pytest.approx(1.0)
    assert _rotate(q, np.array([0, 0, 1.0])) == pytest.approx([0, 0, 1], abs=1e-9)


def test_a_solution_without_burns_heads_into_the_flow():
    sol, pres = _burn_coast_burn()
    sol.arcs = [(0.0, 10.0, "coast")]
    pose = Track(sol, pres).pose(3.0)
    assert pose.axis == pytest.approx([-1, 0, 0])  # heat shield (body -z) forward
    assert pose.throttle == 0.0 and pose.force == pytest.approx([1.0, 0, 0])  # force arrow


def test_readouts_give_speed_mass_thrust_and_range():
    sol, pres = _burn_coast_burn()
    rows = dict(readouts(sol, pres, Track(sol, pres), 5.0))
    assert rows["time"] == "5 s of 10 s"
    assert rows["speed"].startswith("1000 m/s")
    assert rows["mass"] == "495 kg"
    assert rows["thrust"] == "coasting (engine off)"
    assert rows["range to target"] == "7000 m"  # a small body: range to its centre


def test_lunar_readouts_match_the_states():
    from solvers import get_mission
    from solvers.missions.lunar_landing.model import R_MOON

    mission = get_mission("lunar-landing")
    sol = mission.solve(method="hermite-simpson", nodes=20, verify=False)
    pres = mission.present(sol)
    track = Track(sol, pres)
    t = 0.5 * track.tf
    rows = dict(readouts(sol, pres, track, t))
    r = np.interp(t, sol.t, sol.x[:, 0])
    assert rows["altitude above Moon"] == f"{(r - R_MOON) / 1e3:.5g} km"
    assert rows["thrust"] == "burning, throttle 100 %"
    assert rows["mass"].endswith(" kg")


def test_color_by_value_paints_the_path_and_the_legend_shows_the_bar():
    sol, pres = _burn_coast_burn()
    pres.color_by = ColorBy("heating rate", "W/cm²", np.linspace(0.0, 50.0, 101))
    g = build_geometry(pres, sol.t, sol.arcs)
    assert g.colorbar is not None and (g.colorbar.lo, g.colorbar.hi) == (0.0, 50.0)
    first, last = g.segment_colors[0, 0], g.segment_colors[-1, 0]
    assert np.all(first == colormap(np.array([0.25]), 0.0, 50.0)[0])
    assert not np.all(first == last) and not np.any(np.all(g.segment_colors[:, 0] == BURN, 1))
    html = legend_html(g)
    assert "heating rate" in html and "W/cm²" in html and "linear-gradient" in html
    sol, pres = _burn_coast_burn()
    assert "burn arc" in legend_html(build_geometry(pres, sol.t, sol.arcs))


def test_ghosts_brighten_towards_the_optimum():
    _, pres = _burn_coast_burn()
    pres.iterates = [(k, pres.path * (1 + 0.1 * k)) for k in range(4)]
    segs, cols = ghost_geometry(pres)
    assert segs.shape == (4 * 100, 2, 3)
    brightness = cols[::100, 0].astype(int).sum(axis=1)
    assert np.all(np.diff(brightness) > 0)  # each later iterate brighter
    assert ghost_geometry(pres, upto=2)[0].shape == (200, 2, 3)


def test_about_panel_renders_equations_as_mathml():
    pytest.importorskip("latex2mathml")
    from explorer.about import about_html
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    html = about_html(mission, "paper")
    assert html.count("<math") == len(mission.equations) + len(mission.method("paper").equations)
    assert "398.039" in html and "paper 002" in html  # published numbers with their source
    assert "Integral transform" in html


def test_comparison_rows_and_time_marker():
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    a = mission.solve(method="hermite-simpson", nodes=20)
    b = mission.solve(method="multiple-shooting", nodes=20)
    rows = comparison_rows(mission, [a, b])
    table = {r[0]: r[1:] for r in rows}
    assert rows[0] == ["", "hermite-simpson", "multiple-shooting"]
    assert table["status"] == ["optimal", "optimal"]
    for value in table["final time"]:
        assert value.endswith(" s") and float(value[:-2]) == pytest.approx(TF_PAPER, rel=1e-4)
    assert "check: touchdown altitude miss" in table and "solve time" in table
    plots_a, plots_b = mission.present(a).plots, mission.present(b).plots
    figure = PageFigure(figure_tree(plots_a, overlays=[("b", (1, 2, 3), plots_b)]),
                        len(plots_a))
    shapes = json.loads(figure.text(100.0))["layout"]["shapes"]
    assert len(shapes) == len(plots_a) and [s["xref"] for s in shapes][:2] == ["x", "x2"]
    assert all(s["x0"] == 100.0 for s in shapes)
    assert json.loads(figure.text(None))["layout"]["shapes"] == []
    assert "shapes" not in figure.tree["layout"]  # the shared tree itself is never changed


def test_session_passes_its_time_limit_and_runs_comparisons():
    from test_explorer import Recorder, SlowMission

    mission = SlowMission(steps=200, dt=0.01)  # 2 s unless stopped
    session = Session(mission, auto=False, time_limit=0.1)
    rec = Recorder()
    rec.compared = []
    rec.on_compare = lambda request, sols: rec.compared.append(sols)
    rec.on_submit = lambda request: None
    session.listeners.append(rec)
    request = session.submit()
    assert request.solve.time_limit == pytest.approx(COLD_FACTOR * 0.1)  # no warm start yet
    assert session.wait_idle(5.0)
    assert rec.results[-1].status == "time-limit" and session.last_good is None
    session.set_time_limit(None)
    mission.steps = 2
    session.submit()
    assert session.wait_idle(5.0) and session.last_good is not None
    session.set_time_limit(0.5)
    assert session.submit().solve.time_limit == 0.5  # warm now: the plain limit
    assert session.wait_idle(5.0)
    session.compare(["only"])
    assert session.wait_idle(5.0)
    assert len(rec.compared) == 1 and rec.compared[0][0].check["miss_m"] == 0.0
    started = len(mission.started)
    session.auto = True
    session.set_value("x", session.values["x"])  # unchanged: no new solve
    assert session.wait_idle(5.0) and len(mission.started) == started
    session.close()


def test_a_slow_missions_first_solve_gets_the_time_it_states():
    """The asteroid's cold solve takes about 10 s by nature (`cold_seconds`): a session whose
    per-solve limit is made for slider moves still gives its first solve three times that,
    while a mission that states nothing keeps three times the session's limit."""
    from solvers import get_mission

    asteroid, lunar = get_mission("asteroid-rendezvous"), get_mission("lunar-landing")
    assert asteroid.cold_seconds >= 5.0 and lunar.cold_seconds == 0.0
    slow = Session(asteroid, auto=False, time_limit=5.0)
    fast = Session(lunar, auto=False, time_limit=5.0)
    assert slow.request_time_limit() == pytest.approx(COLD_FACTOR * asteroid.cold_seconds)
    assert fast.request_time_limit() == pytest.approx(COLD_FACTOR * 5.0)
    slow.set_time_limit(None)
    assert slow.request_time_limit() is None  # no limit stays no limit
    slow.close()
    fast.close()


def test_exports(tmp_path):
    from explorer.export import scene_html, solution_csv, solution_json
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    sol = mission.solve(method="hermite-simpson", nodes=10)
    data = json.loads(solution_json(sol))
    assert data["quantities"]["tf"] == pytest.approx(TF_PAPER, rel=1e-3) and len(data["t"]) > 10
    csv_lines = solution_csv(sol).decode().splitlines()
    assert csv_lines[0].startswith("t [s],r [m]") and len(csv_lines) == len(sol.t) + 1
    html = scene_html(sol, mission.present(sol))
    assert "__VISER_EMBED_DATA__" in html
    assert "plotly" not in html.lower()  # no plotly panel: no 4.8 MB of plotly.js
    assert len(html) < 3e6


def test_live_view_stays_bounded_over_many_resolves():
    """A real view (server-side GUI and scene, no browser) re-solving 20 times: the scene
    keeps the same nodes and the session keeps one solution, not a history of them."""
    import viser

    from explorer.capture import free_port
    from explorer.view import View
    from solvers import get_mission, list_missions

    mission = get_mission("lunar-landing")
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        view = View(server.gui, server.scene, server.atomic, list_missions(), mission,
                    "hermite-simpson", 20)
        assert view.session.wait_idle(60.0) and view.session.latest.ok
        view.play.ghosts.value = True
        counts, names, moons = [], [], []
        for k in range(20):
            view.session.set_value("thrust", 2000.0 + 50.0 * (k + 1))
            assert view.session.wait_idle(60.0)
            counts.append(view.scene.node_count)
            names.append(len(server.scene._handle_from_node_name))
            moons.append(id(view.scene._context[0]))
        assert view.session.latest.ok and view.drawn >= 20
        assert len(set(counts)) == 1 and len(set(names)) == 1, (counts, names)
        # The Moon's mesh is sent again only when its level of detail steps (it was re-sent
        # on every move: its detail followed the path's size one step at a time).
        assert len(set(moons)) <= 3, f"the Moon was sent {len(set(moons))} times in 20 moves"
        # Play a little: the vehicle moves and the slider, read-outs and marker follow.
        p0 = view.scene.vehicle_position
        view.play.toggle()
        time.sleep(1.0)
        view.play.toggle()
        deadline = time.monotonic() + 5.0  # the player thread makes a last slow update
        slider = view.play.time_slider
        while slider.value != pytest.approx(view.play.t, abs=slider.step):
            assert time.monotonic() < deadline, "the time slider did not follow"
            time.sleep(0.05)
        assert np.linalg.norm(view.scene.vehicle_position - p0) > 0
        assert "altitude above Moon" in view.play.readout.content
        # The vehicle is drawn 3.5 % of the path long (to the 9 % size grid): the scale
        # sits on the meshes (a viser frame's scale does not reach its children in the page).
        from explorer.scene import VEHICLE_FRACTION
        size = VEHICLE_FRACTION * view.geometry.extent
        body = view.scene._vehicle["body"]
        assert np.allclose(body.scale, size, rtol=0.05) and size < 0.1 * view.geometry.extent
        assert threading.active_count() < 200
        view.close()
    finally:
        server.stop()


def test_bodies_with_a_track_move_with_the_animation_time():
    """A body carrying a track (e.g. Earth and the asteroid in the asteroid mission) is put
    where it is at the animation time; fixed bodies stay put."""
    import viser

    from explorer.capture import free_port
    from explorer.scene import SceneView

    sol, pres = _burn_coast_burn()
    track = np.column_stack([np.zeros_like(sol.t), 2e3 * sol.t, np.zeros_like(sol.t)])
    pres.bodies.append(Body("planet", (0.0, 0.0, 0.0), 50.0, (70, 130, 255), track))
    g = build_geometry(pres, sol.t, sol.arcs)
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        view = SceneView(server.scene)
        view.draw(g)
        handles = {name: h for name, h in server.scene._handle_from_node_name.items()
                   if name.startswith("/bodies/")}
        fixed = np.array(handles["/bodies/target"].position)
        view.move_bodies(5.0)
        # 2 km/s x 5 s = 10 km, drawn in km.
        assert np.allclose(handles["/bodies/planet"].position, (0.0, 10.0, 0.0))
        assert np.allclose(handles["/bodies/target"].position, fixed)
    finally:
        server.stop()


def test_a_re_solve_that_only_moves_bodies_curves_and_labels_keeps_their_scene_nodes():
    """A new optimum whose bodies, orbit curve and marker labels only moved (the asteroid's
    launch date moves all of them; the elliptic transfer's orbit curves change their sample
    count) updates those scene nodes in place: the same handles, new positions, points and
    text; a new body makes new nodes."""
    import viser

    from explorer.capture import free_port
    from explorer.scene import SceneView
    from solvers.presentation import Curve

    def presentation(shift: float, date: str, bodies: int = 1, samples: int = 50
                     ) -> Presentation:
        _, pres = _burn_coast_burn()
        angle = np.linspace(0, 6, samples)
        ring = np.column_stack([np.cos(angle), np.sin(angle), 0 * angle]) * 5e3 + [shift, 0, 0]
        pres.curves.append(Curve("orbit", ring, (90, 90, 255)))
        pres.bodies[0] = Body("target", (12e3 + shift, 0, 0), 10.0, (200, 200, 200))
        pres.bodies += [Body(f"moon {i}", (0.0, 3e3 * i, 0.0), 20.0, (90, 90, 90))
                        for i in range(1, bodies)]
        pres.markers[0] = Marker(f"start {date}", (shift, 0.0, 0.0))
        return pres

    sol, _ = _burn_coast_burn()
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        view = SceneView(server.scene)
        view.draw(build_geometry(presentation(0.0, "day 1"), sol.t, sol.arcs))
        nodes = dict(server.scene._handle_from_node_name)
        view.draw(build_geometry(presentation(2e3, "day 2", samples=60), sol.t, sol.arcs))
        after = server.scene._handle_from_node_name
        kept = [name for name in nodes if name.startswith(("/bodies/", "/curves", "/labels/"))]
        assert kept and all(after.get(name) is nodes[name] for name in kept)
        assert np.allclose(after["/bodies/target"].position, (14.0, 0.0, 0.0))  # km
        label = next(h for name, h in after.items() if name.startswith("/labels/"))
        assert label.text == "start day 2" and len(after["/curves"].points) == 59
        view.draw(build_geometry(presentation(2e3, "day 2", bodies=2), sol.t, sol.arcs))
        assert server.scene._handle_from_node_name.get("/bodies/target") is not nodes[
            "/bodies/target"]
    finally:
        server.stop()


def test_grid_map_figure_marks_the_solution():
    from explorer.plots import map_figure
    from solvers.presentation import GridMap

    z = np.add.outer(np.arange(5.0), np.arange(3.0)) * 10.0  # (len(x), len(y))
    fig = map_figure(GridMap("C3", "launch", np.arange(5.0), "flight", np.arange(3.0), "C3",
                             z, z_max=20.0, marker=(2.0, 1.0)))
    contour, marker = fig.data
    assert np.asarray(contour.z).shape == (3, 5)  # plotly wants rows = y
    assert np.asarray(contour.z).max() == 20.0  # clipped at z_max
    assert (marker.x[0], marker.y[0]) == (2.0, 1.0)


def test_every_mission_and_method_equation_renders_as_mathml():
    pytest.importorskip("latex2mathml")
    from explorer.about import mathml
    from solvers import list_missions
    from solvers.registry import mission_file_of

    for mission in list_missions():
        if mission_file_of(mission.key) is not None:
            continue  # a user's mission file needs no equations
        assert mission.equations, f"{mission.key} has no equations for its About panel"
        for caption, latex in mission.equations + tuple(
                eq for m in mission.methods for eq in m.equations):
            assert mathml(latex).startswith("<math"), f"{mission.key}: {caption}"


def test_a_fine_mesh_keeps_its_path_readable():
    """400 nodes on one loop: the node points shrink below their spacing instead of merging
    into a band, and at most MAX_ARROWS thrust arrows are drawn (every k-th node)."""
    from explorer.geometry import MAX_ARROWS, node_size

    angle = np.linspace(0.0, 2 * np.pi, 401)
    ring = np.column_stack([np.cos(angle), np.sin(angle), 0 * angle])
    pres = Presentation("inertial", ring, nodes=ring, thrust=np.tile([0.0, 0.0, 1.0], (401, 1)))
    g = build_geometry(pres, angle, [])
    spacing = 2 * np.pi / 400
    assert node_size(g) < spacing < 0.006 * g.extent
    assert len(g.arrows) <= MAX_ARROWS and len(g.arrows) > MAX_ARROWS / 2
    coarse = Presentation("inertial", ring, nodes=ring[::40])
    assert node_size(build_geometry(coarse, angle, [])) == pytest.approx(
        0.006 * build_geometry(coarse, angle, []).extent, rel=0.05)  # the 9 % size grid


def test_drawn_sizes_stay_put_when_the_extent_barely_moves():
    """Sizes sit on a grid of 1/8 octave: a 1 % change of the path's extent leaves them as
    they were (viser then sends nothing), a doubling doubles them, each within 4.5 % of the
    exact value."""
    from explorer.geometry import steady

    sizes = [steady(0.006 * e) for e in np.linspace(1000.0, 1010.0, 11)]
    assert len(set(sizes)) <= 2 and all(abs(s / 6.0 - 1) <= 0.045 for s in sizes)
    assert steady(12.0) == pytest.approx(2 * steady(6.0))
    assert steady(0.0) == 0.0


def test_a_size_on_a_grid_line_does_not_flip_with_each_step():
    """A path whose extent sits on a grid line of `steady` (slider steps to and fro) keeps
    the size it shows while the new one is within the band; beyond it, the grid value. The
    gizmo of a handle keeps its size over small changes of the path: each new size made the
    page compile a shader program (lunar landing: one per slider step)."""
    from explorer.geometry import steady

    edge = 2.0 ** (2.5 + 1 / 16)  # half way between two grid values
    below, above = edge * 0.99, edge * 1.01
    assert steady(below) != steady(above)  # without what is shown: a flip per step
    shown = steady(below)
    for size in (above, below, above, below):
        shown = steady(size, shown)
    assert shown == steady(below)
    assert steady(1.5 * edge, shown) == steady(1.5 * edge)  # far from it: the grid value
    assert steady(1.3 * edge, shown, band=0.5) == shown  # the gizmo's wider band


def test_marked_points_at_one_spot_share_one_label():
    """The asteroid's launch (at Earth) and arrival a year later lie close together: one
    label names both, both points stay; a distant marker and an axis tick keep theirs."""
    path = np.array([[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]])
    pres = Presentation("inertial", path, markers=[
        Marker("launch 2022-11-30", (0.0, 0.0, 0.0)),
        Marker("arrival 2023-11-29", (1.0, 0.0, 0.0)),
        Marker("tick", (1.0, 0.5, 0.0), point=False),
        Marker("far", (100.0, 0.0, 0.0))])
    names = [(m[0], m[3]) for m in build_geometry(pres, np.arange(2.0), []).markers]
    assert names == [("launch 2022-11-30 · arrival 2023-11-29", True), ("", True),
                     ("tick", False), ("far", True)]


def test_plot_titles_print_units_with_superscripts():
    """A plot title shows "mm/s²", as the status line does, not the data's "mm/s^2" (a
    student saw the caret in the elliptic transfer's plots)."""
    t = np.linspace(0.0, 1.0, 5)
    series = [PlotSeries("|u|", "mm/s^2", t, t)]
    layout = figure_tree(series)["layout"]
    titles = [a["text"] for a in layout.get("annotations", [])] + [
        v.get("title", {}).get("text", "") for k, v in layout.items() if k.startswith("yaxis")]
    assert any("mm/s²" in title for title in titles), titles
    assert not any("^" in title for title in titles), titles


def test_a_link_that_arrives_while_the_view_is_built_waits_for_it(monkeypatch):
    """The page's address reaches the server on another thread, possibly before the view is
    built (seen on a busy server: a malformed link's notice found no camera, and the page
    never said why its link was refused). Here the link arrives at once, from the link
    box's constructor: the view takes it once built and says why it is refused."""
    import viser

    from explorer import view as view_module
    from explorer.capture import free_port
    from explorer.panels.status import StatusPanel
    from solvers import get_mission, list_missions

    errors: list[BaseException] = []
    notices: list[str] = []

    class EagerLink(view_module.CaseLink):
        def __init__(self, gui, restore) -> None:
            super().__init__(gui, restore)

            def arrive() -> None:
                try:
                    restore("mission=lunar-landing&nodes=%C2%B2")
                except BaseException as exc:  # noqa: BLE001 - the test reports it
                    errors.append(exc)

            threading.Thread(target=arrive, daemon=True).start()

    def notice(self, clients, title, message) -> None:
        notices.append(message)

    monkeypatch.setattr(view_module, "CaseLink", EagerLink)
    monkeypatch.setattr(StatusPanel, "notify_kept", notice)
    mission = get_mission("lunar-landing")
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        view = view_module.View(server.gui, server.scene, server.atomic, list_missions(),
                                mission, "hermite-simpson")
        deadline = time.monotonic() + 60.0
        while not (notices or errors) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not errors, errors
        assert notices and "is not a whole number" in notices[0]
        assert view.session.nodes == mission.method("hermite-simpson").nodes[1]
    finally:
        server.stop()
