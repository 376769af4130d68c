"""Handles dragged in the 3D view (issue 19), without a browser: the records bind real
parameters, a drag position inverts to values and stops at the range's end, and a drag in a
live view sets the values, moves the slider and brings a new optimum (checked against the
analytic minimum time of Kirk 1970, ex. 5.3-1: T* = 2 sqrt(d / a)); the keep-out sphere of
the gallery drags and the path re-solves around it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from solvers import get_mission, list_missions
from solvers.handles import Axis, Handle, check_bindings, values_at

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PATIENCE = 120.0


def test_every_missions_handles_bind_numeric_parameters():
    declared = {}
    for m in list_missions():
        check_bindings((*m.handles, *m.shapes), m.all_params(),
                       m.view_params)
        declared[m.key] = {p for h in m.handles for p in h.params}
    assert declared["cw-rendezvous"] == {"x0", "y0", "z0", "vx0", "vy0", "vz0"}
    assert declared["hovercraft"] == {"x0", "y0", "xf", "yf", "vx0", "vy0", "vxf", "vyf"}
    assert declared["bang-bang"] == {"distance"}
    assert declared["lunar-landing"] == {"altitude0"}
    assert declared["apollo-reentry"] == {"h0", "gamma0"}
    assert declared["powered-descent"] == {"downrange0", "crossrange0", "altitude0",
                                           "target_downrange", "target_crossrange"}
    with pytest.raises(ValueError, match="'nope' is not a numeric parameter"):
        check_bindings((Handle("h", "h", ("nope", 0.0, 0.0)),), m.all_params(), ())


def test_a_position_inverts_to_values_locked_axes_ignored_and_clamped_at_the_range():
    cw = get_mission("cw-rendezvous")
    start = cw.handles[0]
    view = cw.view_defaults()
    moved = values_at(start, (20e3, -1e3, 300.0), cw.params, view)
    assert moved.values == {"x0": 20e3, "y0": -1e3, "z0": 300.0} and moved.held == ()
    assert start.where(cw.defaults() | moved.values, view) == (20e3, -1e3, 300.0)
    far = values_at(start, (250e3, 0.0, -80e3), cw.params, view)
    assert far.values["x0"] == 100e3 and far.values["z0"] == -50e3
    assert set(far.held) == {"x0", "z0"}
    assert not start.shown_in(view | {"view": 1})  # the inertial view turns the axes
    # The reentry's entry point: r = R + k h, k the altitude exaggeration (a view option).
    reentry = get_mission("apollo-reentry")
    entry = reentry.handles[0]
    r = entry.axes[0].offset + 20.0 * 100e3
    assert values_at(entry, (r, 5.0, 5.0), reentry.params,
                     {"exaggerate": 20.0}).values == {"h0": pytest.approx(100e3)}
    held = values_at(entry, (r, 0.0, 0.0), reentry.params, {"exaggerate": 10.0})
    assert held.values == {"h0": 180e3} and held.held == ("h0",)  # 200 km > the range
    assert values_at(Handle("a", "a", (Axis("distance", scale=2.0), 0.0, 0.0)), (3.0, 0, 0),
                     get_mission("bang-bang").params, {}).values == {"distance": 1.5}


def test_a_velocity_arrows_tip_starts_at_its_point_and_inverts_to_the_velocity():
    """Hovercraft: the start velocity's tip sits at start + 0.2 s × v; dragged, it sets the
    velocity from the start where it is now, clamped at the range (vx0 >= 0)."""
    hover = get_mission("hovercraft")
    arrow = next(h for h in hover.handles if h.key == "start_velocity")
    values = hover.defaults() | {"x0": 2.0, "y0": 1.0, "vx0": 5.0, "vy0": -1.0}
    assert arrow.is_arrow and arrow.tail(values, {}) == (2.0, 1.0, 0.0)
    assert arrow.where(values, {}) == pytest.approx((3.0, 0.8, 0.0))
    moved = values_at(arrow, (3.6, 1.4, 7.0), hover.params, {}, values)
    assert moved.values == {"vx0": pytest.approx(8.0), "vy0": pytest.approx(2.0)}
    back = values_at(arrow, (0.0, 1.0, 0.0), hover.params, {}, values)
    assert back.values["vx0"] == 0.0 and back.held == ("vx0",)


@pytest.fixture()
def live():
    """`live(mission)`: a real view on a server-side GUI and scene (no browser)."""
    import viser

    from explorer.capture import free_port
    from explorer.view import View

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    views = []

    def make(mission, method=None):
        view = View(server.gui, server.scene, server.atomic, [mission], mission, method)
        view.reports = []
        view.handles.report = lambda title, message: view.reports.append((title, message))
        views.append(view)
        assert view.session.wait_idle(PATIENCE) and view.drawn
        return view

    yield make
    for view in views:
        view.close()
    server.stop()


def _drag(view, key: str, points: list[tuple[float, float, float]]) -> None:
    """A whole gesture through `points` (scene units), then wait for the last solve."""
    handles = view.handles
    handles.drag(key, points[0], "start")
    for p in points:
        handles.drag(key, p)
    handles.drag(key, points[-1], "end")
    assert view.session.wait_idle(PATIENCE)


def test_dragging_the_carts_target_sets_the_distance_the_slider_and_a_new_optimum(live):
    view = live(get_mission("bang-bang"))
    drawn = view.handles.drawn["target"]
    assert tuple(drawn.gizmo.active_axes) == (True, False, False)  # along the rail only
    assert np.allclose(drawn.gizmo.position, (1.0, 0.0, 0.0))  # where the path ends
    _drag(view, "target", [(1.5, 0.0, 0.0), (2.0, 0.3, 0.0)])  # off-rail motion is ignored
    assert view.session.values["distance"] == 2.0
    assert view.controls.fields["distance"].slider.value == 2.0
    sol = view.session.latest
    assert sol.converged and sol.values["distance"] == 2.0
    assert sol.cost.value == pytest.approx(2 * math.sqrt(2.0), rel=2e-3)  # Kirk 1970
    assert np.allclose(view.geometry.points[-1], (2.0, 0.0, 0.0), atol=1e-6)
    # Past the range's end: held at 100 m, said beside the handle and once at release.
    _drag(view, "target", [(50.0, 0.0, 0.0), (500.0, 0.0, 0.0)])
    assert view.session.values["distance"] == 100.0
    assert np.allclose(drawn.gizmo.position, (100.0, 0.0, 0.0))  # snapped back to the end
    assert "end of range" in drawn.label.text
    assert any("held at the end of the range" in m for _, m in view.reports)
    assert view.session.latest.cost.value == pytest.approx(20.0, rel=2e-3)  # 2 sqrt(100)


def test_the_mars_target_drags_on_the_ground_and_the_lander_lands_there(live):
    """Powered descent (issue 21): the target's height is locked (it stays on the ground),
    a drag sets its two coordinates, clamped at ±3 km, and the descent re-solved from the
    same start touches down where it was dropped (drawn surface-fixed, in km)."""
    mission = get_mission("powered-descent")
    target = next(h for h in mission.handles if h.key == "target")
    assert target.active_axes == (True, True, False)
    moved = values_at(target, (500.0, -250.0, 800.0), mission.params, {})
    assert moved.values == {"target_downrange": 500.0, "target_crossrange": -250.0}
    far = values_at(target, (9e3, 0.0, 0.0), mission.params, {})
    assert far.values["target_downrange"] == 3e3 and far.held == ("target_downrange",)
    assert target.where(mission.defaults() | moved.values, {}) == (500.0, -250.0, 0.0)
    view = live(mission)
    drawn = view.handles.drawn["target"]
    assert tuple(drawn.gizmo.active_axes) == (True, True, False)
    assert np.allclose(drawn.gizmo.position, (0.0, 0.0, 0.0))
    _drag(view, "target", [(0.1, -0.1, 0.0), (0.3, -0.2, 0.0)])
    values = view.session.values
    assert values["target_downrange"] == pytest.approx(300.0)
    assert values["target_crossrange"] == pytest.approx(-200.0)
    sol = view.session.latest
    assert sol.converged, sol.message
    assert np.allclose(view.geometry.points[-1], (0.3, -0.2, 0.0), atol=1e-6)
    assert np.allclose(view.geometry.points[0], (2.0, 0.0, 1.5), atol=1e-6)  # start stays


def test_a_marked_point_under_a_handle_leaves_the_label_to_the_handle(live):
    """CW: "chaser start" under "chaser start (15, -0.5, 0) km" covered it; the point stays,
    the handle's label names it; the target far away keeps its own label."""
    view = live(get_mission("cw-rendezvous"))
    start = np.asarray(view.handles.drawn["start"].gizmo.position)
    markers = view.geometry.markers
    bare = [m for m in markers if not m[0] and m[3]]  # points without a label
    assert len(bare) == 1 and np.linalg.norm(bare[0][1] - start) < 0.05 * view.geometry.extent
    names = [m[0] for m in markers]
    assert "target" in names and not any("chaser start" in name for name in names)


def test_dragging_the_start_velocitys_tip_sets_the_velocity_and_a_new_optimum(live):
    view = live(get_mission("hovercraft"))
    drawn = view.handles.drawn["start_velocity"]
    assert drawn.shaft is not None and tuple(drawn.gizmo.active_axes) == (True, True, False)
    assert np.allclose(drawn.gizmo.position, (1.0, 0.0, 0.0))  # 0.2 s × (5, 0) m/s
    _drag(view, "start_velocity", [(0.9, 0.1, 0.0), (0.8, 0.2, 0.0)])
    values = view.session.values
    assert (values["vx0"], values["vy0"]) == (pytest.approx(4.0), pytest.approx(1.0))
    sol = view.session.latest
    assert sol.converged, sol.message
    assert sol.node_x[0, 2:4] == pytest.approx([4.0, 1.0])
    assert np.allclose(drawn.shaft.points[0], [(0.0, 0.0, 0.0), (0.8, 0.2, 0.0)])


def test_the_entry_angles_arrow_turns_with_the_drawn_path_and_sets_gamma0(live):
    """Reentry: the entry direction is a curve handle (the drawn angle is not affine in γ
    under the altitude exaggeration): its arrow lies along the drawn path's first step, and
    its tip dragged upward (towards the local vertical) makes the entry shallower, clamped
    at the range's end; the optimum starts at the new angle."""
    reentry = get_mission("apollo-reentry")
    arrow = next(h for h in reentry.handles if h.key == "entry_angle")
    values, view = reentry.defaults(), reentry.view_defaults()
    tip = values_at(arrow, arrow.where(values, view), reentry.params, view, values)
    assert tip.values["gamma0"] == pytest.approx(values["gamma0"], abs=1e-8) and not tip.held

    view_ = live(reentry)
    drawn = view_.handles.drawn["entry_angle"]
    assert drawn.shaft is not None
    path = view_.geometry.points
    step = path[min(3, len(path) - 1)] - path[0]
    shaft = drawn.shaft.points[0][1] - drawn.shaft.points[0][0]
    cosine = step @ shaft / np.linalg.norm(step) / np.linalg.norm(shaft)
    assert cosine > math.cos(math.radians(3.0))  # along the drawn path's start
    start = np.asarray(drawn.gizmo.position, float)
    _drag(view_, "entry_angle", [tuple(start + (20.0, 0.0, 0.0)), tuple(start + (40.0, 0.0, 0.0))])
    gamma = view_.session.values["gamma0"]
    assert values["gamma0"] < gamma < 0.0  # shallower, still descending
    sol = view_.session.latest
    assert sol.converged, sol.message
    assert sol.node_x[0, 1] == pytest.approx(gamma, abs=1e-9)
    assert view_.controls.fields["gamma0"].slider.value == pytest.approx(
        math.degrees(gamma), rel=1e-6)
    _drag(view_, "entry_angle", [tuple(start + (3000.0, -600.0, 0.0))])
    assert view_.session.values["gamma0"] == pytest.approx(math.radians(-1.0))  # range end
    assert "end of range" in drawn.label.text


def test_the_launch_windows_opening_drags_along_earths_orbit():
    """Asteroid: the opening of the launch window is a point on Earth's orbit at its date
    (ERFA's ephemeris, heliocentric ecliptic); dragged to where Earth is on another date, it
    takes that date, searching a year either side of the current one, so a point of the
    orbit a year on is the nearer date, not the first one the orbit passes; the label gives
    the date."""
    from explorer.handles import describe
    from solvers.dynamics.ephemeris import MJD_2022, earth_state

    asteroid = get_mission("asteroid-rendezvous")
    opens = next(h for h in asteroid.handles if h.key == "window_opens")
    values, view = asteroid.defaults(), asteroid.view_defaults()
    earth, _ = earth_state(MJD_2022 + 100.0)
    assert opens.where(values | {"launch_start": 100.0}, view) == pytest.approx(tuple(earth))
    moved = values_at(opens, earth, asteroid.params, view, values | {"launch_start": 80.0})
    assert moved.values["launch_start"] == pytest.approx(100.0, abs=1e-4) and not moved.held
    a_year_on = values_at(opens, earth, asteroid.params, view,
                          values | {"launch_start": 450.0})  # Earth is there again ~465.25
    assert a_year_on.values["launch_start"] == pytest.approx(465.25, abs=0.5)
    params = {p.key: p for p in asteroid.all_params(asteroid.methods[0].key)}
    assert describe(opens, values | {"launch_start": 147.0}, params) == \
        "launch window opens 2022-05-28"


def test_the_keep_out_sphere_drags_and_the_path_bends_around_it(live):
    from solvers.mission_file import load_mission_file

    mission = load_mission_file(EXAMPLES / "keep_out_rendezvous.py")
    view = live(mission)
    drawn = view.handles.drawn["keep-out"]
    assert drawn.mesh.scale == pytest.approx((800.0,) * 3) and tuple(
        drawn.gizmo.active_axes) == (True, True, False)
    # Display axes are (along-track y, radial x): the centre moves into the corner the path
    # turns, to x = 100, y = -100 m.
    _drag(view, "keep-out", [(-50.0, 50.0, 0.0), (-100.0, 100.0, 0.0)])
    values = view.session.values
    assert (values["zone_x"], values["zone_y"]) == (100.0, -100.0)
    sol = view.session.latest
    assert sol.converged, sol.message
    distance = np.hypot(sol.node_x[:, 0] - 100.0, sol.node_x[:, 1] + 100.0)
    assert distance.min() >= 800.0 * (1 - 1e-6)  # outside the moved zone at every node
    assert (distance < 800.5).sum() >= 3  # and sliding along it: the constraint is active
    origin = np.hypot(sol.node_x[:, 0], sol.node_x[:, 1])
    assert origin[5:-5].min() > 820.0  # pushed out, past the old zone's surface


def test_the_glide_slope_cone_is_drawn_at_its_angle_and_its_apex_drags_the_target(live):
    """A mission file's cone (apex bound to the target, angle to the slope slider) and fixed
    ground plane: the cone's rim is 1100 m / tan γ wide, the plane has no gizmo to grab but
    shows; dragging the apex moves the target, the path's end and the cone with it; a
    steeper slope narrows the cone."""
    from solvers.mission_file import load_mission_file

    view = live(load_mission_file(EXAMPLES / "glide_slope_landing.py"))
    cone, ground = view.handles.drawn["cone"], view.handles.drawn["ground"]
    scale = view.handles._scale
    rim = 1100.0 / math.tan(view.session.values["slope"])
    assert cone.mesh.scale == pytest.approx((scale * rim, scale * rim, scale * 1100.0))
    assert tuple(cone.gizmo.active_axes) == (True, False, False) and cone.gizmo.visible
    assert ground.mesh.visible and not ground.gizmo.visible
    _drag(view, "cone", [(scale * 30.0, 0.0, 0.0), (scale * 60.0, 0.0, 0.0)])
    assert view.session.values["target"] == pytest.approx(60.0)
    sol = view.session.latest
    assert sol.ok, sol.message
    assert sol.node_x[-1, 0] == pytest.approx(60.0) and sol.values["target"] == 60.0
    assert cone.mesh.position == pytest.approx((scale * 60.0, 0.0, 0.0))
    view.session.set_value("slope", math.radians(43.0))
    assert view.session.wait_idle(PATIENCE)
    narrow = 1100.0 / math.tan(math.radians(43.0))
    assert cone.mesh.scale[0] == pytest.approx(scale * narrow)


def test_a_handles_label_is_short_values_in_display_units():
    """The label beside a handle is its name and values (a long one covered the path)."""
    from explorer.handles import describe

    mission = get_mission("powered-descent")
    params = {p.key: p for p in mission.all_params(mission.methods[0].key)}
    handle = mission.handles[0]
    assert describe(handle, mission.defaults(), params) == "start point (2000, 0, 1500) m"
    lunar = get_mission("lunar-landing")
    lunar_params = {p.key: p for p in lunar.all_params(lunar.methods[0].key)}
    target = describe(mission.handles[1], mission.defaults(), params)
    assert target == "landing target (0, 0) m"
    text = describe(lunar.handles[0], lunar.defaults(), lunar_params, held=("altitude0",))
    assert text.startswith("ignition altitude 15 km") and "end of range" in text


class _Browser:
    """A stand-in for a watching browser: its id, a camera that takes a listener, and the
    notifications it was shown."""

    def __init__(self, client_id: int) -> None:
        self.client_id, self.notes = client_id, []
        self.camera = type("Camera", (), {"on_update": lambda _self, _cb: None})()

    def add_notification(self, title: str, body: str, **_kwargs) -> None:
        self.notes.append(title)


def test_in_shared_mode_only_the_driver_drags(live):
    """Issue 19: with every tab showing one case (--shared), only the tab that opened first
    drags; another tab's drag puts the handle back, changes nothing and tells that tab."""
    from viser import TransformControlsEvent

    view = live(get_mission("bang-bang"))
    driver, other = _Browser(1), _Browser(2)
    view.camera.cameras.clients.update({1: driver, 2: other})
    drawn = view.handles.drawn["target"]
    start = tuple(drawn.gizmo.position)

    def hand(browser, x, phase):
        drawn.gizmo.position = (x, 0.0, 0.0)
        view.handles._event(drawn, TransformControlsEvent(browser, browser.client_id,
                                                          drawn.gizmo, phase))

    for phase in ("start", "update", "end"):
        hand(other, 3.0, phase)
    assert view.session.values["distance"] == 1.0 and np.allclose(drawn.gizmo.position, start)
    assert other.notes == ["only the driver drags"] and driver.notes == []
    for phase in ("start", "update", "end"):
        hand(driver, 3.0, phase)
    assert view.session.wait_idle(PATIENCE)
    assert view.session.values["distance"] == 3.0
    assert view.session.latest.cost.value == pytest.approx(2 * math.sqrt(3.0), rel=2e-3)
    del view.camera.cameras.clients[1]  # the driver's tab closes: the next one drives
    assert view.drives(2)
