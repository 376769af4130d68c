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


def _constraints(h_and_jac: HAndJac, z: np.ndarray) -> np.ndarray:
    return np.atleast_1d(np.asarray(h_and_jac(z)[0], dtype=float))


@dataclass
class _AugmentedLagrangian:
    """L(z) = J(z) - lam . h(z) + (sigma / 2) |h(z)|^2 and its gradient, with the multipliers
    and the penalty the outer iterations update; counts its evaluations."""

    f_and_grad: FAndGrad
    h_and_jac: HAndJac
    lam: np.ndarray
    sigma: float
    evaluations: int = 0

    def __call__(self, z: np.ndarray) -> tuple[float, np.ndarray]:
        self.evaluations += 1
        f, g = self.f_and_grad(z)
        h, jac = self.h_and_jac(z)
        h = np.atleast_1d(np.asarray(h, dtype=float))
        jac = np.asarray(jac, dtype=float).reshape(self.lam.size, -1)
        val = float(f) - float(self.lam @ h) + 0.5 * self.sigma * float(h @ h)
        grad = np.asarray(g, dtype=float).ravel() + jac.T @ (self.sigma * h - self.lam)
        return val, grad


def _inner_tolerance(inner_gtol: float, h_norm_old: float, adaptive: bool) -> float:
    """The inner gradient tolerance of an outer iteration: loose while |h| is large."""
    if adaptive and np.isfinite(h_norm_old):
        return max(inner_gtol, min(1e-2, 0.1 * h_norm_old))
    return inner_gtol


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
    h = _constraints(h_and_jac, z)
    m = h.size
    lam = np.zeros(m) if lam0 is None else np.broadcast_to(np.asarray(lam0, float), (m,)).copy()
    tol = np.broadcast_to(np.asarray(tol_h, dtype=float), (m,))
    al = _AugmentedLagrangian(f_and_grad, h_and_jac, lam, float(sigma0))
    history: list[tuple[int, np.ndarray]] = [(0, z.copy())]
    h_norm_old = float(np.max(np.abs(h))) if np.all(np.isfinite(h)) else np.inf
    inner_total, H, converged, grad_norm, message, k = 0, None, False, float("nan"), "", 0
    for k in range(1, max_outer + 1):  # noqa: B007 - `k` is reported after the loop
        res = minimize_bfgs(al, z, ctx=ctx, max_iter=inner_max_iter,
                            gtol=_inner_tolerance(inner_gtol, h_norm_old, adaptive_inner),
                            inv_hessian0=H if reuse_hessian else None, max_step=max_step,
                            report_progress=False)
        inner_total += res.iterations
        grad_norm = res.grad_norm
        if not np.isfinite(res.f):
            message = f"the multiplier method stopped at outer iteration {k}: {res.message}"
            break
        z, H = res.z, res.inv_hessian
        h = _constraints(h_and_jac, z)
        h_norm = float(np.max(np.abs(h)))
        if k <= HISTORY_OUTER:
            history.append((k, z.copy()))
        if ctx is not None:
            ctx.report(k, f"multiplier iteration {k}: f = {float(f_and_grad(z)[0]):.10g}, "
                          f"|h| = {h_norm:.3g}, sigma = {al.sigma:g}")
        converged = bool(np.all(np.abs(h) <= tol) and grad_norm <= 10.0 * inner_gtol)
        al.lam = al.lam - al.sigma * h
        if converged:
            message = (f"converged in {k} outer / {inner_total} BFGS iterations, "
                       f"|h| = {h_norm:.3g}")
            break
        if h_norm > gamma * h_norm_old:
            al.sigma = min(beta * al.sigma, sigma_max)
        h_norm_old = h_norm
    else:
        message = (f"the multiplier method did not converge in {max_outer} outer iterations: "
                   f"|h| = {float(np.max(np.abs(h))):.3g}, inner |grad| = {grad_norm:.3g}")
    if history[-1][0] != k:
        history.append((k, z.copy()))
    return MultiplierResult(z, float(f_and_grad(z)[0]), h, al.lam, al.sigma, k, inner_total,
                            al.evaluations, converged, message, history, grad_norm)
