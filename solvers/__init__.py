"""Numerics of the trajectory explorer: missions, transcriptions, NLP back ends (no GUI)."""

from .mission import Mission
from .problem import Method, Param, Preset, Published
from .registry import get_mission, list_missions
from .solution import Solution

__all__ = [
    "Method",
    "Mission",
    "Param",
    "Preset",
    "Published",
    "Solution",
    "get_mission",
    "list_missions",
]
