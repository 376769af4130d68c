"""The classroom's panels: every tab's Classroom folder (following or exploring, the button
that switches, a name, the challenge and its leaderboard), the teacher's Room folder (who is
connected and what they explore, bring everyone back, a student's case on the projector, the
challenge's frozen values and goal), and the hidden box that hands the teacher's key from
the page's address to the server.

The key is read from the address the page was opened with (the navigation entry, which
`history.replaceState` does not change) and removed from the address bar at once; the server
never sends it to any page. (The script runs as an image's `onerror` handler, whose scope
holds the document's own properties: `URL` there is `document.URL`, hence `window.URL`.)"""

from __future__ import annotations

import html
import json
import math
import secrets
from collections.abc import Callable
from typing import TYPE_CHECKING

import viser

from solvers.mission import Mission

from ..page_scripts import hidden_box_html
from .status import fmt
from .value_input import display_unit, shown_text

if TYPE_CHECKING:
    from ..leaderboard import Leaderboard
    from ..room import Member, Room

KEY_LABEL = "teacher key"
# Takes the key out of the address bar at once, then sends it through the hidden box.
FORGET_KEY = """
  const here = new window.URL(window.location.href);  // bare URL is document.URL here
  const nav = window.performance.getEntriesByType('navigation')[0];
  const opened = new window.URL(nav ? nav.name : here.href);
  const key = opened.searchParams.get('teacher') || here.searchParams.get('teacher');
  if (here.searchParams.has('teacher')) {
    here.searchParams.delete('teacher');
    window.history.replaceState(null, '', here.pathname + here.search + here.hash);
  }
"""


class TeacherKey:
    """The hidden box the page fills with the `teacher` key of its address; `claim(key)`
    hears the first one (the box is emptied at once). The page runs its script again
    whenever the element is mounted again, but fills the box once per connection (a token
    of this box kept in the page), so the key is never put back into the page after its
    claim; a reconnected tab, a new box, hands it over again. A tab claims once, so a
    teacher tab that another one replaced does not take the room back."""

    def __init__(self, gui: viser.GuiApi, claim: Callable[[str], None]) -> None:
        self.claimed = False
        self.box = gui.add_text(KEY_LABEL, "", order=-96)
        self.box.on_update(lambda _: self._sent(claim))
        token = json.dumps(secrets.token_hex(8))
        fill_once = (f"if (key && window.__explorerKeyBox !== {token}) "
                     f"{{ window.__explorerKeyBox = {token}; fill(key); }}")
        self.reader = gui.add_html(hidden_box_html(KEY_LABEL, fill_once, before=FORGET_KEY),
                                   order=-95)

    def _sent(self, claim: Callable[[str], None]) -> None:
        key = str(self.box.value)
        if not key:
            return
        self.box.value = ""
        if not self.claimed:
            self.claimed = True
            claim(key)


# ---- what the panels show (plain functions: the tests read them) ------------------------
def changed_values(mission: Mission, method: str, values: dict[str, float]) -> str:
    """The values that differ from the mission's defaults, in display units."""
    defaults = mission.defaults(method)
    parts = []
    for p in mission.all_params(method):
        v = values.get(p.key)
        if v is not None and v != defaults.get(p.key):
            unit = display_unit(p)
            parts.append(f"{p.label} {shown_text(p, v)}{' ' + unit if unit else ''}")
    return ", ".join(parts) or "defaults"


def cost_text(member: Member) -> str:
    s = member.session
    sol = s.latest
    if sol is None:
        return "—"
    if sol.converged and math.isfinite(sol.cost.value):
        return f"{sol.status}: {sol.cost.label} {fmt(sol.cost.value, sol.cost.unit)}"
    return sol.status


def members_html(members: list[Member]) -> str:
    """The teacher's table: each student, following or exploring, and an explorer's case
    and cost."""
    if not members:
        return "<p><i>no student connected yet</i></p>"
    rows = []
    for m in sorted(members, key=lambda m: m.id):
        s = m.session
        if s.following:
            case, cost = "", ""
        else:
            case = f"{s.mission.key} / {s.method}: " + changed_values(s.mission, s.method,
                                                                   s.values)
            cost = cost_text(m)
        rows.append(f"<tr><td>{html.escape(m.name)}</td><td>{m.state}</td>"
                    f"<td>{html.escape(case)}</td><td>{html.escape(cost)}</td></tr>")
    following = sum(m.session.following for m in members)
    head = (f"<p><b>{len(members)}</b> student{'s' * (len(members) != 1)}: {following} "
            f"following, {len(members) - following} exploring</p>")
    return (head + '<table style="font-size:0.8em;width:100%"><tr><th>student</th>'
            "<th>state</th><th>case</th><th>answer</th></tr>" + "".join(rows) + "</table>")


def board_html(board: Leaderboard | None, running: bool, shown: int = 8) -> str:
    """The challenge's goal, frozen values and the best verified optima."""
    if board is None:
        return ""
    ch = board.challenge
    frozen = ", ".join(f"{k} = {v:.6g}" for k, v in ch.frozen.items()) or "nothing"
    state = "" if running else " (ended)"
    lines = [f"<p><b>Challenge{state}:</b> {html.escape(ch.goal)}<br>"
             f"<small>{html.escape(ch.mission)}; frozen (SI): {html.escape(frozen)}; "
             "only verified optima count</small></p>"]
    ranking = board.ranking()
    if not ranking:
        lines.append("<p><i>no verified optimum yet</i></p>")
    else:
        rows = "".join(
            f"<tr><td>{i}</td><td>{html.escape(e.name)}</td>"
            f"<td>{html.escape(fmt(e.cost, e.solution.cost.unit))}</td>"
            f"<td>{html.escape(e.solution.method)}</td></tr>"
            for i, e in enumerate(ranking[:shown], 1))
        label = html.escape(ranking[0].solution.cost.label)
        lines.append('<table style="font-size:0.8em;width:100%"><tr><th>#</th><th>student</th>'
                     f"<th>{label}</th><th>method</th></tr>{rows}</table>")
    return "".join(lines)


def state_markdown(member: Member, room_url: str) -> str:
    if member.teacher:
        return (f"**You lead the room.** Students open `{room_url}`; they see your case "
                "live.")
    if member.session.following:
        return ("**Following the teacher** — moving a control here makes the case your own "
                "(the teacher's stays as it is).")
    return "**Exploring on your own** — the teacher's case is unchanged."


class ClassroomBar:
    """Every tab's Classroom folder."""

    def __init__(self, gui: viser.GuiApi, room: Room, member_id: int, room_url: str) -> None:
        self.room, self.member_id, self.room_url = room, member_id, room_url
        with gui.add_folder("Classroom", order=-5):
            self.state = gui.add_markdown("")
            self.toggle = gui.add_button("explore on my own", icon=viser.Icon.ARROW_FORK,
                                         hint="Try your own values; the teacher's case stays.")
            self.toggle.on_click(lambda _: self._toggle())
            self.name = gui.add_text("your name", "",
                                     hint="How the teacher's panel and the leaderboard "
                                          "name you.")
            self.name.on_update(lambda _: room.rename(member_id, str(self.name.value)))
            self.board = gui.add_html("")

    def _toggle(self) -> None:
        member = self.room.members.get(self.member_id)
        if member is None or member.teacher:
            return
        if member.session.following:
            self.room.branch(self.member_id)
        else:
            self.room.follow(self.member_id)
        self.refresh()

    def refresh(self) -> None:
        member = self.room.members.get(self.member_id)
        if member is None:
            return
        _set(self.state, state_markdown(member, self.room_url))
        self.toggle.visible = not member.teacher
        self.name.visible = not member.teacher
        label = "follow the teacher again" if not member.session.following \
            else "explore on my own"
        if self.toggle.label != label:
            self.toggle.label = label
        _set(self.board, board_html(self.room.board, self.room.challenge is not None))


class RoomPanel:
    """The teacher's Room folder."""

    def __init__(self, gui: viser.GuiApi, room: Room) -> None:
        self.gui, self.room = gui, room
        self.folder = gui.add_folder("Room", order=-4)
        with self.folder:
            self.table = gui.add_html("")
            back = gui.add_button("bring everyone back", icon=viser.Icon.USERS,
                                  hint="Every exploring student follows you again.")
            back.on_click(lambda _: room.bring_back())
            share = gui.add_checkbox(
                "share my camera and clock", room.sharing,
                hint="Students who follow you see the scene from your camera and the "
                     "animation at your time.")
            share.on_update(lambda _: room.set_sharing(bool(share.value)))
            self.student = gui.add_dropdown("student", ("(none exploring)",))
            project = gui.add_button("show on the projector", icon=viser.Icon.PRESENTATION,
                                     hint="Take this student's case: you and everyone "
                                          "following see it.")
            project.on_click(lambda _: self._project())
            with gui.add_folder("Challenge", expand_by_default=False):
                self.goal = gui.add_text("goal", "least fuel",
                                         hint="In words, e.g. least fuel with thrust "
                                              "≤ 2,000 N.")
                self.freeze_box = gui.add_folder("freeze")
                self.freeze: dict[str, viser.GuiCheckboxHandle] = {}
                self._frozen_for: tuple = ()
                start = gui.add_button("start challenge", icon=viser.Icon.FLAG,
                                       hint="Freeze the ticked values at yours; every "
                                            "student explores within them.")
                start.on_click(lambda _: self._start())
                end = gui.add_button("end challenge", icon=viser.Icon.FLAG_OFF)
                end.on_click(lambda _: room.end_challenge())
        self._names: dict[str, int] = {}

    def _project(self) -> None:
        member = self._names.get(str(self.student.value))
        if member is not None:
            self.room.project(member)

    def _start(self) -> None:
        keys = [k for k, box in self.freeze.items() if box.value]
        try:
            self.room.start_challenge(str(self.goal.value), keys)
        except ValueError as exc:
            self.table.content = f"<p>{html.escape(str(exc))}</p>" + self.table.content

    def _freeze_boxes(self) -> None:
        """One checkbox per parameter of the room's case (rebuilt when it changes)."""
        case = self.room.case
        if case is None:
            return
        params = tuple(p.key for p in case.mission.all_params(case.solve.method))
        key = (case.mission.key, params)
        if key == self._frozen_for:
            return
        self._frozen_for = key
        for box in self.freeze.values():
            box.remove()
        self.freeze.clear()
        with self.freeze_box:
            for p in case.mission.all_params(case.solve.method):
                self.freeze[p.key] = self.gui.add_checkbox(p.label, False)

    def refresh(self) -> None:
        students = self.room.students()
        _set(self.table, members_html(students))
        self._names = {f"{m.name} (#{m.id})": m.id for m in students}
        options = tuple(self._names) or ("(none connected)",)
        if tuple(self.student.options) != options:
            self.student.options = options
        self._freeze_boxes()

    def remove(self) -> None:
        self.folder.remove()


def _set(handle, content: str) -> None:
    """Send content only when it changed (every update is a message to the page)."""
    if handle.content != content:
        handle.content = content
