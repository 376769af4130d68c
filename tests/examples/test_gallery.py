"""The gallery in examples/: every published or analytic optimum a mission file records is
reached by each of its (two or more) methods within the record's tolerance, with the
re-propagated misses inside the file's accuracy targets; the keep-out example really bends
around its keep-out zone."""

from __future__ import annotations

import json
import tempfile
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from solvers.mission_file import load_mission_file
from solvers.problem import Published
from solvers.solution import Solution
from solvers.userproblem import UserMission

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FILES = sorted(p.name for p in EXAMPLES.glob("*.py"))


@cache
def mission(name: str) -> UserMission:
    return load_mission_file(EXAMPLES / name)


@cache
def _solve(name: str, method: str, values: str) -> Solution:
    return mission(name).solve(json.loads(values), method=method)


def solved(name: str, method: str, values: dict[str, float] | None = None) -> Solution:
    """A checked solution, solved once per test session."""
    return _solve(name, method, json.dumps(values or {}, sort_keys=True))


def _cases() -> list:
    cases = []
    for name in FILES:
        m = mission(name)
        assert len(m.methods) >= 2, f"{name}: a gallery example offers two methods or more"
        for pub in m.published:
            for method in pub.methods or [meth.key for meth in m.methods]:
                cases.append(pytest.param(name, pub, method,
                                          id=f"{Path(name).stem}-{pub.name}-{pub.value:.10g}-"
                                             f"{method}"))
    return cases


def test_the_gallery_has_three_classics_with_published_optima():
    with_optimum = [name for name in FILES if mission(name).published]
    assert len(with_optimum) >= 4  # the double integrator and at least three classics
    assert any(m.declaration.path for m in map(mission, FILES))  # and path constraints


@pytest.mark.parametrize(("name", "pub", "method"), _cases())
def test_published_optimum(name: str, pub: Published, method: str) -> None:
    values = dict(pub.case.values) if pub.case is not None else {}
    sol = solved(name, method, values)
    # "inaccurate" by its cost error estimate alone is allowed (issue 17: Bryson–Denham's
    # state-constrained arc at 30 nodes): the published optimum and the misses still hold.
    assert sol.ok or set(sol.misses()) == {"cost_error_estimate"}, f"{name}/{method}: {sol.message}"
    value = sol.value(pub.name)
    assert pub.agrees(value), (f"{name}/{method}: {pub.name} = {value!r}, published "
                               f"{pub.value!r} ({pub.source}; rtol {pub.rtol}, atol {pub.atol})")
    for key, tolerance in mission(name).tolerances.items():
        assert abs(sol.check[key]) <= tolerance, f"{name}/{method}: {key} = {sol.check[key]:.3g}"


@pytest.mark.parametrize("name", FILES)
def test_every_example_draws_and_plots(name: str) -> None:
    m = mission(name)
    sol = solved(name, m.methods[0].key)
    pres = m.present(sol)
    assert pres.path.shape == (len(sol.t), 3) and np.isfinite(pres.path).all()
    titles = [p.title for p in pres.plots]
    assert len(titles) == len(sol.state_names) + len(sol.control_names) + len(
        m.declaration.path)
    assert m.help.startswith(m.summary)


def test_keep_out_zone_is_respected_and_active() -> None:
    name = "keep_out_rendezvous.py"
    radius = mission(name).defaults()["keep_out"]
    costs = {}
    for method in ("hermite-simpson", "multiple-shooting"):
        sol = solved(name, method)
        assert sol.ok, sol.message
        distance = np.hypot(sol.node_x[:, 0], sol.node_x[:, 1])
        assert distance.min() >= radius * (1 - 1e-8)  # never inside at a node
        assert (distance < radius + 0.5).sum() >= 5  # slides along the sphere: an active arc
        costs[method] = sol.cost.value
    assert costs["hermite-simpson"] == pytest.approx(costs["multiple-shooting"], rel=1e-6)
    free = solved(name, "hermite-simpson", {"keep_out": 100.0})
    assert np.hypot(free.node_x[:, 0], free.node_x[:, 1]).min() < 0.6 * radius  # it would cut in
    assert free.cost.value < 0.8 * costs["hermite-simpson"]  # the detour costs effort


def test_the_obstacle_field_goes_round_every_obstacle() -> None:
    """At the defaults the straight line runs through the obstacles: the optimum clears each
    one at every node (the path constraints hold there) and pays for its detour against the
    analytic 6 d²/T³ of the straight line; dragging an obstacle (its centre a parameter)
    moves the optimum with it."""
    name = "obstacle_field.py"
    m = mission(name)
    straight = 6 * 10.0**2 / m.defaults()["duration"]**3  # analytic, obstacles aside
    costs = {}
    for method in ("hermite-simpson", "multiple-shooting"):
        sol = solved(name, method)
        assert sol.converged, sol.message
        radius = sol.values["radius"]
        for i in (1, 2, 3):
            centre = sol.values[f"o{i}_x"], sol.values[f"o{i}_y"]
            gap = np.hypot(sol.node_x[:, 0] - centre[0], sol.node_x[:, 1] - centre[1])
            assert gap.min() >= radius * (1 - 1e-6), f"{method}: inside obstacle {i}"
        assert sol.cost.value > 1.5 * straight  # it goes round: the detour costs effort
        costs[method] = sol.cost.value
    assert costs["hermite-simpson"] == pytest.approx(costs["multiple-shooting"], rel=1e-3)
    default = solved(name, "hermite-simpson")
    moved = m.solve({"o2_y": -1.5}, "hermite-simpson", warm=default)
    assert moved.converged and moved.cost.value != pytest.approx(default.cost.value, rel=1e-3)


def test_the_glide_slope_landing_rides_its_cone_and_a_start_outside_it_is_infeasible() -> None:
    """At the default 40° slope the unconstrained least-energy landing (analytic, 21° at its
    shallowest) would pass under the cone: the optimum keeps z ≥ tan γ |x − x_t| at every
    node, rides the surface on an arc and costs more than the analytic cubic. A target moved
    so that the fixed start is below the slope has no solution: `infeasible`, naming it."""
    name = "glide_slope_landing.py"
    m = mission(name)
    free = m.published[0].value  # the analytic optimum with the slope flat
    for method in ("hermite-simpson", "multiple-shooting"):
        sol = solved(name, method)
        assert sol.ok, f"{method}: {sol.message}"
        x, z = sol.node_x[:, 0], sol.node_x[:, 1]
        above = z - np.tan(sol.values["slope"]) * (np.hypot(x, 1.0) - 1.0)  # the file's ε
        assert above.min() >= -1e-6, f"{method}: under the slope by {-above.min():.3g} m"
        assert (above[z > 10.0] < 0.5).sum() >= 5, f"{method}: the cone is not active"
        assert sol.cost.value > 1.01 * free
    # The estimate is honest where the cone binds (no closed form there): against multiple
    # shooting on 300 intervals, each live default's true error is at most 3x its estimate.
    fine = m.solve({}, method="multiple-shooting", nodes=300)
    assert fine.ok, fine.message
    for method in ("hermite-simpson", "multiple-shooting"):
        sol = solved(name, method)
        assert abs(sol.cost.value - fine.cost.value) <= 3 * sol.cost.error_estimate, method
    outside = m.solve({"target": 300.0}, method="hermite-simpson")
    assert outside.status == "infeasible" and "'glide_slope'" in outside.message
    assert "fixed start" in outside.message


ORBIT_TOLERANCES = '    tolerances={"vr_miss": 1e-5, "circular_miss": 1e-5},\n'
ORBIT_RAMP = "guess=(25 * DEG, 311 * DEG)"
ORBIT_FUNCTION = "guess=lambda tau, p: (25 + 286 * tau) * DEG"


@cache
def orbit_raising_without_tolerances(guess: str = ORBIT_RAMP) -> UserMission:
    """examples/orbit_raising.py without its `tolerances`, the thrust angle guessed by
    `guess` (the file's ramp, or a function of the normalised time)."""
    text = (EXAMPLES / "orbit_raising.py").read_text(encoding="utf-8")
    assert ORBIT_TOLERANCES in text and ORBIT_RAMP in text
    text = text.replace(ORBIT_TOLERANCES, "").replace(ORBIT_RAMP, guess)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "orbit_raising_plain.py"
        path.write_text(text, encoding="utf-8")
        return load_mission_file(path)


@pytest.mark.parametrize("method", ["hermite-simpson", "multiple-shooting"])
def test_orbit_raising_without_tolerances_and_a_guess_function_reaches_its_optimum(method):
    """Issue 17, done when: a file with no `tolerances` and a rotating control seeded by a
    function of time is `optimal` at the published r(tf) = 1.525 ± 5e-4 (Bryson & Ho 1975,
    §2.7, p. 68), its misses within the targets taken from the scales (measured: r(tf) =
    1.525276 (HS, 60 nodes), 1.525277 (MS, 60))."""
    m = orbit_raising_without_tolerances(ORBIT_FUNCTION)
    assert m.tolerances == pytest.approx({"vr_miss": 2e-5, "circular_miss": 1e-5})
    assert m.warnings == ()  # φ is bounded to one turn
    sol = m.solve({}, method=method)
    assert sol.ok, sol.message
    assert abs(sol.quantities["r_final"].value - 1.525) <= 5e-4
    assert {k: sol.targets[k] for k in m.tolerances} == m.tolerances and not sol.misses()


def test_a_miss_beyond_the_default_target_is_inaccurate():
    """Issue 17: without `tolerances`, a too coarse mesh was `optimal` whatever its miss.
    Hermite–Simpson on 30 nodes converges with a final radial-speed miss of 7.6e-5 > 2e-5
    (1e-5 × the half-width 2 of vr's bounds): `inaccurate`, although its cost error
    estimate (2.3e-5) meets its own target (before: `optimal`)."""
    sol = orbit_raising_without_tolerances().solve({}, method="hermite-simpson", nodes=30)
    assert sol.status == "inaccurate", sol.message
    assert set(sol.misses()) == {"vr_miss", "circular_miss"}
    assert sol.misses()["vr_miss"][0] > 2e-5
