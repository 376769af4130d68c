"""Dragging a handle in the 3D view with the mouse (issue 19), through Debian chromium: the
mouse grabs the gizmo's arrow where the camera projects it on the canvas, moves and lets go;
the bound parameter, its slider and the link follow, and a new optimum is drawn. The cart's
check is analytic: T* = 2 sqrt(d / a) (Kirk 1970, ex. 5.3-1). The hovercraft, the CW chaser
and the keep-out sphere of a mission file are dragged the same way; a hovercraft start dragged
too close to its target (no room to brake) keeps the last optimum dimmed and names the bound."""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest
from browser_support import BROWSER, PATIENCE, settled_camera, until

from explorer.panels.value_input import to_display
from solvers import get_mission

pytestmark = BROWSER
pytest.importorskip("playwright.sync_api", reason="Python Playwright is not installed")
KEEP_OUT = Path(__file__).resolve().parents[2] / "examples" / "keep_out_rendezvous.py"
MISSION_FILES = (str(KEEP_OUT),)  # the module's app (conftest) loads this mission file

ARM = 0.6  # where along a gizmo arrow (fraction of its length) the mouse grabs it
STEPS = 12  # mouse moves of one gesture


def _projector(page, view):
    """A function from a world point to page pixels, from the client's settled camera."""
    from explorer.capture import projector

    return projector(page, *settled_camera(view))


def _drag_arrow(page, view, key: str, axis: int, delta: float, tries: int = 3) -> None:
    """Grab handle `key`'s arrow along display `axis` and drag it `delta` scene units; a
    gesture that missed the arrow (it turned the camera instead) is tried again from the
    camera it left."""
    drawn = view.handles.drawn[key]
    direction = np.eye(3)[axis]
    for _ in range(tries):
        project = _projector(page, view)
        grab = np.asarray(drawn.gizmo.position, float) + ARM * drawn.gizmo.scale * direction
        moves = view.handles.moves
        x0, y0 = project(grab)
        x1, y1 = project(grab + delta * direction)
        page.mouse.move(x0, y0)
        page.mouse.down()
        for k in range(1, STEPS + 1):
            page.mouse.move(x0 + (x1 - x0) * k / STEPS, y0 + (y1 - y0) * k / STEPS)
        page.mouse.up()
        deadline = time.monotonic() + 10.0
        while view.handles.moves == moves and time.monotonic() < deadline:
            time.sleep(0.05)
        if view.handles.moves > moves:
            until(lambda: not drawn.dragging, f"the release of '{key}'")
            assert view.session.wait_idle(PATIENCE)
            return
    raise AssertionError(f"{tries} mouse gestures did not grab handle '{key}'")


def _on(tab, mission_key: str):
    page, view = tab()
    view.session.select_mission(get_mission(mission_key))
    until(lambda: view.session.wait_idle(PATIENCE) and view.geometry is not None
          and view.session.latest.mission == mission_key, f"the {mission_key} drawing")
    return page, view


def test_dragging_the_carts_target_with_the_mouse_moves_the_distance_and_the_optimum(tab):
    page, view = _on(tab, "bang-bang")
    drawn_before = view.drawn
    _drag_arrow(page, view, "target", axis=0, delta=1.5)  # from d = 1 m towards 2.5 m
    distance = view.session.values["distance"]
    assert distance == pytest.approx(2.5, rel=0.25) and distance != 1.0
    assert view.controls.fields["distance"].slider.value == pytest.approx(distance)
    until(lambda: f"v.distance={distance:.12g}" in view.link.writer.content, "the link")
    sol = view.session.latest
    assert sol.converged and sol.values["distance"] == distance and view.drawn > drawn_before
    assert sol.cost.value == pytest.approx(2 * math.sqrt(distance), rel=2e-3)  # Kirk 1970


def _drag_and_check(tab, mission_key: str, key: str, axis: int, arms: float) -> str:
    """Drag handle `key` of a mission `arms` gizmo lengths along display `axis`; assert the
    handle stays where the hand left it, its bound parameter moved that way, the slider and
    the link show the new value, and the optimum drawn is solved for it. The parameter."""
    page, view = _on(tab, mission_key)
    drawn = view.handles.drawn[key]
    param = drawn.handle.axes[axis].param
    before, drawn_before = view.session.values[param], view.drawn
    start = float(drawn.gizmo.position[axis])
    delta = arms * float(drawn.gizmo.scale)
    _drag_arrow(page, view, key, axis=axis, delta=delta)
    value = view.session.values[param]
    assert (value - before) * delta > 0, f"{param} did not move with the hand"
    assert float(drawn.gizmo.position[axis]) - start == pytest.approx(delta, rel=0.35)
    p = next(p for p in view.session.mission.all_params(view.session.method) if p.key == param)
    assert view.controls.fields[param].slider.value == pytest.approx(to_display(p, value))
    until(lambda: f"v.{param}={value:.12g}" in view.link.writer.content, "the link")
    sol = view.session.latest
    assert sol.converged and sol.values[param] == value and view.drawn > drawn_before
    return param


def test_dragging_the_hovercrafts_target_moves_yf_and_the_optimum(tab):
    assert _drag_and_check(tab, "hovercraft", "target", axis=1, arms=1.5) == "yf"


def test_dragging_the_cw_chaser_start_moves_x0_and_the_optimum(tab):
    assert _drag_and_check(tab, "cw-rendezvous", "start", axis=0, arms=1.5) == "x0"


def test_dragging_the_keep_out_sphere_of_a_mission_file_moves_its_centre(tab):
    assert _drag_and_check(tab, "keep-out-rendezvous", "keep-out", axis=0, arms=1.0) == "zone_y"


def test_a_drag_with_no_room_to_brake_names_the_bound_and_dims_the_last_optimum(tab):
    """From x0 = 0 at vx0 = 5 m/s to xf = 5 m at rest, A/m = 3 m/s² needs vx0² / (2 A/m) =
    4.17 m of forward travel (vx ≥ 0); a start dragged 2 m forward leaves only 3 m."""
    page, view = _on(tab, "hovercraft")
    drawn = view.handles.drawn["start"]
    _drag_arrow(page, view, "start", axis=0, delta=2.0)
    x0 = view.session.values["x0"]
    assert 5.0 - x0 < 25 / 6, f"x0 = {x0} m leaves room to brake"
    assert view.session.latest.status == "infeasible"
    page.get_by_text("remain between x0 and xf").first.wait_for(timeout=PATIENCE * 1e3)
    page.get_by_text("last good trajectory (dimmed)").first.wait_for(timeout=PATIENCE * 1e3)
    # The last good optimum: one solved on the way (intermediate optima show), with room.
    good = view.session.last_good.values["x0"]
    assert 0.0 <= good < x0 and 5.0 - good >= 25 / 6
    assert float(drawn.gizmo.position[0]) == pytest.approx(x0)  # drawn 1:1, where it was let go
