"""Mission registry: every module in `solvers.missions` that defines `MISSION` is a mission."""

from __future__ import annotations

import importlib
import pkgutil
import warnings
from functools import cache

from .mission import Mission

_IMPORT_ERRORS: dict[str, str] = {}


@cache
def _missions() -> dict[str, Mission]:
    from . import missions as package

    found: dict[str, Mission] = {}
    for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda i: i.name):
        try:
            module = importlib.import_module(f"{package.__name__}.{info.name}")
        except Exception as exc:  # noqa: BLE001 - one broken mission must not take down all
            _IMPORT_ERRORS[info.name] = f"{type(exc).__name__}: {exc}"
            warnings.warn(f"mission module '{info.name}' failed to import: {exc}", stacklevel=2)
            continue
        mission = getattr(module, "MISSION", None)
        if isinstance(mission, Mission):
            found[mission.key] = mission
    order = {key: i for i, key in enumerate(MISSION_ORDER)}
    return dict(sorted(found.items(), key=lambda kv: (order.get(kv[0], len(order)), kv[0])))


MISSION_ORDER = (
    "lunar-landing",
    "cw-rendezvous",
    "elliptic-transfer",
    "hovercraft",
    "apollo-reentry",
    "asteroid-rendezvous",
)


def import_errors() -> dict[str, str]:
    """Mission modules that failed to import, with the error (empty when all is well)."""
    _missions()
    return dict(_IMPORT_ERRORS)


def list_missions() -> list[Mission]:
    """All built-in missions, in teaching order."""
    return list(_missions().values())


def get_mission(key: str) -> Mission:
    """The mission with this key; `ValueError` names the known keys otherwise."""
    missions = _missions()
    if key not in missions:
        raise ValueError(f"unknown mission '{key}' (missions: {', '.join(missions)})")
    return missions[key]
