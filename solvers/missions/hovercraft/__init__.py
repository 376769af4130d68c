"""Mission `hovercraft`: minimum-time steering with a thrust of constant magnitude (paper 004,
example 1; SPEC M5 case 1).

Three general methods solve the paper's problem (direct multiple shooting, the paper's own;
Hermite–Simpson collocation; LGL pseudospectral collocation), each in two stages (thrust
vector, then thrust angle: `two_stage.py`), and the maximum principle solves it
semi-analytically (`model.py`) as an independent reference stored with every solution.
"""

from __future__ import annotations

from ...context import SolveContext
from ...methods import HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING
from ...mission import Mission
from ...problem import Method
from ...solution import Solution
from . import problem, view
from .two_stage import solve_two_stage


class Hovercraft(Mission, records=problem):
    key = "hovercraft"
    title = "Hovercraft minimum time"
    summary = "Steer a constant thrust to reach a point and velocity in the least time."
    # SQP first for multiple shooting, as in the paper.
    methods = (MULTIPLE_SHOOTING.replace(nodes=(2, 10, 120), backends=("sqp", "ipopt")),
               HERMITE_SIMPSON.replace(nodes=(2, 10, 300), backends=("ipopt", "sqp")),
               LGL.replace(nodes=(4, 10, 60), backends=("ipopt", "sqp")))
    # A slider move re-solves in 10 ms by Hermite–Simpson, 25 ms by the paper's multiple
    # shooting and SQP (both `optimal` at their defaults, bench_missions 2026-12-07): the
    # explorer opens with it.
    live_method = "hermite-simpson"
    cost_label = "final time"
    cost_unit = "s"

    def solves_itself(self, method: Method) -> bool:
        """Every method runs the two-stage (thrust vector, then angle) solve."""
        return True

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        return solve_two_stage(values, method, nodes, backend, warm, ctx)

    _present = staticmethod(view.present)


MISSION = Hovercraft()
