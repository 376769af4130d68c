"""A classroom tab's session (presenter mode): while it follows, the room sets its state
to the teacher's case (`Case`) and relays the teacher's events to its listeners; any change
made through it first branches it off into a private session, so nothing a student does
reaches the teacher. A challenge (`Challenge`) freezes some of its values. No viser here.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from solvers.mission import Mission
from solvers.request import SolveRequest
from solvers.solution import Solution

from .requests import Request
from .session import Session

RELAYED_WITH_SESSION = ("on_config", "on_view")  # events whose argument is the session


@dataclass(frozen=True)
class Case:
    """A snapshot of the teacher's case: what a follower's session mirrors."""

    mission: Mission
    solve: SolveRequest  # method, nodes, back end and values
    view: dict[str, float]
    preset: str | None
    last_good: Solution | None
    latest: Solution | None
    request: Request | None = None  # the newest request answered (a redraw needs it)
    checked: bool = False  # the latest solution's re-propagation check has run

    @classmethod
    def of(cls, session: Session, request: Request | None = None,
           checked: bool = False) -> Case:
        return cls(session.mission, session.case(), dict(session.view), session.preset,
                   session.last_good, session.latest, request, checked)

    def apply(self, session: Session) -> None:
        """Set `session`'s state to this case (no event, no solve)."""
        s = self.solve
        session.mission, session.method, session.nodes = self.mission, s.method, s.nodes
        session.backend, session.preset = s.backend, self.preset
        session.values, session.view = dict(s.values), dict(self.view)
        session.last_good, session.latest = self.last_good, self.latest

    def events(self) -> list[tuple[str, tuple]]:
        """The events that show this case as if it had just come: its configuration (whose
        argument, the session, each receiver fills in), its answer and, once run, its check."""
        shown: list[tuple[str, tuple]] = [("on_config", (None,))]
        if self.latest is not None:
            request = self.request or Request(0, self.mission, self.solve)
            shown.append(("on_result", (request, self.latest)))
            if self.checked:
                shown.append(("on_check", (request, self.latest)))
        return shown


@dataclass(frozen=True)
class Challenge:
    """The teacher's challenge: a goal in words, on one mission, some values frozen (SI)."""

    mission: str
    goal: str
    frozen: Mapping[str, float] = field(default_factory=dict)

    def admits(self, sol: Solution) -> bool:
        """A verified optimum (status "optimal", after its check) of this mission with every
        frozen value as frozen."""
        if sol.status != "optimal" or sol.mission != self.mission:
            return False
        if not math.isfinite(sol.cost.value):
            return False
        return all(k in sol.values and math.isclose(sol.values[k], v, rel_tol=1e-9,
                                                     abs_tol=1e-12)
                   for k, v in self.frozen.items())



class RoomSession(Session):
    """A classroom tab's session. While `following`, the room sets its state and relays
    the teacher's events to its listeners, and its own events are dropped; any change made
    through it first branches it off (`on_branch`). A challenge freezes some values
    (`frozen`) and the mission: a change to them is refused through `on_refused`."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.following = True
        self.held = True  # until the room admits it: its view's first solve is not run
        self.frozen: dict[str, float] = {}
        self.locked_mission: str | None = None
        self.on_branch: Callable[[RoomSession], None] | None = None
        self.on_refused: Callable[[str, str], None] | None = None
        self.on_shot: Callable[[Any], None] | None = None  # the teacher's camera and clock
        self._room_lock = threading.RLock()
        self._relaying = False
        super().__init__(*args, **kwargs)

    # ---- the room's side ----------------------------------------------------------------
    def relay(self, case: Case, event: str, args: tuple) -> bool:
        """Mirror `case` and hand its event to the listeners (False: no longer following)."""
        with self._room_lock:
            if not self.following:
                return False
            self._relaying = True
            try:
                case.apply(self)
                Session._emit(self, event, *((self,) if event in RELAYED_WITH_SESSION
                                             else args))
            finally:
                self._relaying = False
            return True

    def lead(self, case: Case | None) -> None:
        """Stop following: this tab drives the room. A follower first takes `case` (the
        room's): relayed events still on their way to it are no longer delivered."""
        with self._room_lock:
            self.following = False
            if case is not None:
                case.apply(self)

    def show_case(self, case: Case, room: object) -> None:
        """Hand `case` to this session's own listeners but `room` (whose followers have it
        already): a new teacher's view draws what the room shows, whatever the relay had
        delivered."""
        with self._room_lock:
            views = [listener for listener in self.listeners if listener is not room]
            for event, args in case.events():
                Session._deliver(views, event, (self,) if event in RELAYED_WITH_SESSION
                                 else args)

    def branch(self) -> None:
        """Explore on one's own from the case on screen (nothing is solved until a move)."""
        with self._room_lock:
            self._moved()

    def follow(self) -> None:
        """Follow again: the running and waiting solves are dropped; the room relays the
        case next."""
        with self._room_lock:
            self.following = True
            self._queue.drop()

    def set_challenge(self, challenge: Challenge | None) -> None:
        with self._room_lock:
            self.frozen = dict(challenge.frozen) if challenge else {}
            self.locked_mission = challenge.mission if challenge else None
            if challenge is not None and self.mission.key == challenge.mission:
                self.values.update({k: v for k, v in self.frozen.items() if k in self.values})

    # ---- hooks of Session -----------------------------------------------------------------
    def _moved(self) -> None:
        """A change made through this session: while following, it branches off first."""
        if self.following and not self._relaying:
            self.following = False
            if self.on_branch is not None:
                self.on_branch(self)

    def _own(self, change: Callable[[], Any]) -> Any:
        with self._room_lock:
            self._moved()
            return change()

    def _refuse(self, key: str, message: str) -> None:
        if self.on_refused is not None:
            self.on_refused(key, message)

    def _emit(self, event: str, *args: object) -> None:
        if self.following and not self._relaying:
            return  # a follower shows the teacher's events only
        super()._emit(event, *args)

    def _configure(self, mission: Mission, method: str | None, nodes: int | None,
                   values: Mapping[str, float]) -> None:
        super()._configure(mission, method, nodes, values)
        if mission.key == getattr(self, "locked_mission", None):
            self.values.update({k: v for k, v in self.frozen.items() if k in self.values})

    def _request(self, compare: tuple[tuple[str, int], ...], cold: bool, refine: bool = False,
               starts: int = 1) -> Request:
        with self._room_lock:
            if self.held:  # the view's first solve: the room relays the teacher's instead
                return Request(0, self.mission, self.case())
            self._moved()
            return super()._request(compare, cold, refine, starts)

    def _locked(self, mission: Mission) -> bool:
        if self.locked_mission is None or mission.key == self.locked_mission:
            return False
        self._refuse("mission", f"the challenge is on {self.locked_mission}: stay on it "
                                "until the teacher ends the challenge")
        Session._emit(self, "on_config", self)  # the dropdown shows the mission again
        return True

    def select_mission(self, mission: Mission) -> None:
        if not self._locked(mission):
            self._own(lambda: Session.select_mission(self, mission))

    def select_method(self, key: str) -> None:
        self._own(lambda: Session.select_method(self, key))

    def apply_preset(self, preset: Any) -> None:
        self._own(lambda: Session.apply_preset(self, preset))

    def restore(self, mission: Mission, method: str | None, nodes: int | None,
                values: Mapping[str, float], view: Mapping[str, float],
                backend: str | None = None) -> None:
        if not self._locked(mission):
            self._own(lambda: Session.restore(self, mission, method, nodes, values, view,
                                              backend))

    def reload_mission(self, mission: Mission) -> None:
        if not self.following:  # a follower takes the teacher's reload when it is relayed
            self._own(lambda: Session.reload_mission(self, mission))

    def set_value(self, key: str, value: float) -> None:
        if self.values.get(key) == float(value):
            return
        if key in self.frozen and self.mission.key == self.locked_mission:
            self._refuse(key, "the challenge keeps this value as the teacher set it")
            return
        self._own(lambda: Session.set_value(self, key, value))

    def set_values(self, values: Mapping[str, float]) -> None:
        moved = {k: v for k, v in values.items() if self.values.get(k) != float(v)}
        if not moved:
            return
        frozen = [k for k in moved if k in self.frozen and self.mission.key == self.locked_mission]
        if frozen:
            self._refuse(frozen[0], "the challenge keeps this value as the teacher set it")
            return
        self._own(lambda: Session.set_values(self, values))

    def set_view(self, key: str, value: float) -> None:
        if self.view.get(key) != float(value):
            self._own(lambda: Session.set_view(self, key, value))

    def set_nodes(self, nodes: int) -> None:
        if self.nodes != int(nodes):
            self._own(lambda: Session.set_nodes(self, nodes))

    def set_backend(self, backend: str) -> None:
        if self.backend != backend:
            self._own(lambda: Session.set_backend(self, backend))
