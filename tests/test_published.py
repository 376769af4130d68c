"""Every published number of every mission, checked straight from the mission records
(`Mission.published`): our solution satisfies the stated relation within the stated
tolerance, or, for a number recorded as not holding, really differs from it; and the
solution's re-propagated miss meets the mission's accuracy targets (`Mission.tolerances`).
The numbers come from the papers (each record names its source: paper, section, table or
figure)."""

from __future__ import annotations

import math

import pytest

import solvers
from solvers.problem import Published


def _cases() -> list:
    cases = []
    for mission in solvers.list_missions():
        for pub in mission.published:
            if not pub.checked:
                continue
            methods = pub.methods or tuple(m.key for m in mission.methods)
            for method in methods:
                marks = [pytest.mark.slow] if pub.slow_for(method) else []
                cases.append(pytest.param(mission.key, pub, method, marks=marks,
                                          id=f"{mission.key}-{pub.name}-{pub.value:g}-{method}"))
    return cases


def _request(mission, pub: Published, method: str) -> tuple[str, int | None, dict]:
    case = pub.case
    if case is None:
        return method, None, {}
    nodes = case.nodes if (case.method in (None, method)) else None
    return method, nodes, dict(case.values)


@pytest.mark.parametrize(("mission_key", "pub", "method"), _cases())
def test_published_number(solved, mission_key: str, pub: Published, method: str) -> None:
    mission = solvers.get_mission(mission_key)
    method, nodes, values = _request(mission, pub, method)
    sol = solved(mission_key, method, nodes, values)
    # An answer may be "inaccurate" by its cost error estimate alone (bang-bang arcs on LGL's
    # capped degree): the published number and the miss targets below still hold.
    assert sol.status == "optimal" or set(sol.misses()) == {"cost_error_estimate"}, (
        f"{mission_key}/{method}: {sol.message}")
    value = sol.value(pub.name)
    assert math.isfinite(value)
    if pub.holds:
        assert pub.agrees(value), (f"{pub.name}: ours {value!r} vs published {pub.value!r} "
                                   f"({pub.relation}, rtol {pub.rtol}, atol {pub.atol})")
    else:
        assert not pub.agrees(value), (f"{pub.name}: recorded as not holding, yet ours "
                                       f"{value!r} agrees with {pub.value!r}: {pub.note}")
    for key, tolerance in mission.tolerances.items():
        assert key in sol.check, f"{mission_key}/{method}: no re-propagated '{key}'"
        assert abs(sol.check[key]) <= tolerance, (
            f"{mission_key}/{method}: re-propagated {key} = {sol.check[key]:.3g} exceeds the "
            f"accuracy target {tolerance:g}")


def test_every_mission_states_accuracy_targets() -> None:
    for mission in solvers.list_missions():
        assert mission.tolerances, f"{mission.key} has no accuracy targets"
