"""Load a mission file: one Python file outside the package that declares a problem.

The file is run as a module of its own; it must define `MISSION`, a `Mission` (usually made
by `solvers.userproblem.UserMission(...)`). Any error — a syntax error, an exception while
running the file, a missing or wrong `MISSION` — becomes a `MissionFileError` whose message
is one line naming the file and the line.
"""

from __future__ import annotations

import importlib.util
import sys
import traceback
from pathlib import Path

from .mission import Mission
from .userproblem.errors import DeclarationError, one_line


class MissionFileError(Exception):
    """A mission file that cannot be used; the message is one line with file and line."""


def _where(path: Path, exc: BaseException) -> str:
    """'file:line' of the deepest frame of `exc` inside the mission file."""
    line = getattr(exc, "lineno", None) if isinstance(exc, SyntaxError) else None
    for frame in traceback.extract_tb(exc.__traceback__):
        if Path(frame.filename).resolve() == path.resolve():
            line = frame.lineno
    return f"{path}:{line}" if line else str(path)


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
    try:
        spec.loader.exec_module(module)
    except BaseException as exc:  # noqa: BLE001 - any failure of a user's file is reported
        if isinstance(exc, KeyboardInterrupt):
            raise
        sys.modules.pop(name, None)
        if isinstance(exc, DeclarationError) and exc.where:  # it knows the line at fault
            raise MissionFileError(str(exc)) from None
        detail = exc.msg if isinstance(exc, SyntaxError) else one_line(exc)
        raise MissionFileError(f"{_where(path, exc)}: {type(exc).__name__}: {detail}") from None
    mission = getattr(module, "MISSION", None)
    if not isinstance(mission, Mission):
        raise MissionFileError(f"{path}: defines no MISSION (a solvers Mission, e.g. "
                               "MISSION = UserMission(...))")
    return mission
