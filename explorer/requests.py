"""What a session hands around: the `Request`, a snapshot of what to solve."""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from solvers.mission import Mission


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
