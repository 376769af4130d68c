"""Every method of a mission agrees with the others within the tolerance the mission states
(`Mission.consistency`), at the mission's defaults: independent transcriptions and the
papers' own methods cross-check each other."""

from __future__ import annotations

import itertools

import pytest

import solvers
from solvers.problem import Consistency


def _cases() -> list:
    return [pytest.param(m.key, c, id=f"{m.key}-{c.name}")
            for m in solvers.list_missions() for c in m.consistency]


@pytest.mark.parametrize(("mission_key", "agreement"), _cases())
def test_methods_agree(solved, mission_key: str, agreement: Consistency) -> None:
    mission = solvers.get_mission(mission_key)
    methods = agreement.methods or tuple(m.key for m in mission.methods)
    values = {}
    for method in methods:
        sol = solved(mission_key, method, None, {})
        assert sol.converged, f"{mission_key}/{method}: {sol.message}"
        values[method] = sol.value(agreement.name)
    scale = max(abs(v) for v in values.values())
    for (a, va), (b, vb) in itertools.combinations(values.items(), 2):
        assert abs(va - vb) <= agreement.rtol * scale, (
            f"{mission_key}: {agreement.name} {a} {va!r} vs {b} {vb!r} (rtol {agreement.rtol})")
