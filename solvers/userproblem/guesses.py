"""The cold start of a declaration: every state and control as a function of normalised time
tau in [0, 1], which each direct method samples on its own grid (`Guess.x_path`/`u_path`).

A state is its `guess` function where it has one, else the straight line between its
start and end: its fixed values where both are fixed, else its number `guess` or the other
end's value at a free end (else mid-range). A control is its `guess` function, its ramp
(start, end), its constant, else mid-range. A guess function `guess=lambda tau, p: ...`
receives the parameters by name (`p.thrust`) and must return one finite number inside the
bounds: it is checked on a grid when the file loads and refused at its line otherwise.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import casadi as ca
import numpy as np

from .declaration import Declaration, resolve
from .errors import DeclarationError, call_user, refine
from .locate import keyword_line
from .records import Control, Named, State

ENDS = np.array([0.0, 1.0])
CHECK_GRID = np.linspace(0.0, 1.0, 21)  # where a guess function is checked at load


def _mid(lo: float, hi: float) -> float:
    """A cold-start value inside [lo, hi]: the centre, or the finite bound, or 0."""
    if math.isfinite(lo) and math.isfinite(hi):
        return (lo + hi) / 2
    return float(np.clip(0.0, lo, hi))


def _guess_line(record: State | Control) -> str:
    """'file:line' of the record's `guess=` keyword (else of the record)."""
    return refine(record.where, lambda path, line: keyword_line(path, line, "guess"))


def _number(value: Any, what: str, record: State | Control) -> float:
    """A guess function's value as one finite number, else a `DeclarationError` at the
    record's `guess=` line (found only then: it reads the file)."""
    if isinstance(value, ca.DM | np.ndarray) and np.size(value) == 1:
        value = float(np.asarray(value, float).item())
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        shape = f" of shape {np.shape(value)}" if np.ndim(value) else ""
        raise DeclarationError(f"{what} returns a {type(value).__name__}{shape}, not one "
                               "number", _guess_line(record))
    if not math.isfinite(value):
        raise DeclarationError(f"{what} is not finite ({value})", _guess_line(record))
    return float(value)


def _sampled(record: State | Control, kind: str, tau: np.ndarray, p: Named) -> np.ndarray:
    """A guess function's values at the times `tau`, each checked to be one finite number."""
    values = []
    for t in tau:
        what = f"{kind} '{record.name}': guess at tau = {t:g}"
        values.append(_number(call_user(record.guess, what, float(t), p), what, record))
    return np.array(values)


def _parameters(decl: Declaration, values: Mapping[str, float]) -> Named:
    return Named(np.array([values[k] for k in decl.param_keys], float), decl.param_keys,
                 "parameter")


def _state_ends(s: State, values: Mapping[str, float]) -> tuple[float, float]:
    """(start, end) of a state without a guess function: fixed values where given, else
    its number `guess`, else the other end's fixed value, else mid-range."""
    lo, hi = (resolve(b, values) for b in s.bounds)
    init = None if s.initial is None else resolve(s.initial, values)
    fin = None if s.final is None else resolve(s.final, values)
    free = s.guess if s.guess is not None else _mid(lo, hi)
    start = init if init is not None else (free if fin is None else fin)
    end = fin if fin is not None else (s.guess if s.guess is not None
                                       else (init if init is not None else free))
    return float(start), float(end)


def _control_ends(c: Control, values: Mapping[str, float]) -> tuple[float, float]:
    """(start, end) of a control without a guess function: its pair, its constant, or the
    middle of its bounds."""
    if c.guess is None:
        start = end = _mid(*(resolve(b, values) for b in c.bounds))
    elif isinstance(c.guess, tuple):
        start, end = c.guess
    else:
        start = end = c.guess
    return float(start), float(end)


def _columns(records: Sequence[State] | Sequence[Control], kind: str, decl: Declaration,
             values: Mapping[str, float], tau: np.ndarray,
             ends: Callable[[Any, Mapping[str, float]], tuple[float, float]]) -> np.ndarray:
    """(len(tau), len(records)) guesses: a guess function sampled, else a ramp between
    `ends`."""
    tau = np.asarray(tau, float)
    p = _parameters(decl, values)
    columns = []
    for r in records:
        if callable(r.guess):
            columns.append(_sampled(r, kind, tau, p))
        else:
            start, end = ends(r, values)
            columns.append(start + tau * (end - start))
    return np.column_stack(columns)


def state_guess(decl: Declaration, values: Mapping[str, float], tau: np.ndarray
                ) -> np.ndarray:
    """(len(tau), nx) cold-start states at the normalised times `tau`."""
    return _columns(decl.states, "state", decl, values, tau, _state_ends)


def control_guess(decl: Declaration, values: Mapping[str, float], tau: np.ndarray
                  ) -> np.ndarray:
    """(len(tau), nu) cold-start controls at the normalised times `tau`."""
    return _columns(decl.controls, "control", decl, values, tau, _control_ends)


def check_guesses(decl: Declaration) -> None:
    """Refuse, at its line, a control guess that is not a finite number, a pair of them or
    a function, and a guess function that raises, returns anything but one finite number or
    leaves the bounds (on `CHECK_GRID`, at the parameters' defaults)."""
    values = decl.defaults
    p = _parameters(decl, values)
    for kind, records in (("state", decl.states), ("control", decl.controls)):
        for r in records:
            lo, hi = (resolve(b, values) for b in r.bounds)
            if callable(r.guess):
                samples = _sampled(r, kind, CHECK_GRID, p)
                outside = [(v, f" at tau = {t:g}") for t, v in zip(CHECK_GRID, samples,
                                                                    strict=True)
                           if not lo <= v <= hi]
            elif isinstance(r, Control) and r.guess is not None:
                outside = [(v, "") for v in _control_pair(r) if not lo <= v <= hi]
            else:
                continue
            if outside:
                value, at = outside[0]
                raise DeclarationError(f"{kind} '{r.name}': guess {value:g}{at} is outside "
                                       f"its bounds [{lo:g}, {hi:g}]",
                                       _guess_line(r) if callable(r.guess) else r.where)


def _control_pair(c: Control) -> np.ndarray:
    """A control's number or (start, end) guess, checked to be finite numbers."""
    ends = c.guess if isinstance(c.guess, tuple) else (c.guess,)
    if len(ends) not in (1, 2) or not all(
            isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)
            for v in ends):
        raise DeclarationError(f"control '{c.name}': guess must be a finite number or a pair "
                               f"(start, end) of them, or a function of (tau, p), not "
                               f"{c.guess!r}", c.where)
    return np.array(ends, float)
