"""One solve request, the same record from the tab to the NLP: the keywords of `Mission.solve`
(same names, same meaning, same defaults) as one picklable value, and the one place that runs
it, in a worker process or in this one."""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass, field

from .context import DEFAULT_TIME_LIMIT, ProgressCallback
from .mission import Mission
from .multistart import multistart
from .solution import Solution


@dataclass(frozen=True)
class SolveRequest:
    """What to solve. `mission` is the registry key (every worker has the same registry);
    the rest are `Mission.solve`'s keywords, and `starts` > 1 asks for a multi-start solve
    (`solvers.multistart`: several cold starts, the best kept)."""

    mission: str
    method: str | None = None
    nodes: int | str | None = None  # a count, or "auto" (refine to the accuracy targets)
    backend: str | None = None
    values: Mapping[str, float] = field(default_factory=dict)
    time_limit: float | None = DEFAULT_TIME_LIMIT  # s; None or 0: none
    tol: float | None = None  # the headline accuracy target (`Mission.accuracy_targets`)
    cold: bool = False  # from the initial guess; with "auto", every refinement step too
    starts: int = 1

    def run(self, mission: Mission, *, warm: Solution | None = None,
            progress: ProgressCallback | None = None, cancel: threading.Event | None = None,
            verify: bool = True) -> Solution:
        """Solve on `mission` (the object behind `self.mission`); bad input raises
        `ValueError`, anything else is said by the solution's status."""
        if self.starts > 1:
            return multistart(mission, dict(self.values), self.method, self.nodes,
                              starts=self.starts, tol=self.tol, backend=self.backend,
                              progress=progress, cancel=cancel, time_limit=self.time_limit)
        return mission.solve(dict(self.values), self.method, self.nodes, tol=self.tol,
                             backend=self.backend, warm=warm, cold=self.cold,
                             progress=progress, cancel=cancel, time_limit=self.time_limit,
                             verify=verify)

    def unanswered(self, mission: Mission, status: str, message: str) -> Solution:
        """The answer without a trajectory for this request when its solve gives none (it
        was cancelled, its worker died or ran out of time): the validated values, the
        method's node count and the cost's label and unit; `ValueError` for bad input."""
        vals, method, nodes = mission.validate(self.values, self.method,
                                               self.nodes if isinstance(self.nodes, int)
                                               else None)
        return mission.empty(vals, method, nodes, self.backend or method.default_backend,
                             status, message)
