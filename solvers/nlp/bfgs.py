"""A small, generic BFGS quasi-Newton minimiser (inverse-Hessian form) with a weak-Wolfe
line search that tolerates non-finite trial points.

Used as the inner solver of the multiplier (augmented Lagrangian) method and of penalty
methods. The objective and its gradient come from one callback `fun_and_grad(z) -> (f, g)`
(e.g. a CasADi Function with exact AD gradients). A trial point whose value or gradient is
NaN/inf (a trajectory that could not be integrated) is treated as "too far" and the step is
shortened, so the iterates never leave the region where the objective is defined.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..context import SolveContext

FunAndGrad = Callable[[np.ndarray], tuple[float, np.ndarray]]


@dataclass
class BFGSResult:
    """Outcome of `minimize_bfgs`. `inv_hessian` can seed a later, similar minimisation."""

    z: np.ndarray
    f: float
    grad_norm: float  # infinity norm of the gradient at z
    iterations: int
    evaluations: int
    converged: bool
    message: str = ""
    grad: np.ndarray | None = None
    inv_hessian: np.ndarray | None = None


def _finite(f: float, g: np.ndarray) -> bool:
    return bool(np.isfinite(f)) and bool(np.all(np.isfinite(g)))


def minimize_bfgs(
    fun_and_grad: FunAndGrad,
    z0,
    ctx: SolveContext | None = None,
    max_iter: int = 200,
    gtol: float = 1e-8,
    *,
    ftol: float = 0.0,
    inv_hessian0: np.ndarray | None = None,
    max_step: float | None = None,
    c1: float = 1e-4,
    c2: float = 0.9,
    max_line_search: int = 30,
    f_noise: float = 1e-12,
    report_progress: bool = True,
) -> BFGSResult:
    """Minimise f(z) from z0 with BFGS.

    Stops when the infinity norm of the gradient is <= gtol (converged), when a step
    reduces f by less than `ftol * max(1, |f|)` (converged if ftol > 0), after `max_iter`
    iterations, or when the line search fails (not converged). `max_step` caps the
    infinity norm of a trial step. Near the noise floor of f the sufficient-decrease test
    also accepts the approximate Wolfe condition of Hager & Zhang (f may rise by at most
    `f_noise * max(1, |f|)` when the directional derivative has fallen enough).
    `ctx.report` is called every iteration when `report_progress` (else only
    `ctx.checkpoint`), so `Cancelled`/`TimeLimit` propagate.
    """
    z = np.array(z0, dtype=float).ravel()
    n = z.size
    nev = 0
    f, g = fun_and_grad(z)
    f = float(f)
    g = np.asarray(g, dtype=float).ravel()
    nev += 1
    if not _finite(f, g):
        return BFGSResult(z, f, float("inf"), 0, nev, False,
                          "the objective is not finite at the starting point", g, None)
    if inv_hessian0 is not None:
        H = np.array(inv_hessian0, dtype=float)
        scaled = True
    else:
        H = np.eye(n)
        scaled = False
    message = f"iteration limit of {max_iter} reached"
    converged = False
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - `it` is reported after the loop
        gnorm = float(np.max(np.abs(g))) if n else 0.0
        if gnorm <= gtol:
            converged, message, it = True, "gradient below tolerance", it - 1
            break
        if ctx is not None:
            if report_progress:
                ctx.report(it, f"BFGS iteration {it}: f = {f:.10g}, |g| = {gnorm:.3g}")
            else:
                ctx.checkpoint()
        d = -H @ g
        slope = float(g @ d)
        if not slope < 0.0:  # H lost positive definiteness: restart along -g
            H = np.eye(n)
            scaled = False
            d = -g
            slope = float(g @ d)
        t = 1.0
        if max_step is not None:
            dmax = float(np.max(np.abs(d)))
            if dmax > max_step:
                t = max_step / dmax
        # Weak-Wolfe bracketing/bisection (Lewis & Overton); non-finite points shrink the step.
        lo, hi = 0.0, np.inf
        accepted = None
        best = None  # best Armijo point, a fallback when curvature never holds
        for _ in range(max_line_search):
            zt = z + t * d
            ft, gt = fun_and_grad(zt)
            ft = float(ft)
            gt = np.asarray(gt, dtype=float).ravel()
            nev += 1
            finite = _finite(ft, gt)
            dslope = float(gt @ d) if finite else np.nan
            armijo = finite and (
                ft <= f + c1 * t * slope
                or (ft <= f + f_noise * max(1.0, abs(f)) and dslope <= (2 * c1 - 1) * slope)
            )
            if not armijo:
                hi = t
            else:
                if best is None or ft < best[1]:
                    best = (zt, ft, gt, t)
                if dslope < c2 * slope:
                    lo = t
                else:
                    accepted = (zt, ft, gt, t)
                    break
            t = 0.5 * (lo + hi) if np.isfinite(hi) else 2.0 * lo
        if accepted is None:
            accepted = best
        if accepted is None:
            message = "line search failed to find a decrease"
            break
        z_new, f_new, g_new, t = accepted
        s = z_new - z
        y = g_new - g
        sy = float(s @ y)
        f_old = f
        z, f, g = z_new, f_new, g_new
        if sy > 1e-12 * float(np.linalg.norm(s) * np.linalg.norm(y)) and sy > 0.0:
            if not scaled:
                H = np.eye(n) * (sy / float(y @ y))
                scaled = True
            rho = 1.0 / sy
            Hy = H @ y
            H = (H - rho * (np.outer(s, Hy) + np.outer(Hy, s))
                 + (rho * rho * float(y @ Hy) + rho) * np.outer(s, s))
        if ftol > 0.0 and f_old - f <= ftol * max(1.0, abs(f)):
            converged, message = True, "relative decrease of f below tolerance"
            break
    gnorm = float(np.max(np.abs(g))) if n else 0.0
    if not converged and gnorm <= gtol:
        converged, message = True, "gradient below tolerance"
    return BFGSResult(z, f, gnorm, it, nev, converged, message, g, H)
