"""Errors in a declared problem, each one line naming the file and line where it was made.

A declaration is checked when it is made (when a mission file is loaded): every record
remembers the line that created it, every function its own first line, and an exception
raised inside a user's function is reported at the line of the user's code that raised it.
"""

from __future__ import annotations

import sys
import traceback
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

_PACKAGE = str(Path(__file__).resolve().parents[1])  # solvers/: frames inside are not the user's
MAX_DETAIL = 240  # characters of a foreign error message kept in ours


class DeclarationError(ValueError):
    """A declaration that cannot be solved; `str()` is one line, "file:line: what"."""

    def __init__(self, message: str, where: str = "") -> None:
        self.where = where
        super().__init__(f"{where}: {message}" if where else message)


def one_line(text: object) -> str:
    """Any message (CasADi's span several lines) as one line of bounded length."""
    flat = " ".join(str(text).split())
    return flat if len(flat) <= MAX_DETAIL else flat[: MAX_DETAIL - 1] + "…"


def caller_location() -> str:
    """'file:line' of the innermost frame outside this package (and outside generated
    dataclass code): the line of the user's file that made the current declaration."""
    frame = sys._getframe(1)
    while frame is not None:
        name = frame.f_code.co_filename
        if not name.startswith("<") and not str(Path(name).resolve()).startswith(_PACKAGE):
            return f"{name}:{frame.f_lineno}"
        frame = frame.f_back
    return ""


def refine(where: str, finder: Callable[[Path, int], int | None]) -> str:
    """'file:line' moved to the line `finder(path, line)` finds in that file (the keyword or
    key at fault inside a call that spans several lines); `where` as it was otherwise."""
    name, _, line = where.rpartition(":")
    if not name or not line.isdigit():
        return where
    found = finder(Path(name), int(line))
    return f"{name}:{found}" if found else where


def warn_at(message: str, where: str) -> None:
    """A `UserWarning` shown at 'file:line' of the user's file (where the faulty record is
    declared), not at a line of this package."""
    name, _, line = where.rpartition(":")
    if name and line.isdigit():
        warnings.warn_explicit(message, UserWarning, name, int(line))
    else:
        warnings.warn(message, UserWarning, stacklevel=2)


def function_location(fn: Callable[..., Any]) -> str:
    """'file:line' where a user's function is defined ('' for a builtin)."""
    code = getattr(fn, "__code__", None)
    return f"{code.co_filename}:{code.co_firstlineno}" if code is not None else ""


def _raising_line(exc: BaseException, fn: Callable[..., Any]) -> str:
    """The deepest frame of `exc` in the file that defines `fn`: the user's line at fault."""
    code = getattr(fn, "__code__", None)
    where = function_location(fn)
    if code is None:
        return where
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename == code.co_filename:
            where = f"{frame.filename}:{frame.lineno}"
    return where


def call_user(fn: Callable[..., Any], what: str, *args: Any) -> Any:
    """Call a user's function; any exception becomes a `DeclarationError` naming `what`
    and the line of the user's code that raised it."""
    try:
        return fn(*args)
    except DeclarationError:
        raise
    except Exception as exc:  # noqa: BLE001 - whatever a user's function raises is reported
        kind = "" if isinstance(exc, AttributeError) else f"{type(exc).__name__}: "
        raise DeclarationError(f"{what}: {kind}{one_line(exc)}",
                               _raising_line(exc, fn)) from None
