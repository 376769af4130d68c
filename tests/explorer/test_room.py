"""The classroom's logic without a browser: followers mirror the teacher's case and draw the
teacher's own solutions (no solve of their own), a follower's move branches and never reaches
the teacher, rejoin and bring-everyone-back, the teacher leaving and coming back, challenges
that freeze values and rank verified optima only."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from explorer.leaderboard import Leaderboard
from explorer.panels.room import board_html, members_html
from explorer.room import Room
from explorer.room_session import Challenge, RoomSession
from explorer.runners import LocalRunner
from explorer.session import Session
from solvers.context import SolveContext
from solvers.mission import Mission
from solvers.problem import Method, Param
from solvers.solution import Quantity, Solution


class SumMission(Mission):
    """cost = x + y; x = 7 fails; y = 9 converges but its check finds it inaccurate."""

    key = "sum"
    title = "Sum test mission"
    summary = "returns x + y as the cost"
    source = "test"
    params = (Param("x", "x", "m", 1.0, 0.0, 10.0, 0.5),
              Param("y", "y", "m", 1.0, 0.0, 10.0, 0.5))
    methods = (Method("only", "only method", "test", "adds", nodes=(2, 3, 9)),)

    def __init__(self) -> None:
        self.solved: list[dict[str, float]] = []
        self.lock = threading.Lock()

    def _solve(self, values, method, nodes, backend, warm, ctx: SolveContext) -> Solution:
        with self.lock:
            self.solved.append(dict(values))
        time.sleep(0.01)
        status = "failed" if values["x"] == 7.0 else "optimal"
        sol = Solution(mission=self.key, method=method.key, nodes=nodes, status=status,
                       message="", cost=Quantity(values["x"] + values["y"], "cost", "m"),
                       values=dict(values), t=np.array([0.0, 1.0]))
        sol.targets = {"miss_m": 1.0}
        miss = 2.0 if values["y"] == 9.0 else 0.0
        sol.checker = lambda: {"miss_m": miss}
        return sol


class Counting(LocalRunner):
    """A runner that counts the solves it starts."""

    def __init__(self) -> None:
        self.started = 0

    def start(self, mission, request, **how):
        self.started += 1
        return super().start(mission, request, **how)


class Heard:
    """A listener keeping the solutions it was shown."""

    def __init__(self) -> None:
        self.results: list[Solution] = []
        self.configs = 0

    def on_config(self, session) -> None:
        self.configs += 1

    def on_result(self, request, solution) -> None:
        self.results.append(solution)


def until(condition, what: str, timeout: float = 10.0):
    deadline = time.monotonic() + timeout
    while not (value := condition()):
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.005)
    return value


@pytest.fixture()
def room():
    mission = SumMission()
    lead = Session(mission)
    room = Room(lead)
    lead.submit()
    students = []

    def student(member_id: int) -> tuple[RoomSession, Heard]:
        session = RoomSession(mission, auto=False, runner=Counting())
        session.auto = True
        session.submit()  # a view's first solve: held, never run
        heard = Heard()
        session.listeners.append(heard)
        room.join(member_id, session)
        students.append(session)
        return session, heard

    yield mission, lead, room, student
    for s in students:
        s.close()
    room.close()
    lead.close()


def test_followers_draw_the_teachers_solution_without_solving(room):
    mission, lead, room, student = room
    (a, heard_a), (b, heard_b) = student(1), student(2)
    until(lambda: heard_a.results and heard_b.results, "the followers' first picture")
    lead.set_value("x", 3.0)
    lead.wait_idle(10)
    until(lambda: heard_a.results[-1] is lead.last_good and heard_b.results[-1]
          is lead.last_good, "the teacher's new optimum on both followers")
    assert a.runner.started == b.runner.started == 0  # one solve for the room, not per tab
    assert a.values["x"] == b.values["x"] == 3.0 and a.last_good is lead.last_good


def test_a_followers_move_branches_and_never_reaches_the_teacher(room):
    mission, lead, room, student = room
    (a, heard_a), (b, heard_b) = student(1), student(2)
    until(lambda: heard_a.results and heard_b.results, "the followers' first picture")
    a.set_value("y", 4.0)
    assert not a.following and room.members[1].state == "exploring"
    a.wait_idle(10)
    assert a.runner.started == 1 and b.runner.started == 0
    assert lead.values["y"] == 1.0 and b.values["y"] == 1.0
    until(lambda: heard_a.results[-1].values["y"] == 4.0, "the student's own answer")
    lead.set_value("x", 2.0)
    lead.wait_idle(10)
    until(lambda: heard_b.results[-1] is lead.last_good, "the follower's new picture")
    assert a.values == {"x": 1.0, "y": 4.0}  # the explorer keeps its own case

    room.follow(1)
    until(lambda: heard_a.results[-1] is lead.last_good, "the rejoined student's picture")
    assert a.following and a.values["x"] == 2.0
    a.branch()
    b.branch()
    room.bring_back()
    assert a.following and b.following


def test_the_teacher_leaves_and_comes_back(room):
    mission, lead, room, student = room
    (_, heard_a), (t, _) = student(1), student(2)
    until(lambda: heard_a.results, "the first picture")
    room.promote(2)
    assert room.lead is t and room.teacher.id == 2 and not t.following
    t.set_value("x", 5.0)
    t.wait_idle(10)
    until(lambda: heard_a.results[-1].values["x"] == 5.0, "the teacher's case on the student")
    room.leave(2)
    assert room.lead is None and room.case.solve.values["x"] == 5.0
    (c, heard_c) = student(3)  # joins while no teacher: the last case
    until(lambda: heard_c.results and heard_c.results[-1].values["x"] == 5.0,
          "the last case on a late student")
    assert [m.id for m in room.students()] == [1, 3]


def test_a_tab_that_leads_before_its_catch_up_arrives_draws_the_rooms_case(room):
    """The teacher's tab joins as a follower, is handed the room's case (configuration
    relayed, answer still on its way) and claims the room: it draws the room's answer. The
    CI run of 01565b3 had the relayed answer dropped once the tab led: the teacher's page
    stayed on "the first solve is on its way" with an optimum in its session. Drawing it
    relays nothing to the followers, who have it."""
    mission, lead, room, student = room
    _, heard_a = student(1)
    until(lambda: heard_a.results, "the first picture")
    t = RoomSession(mission, auto=False, runner=Counting())
    heard = Heard()
    t.listeners.append(heard)
    gate, relay = threading.Event(), t.relay

    def held(case, event, args):
        if event == "on_result":
            gate.wait(10.0)
        return relay(case, event, args)

    t.relay = held
    relayed, hear = [], room._heard
    room._heard = lambda event, args: (relayed.append(event), hear(event, args))
    try:
        room.join(2, t)
        until(lambda: heard.configs, "the room's case relayed to the new tab")
        room.promote(2)
        # The new teacher's view was shown the case; the followers were not sent it again.
        assert not {"on_config", "on_result", "on_check"} & set(relayed), relayed
        gate.set()
        until(lambda: heard.results, "the teacher's first picture")
        assert heard.results[-1] is room.case.latest and t.runner.started == 0
    finally:
        gate.set()
        t.close()


class SlowCheckMission(SumMission):
    """SumMission whose re-propagation check waits for `gate`."""

    def __init__(self) -> None:
        super().__init__()
        self.gate = threading.Event()

    def _solve(self, values, method, nodes, backend, warm, ctx: SolveContext) -> Solution:
        sol = super()._solve(values, method, nodes, backend, warm, ctx)
        check = sol.checker
        sol.checker = lambda: self.gate.wait(10.0) and check()
        return sol


def test_a_teacher_who_claims_during_the_start_up_check_gets_a_checked_answer():
    """The teacher's link opened while the start-up answer was being checked: the start-up
    session is closed with its check, and the whole room said "checking…" until the
    teacher's next move (seen in a screenshot of c152d8e). The teacher solves again."""
    mission = SlowCheckMission()
    start = Session(mission)
    room = Room(start)
    start.submit()
    t = RoomSession(mission, auto=False, runner=Counting())
    heard, checked = Heard(), []
    heard.on_check = lambda request, solution: checked.append(solution)
    t.listeners.append(heard)
    try:
        room.join(1, t)
        until(lambda: heard.results, "the start-up answer, its check still running")
        room.promote(1)
        mission.gate.set()
        until(lambda: checked, "a checked answer on the teacher's tab")
        assert t.runner.started == 1 and room.case.checked
    finally:
        mission.gate.set()
        t.close()
        room.close()


def test_the_teacher_puts_a_students_case_on_the_projector(room):
    mission, lead, room, student = room
    (a, heard_a), (_, heard_b) = student(1), student(2)
    until(lambda: heard_a.results and heard_b.results, "the first picture")
    a.set_value("y", 6.0)
    a.wait_idle(10)
    room.project(1)
    lead.wait_idle(10)
    assert lead.values == {"x": 1.0, "y": 6.0} and lead.last_good.values["y"] == 6.0
    until(lambda: heard_b.results[-1] is lead.last_good, "the projected case on a follower")
    assert not a.following  # the student whose case it is keeps exploring


def test_a_challenge_freezes_values_and_ranks_verified_optima(room):
    mission, lead, room, student = room
    (a, heard_a), (b, heard_b) = student(1), student(2)
    refused: list[str] = []
    a.on_refused = lambda key, message: refused.append(key)
    until(lambda: heard_a.results and heard_b.results, "the first picture")
    room.start_challenge("least x + y", ["x"])
    assert not a.following and a.frozen == {"x": 1.0}
    a.set_value("x", 0.0)  # frozen: refused, nothing solved
    a.set_values({"x": 0.0, "y": 3.0})  # a 3D handle's drag: refused as a whole
    assert refused == ["x", "x"] and a.values == {"x": 1.0, "y": 1.0}
    a.set_value("y", 9.0)  # converges, but its check finds it inaccurate: not ranked
    a.wait_idle(10)
    b.set_value("y", 2.0)
    b.wait_idle(10)
    a.set_value("y", 0.5)
    a.wait_idle(10)
    ranking = until(lambda: len(room.board.ranking()) == 2 and room.board.ranking(),
                    "two entries")
    assert [(e.member, e.cost) for e in ranking] == [(1, 1.5), (2, 3.0)]
    html = board_html(room.board, running=True)
    assert "least x + y" in html and html.index("student 1") < html.index("student 2")
    assert "exploring" in members_html(room.students())
    room.end_challenge()
    a.set_value("x", 0.0)
    assert a.values["x"] == 0.0


def test_the_leaderboard_admits_only_optimal_answers_of_the_challenge():
    board = Leaderboard(Challenge("sum", "least", {"x": 1.0}))

    def sol(status: str, x: float, cost: float, mission: str = "sum") -> Solution:
        return Solution(mission=mission, method="only", nodes=3, status=status, message="",
                        cost=Quantity(cost, "cost", "m"), values={"x": x, "y": 0.0})

    assert not board.offer(1, "a", sol("inaccurate", 1.0, 0.1))
    assert not board.offer(1, "a", sol("optimal", 2.0, 0.1))  # a frozen value moved
    assert not board.offer(1, "a", sol("optimal", 1.0, 0.1, mission="other"))
    assert board.offer(1, "a", sol("optimal", 1.0, 0.5))
    assert not board.offer(1, "a", sol("optimal", 1.0, 0.7))  # worse than a's best
    assert board.offer(2, "b", sol("optimal", 1.0, 0.2))
    assert [e.name for e in board.ranking()] == ["b", "a"]


@pytest.mark.parametrize("argv", [["--teacher-secret", "abcdefgh12"],  # without --classroom
                                  ["--classroom", "--teacher-secret", "short"],
                                  ["--classroom", "--teacher-secret", "has a space in it"],
                                  ["--classroom", "--shared"]])
def test_bad_classroom_options_are_refused(argv, capsys):
    from explorer.__main__ import main

    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    assert "error:" in capsys.readouterr().err


def test_followers_share_the_teachers_plot_figure():
    """Thirty followers once built and encoded thirty figures of each teacher answer (1.2 s
    for the last one); now the answer's figure is built once and every follower sends the
    same JSON."""
    import viser

    from explorer.capture import free_port
    from explorer.page_figures import SHARED
    from explorer.room_view import RoomView
    from explorer.view import View
    from solvers import get_mission

    mission = get_mission("lunar-landing")
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    views = []
    try:
        teacher = View(server.gui, server.scene, server.atomic, [mission], mission,
                       scene_root="/teacher")
        views.append(teacher)
        assert teacher.session.wait_idle(60.0)
        room = Room(teacher.session)
        for i in range(3):
            views.append(RoomView(server.gui, server.scene, server.atomic, [mission], mission,
                                  None, None, 5.0, None, room=room, member_id=i, room_url="",
                                  claim=lambda v, k: None, scene_root=f"/student{i}"))
        followers = views[1:]
        until(lambda: all(v.drawn for v in followers), "the followers' first picture", 60.0)
        built = SHARED.built
        teacher.session.set_value("thrust", 2500.0)
        assert teacher.session.wait_idle(60.0)
        answer = teacher.session.latest
        until(lambda: all(v._shown and v._shown[0] is answer for v in followers),
              "the teacher's answer on every follower", 60.0)
        # One figure for the room, not one per follower: the answer's, and on a slow machine
        # the previous answer dimmed while the solve ran (its progress reached the room).
        assert SHARED.built - built in (1, 2)
        for v in views:  # each answer's plots follow its picture (explorer/deferred.py)
            until(lambda v=v: not v.side.later.waiting, "the plots after the picture", 10.0)
        sent = {v.side.plot._plotly_json_str for v in views}
        assert len(sent) == 1 and '"x": [' in sent.pop()
        room.close()
    finally:
        for view in views:
            view.close()
        server.stop()


def test_followers_take_the_teachers_camera_and_clock_only_while_shared(room):
    """Issue 20: the teacher may share the camera and the animation clock; a follower
    shows them, an explorer keeps its own view, and nothing moves while sharing is off."""
    from explorer.room import Shot

    mission, lead, room, student = room
    (a, _), (b, _) = student(1), student(2)
    seen_a: list[Shot] = []
    seen_b: list[Shot] = []
    a.on_shot, b.on_shot = seen_a.append, seen_b.append
    first = Shot((1.0, 2.0, 3.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 5.0)
    room.share(first)
    b.set_value("y", 2.0)  # b explores
    room.set_sharing(True)  # the last shot goes out at once
    until(lambda: seen_a, "the shared camera on the follower")
    assert seen_a[-1] == first
    second = Shot((4.0, 5.0, 6.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), 7.5)
    room.share(second)
    until(lambda: seen_a[-1] == second, "the teacher's next camera")
    room.set_sharing(False)
    room.share(Shot((9.0, 9.0, 9.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 1.0))
    lead.set_value("x", 2.0)  # an event behind the shot: once relayed, the shot was skipped
    lead.wait_idle(10)
    until(lambda: a.values["x"] == 2.0, "the teacher's case")
    assert seen_a[-1] == second and not seen_b


def test_a_shared_camera_reaches_the_followers_while_the_teachers_solve_is_relayed(room):
    """A shot waiting behind a relayed event, with the teacher's next solve queued behind
    it, was dropped (the relay skipped a shot whenever any event waited, not only a newer
    shot): the followers kept the old camera."""
    from explorer.room import Shot

    mission, lead, room, student = room
    a, heard = student(1)
    until(lambda: heard.results, "the follower's first picture")
    seen: list[Shot] = []
    a.on_shot = seen.append
    room.set_sharing(True)
    gate, relay = threading.Event(), a.relay

    def held(case, event, args):
        gate.wait(10.0)
        relay(case, event, args)

    a.relay = held  # the relay thread now waits inside the next event
    lead.set_value("x", 3.0)
    shot = Shot((4.0, 5.0, 6.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), 7.5)
    room.share(shot)
    lead.set_value("x", 4.0)  # the teacher's next solve, queued behind the shot
    lead.wait_idle(10)
    gate.set()
    until(lambda: seen and seen[-1] == shot, "the shared camera on the follower")
    until(lambda: a.values["x"] == 4.0, "the teacher's case")


def test_the_teachers_panel_offers_a_freeze_box_per_parameter_of_the_case(room):
    """The Room folder's challenge boxes come from the room's case (a real viser GUI, no
    browser): one per parameter of the case's method, rebuilt only when the case's mission
    changes."""
    import viser

    from explorer.capture import free_port
    from explorer.panels.room import RoomPanel

    mission, lead, room, student = room
    student(1)
    until(lambda: room.case is not None and room.case.latest is not None, "the room's case")
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        panel = RoomPanel(server.gui, room)
        panel.refresh()
        assert sorted(panel.freeze) == ["x", "y"]
        boxes = dict(panel.freeze)
        panel.refresh()
        assert panel.freeze == boxes  # the same case: the same boxes
    finally:
        server.stop()
