"""The generalised multiplier method (augmented Lagrangian, Hestenes-Powell) for equality
constrained problems  min J(z)  s.t.  h(z) = 0,  with BFGS as the inner solver.

Each outer iteration minimises

    L(z) = J(z) - lam . h(z) + (sigma / 2) |h(z)|^2

with BFGS from the previous minimiser, then updates the multipliers  lam <- lam - sigma h
and, when |h| did not fall by the factor gamma (|h_new| > gamma |h_old|), the penalty
sigma <- beta sigma. These are the rules of paper 002 (sigma0 = 20, beta = 2, gamma = 0.5).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..context import SolveContext
from .bfgs import minimize_bfgs

FAndGrad = Callable[[np.ndarray], tuple[float, np.ndarray]]
HAndJac = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]

HISTORY_OUTER = 8  # snapshots after each of the first outer iterations (plus the start, last)


@dataclass
class MultiplierResult:
    z: np.ndarray
    f: float
    h: np.ndarray
    lam: np.ndarray
    sigma: float
    outer_iterations: int
    inner_iterations: int
    evaluations: int
    converged: bool
    message: str
    history: list[tuple[int, np.ndarray]] = field(default_factory=list)
    inner_grad_norm: float = float("nan")


def solve_multiplier_method(
    f_and_grad: FAndGrad,
    h_and_jac: HAndJac,
    z0,
    sigma0: float = 20.0,
    beta: float = 2.0,
    gamma: float = 0.5,
    lam0=None,
    tol_h=1e-8,
    ctx: SolveContext | None = None,
    max_outer: int = 50,
    *,
    inner_gtol: float = 1e-8,
    inner_max_iter: int = 200,
    max_step: float | None = None,
    reuse_hessian: bool = True,
    sigma_max: float = 1e12,
    adaptive_inner: bool = True,
) -> MultiplierResult:
    """Solve min f(z) s.t. h(z) = 0 by the multiplier method.

    `f_and_grad(z) -> (f, grad f)`, `h_and_jac(z) -> (h (m,), dh/dz (m, n))`. `tol_h` is a
    scalar or per-constraint bound on |h_i|; convergence needs |h_i| <= tol_h_i and an inner
    gradient norm <= 10 inner_gtol. Callers with an expensive shared evaluation should cache
    it (both callbacks are called at the same z in turn). `ctx.report` is called once per
    outer iteration; `Cancelled`/`TimeLimit` propagate. With `adaptive_inner` the inner
    gradient tolerance of an outer iteration is max(inner_gtol, min(1e-2, 0.1 |h_old|)):
    early subproblems, whose multipliers are still poor, are solved loosely.
    """
    z = np.array(z0, dtype=float).ravel()
    h0, _ = h_and_jac(z)
    h0 = np.atleast_1d(np.asarray(h0, dtype=float))
    m = h0.size
    lam = np.zeros(m) if lam0 is None else np.broadcast_to(np.asarray(lam0, float), (m,)).copy()
    tol = np.broadcast_to(np.asarray(tol_h, dtype=float), (m,))
    sigma = float(sigma0)
    evaluations = 0

    def lagrangian(zz: np.ndarray) -> tuple[float, np.ndarray]:
        nonlocal evaluations
        evaluations += 1
        f, g = f_and_grad(zz)
        h, jac = h_and_jac(zz)
        h = np.atleast_1d(np.asarray(h, dtype=float))
        jac = np.asarray(jac, dtype=float).reshape(m, -1)
        val = float(f) - float(lam @ h) + 0.5 * sigma * float(h @ h)
        grad = np.asarray(g, dtype=float).ravel() + jac.T @ (sigma * h - lam)
        return val, grad

    history: list[tuple[int, np.ndarray]] = [(0, z.copy())]
    h_norm_old = float(np.max(np.abs(h0))) if np.all(np.isfinite(h0)) else np.inf
    h = h0
    inner_total = 0
    H = None
    converged = False
    grad_norm = float("nan")
    message = ""
    k = 0
    for k in range(1, max_outer + 1):  # noqa: B007 - `k` is reported after the loop
        gtol_k = inner_gtol
        if adaptive_inner and np.isfinite(h_norm_old):
            gtol_k = max(inner_gtol, min(1e-2, 0.1 * h_norm_old))
        res = minimize_bfgs(lagrangian, z, ctx=ctx, max_iter=inner_max_iter, gtol=gtol_k,
                            inv_hessian0=H if reuse_hessian else None, max_step=max_step,
                            report_progress=False)
        inner_total += res.iterations
        grad_norm = res.grad_norm
        if not np.isfinite(res.f):
            message = (f"the multiplier method stopped at outer iteration {k}: "
                       f"{res.message}")
            break
        z = res.z
        H = res.inv_hessian
        h, _ = h_and_jac(z)
        h = np.atleast_1d(np.asarray(h, dtype=float))
        f_val = float(f_and_grad(z)[0])
        h_norm = float(np.max(np.abs(h)))
        if k <= HISTORY_OUTER:
            history.append((k, z.copy()))
        if ctx is not None:
            ctx.report(k, f"multiplier iteration {k}: f = {f_val:.10g}, |h| = {h_norm:.3g}, "
                          f"sigma = {sigma:g}")
        if np.all(np.abs(h) <= tol) and grad_norm <= 10.0 * inner_gtol:
            lam = lam - sigma * h
            converged = True
            message = (f"converged in {k} outer / {inner_total} BFGS iterations, "
                       f"|h| = {h_norm:.3g}")
            break
        lam = lam - sigma * h
        if h_norm > gamma * h_norm_old:
            sigma = min(beta * sigma, sigma_max)
        h_norm_old = h_norm
    else:
        message = (f"the multiplier method did not converge in {max_outer} outer iterations: "
                   f"|h| = {float(np.max(np.abs(h))):.3g}, inner |grad| = {grad_norm:.3g}")
    if history[-1][0] != k:
        history.append((k, z.copy()))
    f_final = float(f_and_grad(z)[0])
    return MultiplierResult(z, f_final, h, lam, sigma, k, inner_total, evaluations, converged,
                            message, history, grad_norm)
