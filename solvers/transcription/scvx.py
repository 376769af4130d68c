"""Successive convexification (SCvx; Mao, Szmuk & Açıkmeşe 2016) as a general method: any
`OCP` is transcribed by Hermite–Simpson collocation, and the resulting nonconvex NLP

    min f(z, p)  s.t.  lbg <= g(z, p) <= ubg,  lbx <= z <= ubx

is solved by a sequence of convex subproblems, each about the last iterate z_k:

    min  ∇f·d + ½ dᵀ B d + λ (Σ|ν| + Σ s)
    s.t. g_E + J_E d = b_E + ν            (equalities: dynamics, end conditions; ν virtual control)
         lb - s <= g_I + J_I d <= ub + s  (inequalities: path constraints, s >= 0 virtual buffer)
         lbx <= z_k + d <= ubx,  |d|_∞ <= η  (the trust region)

with the Jacobians from CasADi (exact, sparse) and each subproblem a QP solved by Clarabel
(built in its standard conic form: the Jacobian's values change every iteration, which a
parametric modelling layer would re-canonicalise anyway).

Two departures from Mao et al.'s first-order subproblem, both because a general OCP does not
say which of its constraints are convex (SCvx keeps those exact; here every constraint is
linearised): B is the Hessian of the Lagrangian at the last multipliers shifted to be
positive semidefinite (without it the second-order violation of the linearised convex
constraints, charged λ d², held the trust region near 1e-4 and SCvx stalled 10 % above the
optimum), and a step the ratio test would shrink gets a second-order correction (Fletcher:
the same QP with g(z + d) - J d as its constant) before it is judged. `curvature=False`
gives the first-order subproblem. A step is judged on the nonlinear
penalised cost Φ(z) = f + λ (Σ|g_E - b_E| + Σ violation(g_I)): the ratio ρ of the actual to
the predicted reduction rejects it (ρ < ρ0) or accepts it and shrinks (ρ < ρ1) or grows
(ρ >= ρ2) the trust region. SCvx stops when the predicted reduction vanishes at a point that
satisfies the constraints.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import clarabel
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackNoConvergence, eigsh

from ..context import SolveContext
from ..nlp.casadi_nlp import NLPResult
from ..ocp import OCP
from .hermite_simpson import HermiteSimpson


@dataclass(frozen=True)
class SCvxSettings:
    """Mao et al.'s parameters (ρ0, ρ1, ρ2, shrink α, grow β) and the stopping rule."""

    penalty: float = 10.0  # λ at the start; ×10 while a converged point is infeasible
    penalty_max: float = 1e7
    prox: float = 1e-6  # w, a small proximal term: a unique step where the LP is degenerate
    # The convexified curvature of the Lagrangian in the subproblem's cost (see the module
    # docstring); False gives Mao et al.'s first-order subproblem.
    curvature: bool = True
    radius: float = 1.0  # initial trust region (scaled variables, ∞-norm)
    radius_min: float = 1e-10
    radius_max: float = 10.0
    rho0: float = 0.0
    rho1: float = 0.25
    rho2: float = 0.7
    shrink: float = 2.0
    grow: float = 3.2
    tol: float = 1e-8  # predicted reduction, relative to 1 + |Φ|
    feasible: float = 1e-8  # largest constraint violation of a converged point
    max_iter: int = 300


class SCvxSolver:
    """SCvx on a parametric NLP given symbolically (the same (z, f, g, p) a `casadi_nlp.NLP`
    takes); `solve` has `NLP.solve`'s signature and result."""

    def __init__(self, z: ca.SX, f: ca.SX, g: ca.SX, p: ca.SX,
                 settings: SCvxSettings | None = None) -> None:
        self.settings = settings or SCvxSettings()
        self.n_x, self.n_g = int(z.numel()), int(g.numel())
        self._values = ca.Function("scvx_values", [z, p], [f, g])
        self._linear = ca.Function("scvx_linear", [z, p],
                                   [f, ca.gradient(f, z), g, ca.jacobian(g, z)])
        mu = ca.SX.sym("mu", self.n_g) if isinstance(z, ca.SX) else ca.MX.sym("mu", self.n_g)
        self._hessian = ca.Function("scvx_hessian", [z, p, mu],
                                    [ca.hessian(f + ca.dot(mu, g), z)[0]])

    def solve(self, x0: np.ndarray, p: np.ndarray, lbx: np.ndarray, ubx: np.ndarray,
              lbg: np.ndarray, ubg: np.ndarray, lam_x0: np.ndarray | None = None,
              lam_g0: np.ndarray | None = None, ctx: SolveContext | None = None) -> NLPResult:
        """Iterate from x0 until converged; raises `Cancelled`/`TimeLimit` via `ctx`."""
        s = self.settings
        rows = _Rows(np.asarray(lbg, float), np.asarray(ubg, float))
        lbx, ubx = np.asarray(lbx, float), np.asarray(ubx, float)
        qp = _Subproblem(rows, lbx, ubx)
        z = np.clip(np.asarray(x0, float), lbx, ubx)
        penalty = s.penalty
        phi, f, g = self._merit(z, p, rows, penalty)
        radius, history, status = s.radius, [(0, z.copy())], "Maximum_Iterations_Exceeded"
        mu, k = np.zeros(self.n_g), 0
        for k in range(1, s.max_iter + 1):
            if ctx is not None:
                ctx.report(k, f"SCvx iteration {k}, trust region {radius:.2g}")
            f0, grad, g0, jac = self._linearised(z, p)
            curvature = self._curvature(z, p, mu) if s.curvature else None
            step = qp.solve(f0, grad, g0, jac, z, radius, s, curvature, penalty)
            if step is None:
                radius /= s.shrink
                if radius < s.radius_min:
                    status = "Subproblem_Failed"
                    break
                continue
            d, predicted_value, mu_step = step
            predicted = phi - predicted_value
            if predicted <= s.tol * (1 + abs(phi)):
                if rows.violation(g) <= s.feasible:
                    status = "Solve_Succeeded"
                    break
                if penalty >= s.penalty_max:
                    status = "Infeasible_Problem_Detected"
                    break
                penalty *= 10.0  # λ below the multipliers: a stationary point of Φ that
                phi = self._merit(z, p, rows, penalty)[0]  # is not feasible; penalise harder
                continue
            trial = (*self._merit(z + d, p, rows, penalty), mu_step)
            if (phi - trial[0]) / predicted < s.rho1:
                d, trial = self._corrected(qp, (f0, grad, jac, curvature), z, p, rows, radius,
                                           penalty, d, trial, phi, predicted)
            ratio = (phi - trial[0]) / predicted
            if ratio < s.rho0:
                radius /= s.shrink
            else:
                z, (phi, f, g, mu) = z + d, trial
                history.append((k, z.copy()))
                if ratio < s.rho1:
                    radius /= s.shrink
                elif ratio >= s.rho2:
                    radius = min(radius * s.grow, s.radius_max)
            if radius < s.radius_min:
                status = ("Solve_Succeeded" if rows.violation(g) <= s.feasible
                          else "Search_Direction_Becomes_Too_Small")
                break
        return NLPResult(x=z, f=f, g=g, lam_x=np.zeros(self.n_x), lam_g=np.zeros(self.n_g),
                         iterations=k, return_status=status,
                         success=status == "Solve_Succeeded", max_violation=rows.violation(g),
                         history=history[:1] + history[1:][-12:])

    def _linearised(self, z: np.ndarray, p: np.ndarray
                    ) -> tuple[float, np.ndarray, np.ndarray, sp.coo_matrix]:
        """f, its gradient, g and its (sparse) Jacobian at z: the subproblem's model."""
        f0, grad, g0, jac = self._linear(z, p)
        return (float(f0), np.asarray(grad).ravel(), np.asarray(g0).ravel(),
                sp.coo_matrix(jac.sparse()))

    def _corrected(self, qp: _Subproblem, model: tuple, z: np.ndarray, p: np.ndarray,
                   rows: _Rows, radius: float, penalty: float, d: np.ndarray, trial: tuple,
                   phi: float, predicted: float) -> tuple[np.ndarray, tuple]:
        """A second-order correction (Fletcher) of a step the merit function rejects: the
        curvature the linearisation missed, g(z + d) - J d, as the constant of a second QP;
        kept only if it does better. `trial` is (merit, f, g, multipliers) at z + d."""
        f0, grad, jac, curvature = model
        again = qp.solve(f0, grad, trial[2] - jac @ d, jac, z, radius, self.settings,
                         curvature, penalty)
        if again is None:
            return d, trial
        corrected = (*self._merit(z + again[0], p, rows, penalty), again[2])
        return (again[0], corrected) if corrected[0] < trial[0] else (d, trial)

    def _curvature(self, z: np.ndarray, p: np.ndarray, mu: np.ndarray) -> sp.csc_matrix:
        """The Hessian of the Lagrangian f + μᵀg at z shifted by its most negative eigenvalue
        (sparse Lanczos), so positive semidefinite: a convex quadratic model of the curvature
        the linearised constraints leave out. Where Lanczos does not converge, the least
        diagonal shift that makes it diagonally dominant (safe, more conservative)."""
        H = sp.csc_matrix(self._hessian(z, p, mu).sparse())
        H = sp.csc_matrix(0.5 * (H + H.T))
        if H.nnz == 0:
            return H
        try:
            lowest = float(eigsh(H, k=1, which="SA", tol=1e-4, maxiter=2000,
                                 return_eigenvectors=False)[0])
            shift = sp.identity(H.shape[0]) * max(-1.05 * lowest, 0.0)
        except (ArpackNoConvergence, ValueError):  # no convergence, or too small for ARPACK
            diagonal = H.diagonal()
            off = np.asarray(abs(H).sum(axis=1)).ravel() - np.abs(diagonal)
            shift = sp.diags(np.maximum(off - diagonal, 0.0))
        return sp.csc_matrix(H + shift)

    def _merit(self, z: np.ndarray, p: np.ndarray, rows: _Rows, penalty: float
               ) -> tuple[float, float, np.ndarray]:
        """Φ(z) = f + λ × (the L1 constraint violation), f and g."""
        f, g = (np.asarray(a).ravel() for a in self._values(z, p))
        return float(f[0]) + penalty * rows.l1(g), float(f[0]), g


class _Rows:
    """Which constraint rows are equalities and which sides of the others are finite."""

    def __init__(self, lbg: np.ndarray, ubg: np.ndarray) -> None:
        self.lbg, self.ubg = lbg, ubg
        self.eq = np.flatnonzero(lbg == ubg)
        ineq = lbg != ubg
        self.up = np.flatnonzero(ineq & np.isfinite(ubg))
        self.lo = np.flatnonzero(ineq & np.isfinite(lbg))

    def excess(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.abs(g[self.eq] - self.lbg[self.eq]),
                np.maximum(g[self.up] - self.ubg[self.up], 0.0),
                np.maximum(self.lbg[self.lo] - g[self.lo], 0.0))

    def l1(self, g: np.ndarray) -> float:
        return float(sum(np.sum(e) for e in self.excess(g)))

    def violation(self, g: np.ndarray) -> float:
        return float(max((np.max(e, initial=0.0) for e in self.excess(g)), default=0.0))


class _Subproblem:
    """The convex subproblem in Clarabel's form (min ½wᵀPw + qᵀw, Aw + slack = b, slack in
    the cones), its constant structure laid out once per solve (COO triplets) so an iteration
    only places the new Jacobian.

    Variables w = (d, ν⁺, ν⁻, s_up, s_lo), the virtual control ν = ν⁺ - ν⁻. Rows: zero cone
    (linearised equalities, fixed variables), then the nonnegative cone (upper and lower
    sides of the inequalities, the trust-region box of the free variables, w_slack >= 0)."""

    def __init__(self, rows: _Rows, lbx: np.ndarray, ubx: np.ndarray) -> None:
        self.rows, self.lbx, self.ubx = rows, lbx, ubx
        n = self.n = len(lbx)
        ne, nu, nl = len(rows.eq), len(rows.up), len(rows.lo)
        self.fixed = np.flatnonzero(ubx - lbx <= 1e-12)
        self.free = np.setdiff1d(np.arange(n), self.fixed)
        nf, nfr = len(self.fixed), len(self.free)
        self.nv = n + 2 * ne + nu + nl
        self.n_zero = ne + nf
        self.r_up = self.n_zero
        self.r_lo = self.r_up + nu
        r_box = self.r_lo + nl
        self.n_rows = r_box + 2 * nfr + (self.nv - n)
        ar = np.arange
        triplets = [
            (ar(ne), n + ar(ne), -np.ones(ne)), (ar(ne), n + ne + ar(ne), np.ones(ne)),
            (ne + ar(nf), self.fixed, np.ones(nf)),
            (self.r_up + ar(nu), n + 2 * ne + ar(nu), -np.ones(nu)),
            (self.r_lo + ar(nl), n + 2 * ne + nu + ar(nl), -np.ones(nl)),
            (r_box + ar(nfr), self.free, np.ones(nfr)),
            (r_box + nfr + ar(nfr), self.free, -np.ones(nfr)),
            (r_box + 2 * nfr + ar(self.nv - n), n + ar(self.nv - n), -np.ones(self.nv - n)),
        ]
        self.static = tuple(np.concatenate(parts) for parts in zip(*triplets, strict=True))
        # Where a Jacobian row goes: equality rows, upper sides, lower sides (negated).
        m = len(rows.lbg)
        self.to_eq, self.to_up, self.to_lo = (np.full(m, -1) for _ in range(3))
        self.to_eq[rows.eq] = ar(ne)
        self.to_up[rows.up] = self.r_up + ar(nu)
        self.to_lo[rows.lo] = self.r_lo + ar(nl)

    def solve(self, f0: float, grad: np.ndarray, g0: np.ndarray, jac: sp.coo_matrix,
              z: np.ndarray, radius: float, s: SCvxSettings,
              curvature: sp.csc_matrix | None, penalty: float
              ) -> tuple[np.ndarray, float, np.ndarray] | None:
        """The step d, the model's penalised cost there and the QP's multipliers of the
        constraint rows as multipliers of g (None: the QP failed)."""
        rows, n, nv = self.rows, self.n, self.nv
        r, c, v = jac.row, jac.col, jac.data
        parts = [self.static]
        for target, sign in ((self.to_eq, 1.0), (self.to_up, 1.0), (self.to_lo, -1.0)):
            keep = target[r] >= 0
            parts.append((target[r[keep]], c[keep], sign * v[keep]))
        rr, cc, vv = (np.concatenate(x) for x in zip(*parts, strict=True))
        A = sp.csc_matrix((vv, (rr, cc)), shape=(self.n_rows, nv))
        lo = np.maximum(self.lbx - z, -radius)[self.free]
        hi = np.minimum(self.ubx - z, radius)[self.free]
        b = np.concatenate([rows.lbg[rows.eq] - g0[rows.eq], np.zeros(len(self.fixed)),
                            rows.ubg[rows.up] - g0[rows.up], g0[rows.lo] - rows.lbg[rows.lo],
                            hi, -lo, np.zeros(nv - n)])
        q = np.concatenate([grad, np.full(nv - n, penalty)])
        P = sp.diags(np.concatenate([np.full(n, s.prox), np.zeros(nv - n)]), format="csc")
        if curvature is not None:
            P = P + sp.block_diag([curvature, sp.csc_matrix((nv - n, nv - n))], format="csc")
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        cones = [clarabel.ZeroConeT(self.n_zero),
                 clarabel.NonnegativeConeT(self.n_rows - self.n_zero)]
        solution = clarabel.DefaultSolver(sp.triu(P, format="csc"), q, A, b, cones,
                                          settings).solve()
        if solution.status not in (clarabel.SolverStatus.Solved,
                                   clarabel.SolverStatus.AlmostSolved):
            return None
        w = np.asarray(solution.x)
        dual = np.asarray(solution.z)
        mu = np.zeros(len(g0))
        mu[rows.eq] = dual[:len(rows.eq)]
        mu[rows.up] += dual[self.r_up:self.r_lo]
        mu[rows.lo] -= dual[self.r_lo:self.r_lo + len(rows.lo)]
        d = w[:n].copy()
        d[self.fixed] = 0.0
        return d, f0 + float(q @ w) + 0.5 * float(w @ (P @ w)), mu


class SCvxHermiteSimpson(HermiteSimpson):
    """The Hermite–Simpson NLP of an `OCP`, solved by SCvx instead of an NLP solver."""

    kind = "scvx"

    def __init__(self, ocp: OCP, n_intervals: int, backend: str = "scvx",
                 variable_mesh: int = 0, midpoint_path: int = 0) -> None:
        super().__init__(ocp, n_intervals, "ipopt", variable_mesh, midpoint_path)
        problem = self.nlp._problem  # the symbolic (x, f, g, p) of the collocation NLP
        self.nlp = SCvxSolver(problem["x"], problem["f"], problem["g"], problem["p"])
