"""What a session hands around: the `Request` (a snapshot of what to solve) and the events a
view hears (`SessionListener`)."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

from solvers.mission import Mission
from solvers.solution import Solution

if TYPE_CHECKING:
    from .session import Session


@dataclass(frozen=True)
class Request:
    """A snapshot of what to solve; `cancel` is set when a newer request supersedes it."""

    seq: int
    mission: Mission
    method: str
    nodes: int
    backend: str | None
    values: dict[str, float]
    time_limit: float | None = None
    compare: tuple[tuple[str, int], ...] = ()  # (method, nodes) pairs of a comparison
    cold: bool = False
    refine: bool = False  # nodes "auto": refine until the accuracy targets are met
    starts: int = 1  # several cold starts, keep the best
    cancel: threading.Event = field(default_factory=threading.Event, compare=False)
    # A newer request came in, but this one may finish and be drawn (a slider drag shows
    # its intermediate optima); its check is skipped.
    superseded: threading.Event = field(default_factory=threading.Event, compare=False)
    started: float = field(default_factory=time.monotonic, compare=False)


class SessionListener(Protocol):
    """What a view hears from its session; every call comes from the session's thread,
    except `on_config` and `on_view`, which come from whoever changed the state."""

    def on_config(self, session: Session) -> None:
        """Mission, method or preset changed: rebuild the controls."""

    def on_view(self, session: Session) -> None:
        """A view option changed: redraw the solution on screen (no solve)."""

    def on_submit(self, request: Request) -> None:
        """A request was queued (it supersedes every older one)."""

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        """The running solve reached `iteration`."""

    def on_result(self, request: Request, solution: Solution) -> None:
        """A solve finished (any status); `session.last_good` is already updated."""

    def on_check(self, request: Request, solution: Solution) -> None:
        """The re-propagation check of the solution just delivered has run."""

    def on_error(self, request: Request, message: str) -> None:
        """The request was rejected (bad input): nothing was solved."""

    def on_compare(self, request: Request, solutions: list[Solution]) -> None:
        """A comparison finished: one solution per method, checks already run."""
