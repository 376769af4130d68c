"""Fast tests of the explorer's generic pieces: controls from params, scene geometry from a
Solution, the status line, the plot figure and the session's newest-request-wins solver."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from explorer.camera import fit_camera
from explorer.geometry import (
    ARROW_FRACTION,
    BURN,
    COAST,
    MAX_RINGS,
    RING_NAME,
    RING_POINTS,
    build_geometry,
)
from explorer.panels import setup as ctl
from explorer.panels import value_input as vi
from explorer.panels.status import result_markdown
from explorer.plots import figure_aspect, grid, make_figure
from explorer.session import Session
from solvers.context import SolveContext
from solvers.mission import Mission
from solvers.presentation import Body, Curve, Marker, PlotSeries, Presentation
from solvers.problem import Method, Param
from solvers.solution import Label, Quantity, Solution


# ---- a tiny mission whose solve is slow, cancellable and records what it was given ----
class SlowMission(Mission):
    key = "slow"
    title = "Slow test mission"
    summary = "sleeps, reports progress, returns x as the cost"
    source = "test"
    params = (
        Param("x", "x", "m", 1.0, 0.0, 10.0, 0.5, display_unit="km", display_factor=1e-3),
        Param("mode", "mode", "", 0, 0, 1, 1, options=("a", "b")),
    )
    methods = (Method("only", "only method", "test", "sleeps", nodes=(2, 3, 9)),)

    def __init__(self, steps: int = 20, dt: float = 0.01) -> None:
        self.steps, self.dt = steps, dt
        self.started: list[float] = []
        self.warm_seen: list[float | None] = []
        self.lock = threading.Lock()

    def _solve(self, values, method, nodes, backend, warm, ctx: SolveContext) -> Solution:
        with self.lock:
            self.started.append(values["x"])
            self.warm_seen.append(None if warm is None else warm.values["x"])
        for k in range(self.steps):
            time.sleep(self.dt)
            ctx.report(k)
        status = "failed" if values["x"] == 7.0 else "optimal"
        sol = Solution(mission=self.key, method=method.key, nodes=nodes, status=status,
                       message="", cost=Quantity(values["x"], "x", "m"), values=values,
                       t=np.array([0.0, 1.0]))
        sol.checker = lambda: {"miss_m": 0.0}
        return sol


class Recorder:
    """A SessionListener that keeps what it heard."""

    def __init__(self) -> None:
        self.results: list[Solution] = []
        self.errors: list[str] = []
        self.checks: list[Solution] = []
        self.progress = 0
        self.configs = 0

    def on_config(self, session):
        self.configs += 1

    def on_progress(self, request, iteration, message):
        self.progress += 1

    def on_result(self, request, solution):
        self.results.append(solution)

    def on_check(self, request, solution):
        self.checks.append(solution)

    def on_error(self, request, message):
        self.errors.append(message)


def test_newest_request_wins_and_older_ones_are_cancelled():
    mission = SlowMission(steps=50, dt=0.01)  # a full solve takes at least 0.5 s
    session = Session(mission, auto=False)
    rec = Recorder()
    session.listeners.append(rec)
    requests = []
    t0 = time.perf_counter()
    for x in (1.0, 2.0, 3.0, 4.0):
        session.values["x"] = x
        requests.append(session.submit())
        time.sleep(0.05)  # let the worker start each one, so cancellation is exercised
    assert session.wait_idle(10.0)
    elapsed = time.perf_counter() - t0
    assert [s.values["x"] for s in rec.results] == [4.0]  # only the newest is delivered
    assert all(r.cancel.is_set() for r in requests[:-1])
    assert not requests[-1].cancel.is_set()
    # Older solves were started and then stopped early: far less than 4 full solves (2 s).
    assert len(mission.started) >= 2 and mission.started[-1] == 4.0
    assert elapsed < 1.6
    assert session.last_good is rec.results[-1]
    assert rec.checks and rec.checks[-1].check["miss_m"] == 0.0
    session.close()


def test_warm_start_bad_input_and_failure_keep_the_last_good_solution():
    mission = SlowMission(steps=2, dt=0.001)
    session = Session(mission)  # auto: every change submits
    rec = Recorder()
    session.listeners.append(rec)
    session.set_value("x", 2.0)
    assert session.wait_idle(5.0)
    good = session.last_good
    assert good is not None and good.values["x"] == 2.0
    session.set_value("x", 50.0)  # outside [0, 10]: mission.solve raises ValueError
    assert session.wait_idle(5.0)
    assert rec.errors and "'x'" in rec.errors[-1] and session.last_good is good
    session.set_value("x", 7.0)  # the fake mission fails at 7
    assert session.wait_idle(5.0)
    assert rec.results[-1].status == "failed" and session.last_good is good
    session.set_value("x", 3.0)
    assert session.wait_idle(5.0)
    # Warm-started from the last good solution (later solves: its cost error estimate's).
    assert mission.warm_seen[mission.started.index(3.0)] == 2.0
    assert session.last_good.values["x"] == 3.0
    session.close()


def test_display_conversion_round_trips_for_every_param():
    from solvers import list_missions

    params = [p for m in list_missions() for meth in m.methods for p in m.all_params(meth.key)]
    params += list(SlowMission.params)
    for p in params:
        lo, hi, step = vi.display_range(p)
        assert lo <= vi.to_display(p, p.default) <= hi and step > 0
        for v in (p.min, p.default, p.max):
            assert vi.from_display(p, vi.to_display(p, v)) == pytest.approx(v, rel=1e-12)
            assert p.min <= vi.from_display(p, vi.to_display(p, v)) <= p.max


def test_display_factor_and_labels():
    x = SlowMission.params[0]
    assert vi.display_range(x) == (0.0, 0.01, 0.0005)
    assert vi.label_of(x) == "x [km]"
    assert vi.from_display(x, 0.0025) == 2.5
    assert vi.from_display(x, 0.0100000000001) == 10.0  # clamped, passes validation


@pytest.fixture()
def gui_server():
    import viser

    from explorer.capture import free_port

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server
    server.stop()


def test_a_typed_entry_is_taken_without_writing_the_box_back(gui_server):
    """An accepted entry stays as typed: a canonical echo ("12 s" -> "12") could reach the
    page after a newer entry and overwrite it (the fresh-venv failure of 2026-12-02). A
    refused entry puts the old value back, since there is nothing newer to keep."""
    taken: list[float | None] = []
    reports: list[str] = []
    field = vi.TimeLimitField(gui_server.gui, "limit", 20.0, taken.append,
                              lambda title, message: reports.append(message), hint="")
    field.box.value = "12 s"
    field.commit()
    assert taken == [12.0] and field.box.value == "12 s"
    field.commit()  # the same value again: nothing to apply
    assert taken == [12.0]
    field.box.value = "-5"
    field.commit()
    assert taken == [12.0] and field.box.value == "12" and "outside the allowed range" in reports[0]

    x = SlowMission.params[0]  # shown in km
    applied: list[tuple[str, float]] = []
    number = vi.NumberField(gui_server.gui, x, 1.0, lambda k, v: applied.append((k, v)),
                            lambda title, message: reports.append(message))
    number.box.value = "2.5e-3"
    number.commit()
    assert applied == [("x", 2.5)] and number.box.value == "2.5e-3"
    assert number.slider.value == pytest.approx(0.0025)  # the slider follows
    number.box.value = "0.0025"
    number.commit()  # the same value typed another way
    assert applied == [("x", 2.5)]


class _Rebuild(Recorder):
    """Rebuilds the controls on a configuration change, as the app's view does."""

    def __init__(self, controls: ctl.Controls) -> None:
        super().__init__()
        self.controls = controls

    def on_config(self, session):
        self.controls.rebuild()


def _controls(server, session: Session, missions) -> ctl.Controls:
    controls = ctl.Controls(server.gui, session, missions)
    session.listeners.append(_Rebuild(controls))
    controls.rebuild()
    return controls


def test_controls_built_from_the_lunar_mission(gui_server):
    from solvers import get_mission, list_missions

    mission = get_mission("lunar-landing")
    session = Session(mission, method="hermite-simpson", auto=False)
    controls = _controls(gui_server, session, list_missions())
    keys = {p.key for p in mission.all_params("hermite-simpson")}
    assert keys <= set(controls.inputs)
    assert {"mission", "method", "backend", "nodes"} <= set(controls.inputs)
    altitude = controls.inputs["altitude0"]
    assert (altitude.value, altitude.min, altitude.max) == (15.0, 1.0, 100.0)  # km
    altitude.value = 20.0  # as if moved in the browser
    assert session.values["altitude0"] == 20e3  # the session gets SI
    omega = controls.inputs["omega0"]
    assert omega.value == pytest.approx(0.965)  # mrad/s
    choice = controls.inputs["omega_source"]
    choice.value = "vis-viva from apolune"
    assert session.values["omega_source"] == 1.0
    controls.inputs["method"].value = mission.method("paper").label
    assert session.method == "paper" and "sigma0" in controls.inputs  # rebuilt
    assert "backend" not in controls.inputs  # the paper method has no back ends
    assert controls.inputs["nodes"].value == mission.method("paper").nodes[1]
    controls.inputs["preset"].value = "Heavy lander, 3 kN"  # a preset of the mission
    assert session.values["mass0"] == 1200.0 and session.values["thrust"] == 3000.0
    assert controls.inputs["mass0"].value == 1200.0  # the rebuilt slider shows it
    assert session.values["altitude0"] == 15e3  # the preset starts from the defaults
    session.close()


def test_mission_dropdown_switches_to_another_missions_controls(gui_server):
    from solvers import get_mission

    lunar, slow = get_mission("lunar-landing"), SlowMission()
    session = Session(lunar, auto=False)
    controls = _controls(gui_server, session, [lunar, slow])
    controls.inputs["mission"].value = slow.title
    assert session.mission is slow and session.values == {"x": 1.0, "mode": 0.0}
    assert set(controls.inputs) == {"mission", "method", "nodes", "x", "mode"}
    assert controls.inputs["x"].value == 0.001  # 1 m shown in km
    assert controls.inputs["mode"].value == "a"
    session.close()


def test_a_view_opens_each_mission_with_its_live_method_solved_optimal():
    """A live view opens a mission (and switches to it, and restores a link without a
    method) with its `live_method`, the first method where it names none; that method's
    default is `optimal`. The lunar landing's, the reentry's and the hovercraft's paper
    methods take 25-57 ms a slider move against 7-13 ms (bench_missions): they stay one
    choice away."""
    from solvers import get_mission, list_missions

    for mission in list_missions():
        expected = mission.live_method or mission.methods[0].key
        session = Session(mission, auto=False)
        assert session.method == expected, mission.key
        session.close()
        if mission.live_method is not None:
            assert mission.solve({}, method=expected).status == "optimal", mission.key
    live = {m.key: m.live_method for m in list_missions() if m.live_method}
    assert live == {"lunar-landing": "hermite-simpson", "apollo-reentry": "hermite-simpson",
                    "hovercraft": "hermite-simpson", "asteroid-rendezvous": "burn-coast"}
    session = Session(get_mission("cw-rendezvous"), auto=False)
    session.select_mission(get_mission("apollo-reentry"))
    assert session.method == "hermite-simpson"
    session.restore(get_mission("lunar-landing"), None, None, {}, {})
    assert session.method == "hermite-simpson"
    session.close()


def _toy_solution() -> tuple[Solution, Presentation]:
    t = np.linspace(0.0, 10.0, 11)
    pos = np.column_stack([t * 1e3, np.zeros(11), np.full(11, 2e3)])
    nodes = pos[::3]
    thrust = np.array([[1.0, 0, 0], [0, 0.5, 0], [0, 0, 0], [0, 0, 1.0]])
    sol = Solution(
        mission="toy", method="m", nodes=3, status="optimal", message="",
        cost=Quantity(1.0, "cost", ""), t=t, arcs=[(0.0, 4.0, "burn"), (4.0, 6.0, "coast"),
                                                   (6.0, 10.0, "burn")],
    )
    pres = Presentation(
        "toy", path=pos, nodes=nodes, thrust=thrust, display_unit="km", display_scale=1e-3,
        bodies=[Body("rock", (5e3, 0, 0), 1e3, (90, 90, 90))],
        curves=[Curve("ref", pos[:5], (0, 0, 255))], markers=[Marker("start", (0, 0, 2e3))])
    return sol, pres


def test_scene_geometry_counts_colours_and_units():
    sol, pres = _toy_solution()
    g = build_geometry(pres, sol.t, sol.arcs)
    assert g.segments.shape == (10, 2, 3)
    burn = np.all(g.segment_colors[:, 0] == BURN, axis=1)
    coast = np.all(g.segment_colors[:, 0] == COAST, axis=1)
    assert burn.sum() == 8 and coast.sum() == 2 and coast[4] and coast[5]
    assert g.segments[-1, 1] == pytest.approx([10.0, 0.0, 2.0])  # km
    assert g.nodes.shape == (4, 3)
    assert g.arrows.shape == (3, 2, 3)  # the zero thrust vector draws no arrow
    lengths = np.linalg.norm(g.arrows[:, 1] - g.arrows[:, 0], axis=1)
    assert lengths == pytest.approx(ARROW_FRACTION * g.extent * np.array([1.0, 0.5, 1.0]))
    assert g.curve_segments.shape == (4, 2, 3)
    assert g.spheres[0].radius == 1.0 and len(g.markers) == 1
    dim = build_geometry(pres, sol.t, sol.arcs, dim=True)
    assert not np.any(np.all(dim.segment_colors[:, 0] == BURN, axis=1))


def test_throttle_bounds_are_rings_about_the_arrows_in_their_vertical_plane():
    """Issue 21: each ring is a circle about an arrow's base of radius ARROW_FRACTION ×
    extent × the bound, in the plane of the arrow and the vertical: the tip lies between
    the two rings, on the inner one at the lower bound; at most MAX_RINGS arrows get them,
    spread evenly along the path (nodes bunched at one end do not bunch the rings), sent
    with the reference curves under one legend name."""
    sol, pres = _toy_solution()
    assert not any(name == RING_NAME for name, _, _ in build_geometry(
        pres, sol.t, sol.arcs).curve_names)  # no bounds, no rings
    n = 120
    nodes = np.column_stack([9e3 * np.linspace(0, 1, n) ** 2, np.zeros(n), np.full(n, 2e3)])
    angle = np.linspace(0.0, 3.0, n)
    throttle = np.linspace(0.3, 0.8, n)
    thrust = throttle[:, None] * np.column_stack([np.sin(angle) * np.cos(3 * angle),
                                                  np.sin(angle) * np.sin(3 * angle),
                                                  np.cos(angle)])
    pres.nodes, pres.thrust, pres.thrust_bounds = nodes, thrust, (0.3, 0.8)
    g = build_geometry(pres, sol.t, sol.arcs)
    names = [name for name, _, _ in g.curve_names]
    assert names.count(RING_NAME) == 2 * MAX_RINGS
    rings = g.curve_segments[4:].reshape(MAX_RINGS, 2, RING_POINTS, 2, 3)
    unit = ARROW_FRACTION * g.extent
    bases = g.arrows[:, 0]
    gaps = np.diff(rings[:, 0, :, 0].mean(axis=1)[:, 0])  # the rings' centres, downrange
    assert gaps.min() > 0.6 * gaps.max()
    for pair in rings:
        centre = pair[0, :, 0].mean(axis=0)  # evenly spaced round a circle
        k = int(np.argmin(np.linalg.norm(bases - centre, axis=1)))
        base, d = bases[k], g.arrows[k, 1] - bases[k]
        assert base == pytest.approx(centre, abs=1e-9 * unit)
        for ring, bound in zip(pair, (0.3, 0.8), strict=True):
            points = ring[:, 0] - base
            assert np.linalg.norm(points, axis=1) == pytest.approx(bound * unit)
            normal = np.cross(d, (0.0, 0.0, 1.0))
            if np.linalg.norm(normal) > 1e-9:  # the plane of the arrow and the vertical
                assert points @ normal == pytest.approx(0.0, abs=1e-9 * unit)
        assert 0.3 * unit - 1e-9 <= np.linalg.norm(d) <= 0.8 * unit + 1e-9
    assert np.linalg.norm(g.arrows[0, 1] - g.arrows[0, 0]) == pytest.approx(0.3 * unit)


def test_lunar_scene_and_camera_frame_the_descent():
    from solvers import get_mission
    from solvers.missions.lunar_landing.model import R_MOON

    mission = get_mission("lunar-landing")
    sol = mission.solve(method="hermite-simpson", nodes=20, verify=False)
    g = build_geometry(mission.present(sol), sol.t, sol.arcs)
    assert len(g.segments) == len(sol.t) - 1
    assert len(g.nodes) == 21 and len(g.arrows) == 21
    moon = g.spheres[0]
    assert moon.radius == pytest.approx(R_MOON * 1e-3)  # drawn in km
    # A face must sag less than the 15 km initial altitude (here under about 1.1 km).
    assert moon.subdivisions >= 15
    cam = fit_camera(g, aspect=1.0)
    # The camera is outside the Moon, within a few trajectory extents of the path...
    assert np.linalg.norm(cam.position) > moon.radius
    assert np.linalg.norm(cam.position - g.center) < 3 * g.extent
    # ...and looks at it with the Moon below ('up' is the local vertical).
    assert cam.up @ (g.center / np.linalg.norm(g.center)) > 0.99
    assert cam.far > np.linalg.norm(cam.position) + moon.radius



@pytest.mark.parametrize("bottom", [0.0, 0.39])
def test_the_frame_keeps_room_for_labels_above_and_below(bottom):
    """A label stands above or below its point in screen space (about 22 px high, a
    gizmo's arrow about 40 px): the highest and lowest framed points stay 8 % of the
    half-height from the uncovered part's edges (the hovercraft's target-velocity tip sat
    at 0.94 of the half-height, under the plots panel's 39 %: its label cut off)."""
    from explorer.camera import FOV
    from solvers import get_mission

    mission = get_mission("hovercraft")
    sol = mission.solve(method="hermite-simpson", verify=False)
    g = build_geometry(mission.present(sol), sol.t, sol.arcs)
    g.markers.append(("tip", g.points.max(axis=0) + [0.0, 1.0, 0.0], (0, 0, 0), False,
                      "bottom-left"))
    cam = fit_camera(g, aspect=1.2, bottom=bottom)
    forward = (cam.look_at - cam.position) / np.linalg.norm(cam.look_at - cam.position)
    right = np.cross(forward, cam.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.concatenate([g.points, [m[1] for m in g.markers]]) - cam.position
    ndc_y = (rel @ up) / ((rel @ forward) * np.tan(FOV / 2))
    top, low = 1.0 - 0.08, -1.0 + 2 * bottom + 0.08  # the uncovered part, less the room
    assert ndc_y.max() <= top + 1e-9 and ndc_y.min() >= low - 1e-9

class _FakeCamera:
    """What `Cameras` reads and sets of a browser's camera."""

    def __init__(self, client) -> None:
        self.client, self.aspect, self.image_height = client, 1.5, 700
        self.position, self.look_at = np.array([3.0, 3.0, 3.0]), np.zeros(3)

    def on_update(self, callback) -> None:
        self.callback = callback

    def reports(self, position, look_at) -> None:
        """The browser sends its pose (a message as viser delivers it)."""
        self.position, self.look_at = np.asarray(position, float), np.asarray(look_at, float)
        self.callback(self)


class _FakeClient:
    def __init__(self) -> None:
        self.client_id, self.camera = 7, _FakeCamera(self)

    def atomic(self):
        import contextlib

        return contextlib.nullcontext()


def test_only_a_persons_orbit_sets_the_view_direction():
    """The pose a browser had before a placement, arriving after it, is not a person's
    orbit; after the browser echoes the placement, a new pose is (and kept for later
    framings); a placement never echoed stops being waited for after `ECHO_WAIT_S`."""
    from explorer import camera as cam_module
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    sol = mission.solve(method="hermite-simpson", nodes=20, verify=False)
    g = build_geometry(mission.present(sol), sol.t, sol.arcs)
    cameras, client = cam_module.Cameras(100.0), _FakeClient()
    cameras.attach(client, lambda c: None)
    old_position, old_look_at = client.camera.position.copy(), client.camera.look_at.copy()
    cameras.frame(g, None)
    placed = (np.array(client.camera.position), np.array(client.camera.look_at))
    client.camera.reports(old_position, old_look_at)  # the pose from before, on its way
    assert not cameras.user_view
    client.camera.reports(*placed)  # the echo
    orbited = placed[1] + np.roll(placed[0] - placed[1], 1)
    client.camera.reports(orbited, placed[1])  # a person orbits
    direction = cameras.user_view[7]
    assert np.allclose(direction, (orbited - placed[1]) / np.linalg.norm(orbited - placed[1]))
    cameras.frame(g, None)  # a later framing keeps the person's direction
    back = np.array(client.camera.position) - g.center  # (it aims a little below the centre)
    assert np.allclose(back / np.linalg.norm(back), direction)
    cameras._sent_at[7] -= cam_module.ECHO_WAIT_S  # never echoed: after the wait ...
    client.camera.reports(placed[0], placed[1] + 1.0)
    assert not np.allclose(cameras.user_view[7], direction)  # ... a pose is a person's again


def test_status_line_and_plots():
    sol, _ = _toy_solution()
    sol.quantities = {"tf": Quantity(398.04, "final time", "s")}
    sol.check = {"altitude_m": 0.0024}
    sol.labels = {"altitude_m": Label("touchdown altitude miss", "m")}
    md = result_markdown(sol)
    assert "final time 398.04 s" in md and "touchdown altitude miss 0.0024 m" in md
    sol.status, sol.message = "failed", "no convergence"
    assert "no convergence" in result_markdown(sol, kept=True)
    series = [PlotSeries(f"s{i}", "m", sol.t, sol.t, sol.t[::3], sol.t[::3]) for i in range(5)]
    fig = make_figure(series)
    assert len(fig.data) == 10  # a line and the node markers per series
    assert [grid(n) for n in (1, 3, 5, 8, 10)] == [(1, 1), (1, 3), (2, 3), (2, 4), (3, 4)]
    assert figure_aspect(5, 0.4) == 0.4 and figure_aspect(10, 0.4) == pytest.approx(0.6)


def test_an_app_offers_the_user_missions_its_workers_can_solve():
    """A mission another app of this process registered from a file (a test module's app,
    a library user's) is solved by this app's workers too; one registered only in memory
    (no file for a worker to load) is not offered. Before, the first showed "unknown
    mission" in the page when a later app switched to it."""
    from pathlib import Path

    from explorer.app import ExplorerApp
    from explorer.capture import free_port
    from solvers.mission_file import load_mission_file
    from solvers.registry import load_mission_files, register, unregister
    from solvers.request import SolveRequest

    examples = Path(__file__).resolve().parents[2] / "examples"
    keep_out = examples / "keep_out_rendezvous.py"
    assert load_mission_files([str(keep_out)]) == {}
    memory_only = load_mission_file(examples / "double_integrator.py")
    register(memory_only)
    app = None
    try:
        app = ExplorerApp("127.0.0.1", free_port(), "keep-out-rendezvous", workers=1,
                          prebuild=False)
        keys = [m.key for m in app.missions]
        assert "keep-out-rendezvous" in keys and memory_only.key not in keys
        sol = app.service.submit(SolveRequest("keep-out-rendezvous"), verify=False).result(120)
        assert sol.status in ("optimal", "inaccurate"), sol.message
    finally:
        if app is not None:
            app.stop()
        unregister("keep-out-rendezvous")
        unregister(memory_only.key)


def test_no_setup_folder_shares_a_name_with_the_panels_own():
    """The cart's parameters sat in a second folder called "Problem" under the panel's own
    "Problem" folder; a mission file may name a group anything."""
    from solvers.registry import list_missions

    for mission in list_missions():
        for method in mission.methods:
            labels = list(ctl.group_params(mission.all_params(method.key)))
            assert not set(labels) & set(ctl.OWN_FOLDERS), (mission.key, method.key, labels)
    mine = [Param("a", "a", "m", 1.0, 0.0, 2.0, 0.1, group="Problem"),
            Param("b", "b", "m", 1.0, 0.0, 2.0, 0.1, group="Display"),
            Param("c", "c", "m", 1.0, 0.0, 2.0, 0.1, group="Problem")]
    groups = ctl.group_params(mine)
    assert list(groups) == ["Problem parameters", "Display parameters"]
    assert [p.key for p in groups["Problem parameters"]] == ["a", "c"]
