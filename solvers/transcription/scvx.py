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
satisfies the constraints. The penalty λ rises (×10) whenever a subproblem keeps more than half
of the violation although its trust region does not bind: λ is then below the multipliers, and
Φ's minimum lies outside the feasible set (the steering rule of elastic SQP).

Where the OCP states its path rows as second-order cones (`OCP.path_cones`), the subproblem
keeps them exact, |v + J_v d| <= t + J_t d + σ (σ >= 0 charged λ), in place of the rows:
convex constraints stay convex, as Mao et al. have it.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import clarabel
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackNoConvergence, eigsh

from ..context import SolveContext
from ..nlp.casadi_nlp import SNAPSHOT_ITERATIONS, NLPResult
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
                 settings: SCvxSettings | None = None,
                 cones: list[tuple[ca.SX, ca.SX]] | None = None,
                 replaced_rows: np.ndarray | None = None) -> None:
        """`cones` (v, t): |v| <= t, kept exact; they stand for the rows `replaced_rows` of g."""
        self.settings = settings or SCvxSettings()
        self.n_x, self.n_g = int(z.numel()), int(g.numel())
        self.cones = _Cones(z, p, cones or [])
        self.replaced = np.asarray([] if replaced_rows is None else replaced_rows, int)
        self._values = ca.Function("scvx_values", [z, p], [f, g])
        self._linear = ca.Function("scvx_linear", [z, p],
                                   [f, ca.gradient(f, z), g, ca.jacobian(g, z)])
        mu = ca.SX.sym("mu", self.n_g) if isinstance(z, ca.SX) else ca.MX.sym("mu", self.n_g)
        self._hessian = ca.Function("scvx_hessian", [z, p, mu],
                                    [ca.hessian(f + ca.dot(mu, g), z)[0]])

    def solve(self, x0: np.ndarray, p: np.ndarray, lbx: np.ndarray, ubx: np.ndarray,
              lbg: np.ndarray, ubg: np.ndarray, lam_x0: np.ndarray | None = None,
              lam_g0: np.ndarray | None = None, ctx: SolveContext | None = None) -> NLPResult:
        """Iterate from x0 until converged; raises `Cancelled`/`TimeLimit` via `ctx`. The
        history keeps accepted iterates 0, 1, 2, 3, 5, 8, … (IPOPT's snapshots) and the last."""
        s = self.settings
        lbg, ubg = np.array(lbg, float), np.array(ubg, float)
        lbg[self.replaced], ubg[self.replaced] = -np.inf, np.inf  # kept exact as cones
        rows = _Rows(lbg, ubg)
        lbx, ubx = np.asarray(lbx, float), np.asarray(ubx, float)
        qp = _Subproblem(rows, lbx, ubx, self.cones.dims)
        z = np.clip(np.asarray(x0, float), lbx, ubx)
        penalty = s.penalty
        phi, f, g, viol = self._merit(z, p, rows, penalty)
        radius, history, status = s.radius, [(0, z.copy())], "Maximum_Iterations_Exceeded"
        mu, k = np.zeros(self.n_g), 0
        for k in range(1, s.max_iter + 1):
            if ctx is not None:
                ctx.report(k, f"SCvx iteration {k}, trust region {radius:.2g}")
            f0, grad, g0, jac = self._linearised(z, p)
            curvature = self._curvature(z, p, mu) if s.curvature else None
            model = (f0, grad, jac, curvature, self.cones.linearised(z, p))
            step = qp.solve(model, g0, z, radius, s, penalty)
            if step is None:
                radius /= s.shrink
                if radius < s.radius_min:
                    status = "Subproblem_Failed"
                    break
                continue
            d, predicted_value, mu_step, kept = step
            predicted = phi - predicted_value
            if (viol > s.feasible and kept > 0.5 * (phi - f) / penalty
                    and np.max(np.abs(d), initial=0.0) < 0.99 * radius
                    and penalty < s.penalty_max):
                penalty *= 10.0  # the steering rule: λ below the multipliers
                phi = self._merit(z, p, rows, penalty)[0]
                continue
            if predicted <= s.tol * (1 + abs(phi)):
                if viol <= s.feasible:
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
                d, trial = self._corrected(qp, model, z, p, rows, radius, penalty, d, trial)
            ratio = (phi - trial[0]) / predicted
            if ratio < s.rho0:
                radius /= s.shrink
            else:
                z, (phi, f, g, viol, mu) = z + d, trial
                history.append((k, z.copy()))
                if ratio < s.rho1:
                    radius /= s.shrink
                elif ratio >= s.rho2:
                    radius = min(radius * s.grow, s.radius_max)
            if radius < s.radius_min:
                status = ("Solve_Succeeded" if viol <= s.feasible
                          else "Search_Direction_Becomes_Too_Small")
                break
        return NLPResult(x=z, f=f, g=g, lam_x=np.zeros(self.n_x), lam_g=np.zeros(self.n_g),
                         iterations=k, return_status=status,
                         success=status == "Solve_Succeeded", max_violation=viol,
                         history=[h for i, h in enumerate(history)
                                  if i in SNAPSHOT_ITERATIONS or i == len(history) - 1])

    def _linearised(self, z: np.ndarray, p: np.ndarray
                    ) -> tuple[float, np.ndarray, np.ndarray, sp.coo_matrix]:
        """f, its gradient, g and its (sparse) Jacobian at z: the subproblem's model."""
        f0, grad, g0, jac = self._linear(z, p)
        return (float(f0), np.asarray(grad).ravel(), np.asarray(g0).ravel(),
                sp.coo_matrix(jac.sparse()))

    def _corrected(self, qp: _Subproblem, model: tuple, z: np.ndarray, p: np.ndarray,
                   rows: _Rows, radius: float, penalty: float, d: np.ndarray, trial: tuple
                   ) -> tuple[np.ndarray, tuple]:
        """A second-order correction (Fletcher) of a step the merit function rejects: the
        curvature the linearisation missed, g(z + d) - J d, as the constant of a second QP;
        kept only if it does better. `trial` is (merit, f, g, violation, multipliers) at
        z + d."""
        again = qp.solve(model, trial[2] - model[2] @ d, z, radius, self.settings, penalty)
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
               ) -> tuple[float, float, np.ndarray, float]:
        """Φ(z) = f + λ × (the L1 constraint violation, cones included), f, g and the
        largest violation."""
        f, g = (np.asarray(a).ravel() for a in self._values(z, p))
        outside = self.cones.excess(z, p)
        return (float(f[0]) + penalty * (rows.l1(g) + float(np.sum(outside))), float(f[0]), g,
                max(rows.violation(g), float(np.max(outside, initial=0.0))))


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


class _Cones:
    """Second-order cones |v_j| <= t_j with v_j, t_j affine in z: values, linearisations."""

    def __init__(self, z: ca.SX, p: ca.SX, cones: list[tuple[ca.SX, ca.SX]]) -> None:
        self.dims = [int(ca.vec(v).numel()) for v, _ in cones]
        v = ca.vertcat(*[ca.vec(v) for v, _ in cones]) if cones else ca.SX(0, 1)
        t = ca.vertcat(*[t for _, t in cones]) if cones else ca.SX(0, 1)
        self._values = ca.Function("scvx_cones", [z, p], [v, t])
        self._linear = ca.Function("scvx_cone_model", [z, p],
                                   [v, ca.jacobian(v, z), t, ca.jacobian(t, z)])
        self._owner = np.repeat(np.arange(len(self.dims)), self.dims)

    def excess(self, z: np.ndarray, p: np.ndarray) -> np.ndarray:
        """max(|v_j| - t_j, 0) for every cone."""
        if not self.dims:
            return np.zeros(0)
        v, t = (np.asarray(a).ravel() for a in self._values(z, p))
        norms = np.sqrt(np.bincount(self._owner, v * v, minlength=len(self.dims)))
        return np.maximum(norms - t, 0.0)

    def linearised(self, z: np.ndarray, p: np.ndarray) -> tuple | None:
        """(v, J_v, t, J_t) at z, the Jacobians sparse; None without cones."""
        if not self.dims:
            return None
        v, jv, t, jt = self._linear(z, p)
        return (np.asarray(v).ravel(), sp.coo_matrix(jv.sparse()), np.asarray(t).ravel(),
                sp.coo_matrix(jt.sparse()))


class _Subproblem:
    """The convex subproblem in Clarabel's form (min ½wᵀPw + qᵀw, Aw + slack = b, slack in
    the cones), its constant structure laid out once per solve (COO triplets) so an iteration
    only places the new Jacobian.

    Variables w = (d, ν⁺, ν⁻, s_up, s_lo, σ), the virtual control ν = ν⁺ - ν⁻. Rows: zero
    cone (linearised equalities, fixed variables), the nonnegative cone (upper and lower
    sides of the inequalities, the trust-region box of the free variables, w_slack >= 0),
    then one second-order cone per exact cone: (t + J_t d + σ, v + J_v d)."""

    def __init__(self, rows: _Rows, lbx: np.ndarray, ubx: np.ndarray,
                 cone_dims: list[int]) -> None:
        self.rows, self.lbx, self.ubx = rows, lbx, ubx
        n = self.n = len(lbx)
        ne, nu, nl, nc = len(rows.eq), len(rows.up), len(rows.lo), len(cone_dims)
        self.fixed = np.flatnonzero(ubx - lbx <= 1e-12)
        self.free = np.setdiff1d(np.arange(n), self.fixed)
        nf, nfr = len(self.fixed), len(self.free)
        self.nv = n + 2 * ne + nu + nl + nc
        self.n_zero = ne + nf
        self.r_up = self.n_zero
        self.r_lo = self.r_up + nu
        r_box = self.r_lo + nl
        self.n_nonneg = r_box + 2 * nfr + (self.nv - n) - self.n_zero
        self.cone_dims = cone_dims
        ar = np.arange
        # Each cone's first row (t) and the rows of its v components.
        starts = self.n_zero + self.n_nonneg + np.concatenate(
            [[0], np.cumsum(np.asarray(cone_dims, int) + 1)[:-1]]).astype(int)[:nc]
        self.t_rows = starts
        self.v_rows = np.concatenate(
            [s0 + 1 + ar(m) for s0, m in zip(starts, cone_dims, strict=True)] or [ar(0)])
        self.n_rows = self.n_zero + self.n_nonneg + int(sum(cone_dims)) + nc
        triplets = [
            (ar(ne), n + ar(ne), -np.ones(ne)), (ar(ne), n + ne + ar(ne), np.ones(ne)),
            (ne + ar(nf), self.fixed, np.ones(nf)),
            (self.r_up + ar(nu), n + 2 * ne + ar(nu), -np.ones(nu)),
            (self.r_lo + ar(nl), n + 2 * ne + nu + ar(nl), -np.ones(nl)),
            (r_box + ar(nfr), self.free, np.ones(nfr)),
            (r_box + nfr + ar(nfr), self.free, -np.ones(nfr)),
            (r_box + 2 * nfr + ar(self.nv - n), n + ar(self.nv - n), -np.ones(self.nv - n)),
            (self.t_rows, self.nv - nc + ar(nc), -np.ones(nc)),
        ]
        self.static = tuple(np.concatenate(parts) for parts in zip(*triplets, strict=True))
        # Where a Jacobian row goes: equality rows, upper sides, lower sides (negated).
        m = len(rows.lbg)
        self.to_eq, self.to_up, self.to_lo = (np.full(m, -1) for _ in range(3))
        self.to_eq[rows.eq] = ar(ne)
        self.to_up[rows.up] = self.r_up + ar(nu)
        self.to_lo[rows.lo] = self.r_lo + ar(nl)

    def solve(self, model: tuple, g0: np.ndarray, z: np.ndarray, radius: float,
              s: SCvxSettings, penalty: float
              ) -> tuple[np.ndarray, float, np.ndarray, float] | None:
        """The step d, the model's penalised cost there, the QP's multipliers of the
        constraint rows as multipliers of g and the violation the model keeps (L1; None: the
        QP failed). `model` is (f0, ∇f, J, curvature, cone linearisation or None)."""
        f0, grad, jac, curvature, cones = model
        rows, n, nv = self.rows, self.n, self.nv
        r, c, v = jac.row, jac.col, jac.data
        parts = [self.static]
        for target, sign in ((self.to_eq, 1.0), (self.to_up, 1.0), (self.to_lo, -1.0)):
            keep = target[r] >= 0
            parts.append((target[r[keep]], c[keep], sign * v[keep]))
        cone_b = []
        if cones is not None:
            v0, jv, t0, jt = cones
            parts += [(self.v_rows[jv.row], jv.col, -jv.data),
                      (self.t_rows[jt.row], jt.col, -jt.data)]
            cone_b = np.zeros(self.n_rows - self.n_zero - self.n_nonneg)
            base = self.n_zero + self.n_nonneg
            cone_b[self.t_rows - base], cone_b[self.v_rows - base] = t0, v0
        rr, cc, vv = (np.concatenate(x) for x in zip(*parts, strict=True))
        A = sp.csc_matrix((vv, (rr, cc)), shape=(self.n_rows, nv))
        lo = np.maximum(self.lbx - z, -radius)[self.free]
        hi = np.minimum(self.ubx - z, radius)[self.free]
        b = np.concatenate([rows.lbg[rows.eq] - g0[rows.eq], np.zeros(len(self.fixed)),
                            rows.ubg[rows.up] - g0[rows.up], g0[rows.lo] - rows.lbg[rows.lo],
                            hi, -lo, np.zeros(nv - n), cone_b])
        q = np.concatenate([grad, np.full(nv - n, penalty)])
        P = sp.diags(np.concatenate([np.full(n, s.prox), np.zeros(nv - n)]), format="csc")
        if curvature is not None:
            P = P + sp.block_diag([curvature, sp.csc_matrix((nv - n, nv - n))], format="csc")
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        cone_types = [clarabel.ZeroConeT(self.n_zero), clarabel.NonnegativeConeT(self.n_nonneg),
                      *(clarabel.SecondOrderConeT(m + 1) for m in self.cone_dims)]
        solution = clarabel.DefaultSolver(sp.triu(P, format="csc"), q, A, b, cone_types,
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
        return (d, f0 + float(q @ w) + 0.5 * float(w @ (P @ w)), mu,
                float(np.sum(np.maximum(w[n:], 0.0))))


class SCvxHermiteSimpson(HermiteSimpson):
    """The Hermite–Simpson NLP of an `OCP`, solved by SCvx instead of an NLP solver."""

    kind = "scvx"

    def __init__(self, ocp: OCP, n_intervals: int, backend: str = "scvx",
                 variable_mesh: int = 0, midpoint_path: int = 0) -> None:
        super().__init__(ocp, n_intervals, "ipopt", variable_mesh, midpoint_path)
        problem = self.nlp._problem  # the symbolic (x, f, g, p) of the collocation NLP
        cones, replaced = [], None
        if ocp.path_cones is not None and self.n_path:
            Xp, Up, p = self._path_symbols
            for k in range(self.path_points):
                cones += ocp.path_cones(Xp[:, k], Up[:, k], p)
            if len(cones) != self.n_path * self.path_points:
                raise ValueError("OCP.path_cones must give one cone per path row")
            start = self.n_defects + self.n_terminal + self.n_boundary
            replaced = np.arange(start, start + len(cones))
        self.nlp = SCvxSolver(problem["x"], problem["f"], problem["g"], problem["p"],
                              cones=cones, replaced_rows=replaced)
