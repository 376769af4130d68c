"""Declarative mission inputs: parameters, methods and their validation.

Everything the GUI, the CLI and sweeps show is generated from these records, so a
mission never needs code of its own outside `solvers/missions/`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Param:
    """One scalar input of a mission, always in SI units at the interface.

    `display_unit`/`display_factor` only change how a GUI shows the value
    (e.g. metres shown as km with factor 1e-3); `options` turns the parameter into a
    choice whose value is the index of the chosen option.
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
class Method:
    """A way of solving a mission: a transcription plus an NLP back end.

    `nodes` is (min, default, max) of the method's discretisation size; `params` are inputs
    only this method reads (e.g. a penalty factor); `backends` are the NLP solvers it can use,
    the first being the default.
    """

    key: str
    label: str
    source: str
    summary: str
    nodes: tuple[int, int, int]
    # `equations`: (caption, LaTeX) pairs shown in the method's About panel (as MathML).
    nodes_label: str = "nodes"
    params: tuple[Param, ...] = ()
    backends: tuple[str, ...] = ()
    equations: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class Published:
    """A number printed in a paper (or an independent reference) to compare against."""

    name: str
    value: float
    unit: str
    source: str
    note: str = ""


@dataclass(frozen=True)
class Preset:
    """A named set of values (and optionally a method/node count) for demos."""

    name: str
    values: Mapping[str, float] = field(default_factory=dict)
    method: str | None = None
    nodes: int | None = None
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
