"""The explorer as a teacher meets it (issue 11), through Debian chromium: the camera frames
the path after a change of scale, the inertial CW view is drawn, typed values are parsed and
refused in words, the address bar restores a case in a new tab, and a solve from the initial
guess gives a convergence worth replaying."""

from __future__ import annotations

import numpy as np
from browser_support import BROWSER, HEIGHT, PATIENCE_MS, WIDTH, settled_camera, slider_key, until

pytestmark = BROWSER
CANVAS = {"x": 0.27 * WIDTH, "y": 0.0, "width": 0.73 * WIDTH, "height": 0.6 * HEIGHT}




def _solved(view, key: str | None = None) -> None:
    until(lambda: view.session.wait_idle(120) and view.session.latest is not None
           and view.session.latest.ok
           and (key is None or view.session.latest.mission == key), "an optimal answer")


def _path_box(page, view) -> tuple[float, float]:
    """Width and height of the drawn path's pixels as shares of the 3D area (the burn or
    coast colour, found by hue in a settled screenshot)."""
    from PIL import Image

    from explorer.capture import settle

    settle(page, 30.0)
    import io

    png = np.asarray(Image.open(io.BytesIO(page.screenshot(clip=CANVAS))).convert("RGB"))
    png = png.astype(int)
    mx, mn = png.max(axis=-1), png.min(axis=-1)
    vivid = (mx > 100) & (mx - mn > 0.35 * mx)
    r, g, b = png[..., 0], png[..., 1], png[..., 2]
    orange = vivid & (r > g) & (g > b) & (r - b > 120)
    cyan = vivid & (b > r) & (g > r)
    hits = np.argwhere(orange | cyan)
    if len(hits) < 50:
        return 0.0, 0.0
    (y0, x0), (y1, x1) = hits.min(axis=0), hits.max(axis=0)
    return (x1 - x0) / png.shape[1], (y1 - y0) / png.shape[0]


def _framed(page, view, share: float, case: str) -> None:
    """Wait until the drawn path spans `share` of the 3D area in width or height (the camera
    message and the software renderer may lag the solve on a loaded machine)."""
    seen: list[tuple[float, float]] = []

    def covers() -> bool:
        seen.append(_path_box(page, view))
        return max(seen[-1]) > share

    try:
        until(covers, f"{case}: the path to fill the view")
    except AssertionError:
        width, height = seen[-1]
        raise AssertionError(f"{case}: the path covers only {width:.2f} x {height:.2f} of the "
                             "view") from None


def test_the_camera_frames_the_path_when_its_scale_changes(tab):
    from solvers import get_mission

    page, view = tab()
    view.session.select_mission(get_mission("elliptic-transfer"))
    _solved(view, "elliptic-transfer")
    for x0 in (10.0, 10e3):  # 10 m, then back to 10 km
        view.session.set_value("x0", x0)
        until(lambda x=x0: view.session.wait_idle(60) and view.session.latest.values["x0"] == x
               and view.drawn, f"x0 = {x0} m drawn")
        _framed(page, view, 0.3, f"x0 = {x0} m")


def test_the_camera_stays_where_it_was_put_after_a_switch_and_a_slider_key(tab):
    """Nobody touches the camera: the pose the browser reported before a new mission's
    framing is not taken for a person's orbit (a later re-framing kept that stale direction),
    and an arrow key that steps a focused slider steps the slider only (viser's page also
    turned the camera with it: the asteroid's orbit ended off centre after three steps)."""
    from solvers import get_mission

    page, view = tab()
    _solved(view)
    view.session.select_mission(get_mission("cw-rendezvous"))
    _solved(view, "cw-rendezvous")
    cameras = view.camera.cameras
    position, look_at, _, _ = settled_camera(view)
    placed = next(iter(cameras._placed.values()))
    assert np.allclose(position, placed[0]) and np.allclose(look_at, placed[1])
    assert not cameras.user_view, "a stale camera message was taken for a person's orbit"
    before = view.session.latest
    slider_key(page, "total transfer time [s]", "ArrowRight", times=2)
    until(lambda: view.session.wait_idle(60) and view.session.latest is not before
          and view.drawn, "the stepped slider's optimum")
    position, look_at, _, _ = settled_camera(view)
    placed = next(iter(cameras._placed.values()))
    assert np.allclose(position, placed[0]) and np.allclose(look_at, placed[1]), \
        "the arrow keys turned the camera"
    assert not cameras.user_view


def test_the_inertial_cw_view_is_drawn(tab):
    from solvers import get_mission

    page, view = tab()
    view.session.select_mission(get_mission("cw-rendezvous"))
    _solved(view, "cw-rendezvous")
    drawn = view.drawn
    view.session.set_view("view", 1)  # inertial (magnified): redrawn, not re-solved
    until(lambda: view.drawn > drawn, "the inertial view")
    assert view.presentation.frame.startswith("inertial")
    _framed(page, view, 0.1, "the inertial view")


def _box_with(page, text: str):
    """The typed-value box that shows `text`."""
    handle = page.evaluate_handle(
        "(text) => [...document.querySelectorAll('input[type=text], input:not([type])')]"
        ".find((i) => i.value === text && i.offsetParent !== null)", text)
    element = handle.as_element()
    assert element is not None, f"no box shows {text!r}"
    return element


def test_typed_values_are_parsed_and_refused_in_words(tab):
    page, view = tab()
    _solved(view)
    box = _box_with(page, "2000")  # thrust F [N]
    box.scroll_into_view_if_needed()
    box.fill("1e4")
    until(lambda: view.session.values["thrust"] == 10000.0, "1e4 to be taken as 10000")
    _solved(view)
    box.fill("50000")  # the range ends at 20000 N: refused, not clamped
    page.get_by_text("outside the allowed range").first.wait_for(timeout=PATIENCE_MS)
    page.get_by_text("20000 N").first.wait_for(timeout=PATIENCE_MS)
    assert view.session.values["thrust"] == 10000.0
    until(lambda: box.input_value() == "10000", "the old value back in the box")
    box.fill("abc")
    page.get_by_text("'abc' is not a number").first.wait_for(timeout=PATIENCE_MS)
    assert view.session.values["thrust"] == 10000.0


def test_the_address_restores_the_case_in_a_new_tab(tab):
    page, view = tab()
    _solved(view)
    view.session.set_nodes(36)
    view.session.set_value("mass0", 700.0)
    address = until(lambda: (href := page.evaluate("() => location.href"))
                     and "v.mass0=700" in href and "nodes=36" in href and href, "the address")
    query = address.split("?", 1)[1]
    other_page, other = tab(query)
    until(lambda: other.session.values["mass0"] == 700.0 and other.session.nodes == 36,
           "the case restored from the link")
    # The new tab solves its default case first; the restored case is the answer after it
    # (the values are set a moment before its request is queued, so wait for its answer).
    until(lambda: other.session.wait_idle(120) and (latest := other.session.latest) is not None
           and latest.values["mass0"] == 700.0, "the restored case's answer")
    _solved(other)
    assert other.session.latest.values["mass0"] == 700.0 and other is not view


def test_a_solve_from_the_initial_guess_gives_a_convergence_to_replay(tab):
    from solvers import get_mission

    page, view = tab()
    mission = get_mission("hovercraft")
    view.session.select_mission(mission)
    _solved(view, "hovercraft")
    preset = next(p for p in mission.presets if "T0 = 5" in p.name)
    assert preset.cold
    view.session.apply_preset(preset)
    until(lambda: view.session.wait_idle(60) and view.session.latest.values["T_guess"] == 5.0,
           "the cold solve from T0 = 5")
    sol = view.session.latest
    assert sol.ok and len(sol.history) > 5 and sol.stats["iterations"] > 5
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="replay iterations").click()
    text = until(lambda: "iterate 6 of" in view.play.replay_text.content
                  and view.play.replay_text.content, "the replay past five iterates", 30.0)
    assert int(text.split(" of ")[1].split()[0]) > 5
