"""The presenter mode (issue 20) through Debian chromium: one teacher tab and three student
tabs on a `--classroom` app. The teacher link drives (and its key leaves the address bar); the
teacher moves a slider and every student shows the teacher's new optimum (the teacher's own
solution: no solve of theirs); a student's move while following branches and never changes
the teacher; rejoin and bring-everyone-back; a challenge with a student's verified optimum on
the leaderboard; no student page and no room link carries the secret."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from browser_support import BROWSER, HEIGHT, PATIENCE_MS, WIDTH, until

# In the default set: 6 runs in a row passed (alone and in full tests/explorer runs) after the
# case link's reader stopped taking the teacher's case from a student's address bar (it branched
# 1 student tab in 6 off the room, the failure these tests used to show in full runs).
pytestmark = BROWSER
pytest.importorskip("playwright.sync_api", reason="Python Playwright is not installed")

SECRET = "classroom-test-key-7Qx2"
STUDENTS = 3
THRUST = "thrust F [N]"


@pytest.fixture(scope="module")
def room() -> Iterator:
    """A classroom app, its teacher tab and three student tabs (pages and views)."""
    from explorer.app import ExplorerApp
    from explorer.capture import CAPTURE_TIME_LIMIT, chromium, close_webgl_toast, free_port

    app = ExplorerApp("127.0.0.1", free_port(), "lunar-landing", "hermite-simpson",
                      classroom=True, teacher_secret=SECRET, time_limit=CAPTURE_TIME_LIMIT)
    try:
        with chromium(WIDTH, HEIGHT) as context:
            teacher = _open(app, context, app.teacher_url)
            until(lambda: app.room.teacher is not None, "the teacher link to drive the room")
            students = [_open(app, context, f"{app.url}/") for _ in range(STUDENTS)]
            for page, _ in [teacher, *students]:
                close_webgl_toast(page, timeout=3.0)
            yield app, teacher, students
    finally:
        app.stop()


def _open(app, context, url: str):
    page = context.new_page()
    with app._lock:
        before = set(app.views)
    page.goto(url)

    def drawn_view():
        """The page's view once drawn (a page whose first connection dropped reconnects
        as a new client: its first view is closed and never draws)."""
        with app._lock:
            new = [app.views[k] for k in sorted(set(app.views) - before)]
        return next((v for v in reversed(new) if v.drawn), None)

    view = until(drawn_view, "the tab's first picture")
    return page, view


def _slider_key(page, label: str, key: str, times: int = 1) -> None:
    slider_id = page.locator("label", has_text=label).first.get_attribute("for")
    page.locator(f'[id="{slider_id}"]').get_by_role("slider").focus()
    for _ in range(times):
        page.keyboard.press(key)


def _labelled(page, label: str):
    """The input in the row of the viser label that reads exactly `label`."""
    handle = page.evaluate_handle(
        """(text) => {
          const label = [...document.querySelectorAll('label')].find(
              (l) => l.textContent.trim() === text && l.offsetParent !== null);
          let row = label, input = null;
          for (let i = 0; i < 5 && row && !input; i++) {
            row = row.parentElement;
            input = row && row.querySelector('input');
          }
          return input;
        }""", label)
    element = handle.as_element()
    assert element is not None, f"no input labelled {label!r}"
    return element


def _shows_teachers(view, teacher) -> bool:
    return view.session.latest is teacher.session.latest and view.presentation is not None \
        and view._shown[0] is teacher.session.latest


def test_the_secret_stays_with_the_teacher(room):
    app, (tpage, tview), students = room
    assert app.room.teacher.id == tview.member_id
    until(lambda: SECRET not in tpage.url, "the key to leave the teacher's address bar")
    tpage.get_by_text(f"Students open {app.url}/").first.wait_for(timeout=PATIENCE_MS)
    assert SECRET not in tpage.content()  # the room link shown is the students' one
    tpage.get_by_role("button", name="bring everyone back").wait_for(timeout=PATIENCE_MS)
    for page, view in students:
        assert SECRET not in page.content() and SECRET not in page.url
        assert app.room.members[view.member_id].state == "following"
        assert page.get_by_role("button", name="bring everyone back").count() == 0
    _the_key_stays_out_of_a_remounted_reader(tpage, tview)


def _the_key_stays_out_of_a_remounted_reader(tpage, tview) -> None:
    """The key's script runs again whenever its element is mounted again (a re-render of
    the panel): the key, already handed over on this connection, is not typed into the page
    again (the CI run of 01565b3 read it in the teacher's page after the claim)."""
    import re

    tpage.evaluate("""(secret) => {
      window.__sawSecret = false;
      document.addEventListener('input', (event) => {
        if (event.target.value === secret) window.__sawSecret = true;
      }, true);
    }""", SECRET)
    reader = tview.key.reader
    source = re.search(r'src="(data:,\d+)"', reader.content).group(1)
    image = f'img[src="{source}"]'
    reader.visible = False
    tpage.locator(image).wait_for(state="detached", timeout=PATIENCE_MS)
    reader.visible = True
    tpage.locator(image + "[data-ran]").wait_for(state="attached", timeout=PATIENCE_MS)
    assert not tpage.evaluate("window.__sawSecret")
    assert SECRET not in tpage.content()


def test_the_teacher_moves_and_every_student_shows_the_new_optimum(room):
    from explorer.panels.status import fmt

    app, (tpage, tview), students = room
    before = tview.session.latest
    _slider_key(tpage, THRUST, "ArrowRight", times=3)
    until(lambda: tview.session.wait_idle(120) and tview.session.latest is not before
          and tview.session.latest.ok, "the teacher's new optimum")
    sol = tview.session.latest
    assert sol.values["thrust"] > before.values["thrust"]
    for page, view in students:
        until(lambda v=view: _shows_teachers(v, tview), "a student drawing the teacher's optimum")
        assert view.session.values["thrust"] == sol.values["thrust"]
        page.get_by_text(fmt(sol.cost.value, sol.cost.unit)).first.wait_for(
            timeout=PATIENCE_MS)


def test_the_teacher_shares_the_camera_and_the_clock(room):
    """The teacher ticks "share my camera and clock" and turns the view with the mouse:
    every follower's camera takes the teacher's; a moved animation time follows too."""
    import numpy as np

    app, (tpage, tview), students = room
    tpage.get_by_text("share my camera and clock").first.click()
    until(lambda: app.room.sharing, "the teacher's sharing to start")
    teacher_camera = next(iter(tview.camera.clients.values())).camera
    before = np.array(teacher_camera.position)
    box = tpage.locator("canvas").first.bounding_box()
    x, y = box["x"] + 0.45 * box["width"], box["y"] + 0.35 * box["height"]
    tpage.mouse.move(x, y)
    tpage.mouse.down()
    for k in range(1, 11):
        tpage.mouse.move(x + 12 * k, y + 3 * k)
    tpage.mouse.up()
    until(lambda: not np.allclose(teacher_camera.position, before), "the teacher's camera")

    def same(view) -> bool:
        camera = next(iter(view.camera.clients.values())).camera
        return bool(np.allclose(camera.position, teacher_camera.position, rtol=1e-3)
                    and np.allclose(camera.look_at, teacher_camera.look_at, rtol=1e-3,
                                    atol=1e-6))

    for _, view in students:
        until(lambda v=view: v.session.following and same(v), "a follower's camera")
    track = tview.play.track
    tview.play.t = 0.5 * (track.t0 + track.tf)
    tview.show_time(tview.play.t, slow=True)
    for _, view in students:
        until(lambda v=view: abs(v.play.t - tview.play.t) < 1e-9, "a follower's clock")
    tpage.get_by_text("share my camera and clock").first.click()
    until(lambda: not app.room.sharing, "the sharing to stop")


def test_a_students_move_branches_and_never_changes_the_teacher(room):
    app, (tpage, tview), students = room
    page, view = students[0]
    teacher_thrust = tview.session.values["thrust"]
    _slider_key(page, THRUST, "Home")  # 10 N: too weak to land
    until(lambda: not view.session.following, "the student's move to branch")
    until(lambda: view.session.wait_idle(120) and view.session.latest is not None
          and view.session.latest.values["thrust"] == 10.0, "the student's own answer")
    assert tview.session.values["thrust"] == teacher_thrust
    assert students[1][1].session.values["thrust"] == teacher_thrust
    page.get_by_text("Exploring on your own").first.wait_for(timeout=PATIENCE_MS)

    page.get_by_role("button", name="follow the teacher again").click()
    until(lambda: view.session.following and _shows_teachers(view, tview), "the rejoin")

    for p, v in students[:2]:
        p.get_by_role("button", name="explore on my own").click()
        until(lambda v=v: not v.session.following, "explore on my own")
    tpage.get_by_role("button", name="bring everyone back").click()
    for _, v in students:
        until(lambda v=v: v.session.following and _shows_teachers(v, tview),
              "bring everyone back")


def test_a_challenge_ranks_a_students_verified_optimum(room):
    from explorer.panels.status import fmt

    app, (tpage, tview), students = room
    tpage.get_by_text("Challenge", exact=True).first.click()
    tpage.get_by_role("button", name="start challenge").wait_for(timeout=PATIENCE_MS)
    _labelled(tpage, "goal").fill("least fuel with the thrust frozen")
    box = _labelled(tpage, "thrust F")  # the freeze checkbox (the plot panel may float
    box.focus()  # over it: the keyboard ticks it, as a person tabbing through would)
    tpage.keyboard.press("Space")
    until(lambda: box.is_checked(), "the freeze box ticked")
    tpage.get_by_role("button", name="start challenge").click()
    challenge = until(lambda: app.room.challenge, "the challenge to start")
    assert set(challenge.frozen) == {"thrust"}
    page, view = students[1]
    until(lambda: not view.session.following, "the students to explore")
    _labelled(page, "your name").fill("Ada")
    until(lambda: app.room.members[view.member_id].name == "Ada", "the name")
    _slider_key(page, "initial mass [kg]", "ArrowLeft", times=2)
    until(lambda: app.room.board.ranking(), "a verified optimum on the leaderboard")
    entry = app.room.board.ranking()[0]
    assert entry.name == "Ada" and entry.solution.status == "optimal"
    assert entry.solution.values["thrust"] == challenge.frozen["thrust"]
    shown = fmt(entry.cost, entry.solution.cost.unit)
    tpage.locator("td", has_text="Ada").first.wait_for(timeout=PATIENCE_MS)
    tpage.locator("td", has_text=shown).first.wait_for(timeout=PATIENCE_MS)
    _slider_key(page, THRUST, "End")  # frozen: refused, the value stays
    page.get_by_text("the challenge freezes this").first.wait_for(timeout=PATIENCE_MS)
    assert view.session.values["thrust"] == challenge.frozen["thrust"]
    tpage.get_by_role("button", name="end challenge").click()
    until(lambda: app.room.challenge is None, "the challenge to end")


def test_a_student_who_leaves_is_dropped_and_the_teachers_tab_can_close(room):
    app, (tpage, tview), students = room
    page, view = students[2]
    page.close()
    until(lambda: view.member_id not in app.room.members, "the student to be dropped")
    case = app.room.case
    tpage.close()
    until(lambda: app.room.teacher is None, "the teacher's tab to leave")
    assert app.room.case.solve.values == case.solve.values  # the students keep the last case
    _, again = _open(app, students[0][0].context, app.teacher_url)
    until(lambda: app.room.teacher is not None and app.room.teacher.id == again.member_id,
          "the teacher link to open the room again")
