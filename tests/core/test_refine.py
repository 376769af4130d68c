"""Mesh refinement to an accuracy target (`nodes="auto"`, `solvers.refine`) and the local
error of every interval (`Solution.interval_error`), issue 12."""

from __future__ import annotations

import numpy as np
import pytest

import solvers
from solvers.refine import next_nodes, stalled

LUNAR = solvers.get_mission("lunar-landing")
ASTEROID = solvers.get_mission("asteroid-rendezvous")


def test_auto_stays_at_the_default_mesh_when_it_meets_the_targets():
    sol = LUNAR.solve(method="hermite-simpson", nodes="auto")
    assert sol.ok and sol.nodes == 30 and len(sol.mesh) == 1
    assert abs(sol.check["altitude_m"]) <= LUNAR.tolerances["altitude_m"]


def test_auto_refines_the_lunar_touchdown_to_a_tighter_target():
    sol = LUNAR.solve(method="hermite-simpson", nodes="auto", tol=1e-3)
    assert sol.ok, sol.message
    assert sol.targets["altitude_m"] == pytest.approx(1e-3)
    assert sol.targets["speed_m_s"] == pytest.approx(1e-5)  # scaled with the headline
    assert abs(sol.check["altitude_m"]) <= 1e-3 and sol.check["speed_m_s"] <= 1e-5
    nodes = [step["nodes"] for step in sol.mesh]
    assert nodes == sorted(nodes) and len(nodes) >= 2 and nodes[-1] == sol.nodes
    assert sol.mesh[0]["worst_ratio"] > 1 >= sol.mesh[-1]["worst_ratio"]
    assert all(step["solve_s"] > 0 for step in sol.mesh)
    assert "auto nodes" in sol.message


@pytest.mark.slow  # a 400 and a 450 segment solve with their cost estimates: ~1 min
def test_asteroid_auto_nodes_reach_an_arrival_miss_under_one_kilometre():
    """With a 0.2 N engine the default 400 segments miss by more than 1 km; auto
    refinement (warm-started from the 400-segment answer) gets under it."""
    sol = ASTEROID.solve({"thrust": 0.2}, nodes="auto", tol=1e3)
    assert sol.ok, sol.message
    assert sol.check["arrival_position_miss_m"] < 1e3
    assert sol.mesh[0]["nodes"] == 400 and sol.mesh[0]["miss"] > 1e3
    assert sol.nodes <= ASTEROID.method(None).nodes[2]


def test_auto_solves_cold_reproduce_each_other():
    a = LUNAR.solve(method="multiple-shooting", nodes="auto", tol=1e-6, cold=True)
    b = LUNAR.solve(method="multiple-shooting", nodes="auto", tol=1e-6, cold=True)
    assert a.nodes == b.nodes and a.cost.value == b.cost.value


def test_refinement_stops_when_more_nodes_do_not_help():
    # The paper's method cannot land within 1 mm here: its own solver tolerance and Adams
    # steps set the floor, and refinement says so instead of running to the cap.
    sol = LUNAR.solve(method="paper", nodes="auto", tol=1e-3)
    assert sol.status == "inaccurate"
    assert "did not reduce the miss" in sol.message or "node cap" in sol.message


def test_next_node_count_follows_the_observed_order():
    steps = [{"nodes": 30.0, "worst_ratio": 16.0}]
    assert next_nodes(steps, 4.0, 1000) == 72  # 30 (2 x 16)^(1/4) = 71.3
    steps.append({"nodes": 60.0, "worst_ratio": 4.0})  # observed order 2
    assert next_nodes(steps, 4.0, 1000) == int(np.ceil(60 * min(8.0**0.5, 3.0)))
    assert next_nodes(steps, 4.0, 100) == 100
    assert stalled([{"nodes": 10.0, "worst_ratio": 5.0}, {"nodes": 20.0, "worst_ratio": 4.0}])


@pytest.mark.parametrize(("mission", "method"), [
    ("lunar-landing", "hermite-simpson"), ("cw-rendezvous", "multiple-shooting"),
    ("hovercraft", "lgl"), ("apollo-reentry", "hermite-simpson"),
    ("asteroid-rendezvous", "hermite-simpson")])
def test_interval_error_names_the_worst_interval(solved, mission, method):
    sol = solved(mission, method, None, {})
    err = sol.interval_error
    assert err is not None and len(err.t) == len(sol.node_t) - 1
    assert err.units == ("m",)  # the headline miss is a distance for every one of these
    worst = int(sol.stats["worst_interval"])
    assert sol.stats["worst_interval_error"] == pytest.approx(err.values.max())
    assert sol.node_t[worst] < sol.stats["worst_interval_t"] < sol.node_t[worst + 1]


def test_interval_error_falls_with_the_mesh():
    coarse = LUNAR.solve(method="hermite-simpson", nodes=15).interval_error.values.max()
    fine = LUNAR.solve(method="hermite-simpson", nodes=60).interval_error.values.max()
    assert fine < coarse / 100  # local error of a 4th-order method: h^5


def test_a_bad_tol_is_refused():
    with pytest.raises(ValueError, match="tol"):
        LUNAR.solve(method="hermite-simpson", nodes="auto", tol=0.0)
    with pytest.raises(ValueError, match="'auto'"):
        LUNAR.solve(method="hermite-simpson", nodes="many")
