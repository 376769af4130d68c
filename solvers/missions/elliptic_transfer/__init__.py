"""Mission `elliptic-transfer`: minimum-energy relative transfer about an elliptic target
orbit, Tschauner–Hempel equations in true anomaly, Legendre–Gauss–Lobatto pseudospectral
(paper 001, SPEC M2).

Three methods solve the same linear-quadratic problem (`methods.py`): the paper's two
closed-form laws (`stm-law`, eq. 10; `seq-law`, eq. 16; `laws.py`) and the same LGL
collocation handed to IPOPT as a general NLP (`lgl-nlp`), which must agree with `seq-law`.
"""

from __future__ import annotations

from ...context import SolveContext
from ...mission import Mission
from ...problem import Method
from ...solution import Solution
from . import problem, tables, view
from .methods import METHODS, solve_method
from .model import make_case


class EllipticTransfer(Mission, records=problem):
    key = "elliptic-transfer"
    title = "Relative transfer on an elliptic orbit"
    summary = ("Minimum-energy rendezvous about a 9500 km, e = 0.3 target orbit: "
               "Tschauner–Hempel equations, Legendre–Gauss–Lobatto pseudospectral laws.")
    methods = METHODS

    def help_tables(self) -> dict[str, str]:
        """The cost and convergence tables of help.md, computed once per process."""
        conv = tables.paper_convergence()
        return {**super().help_tables(),
                "k2": tables.sci(conv.k2, 5),
                "costs": tables.cost_markdown(conv, self.published),
                "convergence": tables.convergence_markdown(conv)}

    def _solve(self, values: dict[str, float], method: Method, nodes: int, backend: str,
               warm: Solution | None, ctx: SolveContext) -> Solution:
        case = make_case(values)
        problem.precheck_case(case)
        return solve_method(case, values, method, nodes, backend=backend, warm=warm, ctx=ctx)

    _present = staticmethod(view.present)


MISSION = EllipticTransfer()
