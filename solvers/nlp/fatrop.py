"""FATROP (Vanroye, Sathya, De Schutter & Decré 2023, via CasADi) on a stage-ordered copy of
a transcription's NLP.

FATROP's Riccati recursion needs the variables ordered stage by stage, [y_0, c_0, y_1, c_1,
..., y_N] (stage states y, stage controls c), and each stage's constraints to be the gap
y_k+1 - F(y_k, c_k) = 0 (coefficient exactly 1 on y_k+1) followed by constraints of stage k
alone. A transcription's own layout (all node states, then all controls, then the final
time) is not that, so a method that has a stage structure builds a `Stages`: the same problem
in stage order (the final time copied into every stage, `transcription.stages`), with index
maps to and from the original variables and constraints. The solver then sees the staged
problem and its caller the original one: starting point and bounds are mapped in, the
solution, multipliers and constraint values mapped back.

Through CasADi, FATROP takes a primal starting point only (no multipliers) and calls no
iteration callback: a warm re-solve starts from the previous optimum with a small barrier
parameter, and a stop (cancel, time limit) is checked only before and after a solve, never
mid-way (the solve service's hard limit still ends it); the one iterate kept is the start.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

# FATROP's return flags (fatrop/ip_algorithm/ip_algorithm.hpp, IpSolverReturnFlag) in
# IPOPT's vocabulary, which `casadi_nlp.status_of` reads.
RETURN_STATUS = ("Solve_Succeeded", "Maximum_Iterations_Exceeded",
                 "Search_Direction_Becomes_Too_Small", "Solved_To_Acceptable_Level",
                 "Infeasible_Problem_Detected", "Feasible_Point_Found", "Diverging_Iterates",
                 "Error_In_Step_Computation", "Invalid_Option", "Internal_Error")

_COMMON = {"print_level": 0, "tol": 1e-10, "constr_viol_tol": 1e-9, "max_iter": 3000}
# From a previous optimum: a small barrier parameter and bound push, as for IPOPT's warm start.
_WARM = {"mu_init": 1e-7, "bound_push": 1e-9, "bound_frac": 1e-9}


@dataclass(frozen=True, eq=False)
class Stages:
    """An NLP in FATROP's stage order and the maps to and from the original NLP.

    `x`, `f`, `g`: the staged problem (same parameters as the original); `nx`, `nu`, `ng`:
    stage states, stage controls and non-gap constraints of each stage k = 0..N.
    `source[i]`: the original variable that staged variable i copies; `bounded[i]`: whether
    it carries that variable's bounds (one copy of each does); `primary[j]`: the staged copy
    read back for original variable j; `rows[r]`, `signs[r]`: the staged constraint that is
    original constraint r, times sign (the gaps are the original defects negated)."""

    x: ca.SX | ca.MX
    f: ca.SX | ca.MX
    g: ca.SX | ca.MX
    nx: tuple[int, ...]
    nu: tuple[int, ...]
    ng: tuple[int, ...]
    source: np.ndarray
    bounded: np.ndarray
    primary: np.ndarray
    rows: np.ndarray
    signs: np.ndarray

    def solver(self, name: str, p: ca.SX | ca.MX, warm: bool) -> ca.Function:
        """The FATROP solver of the staged problem, with the stage sizes given explicitly
        (structure_detection "manual": the transcription knows its structure)."""
        opts = {"structure_detection": "manual", "N": len(self.nx) - 1, "nx": list(self.nx),
                "nu": list(self.nu), "ng": list(self.ng), "print_time": False,
                "fatrop": {**_COMMON, **(_WARM if warm else {})}}
        return ca.nlpsol(name, "fatrop", {"x": self.x, "f": self.f, "g": self.g, "p": p}, opts)

    def arguments(self, x0: np.ndarray, p: np.ndarray, lbx: np.ndarray, ubx: np.ndarray,
                  lbg: np.ndarray, ubg: np.ndarray) -> dict[str, np.ndarray]:
        """The staged solver's inputs from the original NLP's: each copy starts at its
        variable's value; bounds on one copy; the gaps equal zero."""
        n_g = int(self.g.numel())
        lo, hi = np.zeros(n_g), np.zeros(n_g)
        lo[self.rows] = np.where(self.signs > 0, lbg, -ubg)
        hi[self.rows] = np.where(self.signs > 0, ubg, -lbg)
        return {"x0": np.asarray(x0, float)[self.source], "p": p,
                "lbx": np.where(self.bounded, np.asarray(lbx, float)[self.source], -np.inf),
                "ubx": np.where(self.bounded, np.asarray(ubx, float)[self.source], np.inf),
                "lbg": lo, "ubg": hi}

    def original(self, out: dict, g_of: ca.Function, p: np.ndarray) -> dict[str, np.ndarray]:
        """The staged solver's outputs as the original NLP's (x, f, g, lam_x, lam_g); g is
        the original constraints evaluated at the mapped point."""
        x = np.asarray(out["x"]).ravel()[self.primary]
        return {"x": x, "f": float(out["f"]), "g": np.asarray(g_of(x, p)).ravel(),
                "lam_x": np.asarray(out["lam_x"]).ravel()[self.primary],
                "lam_g": self.signs * np.asarray(out["lam_g"]).ravel()[self.rows]}


def return_status(stats: dict) -> str:
    """FATROP's verdict in IPOPT's words (its own flag when unknown)."""
    flag = int(stats.get("fatrop", {}).get("return_flag", -1))
    return RETURN_STATUS[flag] if 0 <= flag < len(RETURN_STATUS) else f"FATROP_flag_{flag}"
