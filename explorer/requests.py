"""What a session hands around: the `Request`, a snapshot of what to solve."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from solvers.mission import Mission
from solvers.request import SolveRequest


@dataclass(frozen=True)
class Request:
    """A snapshot of what to solve: `solve`, the record the runner hands on unchanged (nodes
    "auto" when refining), or the `compare` requests, one per method of a comparison.
    `mission` is the object behind `solve.mission` (a test's own mission need not be in the
    registry). `cancel` is set when a newer request supersedes this one."""

    seq: int
    mission: Mission
    solve: SolveRequest
    compare: tuple[SolveRequest, ...] = ()
    cancel: threading.Event = field(default_factory=threading.Event, compare=False)
    # A newer request came in, but this one may finish and be drawn (a slider drag shows
    # its intermediate optima); its check is skipped.
    superseded: threading.Event = field(default_factory=threading.Event, compare=False)
    # Its answer is out and only its check runs: a newer request cancels it at once (the
    # optimum is on screen; waiting for the check of a superseded answer only delays the next).
    answered: threading.Event = field(default_factory=threading.Event, compare=False)
    started: float = field(default_factory=time.monotonic, compare=False)

    @property
    def refine(self) -> bool:
        """Refine until the accuracy targets are met."""
        return self.solve.nodes == "auto"
