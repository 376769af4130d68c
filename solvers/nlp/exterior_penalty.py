"""Exterior penalty method with a BFGS inner solver (paper 000, eq. 12).

Minimises P(z) = f(z) + M_k * sum(violation_i(z)^2) for an increasing penalty sequence
M_k, each from the previous minimiser. Equalities and inequalities (including finite
variable bounds) count through their violations. The constraint error shrinks only like 1/M_k
and the problem grows ill-conditioned with M_k: the method is slow and inaccurate next to
an interior-point or SQP solver, which is why a class should see it.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..context import SolveContext
from .bfgs import minimize_bfgs

PENALTY_SEQUENCE = (1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8)
VIOLATION_TOL = 1e-7


def penalty_functions(x: ca.SX, f: ca.SX, g: ca.SX, p: ca.SX) -> ca.Function:
    """(z, p) -> (f, grad f, g, dg/dz) as one numeric Function."""
    return ca.Function(
        "penalty_parts", [x, p], [f, ca.gradient(f, x), g, ca.jacobian(g, x)]
    )


def solve_exterior_penalty(
    parts: ca.Function,
    x0: np.ndarray,
    p: np.ndarray,
    lbx: np.ndarray,
    ubx: np.ndarray,
    lbg: np.ndarray,
    ubg: np.ndarray,
    ctx: SolveContext | None = None,
    sequence: tuple[float, ...] = PENALTY_SEQUENCE,
) -> tuple[np.ndarray, float, np.ndarray, int, bool, list[tuple[int, np.ndarray]]]:
    """Returns (z, f, g, iterations, converged, history)."""
    fixed = lbx == ubx
    free = ~fixed
    z_full = np.where(fixed, lbx, np.clip(x0, lbx, ubx))
    box_lb = np.where(np.isfinite(lbx[free]), lbx[free], -np.inf)
    box_ub = np.where(np.isfinite(ubx[free]), ubx[free], np.inf)

    def evaluate(zf: np.ndarray):
        z = z_full.copy()
        z[free] = zf
        f, df, g, J = parts(z, p)
        g = np.asarray(g).ravel()
        J = np.asarray(ca.densify(J))[:, free]
        return float(f), np.asarray(df).ravel()[free], g, J

    history: list[tuple[int, np.ndarray]] = [(0, z_full.copy())]
    zf = z_full[free]
    total_iterations = 0
    converged = False
    for k, weight in enumerate(sequence, start=1):

        def fun_and_grad(zf: np.ndarray, weight: float = weight):
            f, df, g, J = evaluate(zf)
            viol = np.maximum(g - ubg, 0.0) - np.maximum(lbg - g, 0.0)
            box = np.maximum(zf - box_ub, 0.0) - np.maximum(box_lb - zf, 0.0)
            value = f + weight * (viol @ viol + box @ box)
            grad = df + 2 * weight * (J.T @ viol + box)
            return value, grad

        inner = minimize_bfgs(fun_and_grad, zf, ctx=None, max_iter=400, gtol=1e-9,
                              report_progress=False)
        zf = inner.z
        total_iterations += inner.iterations
        if ctx is not None:
            ctx.report(k, f"penalty M = {weight:g}")
        z = z_full.copy()
        z[free] = zf
        history.append((k, z))
        _, _, g, _ = evaluate(zf)
        violation = _violation(g, lbg, ubg, zf, box_lb, box_ub)
        if violation < VIOLATION_TOL:
            converged = True
            break
    f, _, g, _ = evaluate(zf)
    z = z_full.copy()
    z[free] = zf
    return z, f, g, total_iterations, converged, history


def _violation(g, lbg, ubg, zf, box_lb, box_ub) -> float:
    return float(
        max(
            np.max(np.maximum(g - ubg, 0.0), initial=0.0),
            np.max(np.maximum(lbg - g, 0.0), initial=0.0),
            np.max(np.maximum(zf - box_ub, 0.0), initial=0.0),
            np.max(np.maximum(box_lb - zf, 0.0), initial=0.0),
        )
    )
