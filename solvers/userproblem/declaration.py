"""A declared problem as one record, and the checks that need no CasADi: names, parameter
references, bounds that exclude the initial or final value, a cost, a final time.

Every message names the line of the user's file that made the faulty record.
"""

from __future__ import annotations

import keyword
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from ..problem import Param
from .errors import DeclarationError
from .records import Control, FinalConstraint, FreeTime, PathConstraint, State, Value

PositionFn = Callable[[Any, Any], Any]


@dataclass(frozen=True)
class Declaration:
    """Everything the numerics need to know about a user's problem (no GUI)."""

    states: tuple[State, ...]
    controls: tuple[Control, ...]
    params: tuple[Param, ...]
    dynamics: Callable[..., Any]
    final_time: float | str | FreeTime
    lagrange: Callable[..., Any] | None = None
    mayer: Callable[..., Any] | None = None
    minimum_time: bool = False
    maximize: bool = False
    path: tuple[PathConstraint, ...] = ()
    final: tuple[FinalConstraint, ...] = ()
    position: tuple[str, ...] | PositionFn = ()
    position_unit: str | None = None
    cost_scale: float = 1.0
    where: str = ""

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def control_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.controls)

    @property
    def param_keys(self) -> tuple[str, ...]:
        return tuple(p.key for p in self.params)

    @property
    def defaults(self) -> dict[str, float]:
        return {p.key: float(p.default) for p in self.params}

    def structure(self) -> str:
        """What sets the size of the NLP (names, fixed ends, free final time): the same in
        every process that loads the file, different once an edit changes the size."""
        return repr((self.state_names, self.control_names, self.param_keys,
                     [c.name for c in self.path], [c.name for c in self.final],
                     [(s.initial is None, s.final is None) for s in self.states],
                     isinstance(self.final_time, FreeTime)))

    def fail(self, message: str, where: str = "") -> DeclarationError:
        return DeclarationError(message, where or self.where)


# One turn in each angle unit a control may be declared in.
TURNS = {"rad": 2 * math.pi, "radian": 2 * math.pi, "radians": 2 * math.pi, "deg": 360.0,
         "degree": 360.0, "degrees": 360.0, "°": 360.0}


def winding_angles(decl: Declaration) -> list[tuple[str, str]]:
    """(warning, 'file:line') for each angle control (unit rad or deg) whose bounds span more
    than one turn at the parameters' defaults: φ and φ + 2π steer alike, so the angle can
    wind and the optimum may not be unique (the NLP may end on another branch)."""
    found = []
    for c in decl.controls:
        turn = TURNS.get(c.unit.strip().lower())
        lo, hi = (resolve(b, decl.defaults) for b in c.bounds)
        if turn is None or not hi - lo > turn * (1 + 1e-9):
            continue
        span = "unbounded" if not math.isfinite(hi - lo) else f"{(hi - lo) / turn:.3g} turns"
        found.append((f"control '{c.name}': bounds [{lo:g}, {hi:g}] {c.unit} span {span}: "
                      f"the angle can wind ({c.name} and {c.name} + {turn:g} {c.unit} steer "
                      f"alike), so the optimum may not be unique; bound it to one turn "
                      f"around where it runs", c.where))
    return found


def resolve(value: Value, values: Mapping[str, float]) -> float:
    """A number as it stands, or the value of the parameter it names."""
    return float(values[value]) if isinstance(value, str) else float(value)


def check(decl: Declaration) -> None:
    """Raise `DeclarationError` for the first thing wrong with `decl` that CasADi is not
    needed to see."""
    _check_names(decl)
    _check_references(decl)
    defaults = decl.defaults
    for s in decl.states:
        _check_state(s, defaults)
    for c in decl.controls:
        _check_control(c, defaults)
    _check_cost_and_time(decl, defaults)


def _check_control(c: Control, defaults: Mapping[str, float]) -> None:
    lo, hi = (resolve(b, defaults) for b in c.bounds)
    if not lo < hi:
        raise DeclarationError(f"control '{c.name}': bounds [{lo:g}, {hi:g}] are empty",
                               c.where)


def _check_names(decl: Declaration) -> None:
    if not decl.states:
        raise decl.fail("declare at least one state")
    if not decl.controls:
        raise decl.fail("declare at least one control")
    seen: dict[str, str] = {}
    for kind, items in (("state", decl.states), ("control", decl.controls)):
        for item in items:
            if not item.name.isidentifier() or keyword.iskeyword(item.name) \
                    or item.name.startswith("_"):
                raise DeclarationError(f"{kind} name '{item.name}' is not a Python name "
                                       "(letters, digits, '_', not starting with '_')",
                                       item.where)
            if item.name in seen:
                raise DeclarationError(f"{kind} '{item.name}' is declared twice (also a "
                                       f"{seen[item.name]})", item.where)
            seen[item.name] = kind
    keys = [p.key for p in decl.params]
    twice = sorted({k for k in keys if keys.count(k) > 1})
    if twice:
        raise decl.fail(f"parameter '{twice[0]}' is declared twice")
    for items, kind in ((decl.path, "path constraint"), (decl.final, "final constraint")):
        names = [c.name for c in items]
        for c in items:
            if names.count(c.name) > 1:
                raise DeclarationError(f"{kind} '{c.name}' is declared twice", c.where)


def _check_references(decl: Declaration) -> None:
    """Every parameter key used in place of a number names a declared parameter."""
    keys = set(decl.param_keys)
    known = ", ".join(decl.param_keys) or "none declared"

    def ref(value: object, what: str, where: str) -> None:
        if isinstance(value, str) and value not in keys:
            raise DeclarationError(f"{what} '{value}' is not a parameter (parameters: {known})",
                                   where)

    for s in decl.states:
        ref(s.initial, f"state '{s.name}': initial", s.where)
        ref(s.final, f"state '{s.name}': final", s.where)
        for b in s.bounds:
            ref(b, f"state '{s.name}': bound", s.where)
    for c in decl.controls:
        for b in c.bounds:
            ref(b, f"control '{c.name}': bound", c.where)
    ref(decl.final_time, "final_time", decl.where)
    if not isinstance(decl.position, tuple):
        return
    if len(decl.position) > 3:
        raise decl.fail(f"position names at most 3 states, not {len(decl.position)}")
    for name in decl.position:
        if name not in decl.state_names:
            raise decl.fail(f"position: unknown state '{name}' (states: "
                            f"{', '.join(decl.state_names)})")


def _check_state(s: State, defaults: Mapping[str, float]) -> None:
    lo, hi = (resolve(b, defaults) for b in s.bounds)
    if not lo < hi:
        raise DeclarationError(f"state '{s.name}': bounds [{lo:g}, {hi:g}] are empty", s.where)
    for end in ("initial", "final"):
        value = getattr(s, end)
        if value is None:
            continue
        v = resolve(value, defaults)
        if not math.isfinite(v):
            raise DeclarationError(f"state '{s.name}': {end} value {v} is not finite", s.where)
        if not lo <= v <= hi:
            source = f" (parameter '{value}' at its default)" if isinstance(value, str) else ""
            raise DeclarationError(f"state '{s.name}': {end} value {v:g}{source} is outside "
                                   f"its bounds [{lo:g}, {hi:g}]", s.where)
    if s.scale is not None and not s.scale > 0:
        raise DeclarationError(f"state '{s.name}': scale must be positive, not {s.scale}",
                               s.where)


def _check_cost_and_time(decl: Declaration, defaults: Mapping[str, float]) -> None:
    if decl.mayer is None and decl.lagrange is None and not decl.minimum_time:
        raise decl.fail("no cost: give mayer, lagrange or minimum_time=True")
    ft = decl.final_time
    if isinstance(ft, FreeTime):
        if not 0 <= ft.lower < ft.guess < ft.upper or not math.isfinite(ft.upper):
            raise DeclarationError(f"FreeTime: need 0 <= lower < guess < upper < inf, got "
                                   f"{ft.lower:g} < {ft.guess:g} < {ft.upper:g}", ft.where)
        return
    if decl.minimum_time:
        raise decl.fail("minimum_time=True needs a free final time (final_time=FreeTime(...))")
    if not resolve(ft, defaults) > 0:
        raise decl.fail(f"final_time must be positive, not {resolve(ft, defaults):g}")
