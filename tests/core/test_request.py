"""One solve request from the tab to the NLP (issue 18): `SolveRequest` is `Mission.solve`'s
keywords as a record, and every runner (worker, this process) runs it the same way."""

from __future__ import annotations

import dataclasses
import inspect
import threading

from solvers.mission import Mission
from solvers.registry import get_mission
from solvers.request import SolveRequest

# What a call has and a record cannot carry across a process boundary (or names the mission).
CALL_ONLY = {"self", "warm", "progress", "cancel", "verify"}
RECORD_ONLY = {"mission", "starts"}


def test_the_record_has_the_keywords_of_mission_solve_with_their_defaults():
    """Fails if `Mission.solve` gains a keyword the record lacks (the drift that left the
    in-process runner without the time limit), or a default differs."""
    solve = {k: p.default for k, p in inspect.signature(Mission.solve).parameters.items()
             if k not in CALL_ONLY}
    fields = {f.name: f for f in dataclasses.fields(SolveRequest) if f.name not in RECORD_ONLY}
    assert set(fields) == set(solve)
    for name, f in fields.items():
        default = f.default_factory() if f.default_factory is not dataclasses.MISSING \
            else f.default
        assert default == ({} if name == "values" else solve[name]), name  # None: {} there


def test_a_multistart_request_passes_on_the_time_limit_and_the_cancel():
    """The in-process runner's multi-start ignored both; a cancelled multi-start stops."""
    cancel = threading.Event()
    cancel.set()
    request = SolveRequest("hovercraft", "hermite-simpson", starts=3, time_limit=30.0)
    sol = request.run(get_mission("hovercraft"), cancel=cancel)
    assert sol.status == "cancelled", (sol.status, sol.message)
