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


@dataclass(frozen=True)
class _LineSearch:
    """The weak-Wolfe line search's constants (see `minimize_bfgs`)."""

    c1: float
    c2: float
    max_trials: int
    f_noise: float


_Point = tuple[np.ndarray, float, np.ndarray, float]  # z, f, g and the step t that gave it


def _evaluate(fun_and_grad: FunAndGrad, z: np.ndarray) -> tuple[float, np.ndarray]:
    f, g = fun_and_grad(z)
    return float(f), np.asarray(g, dtype=float).ravel()


def _wolfe_step(fun_and_grad: FunAndGrad, z: np.ndarray, f: float, d: np.ndarray,
                slope: float, t: float, ls: _LineSearch) -> tuple[_Point | None, int]:
    """Weak-Wolfe bracketing/bisection along d from z (Lewis & Overton); a non-finite trial
    point shrinks the step. Returns the accepted point (or, when curvature never holds, the
    best sufficient-decrease point; None if there is none) and the evaluations spent."""
    lo, hi = 0.0, np.inf
    best = None
    for trial in range(1, ls.max_trials + 1):
        zt = z + t * d
        ft, gt = _evaluate(fun_and_grad, zt)
        finite = _finite(ft, gt)
        dslope = float(gt @ d) if finite else np.nan
        armijo = finite and (
            ft <= f + ls.c1 * t * slope
            or (ft <= f + ls.f_noise * max(1.0, abs(f)) and dslope <= (2 * ls.c1 - 1) * slope)
        )
        if not armijo:
            hi = t
        else:
            if best is None or ft < best[1]:
                best = (zt, ft, gt, t)
            if dslope < ls.c2 * slope:
                lo = t
            else:
                return (zt, ft, gt, t), trial
        t = 0.5 * (lo + hi) if np.isfinite(hi) else 2.0 * lo
    return best, ls.max_trials


def _bfgs_update(H: np.ndarray, s: np.ndarray, y: np.ndarray,
                 scaled: bool) -> tuple[np.ndarray, bool]:
    """The inverse-Hessian BFGS update with step s and gradient change y, skipped when the
    curvature s·y is not safely positive; the first update scales the identity by s·y/y·y."""
    sy = float(s @ y)
    if not (sy > 1e-12 * float(np.linalg.norm(s) * np.linalg.norm(y)) and sy > 0.0):
        return H, scaled
    if not scaled:
        H = np.eye(s.size) * (sy / float(y @ y))
    rho = 1.0 / sy
    Hy = H @ y
    H = (H - rho * (np.outer(s, Hy) + np.outer(Hy, s))
         + (rho * rho * float(y @ Hy) + rho) * np.outer(s, s))
    return H, True


def _descent_direction(H: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, float, bool]:
    """d = -H g and its slope g·d; if H lost positive definiteness, a restart along -g
    (the returned flag says whether H is kept)."""
    d = -H @ g
    slope = float(g @ d)
    if slope < 0.0:
        return d, slope, True
    return -g, float(g @ -g), False


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
    ls = _LineSearch(c1, c2, max_line_search, f_noise)
    z = np.array(z0, dtype=float).ravel()
    n = z.size
    f, g = _evaluate(fun_and_grad, z)
    nev = 1
    if not _finite(f, g):
        return BFGSResult(z, f, float("inf"), 0, nev, False,
                          "the objective is not finite at the starting point", g, None)
    scaled = inv_hessian0 is not None
    H = np.array(inv_hessian0, dtype=float) if scaled else np.eye(n)
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
        d, slope, kept = _descent_direction(H, g)
        if not kept:
            H, scaled = np.eye(n), False
        dmax = float(np.max(np.abs(d))) if max_step is not None else 0.0
        t = max_step / dmax if max_step is not None and dmax > max_step else 1.0
        accepted, spent = _wolfe_step(fun_and_grad, z, f, d, slope, t, ls)
        nev += spent
        if accepted is None:
            message = "line search failed to find a decrease"
            break
        z_new, f_new, g_new, _ = accepted
        H, scaled = _bfgs_update(H, z_new - z, g_new - g, scaled)
        f_old = f
        z, f, g = z_new, f_new, g_new
        if ftol > 0.0 and f_old - f <= ftol * max(1.0, abs(f)):
            converged, message = True, "relative decrease of f below tolerance"
            break
    gnorm = float(np.max(np.abs(g))) if n else 0.0
    if not converged and gnorm <= gtol:
        converged, message = True, "gradient below tolerance"
    return BFGSResult(z, f, gnorm, it, nev, converged, message, g, H)
