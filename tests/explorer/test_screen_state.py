"""What the screen says, without a browser (issue 16): labels with units from the mission
records, readable numbers, an unchecked optimum called "converged", refusals of bad typed
values, time limits and links that name the range and never echo a pasted page."""

from __future__ import annotations

import pytest

from explorer.link import parse_case
from explorer.panels.compare import comparison_html
from explorer.panels.status import check_line, fmt, number, result_markdown, unit_text
from explorer.panels.value_input import parse_time_limit, parse_typed
from solvers import get_mission, list_missions
from solvers.service.pool import CRASHED
from solvers.solution import COMMON_LABELS, Quantity, Solution


def _solution(**fields) -> Solution:
    base = dict(mission="lunar-landing", method="hermite-simpson", nodes=30, status="optimal",
                message="converged", cost=Quantity(270.8, "fuel", "kg"))
    return Solution(**(base | fields))


def test_a_check_is_named_by_its_label_in_a_readable_unit():
    mission = get_mission("asteroid-rendezvous")
    sol = _solution(mission=mission.key, check={"arrival_position_miss_m": 2.98e4},
                    labels=dict(mission.labels))
    assert check_line(sol) == "re-propagation check: arrival position miss 29.8 km"


@pytest.mark.parametrize("key, method", [("bang-bang", "hermite-simpson"),
                                         ("lunar-landing", "hermite-simpson")])
def test_every_name_a_solve_reports_has_a_label(key, method):
    sol = get_mission(key).solve(method=method, nodes=20)
    names = [*sol.state_names, *sol.control_names, *sol.check, *sol.stats]
    unlabelled = [n for n in names if n not in sol.labels and n not in COMMON_LABELS
                  and n not in ("x", "y", "z", "vx", "vy", "vz", "wall_s")]
    assert not unlabelled
    assert get_mission("lunar-landing").labels["v"].text == "radial speed"


@pytest.mark.parametrize("key", [m.key for m in list_missions()])
def test_every_accuracy_target_has_a_label(key):
    mission = get_mission(key)
    assert set(mission.tolerances) <= set(mission.labels)


def test_numbers_and_units_are_printed_for_people():
    assert unit_text("m^2/s^3") == "m²/s³"
    assert fmt(1.0, "m^2/s^3") == "1 m²/s³"
    assert fmt(1.12086e-26, "m") == "< 1 mm"
    assert number(1.12086e-26, 3) == "1.12×10⁻²⁶"
    html = comparison_html(get_mission("lunar-landing"),
                           [_solution(check={"altitude_m": 1.12086e-26},
                                      labels=dict(get_mission("lunar-landing").labels))],
                           [(255, 0, 0)])
    assert "1.12086e-26" not in html and "&lt; 1 mm" in html and "nowrap" in html


def test_an_optimum_before_its_check_is_only_converged():
    sol = _solution()
    unchecked = result_markdown(sol, checking=True, nodes_label="intervals")
    assert "converged · checking…" in unchecked and "**optimal**" not in unchecked
    assert "intervals 30" in unchecked  # the slider's word for the node count
    assert "**optimal**" in result_markdown(sol)


def test_a_crash_does_not_claim_an_answer_was_kept():
    sol = _solution(status="failed", message=CRASHED.format(why="killed"))
    assert "kept" not in result_markdown(sol, kept=False)
    assert "last good trajectory" in result_markdown(sol, kept=True)


def test_a_typed_value_takes_a_prefixed_unit_and_never_echoes_a_page():
    thrust = next(p for p in get_mission("lunar-landing").params if p.key == "thrust")
    assert parse_typed(thrust, "3 kN") == parse_typed(thrust, "3000 N") == 3000.0
    with pytest.raises(ValueError, match="not in N"):
        parse_typed(thrust, "3 kg")
    with pytest.raises(ValueError) as refused:
        parse_typed(thrust, "x" * 100_000)
    assert len(str(refused.value)) < 200 and "100000 characters" in str(refused.value)


@pytest.mark.parametrize("typed", ["-5", "1e999", "0.0001", "abc", ""])
def test_the_time_limit_refuses_bad_entries_with_the_range(typed):
    with pytest.raises(ValueError, match="enter a time from 0.1 to 600 s, or 0 for no limit"):
        parse_time_limit(typed)


def test_the_time_limit_takes_seconds_or_no_limit():
    assert parse_time_limit("12 s") == 12.0 and parse_time_limit("0") is None
    assert parse_time_limit("no limit") is None


def test_a_bad_link_is_refused_in_one_short_line():
    missions = {m.key: m for m in list_missions()}
    with pytest.raises(ValueError, match="not a whole number"):
        parse_case("mission=lunar-landing&nodes=%C2%B2", missions)
    with pytest.raises(ValueError, match="too long") as refused:
        parse_case("mission=lunar-landing&v.thrust=" + "9" * 100_000, missions)
    assert len(str(refused.value)) < 200
    with pytest.raises(ValueError) as refused:
        parse_case("mission=lunar-landing&v.thrust=" + "x" * 1000, missions)
    assert len(str(refused.value)) < 200
    for query in ("method=" + "y" * 1000, "v." + "x" * 1000 + "=1"):
        with pytest.raises(ValueError, match="names no") as refused:
            parse_case(f"mission=lunar-landing&{query}", missions)
        assert len(str(refused.value)) < 200
