"""Load a mission file: one Python file outside the package that declares a problem.

The file is run as a module of its own; it must define `MISSION`, a `Mission` (usually made
by `solvers.userproblem.UserMission(...)`). Any error — a syntax error, an exception while
running the file, a missing or wrong `MISSION` — becomes a `MissionFileError` whose message
is one line naming the file and the line.
"""

from __future__ import annotations

import difflib
import importlib.util
import inspect
import re
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from types import FrameType
from typing import Any

from . import userproblem
from .mission import Mission
from .userproblem.errors import DeclarationError, one_line, refine
from .userproblem.locate import (
    keyword_line,
    positional_after_keyword_line,
    unclosed_bracket_line,
)

# Seconds a mission file's own code may run while it loads (its top level and the functions
# it defines, traced once): an endless loop there would hold the explorer's reload for good.
LOAD_TIME_LIMIT = 5.0


class MissionFileError(Exception):
    """A mission file that cannot be used; the message is one line with file and line."""


class _TooLong(BaseException):
    """The file's code ran past the load time limit (raised inside the file's frames; not an
    `Exception`, so the file's own `except Exception` and `call_user` let it through)."""


class _Deadline:
    """Stop the file's own Python code once `limit` seconds have passed: a line tracer on
    the file's frames only (library code runs untraced), restored on exit."""

    def __init__(self, path: Path, limit: float) -> None:
        self.file, self.limit = str(path.resolve()), limit
        self.line = 0

    def __enter__(self) -> _Deadline:
        self.deadline = time.monotonic() + self.limit
        self.previous = sys.gettrace()
        sys.settrace(self._call)
        return self

    def __exit__(self, *exc: object) -> None:
        sys.settrace(self.previous)

    def _call(self, frame: FrameType, event: str, arg: object) -> Callable[..., Any] | None:
        return self._line if str(Path(frame.f_code.co_filename).resolve()) == self.file \
            else None

    def _line(self, frame: FrameType, event: str, arg: object) -> Callable[..., Any]:
        if time.monotonic() > self.deadline:
            self.line = frame.f_lineno
            raise _TooLong
        return self._line


def _where(path: Path, exc: BaseException) -> str:
    """'file:line' of the deepest frame of `exc` inside the mission file."""
    line = getattr(exc, "lineno", None) if isinstance(exc, SyntaxError) else None
    for frame in traceback.extract_tb(exc.__traceback__):
        if Path(frame.filename).resolve() == path.resolve():
            line = frame.lineno
    return f"{path}:{line}" if line else str(path)


def _at_fault(path: Path, exc: BaseException, where: str) -> str:
    """`where` moved from the first line of a call to the line at fault: the misspelt
    keyword (from the file's AST); for a syntax error, from its tokens, the bracket left open
    or the positional argument after keyword ones."""
    if isinstance(exc, TypeError) and (word := _unexpected_keyword(exc)):
        return refine(where, lambda file, line: keyword_line(file, line, word))
    if not isinstance(exc, SyntaxError):
        return where
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return where
    line = None
    if "was never closed" in str(exc.msg):
        line = unclosed_bracket_line(text)
    elif "positional argument follows keyword argument" in str(exc.msg) and exc.lineno:
        line = positional_after_keyword_line(text, exc.lineno)
    return f"{path}:{line}" if line else where


def _unexpected_keyword(exc: TypeError) -> str | None:
    match = re.search(r"unexpected keyword argument '(\w+)'", str(exc))
    return match.group(1) if match else None


def _hint(exc: BaseException) -> str:
    """For a misspelt keyword of the file API, the nearest keyword it accepts."""
    word = _unexpected_keyword(exc) if isinstance(exc, TypeError) else None
    match = re.match(r"(\w+)(?:\.__init__)?\(\)", str(exc))
    target = getattr(userproblem, match.group(1), None) if match and word else None
    if target is None:
        return ""
    accepted = [k for k in inspect.signature(target).parameters if k != "self"]
    close = difflib.get_close_matches(word, accepted, n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def load_mission_file(path: str | Path) -> Mission:
    """Run the file and return its `MISSION` (a new module each call, so an edited file
    is read afresh)."""
    path = Path(path)
    if not path.is_file():
        raise MissionFileError(f"{path}: no such file")
    name = f"mission_file_{abs(hash(str(path.resolve())))}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise MissionFileError(f"{path}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    deadline = _Deadline(path, LOAD_TIME_LIMIT)
    try:
        with deadline:
            spec.loader.exec_module(module)
    except BaseException as exc:  # noqa: BLE001 - any failure of a user's file is reported
        if isinstance(exc, KeyboardInterrupt):
            raise
        sys.modules.pop(name, None)
        if isinstance(exc, _TooLong):
            raise MissionFileError(
                f"{path}:{deadline.line}: the file's code did not finish within "
                f"{LOAD_TIME_LIMIT:g} s (an endless loop at top level?)") from None
        if isinstance(exc, DeclarationError) and exc.where:  # it knows the line at fault
            raise MissionFileError(str(exc)) from None
        detail = exc.msg if isinstance(exc, SyntaxError) else one_line(exc)
        raise MissionFileError(f"{_at_fault(path, exc, _where(path, exc))}: "
                               f"{type(exc).__name__}: {detail}{_hint(exc)}") from None
    mission = getattr(module, "MISSION", None)
    if not isinstance(mission, Mission):
        raise MissionFileError(f"{path}: defines no MISSION (a solvers Mission, e.g. "
                               "MISSION = UserMission(...))")
    return mission
