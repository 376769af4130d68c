"""The records a problem is declared with: states, controls, free final time, constraints,
and `Named`, the by-name view of a vector that the problem's functions receive.

Values are SI (or whatever consistent units the problem is written in). Wherever a number
is expected (a bound, an initial or final value, a fixed final time) the key of a parameter
may stand instead, so that value becomes a slider and a CLI `--set`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import caller_location

Value = float | str  # a number, or the key of a parameter
GuessFn = Callable[[float, "Named"], float]  # guess(tau, p): tau in [0, 1], p by name
INF = math.inf


class UnknownName(AttributeError):
    """A name that is not one of the vector's (a typo in `x.vv`)."""


class Named:
    """Entries of a vector by name: `x.v`, `x["v"]`, `x[1]`, and `r, v = x` to unpack.

    Over a CasADi vector each entry is a scalar expression; over a numeric array of shape
    (samples, n) each entry is a column, so the same function draws a whole trajectory.
    """

    __slots__ = ("_values", "_index", "_kind")

    def __init__(self, values: Any, names: Sequence[str], kind: str) -> None:
        self._values = values
        self._index = {name: i for i, name in enumerate(names)}
        self._kind = kind

    def _entry(self, i: int) -> Any:
        v = self._values
        return v[:, i] if isinstance(v, np.ndarray) and v.ndim == 2 else v[i]

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        if name not in self._index:
            known = ", ".join(self._index) or "none"
            raise UnknownName(f"unknown {self._kind} '{name}' ({self._kind}s: {known})")
        return self._entry(self._index[name])

    def __getitem__(self, key: int | str) -> Any:
        return self.__getattr__(key) if isinstance(key, str) else self._entry(key)

    def __len__(self) -> int:
        return len(self._index)

    def __iter__(self) -> Iterator[Any]:
        return (self._entry(i) for i in range(len(self._index)))


def _located(record: object) -> None:
    object.__setattr__(record, "where", caller_location())


@dataclass(frozen=True)
class State:
    """A state. `initial`/`final`: a value, a parameter key, or None (free). `guess`: the
    cold-start value where the state is free, or a function `guess(tau, p)` of the
    normalised time tau in [0, 1] and the parameters by name giving the whole cold start
    (default: the straight line between fixed initial and final values, else the fixed
    value). `scale`: the magnitude the NLP divides by (default: from the bounds, else from
    the values); the default accuracy target of a fixed final value is 1e-5 of it."""

    name: str
    unit: str = ""
    bounds: tuple[Value, Value] = (-INF, INF)
    initial: Value | None = None
    final: Value | None = None
    scale: float | None = None
    guess: float | GuessFn | None = None
    label: str = ""
    where: str = field(default="", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _located(self)


@dataclass(frozen=True)
class Control:
    """A control with its bounds, scale and cold-start value: a number (constant), a pair
    (start, end): linear in time from the first at the initial time to the second at the
    final time (a thrust angle that turns through the flight), a function `guess(tau, p)` of
    the normalised time tau in [0, 1] and the parameters by name, or None (mid-range)."""

    name: str
    unit: str = ""
    bounds: tuple[Value, Value] = (-INF, INF)
    scale: float | None = None
    guess: float | tuple[float, float] | GuessFn | None = None  # a list [start, end] too
    label: str = ""
    where: str = field(default="", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _located(self)
        if isinstance(self.guess, list):
            object.__setattr__(self, "guess", tuple(self.guess))


@dataclass(frozen=True)
class FreeTime:
    """A free final time: the cold-start guess and the bounds (default guess/100 to
    guess*100), in seconds."""

    guess: float
    bounds: tuple[float, float] | None = None
    where: str = field(default="", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _located(self)

    @property
    def lower(self) -> float:
        return self.guess / 100 if self.bounds is None else float(self.bounds[0])

    @property
    def upper(self) -> float:
        return self.guess * 100 if self.bounds is None else float(self.bounds[1])


@dataclass(frozen=True)
class PathConstraint:
    """lower <= fn(x, u, p) <= upper at every node (a keep-out zone, a load limit)."""

    name: str
    fn: Callable[[Named, Named, Named], Any]
    lower: float = -INF
    upper: float = INF
    unit: str = ""
    scale: float | None = None
    where: str = field(default="", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _located(self)


@dataclass(frozen=True)
class FinalConstraint:
    """lower <= fn(x(tf), p) <= upper at the final time (default: = 0), e.g. a circular
    final orbit."""

    name: str
    fn: Callable[[Named, Named], Any]
    lower: float = 0.0
    upper: float = 0.0
    unit: str = ""
    scale: float | None = None
    where: str = field(default="", init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _located(self)


def unit_key(unit: str) -> str:
    """A unit as a key suffix: "m/s" -> "_m_s", "" -> ""."""
    cleaned = "".join(c if c.isalnum() else "_" for c in unit.replace("²", "2").replace("³", "3"))
    cleaned = "_".join(part for part in cleaned.split("_") if part)
    return f"_{cleaned}" if cleaned else ""
