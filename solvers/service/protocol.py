"""What crosses the process boundary between the solve service and its workers.

Messages are tuples whose first item names them (all picklable):

server -> worker: ("solve", job_id, SolveRequest, session, warm, verify, test_hook) (warm: a
                  Solution, the job id of one the worker kept for the session, or None) ·
                  ("cancel", job_id) · ("stop",) · ("reload", mission_files) ·
                  ("forget", session) (drop what is kept for it)
worker -> server: ("ready", pid) · ("ack", job_id) (a solve received, sent at once) ·
                  ("begin", job_id, Solution) (its solve starts: the time limit runs from
                  here; the empty answer, validated, the service gives if none comes) ·
                  ("progress", job_id, iteration, text) ·
                  ("result", job_id, Solution) · ("error", job_id, text) (bad input) ·
                  ("check", job_id, CheckUpdate) · ("rss", bytes) · ("retire", reason) ·
                  ("prebuilt",) (its start-up builds are done)
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..solution import Label, Quantity, Series, Solution


@dataclass
class CheckUpdate:
    """What the deferred re-propagation check adds to a solution already delivered: the
    miss, the verdict on it (status "inaccurate" when it misses a target), the local error
    of every interval and the indirect reference."""

    check: dict[str, float]
    quantities: dict[str, Quantity]
    references: dict[str, Series]
    message: str
    status: str = "optimal"
    interval_error: Series | None = None
    stats: dict[str, float] = field(default_factory=dict)
    cost: Quantity | None = None  # with its error estimate (`solvers.cost_error`)
    targets: dict[str, float] = field(default_factory=dict)
    labels: dict[str, Label] = field(default_factory=dict)

    @staticmethod
    def of(sol: Solution) -> CheckUpdate:
        return CheckUpdate(dict(sol.check), dict(sol.quantities), dict(sol.references),
                           sol.message, sol.status, sol.interval_error, dict(sol.stats),
                           sol.cost, dict(sol.targets), dict(sol.labels))

    def apply(self, sol: Solution) -> None:
        sol.check.update(self.check)
        sol.quantities.update(self.quantities)
        sol.references.update(self.references)
        sol.message = self.message
        sol.status = self.status
        sol.interval_error = self.interval_error
        sol.stats.update(self.stats)
        if self.cost is not None:
            sol.cost = self.cost
        sol.targets.update(self.targets)
        sol.labels.update(self.labels)


def light_warm(sol: Solution | None) -> Solution | None:
    """A warm-start solution without what the next solve never reads (iterate history,
    references, estimates), so less crosses the pipe."""
    if sol is None:
        return None
    copy = Solution(**{k: v for k, v in sol.__dict__.items() if k != "checker"})
    copy.history, copy.references = [], {}
    copy.costates = copy.hamiltonian = copy.switching = copy.interval_error = None
    return copy
