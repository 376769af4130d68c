"""The state box between nodes (`solvers.state_box`, issue 17): a direct method enforces
its state bounds at the nodes only; the path its control flies between them must stay in
the box too, or the answer is not `optimal`."""

from __future__ import annotations

import numpy as np

import solvers
from solvers import state_box
from solvers.solution import Quantity, Solution


def _blank() -> Solution:
    return Solution(mission="m", method="hermite-simpson", nodes=10, status="optimal",
                    message="converged", cost=Quantity(1.0, "T", "s"))


def test_excursion_is_measured_against_each_states_scale() -> None:
    t = np.linspace(0.0, 1.0, 5)
    paths = np.column_stack([np.zeros(5), [0.0, -0.02, -0.5, 0.0, 0.0]])  # (x, vx)
    lb, ub = np.array([-1.0, 0.0]), np.array([1.0, np.inf])
    sol = _blank()
    entry = state_box.check(sol, t, paths, lb, ub, np.array([1.0, 5.0]), ("x", "vx"),
                            ("m", "m/s"))
    # vx dips 0.5 m/s below 0; its tolerance is BOX_RTOL x its scale of 5 m/s.
    assert np.isclose(entry[state_box.KEY], 0.5 / (state_box.BOX_RTOL * 5.0))
    assert "vx reaches -0.5 m/s at t = 0.5" in sol.reasons[state_box.KEY]
    sol.check.update(entry)
    sol.judge()
    assert sol.status == "inaccurate"
    assert "leaves the state box" in sol.message


def test_a_path_inside_the_box_or_unbounded_passes() -> None:
    t = np.linspace(0.0, 1.0, 4)
    paths = np.column_stack([np.linspace(-1.0, 1.0, 4), np.full(4, 1e9)])
    sol = _blank()
    entry = state_box.check(sol, t, paths, np.array([-1.0, -np.inf]),
                            np.array([1.0, np.inf]), np.ones(2), ("x", "y"), ("m", "m"))
    assert entry[state_box.KEY] == 0.0 and state_box.KEY not in sol.reasons
    sol.check.update(entry)
    sol.judge()
    assert sol.status == "optimal"


def test_hovercraft_coarse_answer_that_dips_below_its_speed_bound_is_not_optimal() -> None:
    """The slow fuzz's request (a run on 2026-12-07): the Hermite–Simpson answer on 10
    intervals keeps vx >= 0 at its nodes while the path its control flies dips to about
    -0.28 m/s between them (the request needs an arc on vx = 0 at full thrust)."""
    values = dict(steering=1.0, x0=1.1926, y0=1.1926, vx0=1.1926, vy0=0.0, xf=1.5213,
                  yf=1.5213, vxf=1.1926, vyf=3.8565, accel=7.8734, alpha_guess=-1.04,
                  T_guess=3.55)
    sol = solvers.get_mission("hovercraft").solve(values, "hermite-simpson", 10)
    assert sol.status == "inaccurate", sol.message
    assert sol.check[state_box.KEY] > 10.0
    assert "vx reaches -" in sol.reasons[state_box.KEY]
    assert "leaves the state box" in sol.message


def test_every_default_stays_in_its_box() -> None:
    """The defaults of the missions with state bounds fly inside them between nodes."""
    for key, method in [("hovercraft", "hermite-simpson"), ("lunar-landing", "hermite-simpson"),
                        ("bang-bang", "hermite-simpson")]:
        sol = solvers.get_mission(key).solve({}, method)
        assert sol.status == "optimal", (key, sol.message)
        assert 0.0 <= sol.check[state_box.KEY] <= 1.0, key


def test_a_lunar_landing_that_grazes_the_surface_between_nodes_is_not_optimal() -> None:
    """A fuzz request (issue 17) whose 5480 s optimum touches the surface near t = 3380 s:
    multiple shooting on 30 intervals keeps r >= R at its nodes, but the path its control
    flies dips about 1 km underground between two of them (and spends 19 g less for it); on
    60 intervals the path stays above the surface within the tolerance (10 m)."""
    values = {"altitude0": 51349.5, "omega_source": 0.0, "omega0": 7.92665e-4,
              "apolune_altitude": 1009838.0, "mass0": 3018.1, "thrust": 1698.77,
              "exhaust_speed": 4286.5}
    mission = solvers.get_mission("lunar-landing")
    coarse = mission.solve(values, "multiple-shooting", 30, time_limit=60)
    assert coarse.status == "inaccurate" and coarse.check[state_box.KEY] > 10.0
    assert "r reaches 1.737e+06 m" in coarse.reasons[state_box.KEY]
    fine = mission.solve(values, "multiple-shooting", 60, time_limit=60)
    assert fine.ok and fine.check[state_box.KEY] <= 1.0, fine.message
    assert fine.cost.value > coarse.cost.value  # the tunnel was cheaper
