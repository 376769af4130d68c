"""The user's functions traced once with CasADi symbols into CasADi Functions.

Tracing is the load-time check: a function that fails, uses an unknown name, returns the
wrong number of values or something that is not a number is reported at its own line. The
Functions then serve every transcription (with SX or MX symbols) and the numeric checks.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from .declaration import Declaration
from .errors import DeclarationError, call_user, function_location, one_line
from .locate import numeric_call_line
from .records import Named


@dataclass(frozen=True)
class Traced:
    """CasADi Functions of a declaration (signatures in the docstrings of `trace`)."""

    f: ca.Function
    lagrange: ca.Function | None
    mayer: ca.Function | None
    path: ca.Function | None
    final: ca.Function | None


def _scalar(value: Any, what: str, where: str) -> ca.SX:
    """One entry of a returned value as a 1x1 expression."""
    if isinstance(value, ca.SX | ca.MX | ca.DM):
        if value.numel() != 1:
            raise DeclarationError(f"{what} has {value.numel()} entries, not one", where)
        return ca.SX(value) if isinstance(value, ca.DM) else value
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.item()
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return ca.SX(float(value))
    raise DeclarationError(f"{what} is a {type(value).__name__}, not a number or a CasADi "
                           "expression", where)


def _entries(value: Any) -> list[Any]:
    if isinstance(value, ca.SX | ca.MX | ca.DM):
        return [value[i] for i in range(value.numel())]
    if isinstance(value, np.ndarray):
        return list(value.ravel())
    if isinstance(value, list | tuple):
        return list(value)
    return [value]


def as_vector(value: Any, names: Sequence[str], what: str, where: str) -> ca.SX:
    """A returned list / tuple / vector / {name: value} dict with one entry per state."""
    if isinstance(value, Mapping):
        extra = [k for k in value if k not in names]
        if extra:
            raise DeclarationError(f"{what}: unknown name '{extra[0]}' (expected: "
                                   f"{', '.join(names)})", where)
        missing = [n for n in names if n not in value]
        if missing:
            raise DeclarationError(f"{what}: no value for '{missing[0]}'", where)
        items = [value[n] for n in names]
    else:
        items = _entries(value)
        if len(items) != len(names):
            raise DeclarationError(f"{what} returns {len(items)} value"
                                   f"{'s' if len(items) != 1 else ''} for {len(names)} "
                                   f"states ({', '.join(names)})", where)
    return ca.vertcat(*[_scalar(v, f"{what}: the value for '{n}'", where)
                        for v, n in zip(items, names, strict=True)])


def as_scalar(value: Any, what: str, where: str) -> ca.SX:
    items = _entries(value)
    if len(items) != 1:
        raise DeclarationError(f"{what} returns {len(items)} values, not one", where)
    return _scalar(items[0], what, where)


def _function(name: str, args: list[ca.SX], out: ca.SX, what: str, where: str) -> ca.Function:
    try:
        return ca.Function(name, args, [out])
    except RuntimeError as exc:
        raise DeclarationError(f"{what} depends on symbols other than its arguments "
                               f"({one_line(exc)})", where) from None


def trace(decl: Declaration) -> Traced:
    """f(x, u, p) -> x'; lagrange(x, u, p); mayer(xf, p); path(x, u, p) -> one entry per
    path constraint; final(xf, p) -> one entry per final constraint. Each is the user's
    expression as written (no sign or scale)."""
    x = ca.SX.sym("x", len(decl.states))
    u = ca.SX.sym("u", len(decl.controls))
    p = ca.SX.sym("p", len(decl.params))
    X = Named(x, decl.state_names, "state")
    U = Named(u, decl.control_names, "control")
    P = Named(p, decl.param_keys, "parameter")

    def traced(fn: Callable[..., Any], what: str, args: tuple, shape: Sequence[str] | None
               ) -> ca.SX:
        where = function_location(fn)
        value = call_user(fn, what, *args)
        return as_scalar(value, what, where) if shape is None else \
            as_vector(value, shape, what, where)

    dyn = traced(decl.dynamics, "dynamics", (X, U, P), decl.state_names)
    f = _function("f", [x, u, p], dyn, "dynamics", function_location(decl.dynamics))
    lagrange = mayer = path = final = None
    if decl.lagrange is not None:
        expr = traced(decl.lagrange, "lagrange", (X, U, P), None)
        lagrange = _function("L", [x, u, p], expr, "lagrange", function_location(decl.lagrange))
    if decl.mayer is not None:
        expr = traced(decl.mayer, "mayer", (X, P), None)
        mayer = _function("M", [x, p], expr, "mayer", function_location(decl.mayer))
    if decl.path:
        rows = [traced(c.fn, f"path constraint '{c.name}'", (X, U, P), None)
                for c in decl.path]
        path = _function("path", [x, u, p], ca.vertcat(*rows), "a path constraint",
                         decl.path[0].where)
    if decl.final:
        rows = [traced(c.fn, f"final constraint '{c.name}'", (X, P), None) for c in decl.final]
        final = _function("final", [x, p], ca.vertcat(*rows), "a final constraint",
                          decl.final[0].where)
    return Traced(f, lagrange, mayer, path, final)


def check_finite(traced: Traced, decl: Declaration, x0: np.ndarray, xf: np.ndarray,
                 u: np.ndarray, p: np.ndarray) -> None:
    """Every function is finite on the cold-start guess (a NaN there stops any solver)."""
    checks = [("dynamics", decl.state_names, traced.f(x0, u, p), decl.dynamics,
               function_location(decl.dynamics))]
    if traced.lagrange is not None:
        checks.append(("lagrange", ("value",), traced.lagrange(x0, u, p), decl.lagrange,
                       function_location(decl.lagrange)))
    if traced.mayer is not None:
        checks.append(("mayer", ("value",), traced.mayer(xf, p), decl.mayer,
                       function_location(decl.mayer)))
    if traced.path is not None:
        values = np.asarray(traced.path(x0, u, p), float).ravel()
        checks += [(f"path constraint '{c.name}'", ("value",), v, c.fn, c.where)
                   for c, v in zip(decl.path, values, strict=True)]
    for what, names, value, fn, where in checks:
        values = np.asarray(value, float).ravel()
        bad = [(n, v) for n, v in zip(names, values, strict=True) if not np.isfinite(v)]
        if not bad:
            continue
        numeric = numeric_call_line(fn)
        if numeric is not None:
            line, name = numeric
            raise DeclarationError(
                f"{what} is not finite ({bad[0][0]} = {bad[0][1]}): {name} computes with "
                f"numbers, and a state, control or parameter here is a CasADi symbol: use "
                f"CasADi's function instead (ca.{name.split('.')[-1]} after `import casadi as "
                f"ca`, or `from casadi import {name.split('.')[-1]}`)",
                f"{code_file(fn)}:{line}")
        raise DeclarationError(f"{what} is not finite ({bad[0][0]} = {bad[0][1]}) at the "
                               f"start of the cold-start guess: x = {_fmt(x0)}, "
                               f"u = {_fmt(u)}", where)


def code_file(fn: Callable[..., Any]) -> str:
    """The file that defines a user's function."""
    code = getattr(fn, "__code__", None)
    return code.co_filename if code is not None else ""


def _fmt(v: np.ndarray) -> str:
    return "[" + ", ".join(f"{float(a):g}" for a in np.ravel(v)) + "]"
