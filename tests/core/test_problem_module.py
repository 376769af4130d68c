"""A mission class takes its records and hooks from its `problem` module
(`solvers.problem_module`): a hook function takes the hook's arguments it names, the class
body wins, and a function of a hook's name that asks for anything else is refused."""

from __future__ import annotations

import types

import numpy as np
import pytest

from solvers.mission import Mission
from solvers.problem import Param


def _module(**attrs: object) -> types.ModuleType:
    module = types.ModuleType("fake_problem")
    module.__dict__.update(attrs)
    return module


def test_records_and_hooks_come_from_the_problem_module():
    seen = []
    module = _module(PARAMS=(Param("d", "distance", "m", 1.0, 0.1, 10.0, 0.1),),
                     parameter_vector=lambda values: np.array([values["d"]]),
                     precheck=lambda p: seen.append(("p", p[0])),
                     check_values=lambda values: seen.append(("values", values["d"])))

    class Fake(Mission, records=module):
        key = "fake"

    fake = Fake()
    assert [p.key for p in fake.params] == ["d"]
    p = fake.parameter_vector({"d": 2.0})
    fake.precheck({"d": 2.0}, p)
    fake.check_values({"d": 3.0})
    assert seen == [("p", 2.0), ("values", 3.0)]


def test_the_class_body_wins_over_the_module():
    module = _module(ocp=lambda: "module")

    class Fake(Mission, records=module):
        key = "fake"

        def ocp(self, method, values):
            return "class"

    assert Fake().ocp(None, {}) == "class"


def test_a_hook_named_function_asking_for_something_else_is_refused():
    module = _module(ocp=lambda vector: None)
    with pytest.raises(TypeError, match=r"ocp\(vector\) cannot be the mission hook"):
        class Fake(Mission, records=module):
            key = "fake"
