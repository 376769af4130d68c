"""The classroom (presenter mode): the teacher drives, the students follow, branch off to
explore on their own and rejoin; a challenge freezes some parameters and ranks the students'
verified optima.

Following costs no solve: the room listens to the teacher's session and relays each of its
events, with a snapshot of the teacher's case (`Case`), to every following student's
`RoomSession`, whose view then draws the teacher's own `Solution`. While a `RoomSession`
follows, a change made through it (a slider, a button) first branches it off: it becomes a
private session starting from the teacher's case, so nothing a student does reaches the
teacher. The room's logic (`Room`, `RoomSession`, `Leaderboard`) knows no viser: tests drive
it with plain sessions; `RoomView` (room_view.py) is the View a classroom tab gets.
"""

from __future__ import annotations

import itertools
import queue
import threading
import traceback
from collections.abc import Callable
from dataclasses import dataclass

from solvers.solution import Solution

from .leaderboard import Leaderboard
from .requests import Request
from .room_session import RELAYED_WITH_SESSION, Case, Challenge, RoomSession
from .session import Session


@dataclass(frozen=True)
class Shot:
    """What a teacher shares besides the case: the camera (scene units) and the animation
    time (s)."""

    position: tuple[float, float, float]
    look_at: tuple[float, float, float]
    up: tuple[float, float, float]
    t: float


@dataclass
class Member:
    """A tab in the room."""

    id: int
    name: str
    session: RoomSession
    teacher: bool = False

    @property
    def state(self) -> str:
        if self.teacher:
            return "teacher"
        return "following" if self.session.following else "exploring"


class _Watch:
    """Hears a member's own answers (not the relayed ones): the panel shows them and a
    challenge ranks them."""

    def __init__(self, room: Room, member: Member) -> None:
        self.room, self.member = room, member

    def on_result(self, request: Request, solution: Solution) -> None:
        if not self.member.session.following:
            self.room.changed()

    def on_check(self, request: Request, solution: Solution) -> None:
        if self.member.teacher or self.member.session.following:
            return
        board = self.room.board
        if board is not None and self.room.challenge is board.challenge \
                and board.offer(self.member.id, self.member.name, solution):
            self.room.changed()


class Room:
    """The teacher's case relayed to the following members, on one thread of the room's
    own (a slow tab never holds up the teacher's session). Before any teacher connects
    the room follows a `placeholder` session (the start-up case, solved once);
    `listeners` are called (no argument) whenever the panel should be redrawn."""

    def __init__(self, placeholder: Session | None = None) -> None:
        self.members: dict[int, Member] = {}
        self.lead: Session | None = None
        self.case: Case | None = None
        self.challenge: Challenge | None = None
        self.board: Leaderboard | None = None
        self.listeners: list[Callable[[], None]] = []
        self.sharing = False  # the teacher shares the camera and the animation clock
        self.shot: Shot | None = None
        self._placeholder = placeholder
        self._request: Request | None = None
        self._checked = False
        self._lock = threading.RLock()
        self._names = itertools.count(1)
        self._queue: queue.Queue = queue.Queue()
        self._thread = threading.Thread(target=self._relay_loop, name="explorer-room",
                                        daemon=True)
        self._thread.start()
        if placeholder is not None:
            self._lead_by(placeholder)
            self.case = Case.of(placeholder)

    # ---- members ------------------------------------------------------------------------
    def join(self, member_id: int, session: RoomSession) -> Member:
        """A new tab: it follows, and is shown the current case at once."""
        with self._lock:
            member = Member(member_id, f"student {next(self._names)}", session)
            self.members[member_id] = member
            session.held = False
            session.on_branch = lambda _: self.changed()
            session.set_challenge(self.challenge)
            session.listeners.append(_Watch(self, member))
        self._catch_up([member])
        start = self._placeholder
        if start is not None and start is self.lead and not start.busy \
                and (start.latest is None or not start.latest.converged):
            start.submit()  # the start-up solve failed (workers still starting): again
        self.changed()
        return member

    def leave(self, member_id: int) -> None:
        """A tab closed or lost its connection: dropped from the room (a teacher's tab
        leaves the room without a driver: the students keep the last case)."""
        with self._lock:
            member = self.members.pop(member_id, None)
            if member is None:
                return
            if member.session is self.lead:
                self._unlead()
            if self.board is not None:
                self.board.drop(member_id)
        self.changed()

    def rename(self, member_id: int, name: str) -> None:
        name = " ".join(name.split())[:40]
        with self._lock:
            member = self.members.get(member_id)
            if member is not None and name:
                member.name = name
        self.changed()

    def students(self) -> list[Member]:
        with self._lock:
            return [m for m in self.members.values() if not m.teacher]

    @property
    def teacher(self) -> Member | None:
        with self._lock:
            return next((m for m in self.members.values() if m.teacher), None)

    # ---- the teacher --------------------------------------------------------------------
    def promote(self, member_id: int) -> Member:
        """This member drives the room from now on (an earlier teacher tab follows)."""
        with self._lock:
            member = self.members[member_id]
            old = self.teacher
            if old is member:
                return member
            if old is not None:
                old.teacher = False
            self._unlead()
            if self._placeholder is not None:
                self._placeholder.close()
                self._placeholder = None
            shown = self.case if member.session.following else None
            member.teacher = True
            member.session.set_challenge(None)
            member.session.lead(shown)
            if self.board is not None:
                self.board.drop(member_id)
            self._lead_by(member.session)
            good = member.session.latest
            # The teacher solves (warm) when nothing good is on screen, or when the check of
            # the answer shown was cut off with the start-up session (closed above): the
            # room would say "checking…" until the teacher's next move.
            solve = (good is None or not good.converged
                     or (shown is not None and not shown.checked))
            if not solve and shown is None:  # the teacher's own case becomes the room's
                self.case = Case.of(member.session, self._request, self._checked)
                self._catch_up(None)
        if shown is not None:  # its view draws the room's case (its relay may not have)
            member.session.show_case(shown, self)
        if solve:
            member.session.submit()
        if old is not None:
            self.follow(old.id)
        self.changed()
        return member

    def _lead_by(self, session: Session) -> None:
        self.lead = session
        session.listeners.append(self)

    def _unlead(self) -> None:
        if self.lead is not None:
            if self in self.lead.listeners:
                self.lead.listeners.remove(self)
            self.lead = None

    def branch(self, member_id: int) -> None:
        member = self.members.get(member_id)
        if member is not None and not member.teacher:
            member.session.branch()

    def follow(self, member_id: int) -> None:
        """The member follows the teacher again and is shown the room's case."""
        member = self.members.get(member_id)
        if member is None or member.teacher:
            return
        member.session.follow()
        self._catch_up([member])
        self.changed()

    def bring_back(self) -> None:
        """Every exploring student follows again."""
        for member in self.students():
            if not member.session.following:
                self.follow(member.id)

    def project(self, member_id: int) -> None:
        """Put a student's case on the projector: the teacher's session takes it (warm from
        the student's answer) and the room follows."""
        lead, member = self.lead, self.members.get(member_id)
        if lead is None or member is None or member.teacher:
            return
        case = Case.of(member.session)
        good = case.last_good
        if good is not None and good.mission == lead.mission.key and good.converged:
            lead.last_good = good
        c = case.solve
        lead.restore(case.mission, c.method, c.nodes, c.values, case.view, c.backend)

    # ---- the teacher's camera and clock ----------------------------------------------
    def set_sharing(self, on: bool) -> None:
        """Share the teacher's camera and animation time with the following students (or
        stop: each keeps the view it has)."""
        self.sharing = bool(on)
        if self.sharing and self.shot is not None:
            self._queue.put((None, "shot", (self.shot,), None))
        self.changed()

    def share(self, shot: Shot) -> None:
        """The teacher's camera or clock moved: followers take it (the newest one only, if
        several wait)."""
        self.shot = shot
        if self.sharing:
            self._queue.put((None, "shot", (shot,), None))

    def _show_shot(self, shot: Shot, members: list[Member]) -> None:
        for member in members:
            session = member.session
            if session.following and session.on_shot is not None:
                session.on_shot(shot)

    # ---- challenges ---------------------------------------------------------------------
    def start_challenge(self, goal: str, frozen: list[str]) -> Challenge:
        """Freeze `frozen` at the room's values on its mission; every student explores."""
        case = self.case
        if case is None:
            raise ValueError("there is no case on the projector yet")
        unknown = [k for k in frozen if k not in case.solve.values]
        if unknown:
            raise ValueError(f"{', '.join(unknown)}: not a parameter of {case.mission.key}")
        challenge = Challenge(case.mission.key, goal.strip() or "least cost",
                              {k: case.solve.values[k] for k in frozen})
        with self._lock:
            self.challenge, self.board = challenge, Leaderboard(challenge)
            for member in self.students():
                member.session.set_challenge(challenge)
                member.session.branch()
        self.changed()
        return challenge

    def end_challenge(self) -> None:
        """The challenge ends (its leaderboard stays on screen until the next one)."""
        with self._lock:
            self.challenge = None
            for member in self.students():
                member.session.set_challenge(None)
        self.changed()

    # ---- relaying -----------------------------------------------------------------------
    def changed(self) -> None:
        for listener in list(self.listeners):
            try:
                listener()
            except Exception:  # noqa: BLE001 - one broken panel must not break the room
                traceback.print_exc()

    def _heard(self, event: str, args: tuple) -> None:
        """An event of the lead: the case is snapshotted now and relayed in order."""
        with self._lock:
            if event not in RELAYED_WITH_SESSION:
                request = args[0]
                if event in ("on_result", "on_check", "on_compare", "on_error"):
                    self._request = request
                if event in ("on_submit", "on_result"):
                    self._checked = False
                elif event == "on_check":
                    self._checked = True
            if self.lead is None:
                return
            self.case = Case.of(self.lead, self._request, self._checked)
            self._queue.put((self.case, event, args, None))

    def _catch_up(self, members: list[Member] | None) -> None:
        """Show the room's case to `members` (None: every follower) as if it just came."""
        case = self.case
        if case is None:
            return
        for event, args in case.events():
            self._queue.put((case, event, args, members))

    def _relay_loop(self) -> None:
        while True:
            item = self._queue.get()
            if item is None:
                return
            case, event, args, members = item
            if event == "on_progress" and not self._queue.empty():
                continue  # a newer event is waiting: the followers skip this one
            if members is None:
                with self._lock:
                    members = [m for m in self.members.values() if not m.teacher]
            try:
                if event == "shot":  # only the newest (an older one waiting was replaced)
                    if self.sharing and args[0] is self.shot:
                        self._show_shot(args[0], members)
                    continue
                for member in members:
                    try:
                        member.session.relay(case, event, args)
                    except Exception:  # noqa: BLE001 - one tab must not stop the others
                        traceback.print_exc()
            except Exception:  # noqa: BLE001 - the room's thread must survive anything
                traceback.print_exc()

    def close(self) -> None:
        self._queue.put(None)
        if self._placeholder is not None:
            self._placeholder.close()

    # SessionListener of the lead
    def on_config(self, session: Session) -> None:
        self._heard("on_config", (session,))

    def on_view(self, session: Session) -> None:
        self._heard("on_view", (session,))

    def on_submit(self, request: Request) -> None:
        self._heard("on_submit", (request,))

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        self._heard("on_progress", (request, iteration, message))

    def on_result(self, request: Request, solution: Solution) -> None:
        self._heard("on_result", (request, solution))

    def on_check(self, request: Request, solution: Solution) -> None:
        self._heard("on_check", (request, solution))

    def on_error(self, request: Request, message: str) -> None:
        self._heard("on_error", (request, message))

    def on_compare(self, request: Request, solutions: list[Solution]) -> None:
        self._heard("on_compare", (request, solutions))
