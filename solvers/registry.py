"""Mission registry: every package of `solvers.missions` that defines `MISSION` is a mission,
and so is every mission file a user hands in (`load_mission_file`)."""

from __future__ import annotations

import importlib
import pkgutil
import threading
import warnings
from functools import cache
from pathlib import Path

from . import missions as builtin_missions
from .mission import Mission
from .mission_file import MissionFileError, load_mission_file

_IMPORT_ERRORS: dict[str, str] = {}
_USER: dict[str, Mission] = {}  # missions from mission files, by key
_USER_FILES: dict[str, str] = {}  # mission key -> the file it came from
_LOCK = threading.Lock()

MISSION_ORDER = (
    "lunar-landing",
    "cw-rendezvous",
    "elliptic-transfer",
    "hovercraft",
    "apollo-reentry",
    "asteroid-rendezvous",
)


@cache
def _builtin() -> dict[str, Mission]:
    found: dict[str, Mission] = {}
    for info in sorted(pkgutil.iter_modules(builtin_missions.__path__), key=lambda i: i.name):
        try:
            module = importlib.import_module(f"{builtin_missions.__name__}.{info.name}")
        except Exception as exc:  # noqa: BLE001 - one broken mission must not take down all
            _IMPORT_ERRORS[info.name] = f"{type(exc).__name__}: {exc}"
            warnings.warn(f"mission module '{info.name}' failed to import: {exc}", stacklevel=2)
            continue
        mission = getattr(module, "MISSION", None)
        if isinstance(mission, Mission):
            found[mission.key] = mission
    order = {key: i for i, key in enumerate(MISSION_ORDER)}
    return dict(sorted(found.items(), key=lambda kv: (order.get(kv[0], len(order)), kv[0])))


def import_errors() -> dict[str, str]:
    """Mission modules that failed to import, with the error (empty when all is well)."""
    _builtin()
    return dict(_IMPORT_ERRORS)


def list_missions() -> list[Mission]:
    """All missions: the built-in ones in teaching order, then the users' in load order."""
    with _LOCK:
        return list(_builtin().values()) + list(_USER.values())


def get_mission(key: str) -> Mission:
    """The mission with this key; `ValueError` names the known keys otherwise."""
    with _LOCK:
        missions = {**_builtin(), **_USER}
    if key not in missions:
        raise ValueError(f"unknown mission '{key}' (missions: {', '.join(missions)})")
    return missions[key]


def register(mission: Mission, source: str = "") -> None:
    """Add (or replace) a user mission; a built-in key cannot be taken. `source` is the
    file it came from (a worker loads it from there); a mission replaced by one without a
    file keeps none (the old file would give the workers the old mission)."""
    if mission.key in _builtin():
        raise ValueError(f"'{mission.key}' is a built-in mission: choose another key")
    with _LOCK:
        _USER[mission.key] = mission
        if source:
            _USER_FILES[mission.key] = source
        else:
            _USER_FILES.pop(mission.key, None)


def unregister(key: str) -> None:
    with _LOCK:
        _USER.pop(key, None)
        _USER_FILES.pop(key, None)


def is_user_mission(key: str) -> bool:
    """Whether `key` is a registered user mission (not a built-in one)."""
    with _LOCK:
        return key in _USER


def mission_file_of(key: str) -> str | None:
    """The file a user mission came from (None for a built-in one)."""
    with _LOCK:
        return _USER_FILES.get(key)


def load_mission_files(paths: list[str]) -> dict[str, str]:
    """Load and register mission files (a folder stands for its *.py files); returns
    {path: one-line error} for those that failed (the others are registered)."""
    errors: dict[str, str] = {}
    for path in expand_mission_paths(paths):
        try:
            register(load_mission_file(path), str(path))
        except (MissionFileError, ValueError) as exc:
            errors[str(path)] = str(exc)
    return errors


def expand_mission_paths(paths: list[str]) -> list[Path]:
    """Files as given; a folder as its *.py files in name order."""
    out: list[Path] = []
    for p in map(Path, paths):
        out += sorted(p.glob("*.py")) if p.is_dir() else [p]
    return out
