"""The solve service: worker processes that run every solve, build and check (see pool.py).
What it solves is a `solvers.request.SolveRequest`."""

from .job import Job
from .pool import SolveService
from .protocol import CheckUpdate

__all__ = ["CheckUpdate", "Job", "SolveService"]
