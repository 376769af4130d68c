"""The solve service: worker processes that run every solve, build and check (see pool.py)."""

from .job import Job
from .pool import SolveService
from .protocol import CheckUpdate, SolveSpec

__all__ = ["CheckUpdate", "Job", "SolveService", "SolveSpec"]
