"""Shared fixtures: one solve per (mission, method, nodes, values) for the whole test run,
so the published-number test and each mission's tests do not solve the same case twice."""

from __future__ import annotations

import json
from collections.abc import Mapping

import pytest

import solvers
from solvers.solution import Solution

_SOLVED: dict[str, Solution] = {}


def solve_once(mission_key: str, method: str | None = None, nodes: int | None = None,
               values: Mapping[str, float] | None = None) -> Solution:
    """The checked solution of a request, solved once per test session (cold start)."""
    key = json.dumps([mission_key, method, nodes, sorted((values or {}).items())])
    if key not in _SOLVED:
        mission = solvers.get_mission(mission_key)
        _SOLVED[key] = mission.solve(dict(values or {}), method=method, nodes=nodes)
    return _SOLVED[key]


@pytest.fixture(scope="session")
def solved():
    """`solved(mission_key, method, nodes, values)`: a cached, checked solution."""
    return solve_once
