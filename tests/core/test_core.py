"""Core contracts: parameter validation, the Solution record, the registry, verification and
the generic direct transcriptions on problems with known analytic optima."""

from __future__ import annotations

import json
import math

import casadi as ca
import numpy as np
import pytest
from core_ocps import double_integrator

import solvers
from solvers.context import SolveContext
from solvers.ocp import OCP
from solvers.problem import Param, validate_values
from solvers.solution import Quantity, Solution
from solvers.transcription.hermite_simpson import HermiteSimpson
from solvers.transcription.multiple_shooting import MultipleShooting
from solvers.verify import repropagate

PARAMS = (
    Param("mass", "mass", "kg", 10.0, 1.0, 100.0, 1.0),
    Param("kind", "kind", "", 0, 0, 2, 1, options=("a", "b", "c")),
)


def test_validation_fills_defaults_and_accepts_in_range():
    assert validate_values(PARAMS, {"mass": 50}) == {"mass": 50.0, "kind": 0.0}


@pytest.mark.parametrize(
    ("values", "fragments"),
    [
        ({"speed": 1.0}, ["unknown parameter 'speed'", "mass"]),
        ({"mass": float("nan")}, ["'mass'", "nan", "[1, 100] kg"]),
        ({"mass": float("inf")}, ["'mass'", "inf", "not finite"]),
        ({"mass": 101.0}, ["'mass'", "101", "[1, 100] kg"]),
        ({"mass": "heavy"}, ["'mass'", "heavy", "not a number"]),
        ({"kind": 1.5}, ["'kind'", "whole number"]),
        ({"kind": 3}, ["'kind'", "0=a | 1=b | 2=c"]),
    ],
)
def test_validation_messages_name_key_value_and_range(values, fragments):
    with pytest.raises(ValueError) as err:
        validate_values(PARAMS, values)
    for fragment in fragments:
        assert fragment in str(err.value)


def test_solution_json_is_strict_and_maps_nan_to_null():
    sol = Solution(
        mission="m", method="x", nodes=3, status="failed", message="no",
        cost=Quantity(float("nan"), "cost", "kg"), node_t=np.array([0.0, np.nan]),
    )
    data = json.loads(sol.to_json())
    assert data["cost"]["value"] is None
    assert data["node_t"] == [0.0, None]


def test_registry_lists_lunar_landing_and_rejects_unknown():
    from solvers.registry import import_errors

    assert import_errors() == {}
    keys = [m.key for m in solvers.list_missions()]
    assert "lunar-landing" in keys
    with pytest.raises(ValueError, match="unknown mission 'mars'"):
        solvers.get_mission("mars")


def test_every_mission_declares_a_consistent_contract():
    for mission in solvers.list_missions():
        assert mission.methods, mission.key
        for method in mission.methods:
            lo, default, hi = method.nodes
            assert lo <= default <= hi
            vals, m, n = mission.validate(None, method.key)
            assert n == default and m.key == method.key
            assert set(vals) == {p.key for p in mission.all_params(method.key)}


def test_repropagate_matches_harmonic_oscillator():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] ** 2 * x[0] + u[0])])
    w = 2.0
    t, X = repropagate(f, np.array([w]), np.array([1.0, 0.0]), lambda t, x: np.zeros(1),
                       np.linspace(0, 3, 4))
    assert np.allclose(X[:, 0], np.cos(w * t), atol=1e-9)
    assert np.allclose(X[:, 1], -w * np.sin(w * t), atol=1e-9)


@pytest.mark.parametrize("cls", [HermiteSimpson, MultipleShooting])
def test_min_energy_double_integrator_analytic_optimum(cls):
    res = cls(double_integrator(), 10).solve(np.zeros(1))
    assert res.status == "optimal"
    # Analytic: u(t) = 6 - 12 t, J = 1/2 * integral of u^2 = 6 (linear u is exact in both).
    assert res.cost == pytest.approx(6.0, rel=1e-8)
    assert np.allclose(res.U[:, 0], 6 - 12 * res.t_nodes, atol=1e-6)


@pytest.mark.parametrize("cls", [HermiteSimpson, MultipleShooting])
def test_min_time_double_integrator_and_warm_restart(cls):
    ocp = double_integrator(min_time=True)
    res = cls(ocp, 20).solve(np.zeros(1))
    # Analytic: bang-bang, T = 2. A control linear between nodes cannot switch instantly,
    # so the discrete optimum lies slightly above 2 and approaches it as the mesh refines.
    assert res.status == "optimal"
    assert 2.0 - 1e-9 <= res.T <= 2.0 * (1 + 1 / 20)
    again = cls(ocp, 20).solve(np.zeros(1), warm=res.warm)
    assert again.iterations <= 3
    assert again.T == pytest.approx(res.T, rel=1e-9)
    finer = cls(ocp, 40).solve(np.zeros(1), warm=res.warm)  # re-interpolated warm start
    assert finer.status == "optimal"
    assert 2.0 - 1e-9 <= finer.T < res.T


def test_cancelled_context_stops_the_nlp():
    import threading

    from solvers.context import Cancelled

    event = threading.Event()
    event.set()
    with pytest.raises(Cancelled):
        HermiteSimpson(double_integrator(min_time=True), 20).solve(
            np.zeros(1), ctx=SolveContext(cancel=event)
        )


def test_time_limit_reports_status_not_exception():
    mission = solvers.get_mission("lunar-landing")
    sol = mission.solve(method="hermite-simpson", nodes=150, time_limit=1e-4)
    assert sol.status == "time-limit"
    assert "time limit" in sol.message
    assert math.isnan(sol.cost.value)


def test_validation_accepts_exactly_the_documented_range():
    from hypothesis import given
    from hypothesis import strategies as st

    @given(st.floats(allow_nan=True, allow_infinity=True, width=64))
    def check(value):
        inside = math.isfinite(value) and 1.0 <= value <= 100.0
        try:
            out = validate_values(PARAMS, {"mass": value})
        except ValueError as err:
            assert not inside and "'mass'" in str(err)
        else:
            assert inside and out["mass"] == value

    check()


def test_a_failing_check_is_reported_not_raised():
    sol = Solution(mission="m", method="x", nodes=1, status="optimal", message="ok",
                   cost=Quantity(1.0, "cost", ""))

    def broken():
        raise RuntimeError("integrator blew up")

    sol.checker = broken
    check = sol.run_check()
    assert math.isnan(check["error"]) and "integrator blew up" in sol.message
    assert sol.checker is None


def test_concurrent_builds_and_solves_are_safe():
    """Explorer sessions build and solve NLPs on their own threads at the same time; CasADi
    builds are not thread-safe, so they are serialised (this crashed the process before)."""
    from concurrent.futures import ThreadPoolExecutor

    lunar = solvers.get_mission("lunar-landing")
    hover = solvers.get_mission("hovercraft")
    jobs = [(lunar, "hermite-simpson", n) for n in (41, 43, 47)]
    jobs += [(lunar, "multiple-shooting", 23), (hover, "lgl", 13), (hover, "hermite-simpson", 17)]
    with ThreadPoolExecutor(max_workers=len(jobs)) as pool:
        sols = list(pool.map(lambda job: job[0].solve(method=job[1], nodes=job[2],
                                                      verify=False), jobs))
    assert all(s.ok for s in sols), [s.message for s in sols]
    tfs = [s.quantities["tf"].value for s in sols[:4]]
    assert max(tfs) - min(tfs) < 1e-3  # the same optimum whatever ran alongside


def test_ocp_functions_follow_the_object_not_a_recycled_id():
    """A garbage-collected OCP's functions must never be served to a new OCP (an id()-keyed
    cache did that when CPython reused the address)."""
    import gc

    for _ in range(50):
        small = double_integrator(min_time=True)
        assert small.functions().f.size1_in(0) == 2
        del small
        gc.collect()
        big = OCP(
            states=("a", "b", "c"), controls=("u",), n_params=1,
            dynamics=lambda x, u, p: ca.vertcat(x[1], x[2], u[0]),
            initial_state=lambda p: ca.vertcat(0, 0, 0),
            terminal=lambda xf, p: xf, bounds=None, guess=None,
            x_scale=np.ones(3), u_scale=np.ones(1), T_scale=1.0, terminal_scale=np.ones(3),
        )
        assert big.functions().f.size1_in(0) == 3
        del big
        gc.collect()
