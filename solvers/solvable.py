"""What the solve pipeline (refinement, the cost error estimate, the interval error) asks of a
mission: `Mission` satisfies it, and the pipeline modules type against this protocol, so
`Mission.solve` can call them without their importing `Mission` back."""

from __future__ import annotations

import threading
from collections.abc import Mapping
from typing import Protocol

import numpy as np

from .context import ProgressCallback, SolveContext
from .ocp import OCP, OCPResult
from .problem import Method, Param
from .solution import Solution


class SolvableMission(Protocol):
    """The records and hooks of `Mission` that refinement and the checks use."""

    key: str
    cost_rtol: float

    def method(self, key: str | None) -> Method:
        """The method `key` (None: the first)."""

    def validate(self, values: Mapping[str, float] | None, method: str | None = None,
                 nodes: int | str | None = None) -> tuple[dict[str, float], Method, int]:
        """Complete and check a request; `ValueError` names what is wrong."""

    def accuracy_targets(self, tol: float | None = None) -> dict[str, float]:
        """The re-propagated miss targets."""

    def solve(self, values: Mapping[str, float] | None = None, method: str | None = None,
              nodes: int | str | None = None, *, tol: float | None = None,
              backend: str | None = None, warm: Solution | None = None, cold: bool = False,
              progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None, time_limit: float | None = ...,
              verify: bool = True) -> Solution:
        """Solve one request (see `Mission.solve`)."""

    methods: tuple[Method, ...]

    def all_params(self, method: str | None = None) -> tuple[Param, ...]:
        """The mission's params and the method's own."""

    def solve_validated(self, vals: dict[str, float], m: Method, n: int, backend: str,
                        warm: Solution | None, ctx: SolveContext) -> Solution:
        """One solve of a validated request, without its checks or any rescue."""

    def ocp(self, method: Method, values: dict[str, float]) -> OCP:
        """The optimal control problem the general methods solve."""

    def check_direct(self, problem: OCP, p: np.ndarray, res: OCPResult) -> dict[str, float]:
        """The re-propagated terminal miss of a general method's answer."""

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str] | None:
        """Per-interval state errors in the headline miss's unit, or None."""

    def indirect_reference(self, sol: Solution, p: np.ndarray) -> None:
        """Attach the indirect method's reference to `sol` where the mission has one."""

    def check_atol(self, ocp: OCP) -> np.ndarray:
        """Absolute tolerances of the re-propagation."""
