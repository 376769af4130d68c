"""Declarative mission inputs: parameters, methods and their validation.

Everything the GUI, the CLI and sweeps show is generated from these records, so a
mission never needs code of its own outside `solvers/missions/`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

from .nlp.backends import backend


@dataclass(frozen=True)
class Param:
    """One scalar input of a mission, always in SI units at the interface.

    `display_unit`/`display_factor` only change how a GUI shows the value
    (e.g. metres shown as km with factor 1e-3); `options` turns the parameter into a
    choice whose value is the index of the chosen option. `guess=True` marks a parameter of
    the initial guess or of the solver's start: changing it solves from the initial guess
    (a warm start from the last answer would ignore it). `epoch` makes a day count a date:
    the GUI shows and takes it as an ISO date.
    """

    key: str
    label: str
    unit: str
    default: float
    min: float
    max: float
    step: float
    group: str = "Mission"
    help: str = ""
    display_unit: str | None = None
    display_factor: float = 1.0
    options: tuple[str, ...] = ()
    integer: bool = False
    guess: bool = False
    epoch: str | None = None  # ISO date: the value counts days from it (shown as a date)

    def __post_init__(self) -> None:
        if not self.min <= self.default <= self.max:
            raise ValueError(
                f"Param {self.key}: default {self.default} outside [{self.min}, {self.max}]"
            )
        if self.options and (self.min != 0 or self.max != len(self.options) - 1):
            raise ValueError(f"Param {self.key}: a choice ranges over 0..{len(self.options) - 1}")

    @property
    def is_choice(self) -> bool:
        return bool(self.options)

    def describe_range(self) -> str:
        if self.options:
            return " | ".join(f"{i}={name}" for i, name in enumerate(self.options))
        unit = f" {self.unit}" if self.unit else ""
        return f"[{self.min:g}, {self.max:g}]{unit}"


@dataclass(frozen=True)
class Preset:
    """A named set of values (and optionally a method, node count and view options) for
    demos. `cold` solves from the method's initial guess instead of the current optimum, for
    presets about guesses and convergence."""

    name: str
    values: Mapping[str, float] = field(default_factory=dict)
    method: str | None = None
    nodes: int | None = None
    note: str = ""
    cold: bool = False
    view: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class Method:
    """A way of solving a mission: a transcription with its options plus NLP back ends.

    `transcription` names a general transcription of `solvers.transcription` ("hermite-simpson",
    "multiple-shooting", "lgl") that solves the mission's `OCP` with no mission code; None
    marks a method the mission implements itself (a paper's own). `nodes` is (min, default,
    max) of the discretisation size; `params` are inputs only this method reads; `backends`
    are keys of `solvers.nlp.backends.BACKENDS`, the first being the default. The general
    methods are declared once in `solvers.methods` and listed by the missions that offer them
    (with `replace` for a mission's own node range or back ends).
    """

    key: str
    label: str
    source: str
    summary: str
    nodes: tuple[int, int, int]
    nodes_label: str = "nodes"
    params: tuple[Param, ...] = ()
    backends: tuple[str, ...] = ()
    # (caption, LaTeX) pairs shown in the method's About panel (as MathML).
    equations: tuple[tuple[str, str], ...] = ()
    transcription: str | None = None
    options: tuple[tuple[str, int], ...] = ()  # transcription options, e.g. (("substeps", 4),)
    # True: the method answers another problem than the mission's OCP (the asteroid's
    # impulsive first stage), so no other method's answer may stand in for it.
    other_problem: bool = False

    def __post_init__(self) -> None:
        for key in self.backends:
            backend(key)  # raises ValueError naming the known back ends
        lo, default, hi = self.nodes
        if not lo <= default <= hi:
            raise ValueError(f"Method {self.key}: default nodes {default} outside [{lo}, {hi}]")

    def replace(self, **changes: object) -> Method:
        """This method with some fields changed (a mission's node range, back ends...)."""
        return replace(self, **changes)

    @property
    def default_backend(self) -> str:
        return self.backends[0] if self.backends else ""


RELATIONS = ("equal", "at-most", "at-least")


@dataclass(frozen=True)
class Published:
    """A number printed in a paper (or an independent reference) with the agreement we
    expect, checked by `tests/test_published.py` straight from this record.

    `name` is a key of the solution's quantities, stats or check (or "cost"). `relation`
    "equal" expects |ours - value| <= atol + rtol |value|; "at-most"/"at-least" expect ours on
    that side of the value (a bound the paper states). `holds=False` records a published
    number that does not hold, with the reason in `note`: the test then asserts that ours
    really differs by more than the tolerance, so the claim is checked too. `case` is the
    request that reproduces it (default: the mission's defaults); `methods` the methods that
    must reproduce it (default: every method of the mission); `slow` moves the check to the
    slow test set: True for every method, or the methods named. `checked=False` marks a
    number that only a mission's own test can check (e.g. a spread over several solves);
    `note` says which.
    """

    name: str
    value: float
    unit: str
    source: str
    note: str = ""
    rtol: float = 1e-3
    atol: float = 0.0
    relation: str = "equal"
    holds: bool = True
    case: Preset | None = None
    methods: tuple[str, ...] = ()
    slow: bool | tuple[str, ...] = False
    checked: bool = True

    def __post_init__(self) -> None:
        if self.relation not in RELATIONS:
            raise ValueError(f"Published {self.name}: relation must be one of {RELATIONS}")

    def slow_for(self, method: str) -> bool:
        """Whether the check of `method` belongs to the slow test set."""
        return self.slow is True or (isinstance(self.slow, tuple) and method in self.slow)

    def agrees(self, ours: float) -> bool:
        """Whether our value satisfies the stated relation within the tolerance."""
        slack = self.atol + self.rtol * abs(self.value)
        if not math.isfinite(ours):
            return False
        if self.relation == "at-most":
            return ours <= self.value + slack
        if self.relation == "at-least":
            return ours >= self.value - slack
        return abs(ours - self.value) <= slack


@dataclass(frozen=True)
class Consistency:
    """Methods of one mission that must agree on a quantity (or "cost") at the mission's
    defaults, within `rtol` (relative to the largest magnitude): the per-method consistency
    check of `tests/test_consistency.py`. `methods` () means every method."""

    name: str
    rtol: float
    methods: tuple[str, ...] = ()
    note: str = ""


def validate_values(
    params: tuple[Param, ...], values: Mapping[str, float] | None
) -> dict[str, float]:
    """Return a complete value set (defaults filled in) or raise `ValueError`.

    Rejects unknown keys, non-numeric and non-finite values and values outside
    [min, max]; the message names the key, the value and the allowed range.
    """
    by_key = {p.key: p for p in params}
    out = {p.key: float(p.default) for p in params}
    for key, raw in (values or {}).items():
        if key not in by_key:
            known = ", ".join(sorted(by_key))
            raise ValueError(f"unknown parameter '{key}' (known: {known})")
        param = by_key[key]
        try:
            value = float(raw)
        except (TypeError, ValueError):
            raise ValueError(
                f"parameter '{key}' = {raw!r} is not a number; allowed {param.describe_range()}"
            ) from None
        if not math.isfinite(value):
            raise ValueError(
                f"parameter '{key}' = {value} is not finite; allowed {param.describe_range()}"
            )
        if not param.min <= value <= param.max:
            raise ValueError(
                f"parameter '{key}' = {value:g} is outside the allowed range "
                f"{param.describe_range()}"
            )
        if (param.integer or param.options) and value != round(value):
            raise ValueError(f"parameter '{key}' = {value:g} must be a whole number")
        out[key] = value
    return out
