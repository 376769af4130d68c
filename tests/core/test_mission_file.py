"""Mission files: a declared problem loads, solves with the general methods, draws and plots
with no view code, reports its final misses; a broken file is one line naming the file and
line; the command line lists, solves and sweeps it."""

from __future__ import annotations

import json
import math
import pickle
import re
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from solvers.mission_file import MissionFileError, load_mission_file
from solvers.registry import (
    get_mission,
    load_mission_files,
    mission_file_of,
    register,
    unregister,
)
from solvers.service.worker import _load_quietly
from solvers.userproblem import (
    Control,
    DeclarationError,
    FinalConstraint,
    FreeTime,
    State,
    UserMission,
)

ROOT = Path(__file__).resolve().parents[2]
DOUBLE_INTEGRATOR = ROOT / "examples" / "double_integrator.py"

GOOD = '''\
from solvers.userproblem import Control, FreeTime, State, UserMission

MISSION = UserMission(
    key="tiny",
    title="Tiny minimum-time hop",
    states=(State("x", "m", bounds=(-10, 10), initial=0.0, final=1.0),
            State("v", "m/s", bounds=(-10, 10), initial=0.0, final=0.0)),
    controls=(Control("a", "m/s²", bounds=(-1, 1)),),
    dynamics=lambda x, u, p: [x.v, u.a],
    final_time=FreeTime(2.0),
    minimum_time=True,
)
'''


def _file(tmp_path: Path, text: str, name: str = "problem.py") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _error(path: Path) -> str:
    with pytest.raises(MissionFileError) as info:
        load_mission_file(path)
    message = str(info.value)
    assert "\n" not in message
    return message


def _line_of(path: Path, fragment: str) -> int:
    lines = path.read_text(encoding="utf-8").splitlines()
    return next(i for i, line in enumerate(lines, 1) if fragment in line)


# ---- broken files: one line, file and line ---------------------------------------------------
def test_syntax_error_names_file_and_line(tmp_path):
    path = _file(tmp_path, GOOD.replace("minimum_time=True,\n)", "minimum_time=True,\n))"))
    line = next(i for i, text in enumerate(path.read_text().splitlines(), 1) if text == "))")
    assert _error(path).startswith(f"{path}:{line}: SyntaxError")


def test_dynamics_of_the_wrong_size_name_their_line(tmp_path):
    path = _file(tmp_path, GOOD.replace("[x.v, u.a]", "[x.v, u.a, 0.0]"))
    assert _error(path) == (f"{path}:{_line_of(path, 'dynamics=')}: dynamics returns 3 values "
                            "for 2 states (x, v)")


def test_an_unknown_state_name_points_at_the_line_that_uses_it(tmp_path):
    text = GOOD.replace("dynamics=lambda x, u, p: [x.v, u.a],", "dynamics=rhs,").replace(
        "MISSION =", "def rhs(x, u, p):\n    accel = u.a\n    return [x.vel, accel]\n\n\n"
                     "MISSION =")
    path = _file(tmp_path, text)
    assert _error(path) == (f"{path}:{_line_of(path, 'x.vel')}: dynamics: unknown state 'vel' "
                            "(states: x, v)")


def test_a_bound_that_excludes_the_initial_state_names_the_state(tmp_path):
    path = _file(tmp_path, GOOD.replace('bounds=(-10, 10), initial=0.0, final=1.0',
                                        'bounds=(0.5, 10), initial=0.0, final=1.0'))
    line = _line_of(path, 'State("x"')
    assert _error(path) == (f"{path}:{line}: state 'x': initial value 0 is outside its bounds "
                            "[0.5, 10]")


def test_a_function_that_fails_is_reported_at_its_line(tmp_path):
    path = _file(tmp_path, GOOD.replace("[x.v, u.a]", "[x.v, u.a + gain]"))
    assert _error(path) == (f"{path}:{_line_of(path, 'dynamics=')}: dynamics: NameError: name "
                            "'gain' is not defined")


def test_dynamics_that_are_not_finite_at_the_guess(tmp_path):
    path = _file(tmp_path, GOOD.replace("[x.v, u.a]", "[x.v, u.a / x.x]"))
    assert _error(path).startswith(f"{path}:{_line_of(path, 'dynamics=')}: dynamics is not "
                                   "finite (v = nan) at the start of the cold-start guess")


def test_a_misspelt_field_is_named_at_its_own_line(tmp_path):
    """Issue 16: reported at the line of `UserMission(`; now at the keyword, with the field
    it resembles."""
    path = _file(tmp_path, GOOD.replace("minimum_time=True,",
                                        'minimum_time=True,\n    posiiton=("x", "v"),'))
    assert _error(path) == (f"{path}:{_line_of(path, 'posiiton=')}: TypeError: "
                            "UserMission.__init__() got an unexpected keyword argument "
                            "'posiiton' (did you mean 'position'?)")


@pytest.mark.parametrize(("old", "new", "fault", "message"), [
    ("initial=0.0, final=1.0),", "initial=0.0, final=1.0,", 'State("x"',
     "'(' was never closed"),
    ("    minimum_time=True,", "    minimum_time==True,", "minimum_time==",
     "positional argument follows keyword argument"),
])
def test_a_syntax_error_inside_the_call_is_named_at_its_line(tmp_path, old, new, fault,
                                                             message):
    """Python names the `UserMission(` line for the unclosed State( and the call's closing
    bracket for the `==`: each is reported at the line of the mistake."""
    path = _file(tmp_path, GOOD.replace(old, new))
    assert _error(path) == f"{path}:{_line_of(path, fault)}: SyntaxError: {message}"


def test_a_bad_tolerances_key_is_named_at_its_line(tmp_path):
    path = _file(tmp_path, GOOD.replace("minimum_time=True,", "minimum_time=True,\n"
                                        '    tolerances={\n        "x_miss_m": 1e-6,\n'
                                        '        "speed": 1e-3},'))
    line = _line_of(path, '"speed"')
    assert _error(path).startswith(f"{path}:{line}: tolerances: 'speed' is not a "
                                   "re-propagated miss")


@pytest.mark.parametrize(("module", "call"), [("math", "math.exp(-x.x)"),
                                              ("math", "math.sqrt(x.x + 1)")])
def test_math_on_a_symbol_says_to_use_casadi(tmp_path, module, call):
    """math's functions turn a CasADi symbol into NaN: the message says which call, where,
    and what to use instead (not "not finite at the cold-start guess")."""
    text = f"import {module}\n" + GOOD.replace(
        "minimum_time=True,", f"lagrange=lambda x, u, p: u.a ** 2 *\n        {call},")
    path = _file(tmp_path, text)
    name = call.split("(")[0]
    message = _error(path)
    assert message.startswith(f"{path}:{_line_of(path, call)}: lagrange is not finite")
    assert f"{name} computes with numbers" in message
    assert f"ca.{name.split('.')[1]}" in message and "cold-start" not in message


def test_a_position_function_that_gives_nan_is_refused_at_load(tmp_path):
    path = _file(tmp_path, GOOD.replace(
        "minimum_time=True,",
        'minimum_time=True,\n    position=lambda x, p: (x.x, float("nan") * x.v, 0.0),'))
    assert _error(path).startswith(f"{path}:{_line_of(path, 'position=')}: position is not "
                                   "finite ([0, nan, 0])")


def test_a_file_without_mission_and_an_error_at_run_time(tmp_path):
    assert "defines no MISSION" in _error(_file(tmp_path, "X = 1\n"))
    path = _file(tmp_path, "import math\n\nVALUE = math.sqrt(-1)\n", "runtime.py")
    assert _error(path) == f"{path}:3: ValueError: math domain error"


def test_a_declaration_made_in_python_names_the_callers_line():
    with pytest.raises(DeclarationError) as info:
        UserMission(key="no-cost", title="t", states=(State("x", initial=0.0),),
                    controls=(Control("u"),), dynamics=lambda x, u, p: [u.u],
                    final_time=1.0)
    assert str(info.value).startswith(f"{__file__}:")
    assert str(info.value).endswith("no cost: give mayer, lagrange or minimum_time=True")


@pytest.mark.parametrize(("change", "expected"), [
    ({"published": "bogus"}, "published 'bogus' is not reported by this mission"),
    ({"tolerances": "x_m"}, "tolerances: 'x_m' is not a re-propagated miss (misses: x_miss)"),
    ({"key": "Tiny Key"}, "key 'Tiny Key': use lower-case letters"),
    ({"position": "z"}, "position: unknown state 'z' (states: x)"),
])
def test_records_that_name_nothing_are_refused(change, expected):
    from solvers.problem import Published

    kwargs = dict(key="tiny", title="t", states=(State("x", initial=0.0, final=1.0),),
                  controls=(Control("u", bounds=(-1, 1)),), dynamics=lambda x, u, p: [u.u],
                  final_time=FreeTime(2.0), minimum_time=True)
    if "published" in change:
        kwargs["published"] = (Published(change["published"], 1.0, "", "nowhere"),)
    if "tolerances" in change:
        kwargs["tolerances"] = {change["tolerances"]: 1e-6}
    if "key" in change:
        kwargs["key"] = change["key"]
    if "position" in change:
        kwargs["position"] = (change["position"],)
    with pytest.raises(DeclarationError, match=expected.replace("(", r"\(").replace(")", r"\)")):
        UserMission(**kwargs)


@pytest.mark.parametrize(("guess", "expected"), [
    ((0.0, 2.0), "guess 2 is outside its bounds [-1, 1]"),
    ((0.0, float("nan")), "guess must be a finite number or a pair (start, end)"),
    ((0.0, 0.5, 1.0), "guess must be a finite number or a pair (start, end)"),
])
def test_a_bad_control_guess_is_refused_at_its_line(guess, expected):
    with pytest.raises(DeclarationError, match=re.escape(expected)):
        UserMission(key="tiny", title="t", states=(State("x", initial=0.0, final=1.0),),
                    controls=(Control("u", bounds=(-1, 1), guess=guess),),
                    dynamics=lambda x, u, p: [u.u], final_time=FreeTime(2.0),
                    minimum_time=True)


def test_a_control_guess_pair_is_a_ramp_from_the_first_to_the_last_node():
    """Issue 17: a control could only be guessed as a constant, so a thrust angle that turns
    through the flight (orbit raising: 25 deg -> 311 deg) could not be seeded. The cold
    start of every direct method interpolates linearly in time between the pair."""
    from solvers.transcription import direct_transcription

    m = UserMission(key="ramp", title="t", states=(State("x", initial=0.0, final=1.0),),
                    controls=(Control("u", bounds=(-1, 1), guess=[-0.5, 0.75]),),
                    dynamics=lambda x, u, p: [u.u], final_time=2.0,
                    lagrange=lambda x, u, p: u.u**2)
    values = m.defaults("hermite-simpson")
    p = m.parameter_vector(values)
    for kind in ("hermite-simpson", "multiple-shooting", "lgl"):
        t = direct_transcription(kind, m.ocp(m.method(kind), values), 8)
        U = t._unpack(t._cold_guess(p, t.tau), p)[1]
        np.testing.assert_allclose(np.ravel(U), -0.5 + 1.25 * t.tau, atol=1e-12)


def _cold_start(mission: UserMission, kind: str, nodes: int = 8
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(tau, X, U) of a direct method's cold start at the mission's defaults."""
    from solvers.transcription import direct_transcription

    values = mission.defaults(kind)
    p = mission.parameter_vector(values)
    t = direct_transcription(kind, mission.ocp(mission.method(kind), values), nodes)
    X, U = t._unpack(t._cold_guess(p, t.tau), p)[:2]
    return t.tau, X, U


def test_a_guess_function_of_time_seeds_every_direct_method():
    """Issue 17: a guess could be a number or a control's ramp only. `guess=lambda tau, p:`
    gives a state or a control as a function of the normalised time, the parameters by name;
    every direct method samples it on its own cold-start grid."""
    from solvers.userproblem import Param

    m = UserMission(key="bump", title="t",
                    params=(Param("height", "height", "m", 0.5, 0.1, 1.0, 0.1),),
                    states=(State("x", "m", bounds=(-2, 2), initial=0.0, final=0.0,
                                  guess=lambda tau, p: p.height * math.sin(math.pi * tau)),),
                    controls=(Control("u", "m/s", bounds=(-5, 5),
                                      guess=lambda tau, p: p.height * math.pi
                                      * math.cos(math.pi * tau)),),
                    dynamics=lambda x, u, p: [u.u], final_time=1.0,
                    lagrange=lambda x, u, p: u.u**2)
    for kind in ("hermite-simpson", "multiple-shooting", "lgl"):
        tau, X, U = _cold_start(m, kind)
        np.testing.assert_allclose(X[:, 0], 0.5 * np.sin(np.pi * tau), atol=1e-12)
        np.testing.assert_allclose(U[:, 0], 0.5 * np.pi * np.cos(np.pi * tau), atol=1e-12)


def test_a_state_fixed_at_both_ends_starts_on_the_straight_line():
    """Without a guess, a state whose initial and final values are fixed (a number, a
    parameter key) is cold-started on the line between them; one with a free end at its
    fixed value, one with a number guess from its fixed start to the guess. (Already the
    behaviour before issue 17's guess functions: this pins it.)"""
    from solvers.userproblem import Param

    m = UserMission(key="line", title="t",
                    params=(Param("target", "target", "m", 3.0, 1.0, 5.0, 0.5),),
                    states=(State("x", "m", bounds=(-10, 10), initial=-1.0, final="target"),
                            State("y", "m", bounds=(-10, 10), initial=2.0),
                            State("z", "m", bounds=(-10, 10), initial=1.0, guess=4.0)),
                    controls=(Control("u", bounds=(-5, 5)),),
                    dynamics=lambda x, u, p: [u.u, u.u, u.u], final_time=1.0,
                    lagrange=lambda x, u, p: u.u**2)
    for kind in ("hermite-simpson", "multiple-shooting", "lgl"):
        tau, X, _ = _cold_start(m, kind)
        np.testing.assert_allclose(X, np.column_stack([-1.0 + 4.0 * tau, np.full_like(tau, 2.0),
                                                       1.0 + 3.0 * tau]), atol=1e-12)


@pytest.mark.parametrize(("guess", "message"), [
    ("1 / (tau - tau)", "control 'a': guess at tau = 0: ZeroDivisionError: float division by "
                        "zero"),
    ("p.gain * tau", "control 'a': guess at tau = 0: unknown parameter 'gain' (parameters: "
                     "none)"),
    ('float("nan") + tau', "control 'a': guess at tau = 0 is not finite (nan)"),
    ("[tau, tau]", "control 'a': guess at tau = 0 returns a list of shape (2,), not one number"),
    ("2 * tau", "control 'a': guess 1.1 at tau = 0.55 is outside its bounds [-1, 1]"),
])
def test_a_bad_guess_function_is_refused_at_its_line(tmp_path, guess, message):
    """A guess function runs on a grid at load: one that raises, returns anything but one
    finite number or leaves the bounds is refused at the line of its `guess=`."""
    path = _file(tmp_path, GOOD.replace(
        'controls=(Control("a", "m/s²", bounds=(-1, 1)),),',
        f'controls=(Control("a", "m/s²", bounds=(-1, 1),\n'
        f'                  guess=lambda tau, p: {guess}),),'))
    assert _error(path) == f"{path}:{_line_of(path, 'guess=')}: {message}"


def test_a_state_guess_function_outside_the_bounds_is_refused(tmp_path):
    path = _file(tmp_path, GOOD.replace(
        'State("v", "m/s", bounds=(-10, 10), initial=0.0, final=0.0)',
        'State("v", "m/s", bounds=(-10, 10), initial=0.0, final=0.0,\n'
        '                  guess=lambda tau, p: 20 * tau)'))
    assert _error(path) == (f"{path}:{_line_of(path, 'guess=')}: state 'v': guess 11 at tau "
                            "= 0.55 is outside its bounds [-10, 10]")


def _tiny(**kwargs) -> UserMission:
    """A rest-to-rest hop whose final position is a fixed state, its stop a final constraint."""
    return UserMission(
        key="tiny", title="t",
        states=(State("x", "m", bounds=(-10, 30), initial=0.0, final=1.0),
                State("v", "m/s", scale=4.0, initial=0.0)),
        controls=(Control("a", "m/s²", bounds=(-1, 1)),),
        final=(FinalConstraint("stop", lambda xf, p: xf.v, unit="m/s", scale=0.5),),
        dynamics=lambda x, u, p: [x.v, u.a], final_time=FreeTime(2.0), minimum_time=True,
        **kwargs)


def test_accuracy_targets_default_to_the_scales():
    """Issue 17: without `tolerances` a solution was `optimal` whatever it missed (a
    fixed-time transfer by 0.097 in radial speed). Each miss's default target is 1e-5 of its
    scale (x: the half-width 20 of its bounds; stop: its own scale 0.5); a file's own
    targets win key by key and come first (the headline); the About text says which is
    which."""
    m = _tiny()
    assert m.tolerances == pytest.approx({"x_miss_m": 2e-4, "stop_miss_m_s": 5e-6})
    assert ("Accuracy targets of the re-propagated final misses, from the scales, as no "
            "`tolerances` are given (1e-05 × the state's or constraint's scale): "
            "`x_miss_m` ≤ 0.0002, `stop_miss_m_s` ≤ 5e-06.") in m.help
    own = _tiny(tolerances={"stop_miss_m_s": 1e-9})
    assert list(own.tolerances.items()) == [("stop_miss_m_s", 1e-9),
                                            ("x_miss_m", pytest.approx(2e-4))]
    assert "the file's `tolerances`, and for `x_miss_m` the scale" in own.help


def test_an_angle_control_bounded_to_more_than_one_turn_is_warned_about():
    """φ and φ + 2π steer alike: an angle bounded to two turns can wind and end on another
    branch (orbit raising bounded to [-π, 3π]: r(tf) 1.4983 instead of 1.5253 on 40
    Hermite–Simpson nodes). It loads, with a warning at its line and in the About text."""
    def declare(unit: str, bounds: tuple[float, float]) -> UserMission:
        return UserMission(key="turn", title="t", states=(State("x", initial=0.0, final=1.0),),
                           controls=(Control("phi", unit, bounds=bounds),),
                           dynamics=lambda x, u, p: [u.phi],
                           final_time=1.0, lagrange=lambda x, u, p: u.phi**2)

    with pytest.warns(UserWarning, match="can wind") as record:
        wound = declare("rad", (-math.pi, 3 * math.pi))
    assert record[0].filename == __file__
    assert wound.warnings == ("control 'phi': bounds [-3.14159, 9.42478] rad span 2 turns: "
                              "the angle can wind (phi and phi + 6.28319 rad steer alike), so "
                              "the optimum may not be unique; bound it to one turn around "
                              "where it runs",)
    assert f"**Warning:** {wound.warnings[0]}." in wound.help
    with pytest.warns(UserWarning, match=r"span 1\.11 turns"):
        assert declare("deg", (-20.0, 380.0)).warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert declare("rad", (0.0, 2 * math.pi)).warnings == ()
        assert declare("m", (-100.0, 100.0)).warnings == ()


def test_a_worker_loads_a_file_without_repeating_its_warnings(tmp_path):
    """The process that starts the service shows a file's warnings; its workers load the
    same file quietly (the CLI printed the angle warning twice, the explorer once per
    worker more)."""
    path = _file(tmp_path, GOOD.replace('key="tiny"', 'key="tiny-turns"').replace(
        'Control("a", "m/s²", bounds=(-1, 1))', 'Control("a", "rad", bounds=(-7, 7))'))
    try:
        with pytest.warns(UserWarning, match="can wind"):
            assert not load_mission_files([str(path)])
        with warnings.catch_warnings(record=True) as shown:
            warnings.simplefilter("always")
            assert not _load_quietly([str(path)])
    finally:
        unregister("tiny-turns")
    assert not [w for w in shown if "can wind" in str(w.message)]


# ---- the double integrator: analytic optimum, misses, drawing -------------------------------
@pytest.fixture(scope="module")
def double_integrator():
    return load_mission_file(DOUBLE_INTEGRATOR)


@pytest.mark.parametrize("method", ["hermite-simpson", "lgl", "multiple-shooting"])
def test_double_integrator_reaches_its_analytic_optimum(double_integrator, method):
    d, T = 2.5, 1.5
    sol = double_integrator.solve({"distance": d, "duration": T}, method=method)
    assert sol.ok, sol.message
    assert sol.cost.value == pytest.approx(6 * d**2 / T**3, rel=1e-8)
    # u(t) = 6 d / T² (1 - 2 t / T) at every node
    np.testing.assert_allclose(sol.node_u[:, 0], 6 * d / T**2 * (1 - 2 * sol.node_t / T),
                               atol=1e-6)
    assert sol.quantities["x_final"].value == pytest.approx(d, abs=1e-9)
    assert abs(sol.check["x_miss_m"]) < 1e-8 and abs(sol.check["v_miss_m_s"]) < 1e-8


def test_the_other_nlp_back_end_needs_no_extra_code(double_integrator):
    sol = double_integrator.solve({}, method="multiple-shooting", backend="sqp")
    assert sol.ok and sol.backend == "sqp"
    assert sol.cost.value == pytest.approx(6.0, rel=1e-8)


def test_a_user_mission_draws_plots_pickles_and_explains_itself(double_integrator):
    sol = double_integrator.solve({}, method="hermite-simpson")
    pres = double_integrator.present(sol)
    assert pres.path.shape == (len(sol.t), 3)
    np.testing.assert_allclose(pres.path[:, 0], sol.x[:, 0])  # position = ("x",)
    assert [p.title for p in pres.plots] == ["x", "v", "a"]
    assert [m.name for m in pres.markers] == ["start", "end"]
    assert pickle.loads(pickle.dumps(sol)).cost.value == sol.cost.value
    assert "| x | m | [-20, 20] | 0 | `distance` |" in double_integrator.help
    assert "cost = 6" in double_integrator.help


def test_parameter_values_outside_a_bound_are_refused_before_solving(tmp_path):
    mission = load_mission_file(_file(tmp_path, GOOD.replace(
        'final=1.0),', 'final="target"),').replace(
        "MISSION = UserMission(\n", "MISSION = UserMission(\n    params=(Param("
        "'target', 'target', 'm', 1.0, 0.0, 20.0, 0.5),),\n").replace(
        "import Control,", "import Param, Control,")))
    sol = mission.solve({"target": 15.0})
    assert sol.status == "infeasible"
    assert "final x = 15 m is outside its bounds [-10, 10]" in sol.message


def test_a_path_constraint_broken_at_the_fixed_start_is_infeasible_before_solving():
    """x(0) = 0 fixed and x ≥ gap at every node: no control can help, so the case is refused
    naming the constraint; a constraint that reads the control (x + a² ≥ gap) may be met by a
    control at the start and is left to the solver; gap ≤ 0 solves."""
    from solvers.userproblem import Param, PathConstraint

    def declare(fn):
        return UserMission(
            key="fixed-start", title="t", params=(Param("gap", "gap", "m", -1.0, -2.0, 2.0, 0.1),),
            states=(State("x", "m", bounds=(-5, 5), initial=0.0, final=1.0),
                    State("v", "m/s", bounds=(-5, 5), initial=0.0, final=0.0)),
            controls=(Control("a", "m/s²", bounds=(-10, 10)),),
            dynamics=lambda x, u, p: [x.v, u.a], lagrange=lambda x, u, p: 0.5 * u.a**2,
            final_time=1.0, path=(PathConstraint("floor", fn, lower=0.0, unit="m"),))

    states_only = declare(lambda x, u, p: x.x - p.gap)
    refused = states_only.solve({"gap": 0.5})
    assert refused.status == "infeasible"
    assert "path constraint 'floor' is -0.5 m at the fixed start; it must be ≥ 0 m" in \
        refused.message
    assert states_only.solve({"gap": -0.5}).ok
    with_control = declare(lambda x, u, p: x.x + u.a**2 - p.gap).solve({"gap": 0.5})
    assert "fixed start" not in with_control.message and with_control.converged


def test_a_minimum_time_problem_with_free_final_time(tmp_path):
    mission = load_mission_file(_file(tmp_path, GOOD))
    for method in ("hermite-simpson", "lgl"):
        sol = mission.solve({}, method=method)
        # bang-bang: accelerate 1 s, brake 1 s
        assert sol.converged and sol.cost.value == pytest.approx(2.0, rel=1e-3), method


def test_free_initial_state_final_constraints_and_a_position_function():
    """x(0) free, v(0) = 1; x(1) >= 1 and v(1) = 0 as final constraints; cost ∫a²/2 + x(1).
    Braking uniformly (a = -1, cost 1/2) covers 1/2 m, so the optimum starts at x(0) = 1/2
    and stops on the bound x(1) = 1: cost 3/2. The path is drawn by a function."""
    mission = UserMission(
        key="free-start", title="t",
        states=(State("x", "m", bounds=(-5, 5)), State("v", "m/s", initial=1.0)),
        controls=(Control("a", "m/s²", bounds=(-50, 50)),),
        dynamics=lambda x, u, p: [x.v, u.a], lagrange=lambda x, u, p: 0.5 * u.a**2,
        mayer=lambda xf, p: xf.x,
        final=(FinalConstraint("reach", lambda xf, p: xf.x, lower=1.0, upper=np.inf,
                               unit="m"),
               FinalConstraint("stop", lambda xf, p: xf.v, unit="m/s")),
        final_time=1.0, position=lambda x, p: (x.x, 2 * x.x))
    for method in ("hermite-simpson", "multiple-shooting"):
        sol = mission.solve({}, method=method)
        assert sol.converged, sol.message
        assert sol.cost.value == pytest.approx(1.5, rel=1e-8)
        assert sol.node_x[0, 0] == pytest.approx(0.5, abs=1e-8)
        assert set(sol.check) == {"max_defect", "reach_miss_m", "stop_miss_m_s",
                                  "cost_error_estimate", "state_box_excursion"}
        assert abs(sol.check["reach_miss_m"]) < 1e-8 and abs(sol.check["stop_miss_m_s"]) < 1e-8
    pres = mission.present(sol)
    np.testing.assert_allclose(pres.path[:, 1], 2 * sol.x[:, 0])
    assert pres.frame == "the problem's position function"


def test_warm_starts_across_an_edited_and_reloaded_file(tmp_path):
    path = _file(tmp_path, GOOD)
    first = load_mission_file(path)
    sol = first.solve({}, method="hermite-simpson")
    warm = first.solve({}, method="hermite-simpson", warm=sol)
    assert warm.converged and warm.stats["iterations"] < sol.stats["iterations"]
    # A new target: same NLP size, the old optimum is a good start.
    path.write_text(GOOD.replace("final=1.0", "final=2.0"), encoding="utf-8")
    moved = load_mission_file(path).solve({}, method="hermite-simpson", warm=sol)
    assert moved.converged and moved.cost.value == pytest.approx(2 * np.sqrt(2), rel=1e-3)
    # A new state: the old warm start does not fit and is dropped, not a failure.
    path.write_text(GOOD.replace("[x.v, u.a]", "[x.v, u.a, 1.0]").replace(
        "final=0.0)),", "final=0.0),\n            State(\"clock\", \"s\", initial=0.0)),"),
        encoding="utf-8")
    grown = load_mission_file(path).solve({}, method="hermite-simpson", warm=sol)
    assert grown.converged
    assert grown.quantities["clock_final"].value == pytest.approx(2.0, rel=1e-3)


def test_folders_and_clashes_in_the_registry(tmp_path):
    _file(tmp_path, GOOD, "a.py")
    _file(tmp_path, GOOD.replace('key="tiny"', 'key="lunar-landing"'), "b.py")
    try:
        errors = load_mission_files([str(tmp_path)])
        assert get_mission("tiny").title == "Tiny minimum-time hop"
        assert list(errors) == [str(tmp_path / "b.py")]
        assert "built-in mission" in errors[str(tmp_path / "b.py")]
    finally:
        unregister("tiny")


def test_a_mission_replaced_in_memory_loses_its_file(tmp_path):
    """A worker loads a user mission from its file: a mission registered again without one
    (built in memory) must not keep the old file, whose mission is another (an app offered
    it as solvable, and its workers solved the file's version)."""
    path = _file(tmp_path, GOOD, "a.py")
    try:
        assert load_mission_files([str(path)]) == {}
        assert mission_file_of("tiny") == str(path)
        register(load_mission_file(path))  # the same key, from memory
        assert mission_file_of("tiny") is None
    finally:
        unregister("tiny")


# ---- the command line ----------------------------------------------------------------------
def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solvers", *args], capture_output=True,
                          text=True, timeout=120, cwd=ROOT)


def test_cli_lists_a_mission_file_like_a_built_in_one():
    res = _cli("list", "--mission-file", str(DOUBLE_INTEGRATOR))
    assert res.returncode == 0, res.stderr
    lines = res.stdout.splitlines()
    assert any(line.startswith("double-integrator ") for line in lines)
    assert any(line.startswith("lunar-landing ") for line in lines)


def test_cli_solves_a_mission_file_as_json():
    res = _cli("solve", "double-integrator", "--mission-file", str(DOUBLE_INTEGRATOR),
               "--method", "lgl", "--set", "distance=2", "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["status"] == "optimal" and out["method"] == "lgl"
    assert out["cost"]["value"] == pytest.approx(24.0, rel=1e-8)
    assert abs(out["check"]["x_miss_m"]) < 1e-8  # the worker ran the re-propagation


def test_cli_refuses_a_broken_file_with_its_line(tmp_path):
    path = _file(tmp_path, GOOD.replace("[x.v, u.a]", "[x.v]"))
    res = _cli("solve", "tiny", "--mission-file", str(path))
    assert res.returncode == 2
    assert res.stderr.strip() == (f"error: {path}:{_line_of(path, 'dynamics=')}: dynamics "
                                  "returns 1 value for 2 states (x, v)")


def test_cli_warns_of_an_angle_control_that_can_wind(tmp_path):
    path = _file(tmp_path, GOOD.replace('Control("a", "m/s²", bounds=(-1, 1))',
                                        'Control("a", "deg", bounds=(-360, 360))'))
    res = _cli("params", "tiny", "--mission-file", str(path))
    assert res.returncode == 0, res.stderr
    assert (f"{path}:{_line_of(path, 'Control(')}: UserWarning: control 'a': bounds [-360, "
            "360] deg span 2 turns: the angle can wind") in res.stderr


LOOP = "from solvers.userproblem import State\n\nX = 1\nwhile True:\n    X += 1\n"


def test_a_file_that_loops_is_stopped_at_the_time_limit(tmp_path, monkeypatch):
    """Issue 16: `while True` at top level wedged the explorer's reload for good."""
    import solvers.mission_file as mission_file

    monkeypatch.setattr(mission_file, "LOAD_TIME_LIMIT", 0.5)
    path = _file(tmp_path, LOOP)
    start = time.perf_counter()
    assert _error(path).startswith(f"{path}:") and _error(path).endswith(
        "the file's code did not finish within 0.5 s (an endless loop at top level?)")
    assert time.perf_counter() - start < 5.0
    assert sys.gettrace() is None or "coverage" in type(sys.gettrace()).__module__
    monkeypatch.undo()  # the good file builds CasADi functions: 0.5 s is short on a busy machine
    assert load_mission_file(_file(tmp_path, GOOD, "good.py")).key == "tiny"  # loads after


def test_the_explorer_reload_survives_a_file_that_loops(tmp_path, monkeypatch):
    """Issue 16: saving a file with `while True` at top level wedged the hot reload for good
    (and held the server at 99 % CPU). The reload says why, and the next save loads."""
    import threading

    import solvers.mission_file as mission_file
    from explorer.reload import MissionFiles

    path = _file(tmp_path, GOOD)
    errors: list[str] = []
    loaded = threading.Event()
    files = MissionFiles([str(path)], lambda mission, where: loaded.set(),
                         lambda where, message: errors.append(message))
    try:
        monkeypatch.setattr(mission_file, "LOAD_TIME_LIMIT", 0.5)
        path.write_text(LOOP, encoding="utf-8")
        assert _wait(lambda: errors), "no report of the looping file"
        assert errors[0].endswith("did not finish within 0.5 s (an endless loop at top level?)")
        monkeypatch.undo()  # the good file's load may take longer than 0.5 s on a busy machine
        path.write_text(GOOD.replace("Tiny minimum-time hop", "Tiny hop, fixed"),
                        encoding="utf-8")
        assert loaded.wait(30.0), "the reload stayed wedged"
        assert get_mission("tiny").title == "Tiny hop, fixed"
    finally:
        files.stop()
        unregister("tiny")


def _wait(condition, timeout: float = 30.0) -> bool:
    """Poll `condition` until it holds or `timeout` s pass."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.05)
    return False


def test_cli_stops_a_file_that_loops(tmp_path):
    path = _file(tmp_path, LOOP)
    start = time.perf_counter()
    res = _cli("solve", "tiny", "--mission-file", str(path))
    assert time.perf_counter() - start < 60.0
    assert res.returncode == 2 and "did not finish within 5 s" in res.stderr


def test_cli_sweeps_a_mission_file():
    res = _cli("sweep", "double-integrator", "--mission-file", str(DOUBLE_INTEGRATOR),
               "--grid", "distance=1,2", "--workers", "1")
    assert res.returncode == 0, res.stderr
    costs = [float(line.split()[2]) for line in res.stdout.splitlines()[1:]]
    assert costs == pytest.approx([6.0, 24.0], rel=1e-8)
