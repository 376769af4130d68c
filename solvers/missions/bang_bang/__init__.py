"""Mission `bang-bang`: a cart on a rail in minimum time, the textbook bang–bang problem with
the analytic optimum T* = 2 sqrt(d/a). One folder, no code outside it: the general methods
solve its OCP, and the explorer and the CLI list it by themselves."""

from __future__ import annotations

import numpy as np

from ...methods import HERMITE_SIMPSON, LGL, MULTIPLE_SHOOTING
from ...mission import Mission
from ...ocp import OCPResult
from ...solution import Quantity, Solution
from . import problem, view


class BangBang(Mission, records=problem):
    key = "bang-bang"
    title = "Cart on a rail, minimum time"
    summary = "Rest to rest over a distance with bounded acceleration, in the least time."
    methods = (HERMITE_SIMPSON.replace(nodes=(4, 100, 200)),
               MULTIPLE_SHOOTING.replace(nodes=(4, 100, 200)), LGL.replace(nodes=(6, 40, 80)))
    cost_label = "final time"
    cost_unit = "s"

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        optimum = problem.optimal_time(p)
        sol.quantities = {
            "T": Quantity(res.T, "final time", "s"),
            "T_analytic": Quantity(optimum, "T* = 2√(d/a)", "s"),
            "T_error": Quantity(res.T - optimum, "T − T*", "s"),
        }

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        return {"position_miss_m": float(x_final[0] - p[problem.P_D]),
                "velocity_miss_m_s": float(x_final[1])}

    _present = staticmethod(view.present)


MISSION = BangBang()
