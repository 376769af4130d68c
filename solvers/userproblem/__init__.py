"""Declare your own optimal control problem; the general methods, the CLI and the explorer
do the rest.

    from solvers.userproblem import Control, FreeTime, Param, State, UserMission

    MISSION = UserMission(key="my-problem", title="...", states=(State("x", "m", ...), ...),
                          controls=(Control("a", "m/s²", bounds=(-1, 1)),),
                          dynamics=lambda x, u, p: [x.v, u.a], final_time=FreeTime(2.0),
                          minimum_time=True)

A mission file defines `MISSION` like this (`python -m solvers solve my-problem
--mission-file my_problem.py`); the README's "Bring your own problem"
describes every field.
"""

from ..handles import Axis, Handle
from ..methods import HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING
from ..problem import Consistency, Param, Preset, Published
from ..shapes import Box, Cone, Cylinder, Plane, Sphere
from .errors import DeclarationError
from .mission import UserMission
from .records import Control, FinalConstraint, FreeTime, Named, PathConstraint, State

__all__ = [
    "HERMITE_SIMPSON",
    "LGL",
    "MULTIPLE_SHOOTING",
    "Axis",
    "Box",
    "Cone",
    "Consistency",
    "Control",
    "Cylinder",
    "DeclarationError",
    "FinalConstraint",
    "FreeTime",
    "Handle",
    "Named",
    "Param",
    "PathConstraint",
    "Plane",
    "Preset",
    "Published",
    "Sphere",
    "State",
    "UserMission",
]
