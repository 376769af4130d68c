"""The lossless convexification of the powered-descent problem as a parametric SOCP
(Açıkmeşe & Ploen 2007; Blackmore, Açıkmeşe & Scharf 2010), built once per node count with
CVXPY parameters and re-solved by Clarabel with new data: a slider move costs a solve.

Variables at N+1 nodes: r, v, z = ln m, u = T/m and the slack σ = Γ/m ≥ |u|; u and σ are
linear between nodes (first-order hold), so r and v are integrated exactly and z by the
trapezoid rule. The nodes sit at t = τ t_f on a mesh τ that is a parameter too: equal steps
during the final-time search, then one that follows the thrust switches (`switch_mesh.py`).
The thrust bounds ρ1 ≤ Γ ≤ ρ2 become, with μ_i = ρ_i e^{-z_lin},
μ1 (1 - δ + δ²/2) ≤ σ ≤ μ2 (1 - δ),  δ = z - z_lin (the papers' Taylor bounds about z_lin);
the papers expand about the max-thrust mass profile z0(t) = ln(m_wet - ρ2 t / c), and here the
expansion is repeated about the last solution's z until it no longer moves, so the bounds are
the exact ones at the answer.

The free final time is a golden-section search over t_f on the SOCP's optimum (the papers'
outer line search); the minimum-landing-error problem (Blackmore et al.) first minimises the
horizontal distance of the touchdown from the target, then the fuel at that distance.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import cvxpy as cp
import numpy as np

from ...context import Infeasible, SolveContext
from ...nlp.cache import built_once
from .model import (
    P_C,
    P_COS_POINT,
    P_G,
    P_MDRY,
    P_MWET,
    P_RHO1,
    P_RHO2,
    P_TAN_GS,
    P_VMAX,
    flight_time_bounds,
)
from .switch_mesh import SHORT, anchored_mesh, equal_mesh, switch_times

GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0
REACHED = 0.1  # m: a least landing error below this reaches the target (minimum fuel then)
SOLVED = (cp.OPTIMAL, cp.OPTIMAL_INACCURATE)
ROUNDS = 3  # re-centrings of the mesh on the switches
SCAN = 12  # final times scanned across the papers' bracket


@dataclass
class SOCPResult:
    """One SOCP optimum at a fixed final time (problem units)."""

    tf: float
    t: np.ndarray  # (N+1,) node times, s
    r: np.ndarray  # (N+1, 3)
    v: np.ndarray
    z: np.ndarray  # (N+1,)
    u: np.ndarray  # (N+1, 3) thrust acceleration T/m
    sigma: np.ndarray  # (N+1,) slack Γ/m
    fuel: float
    miss: float  # horizontal distance of the touchdown from the target, m
    solve_time: float


class DescentSOCP:
    """The relaxed problem at N intervals, compiled once (DPP); `solve` sets the parameters."""

    def __init__(self, n_intervals: int) -> None:
        N = self.N = n_intervals
        self.r = cp.Variable((N + 1, 3))
        self.v = cp.Variable((N + 1, 3))
        self.z = cp.Variable(N + 1)
        self.u = cp.Variable((N + 1, 3))
        self.sigma = cp.Variable(N + 1)
        par = cp.Parameter
        self.r0, self.v0 = par(3), par(3)
        # Per interval k (rows): h_k / 2 and h_k² (repeated over the 3 axes), g h_k,
        # g h_k² / 2 and h_k / (2 c).
        self.half_h, self.h2 = par((N, 3), nonneg=True), par((N, 3), nonneg=True)
        self.gdt, self.gdt2 = par((N, 3)), par((N, 3))
        self.alpha_h = par(N, nonneg=True)
        self.z_lin = par(N + 1)  # where e^{-z} is expanded
        self.inv_mu1 = par(N + 1, nonneg=True)  # 1 / (ρ1 e^{-z_lin})
        self.inv_mu2 = par(N + 1, nonneg=True)
        self.z_lo, self.z_hi = par(N + 1), par(N + 1)
        self.z_wet, self.z_dry = par(), par()
        self.tan_gs = par(nonneg=True)
        self.v_max = par(nonneg=True)
        self.cos_point = par()
        self.miss_bound = par(nonneg=True)  # horizontal touchdown distance allowed, m
        r, v, z, u, s = self.r, self.v, self.z, self.u, self.sigma
        cons = [
            r[0] == self.r0, v[0] == self.v0, z[0] == self.z_wet,
            v[1:] == v[:-1] + cp.multiply(self.half_h, u[:-1] + u[1:]) + self.gdt,
            r[1:] == r[:-1] + 2 * cp.multiply(self.half_h, v[:-1])
            + cp.multiply(self.h2, u[:-1] / 3 + u[1:] / 6) + self.gdt2,
            z[1:] == z[:-1] - cp.multiply(self.alpha_h, s[:-1] + s[1:]),
            cp.norm(u, 2, axis=1) <= s,
            cp.multiply(self.inv_mu1, s) >= 1 - (z - self.z_lin)
            + cp.square(z - self.z_lin) / 2,
            cp.multiply(self.inv_mu2, s) <= 1 - (z - self.z_lin),
            z >= self.z_lo, z <= self.z_hi, z[N] >= self.z_dry,
            # The glide-slope cone with its apex at the touchdown point (the target when
            # the landing error is zero): convex either way.
            r[:, 2] >= self.tan_gs * cp.norm(r[:, :2] - np.ones((N + 1, 1)) @ r[N:, :2], 2,
                                              axis=1),
            cp.norm(v, 2, axis=1) <= self.v_max,
            u[:, 2] >= self.cos_point * s,
            r[N, 2] == 0, v[N] == 0,
            cp.norm(r[N, :2]) <= self.miss_bound,
        ]
        self.fuel_problem = cp.Problem(cp.Maximize(z[N]), cons)
        self.miss_problem = cp.Problem(cp.Minimize(cp.norm(r[N, :2])), cons)

    def set_data(self, p: np.ndarray, tf: float, z_lin: np.ndarray | None = None,
                 tau: np.ndarray | None = None) -> np.ndarray:
        """Parameters for the final time tf on the mesh tau (default: equal steps); e^{-z}
        expanded about z_lin (default: the max-thrust mass profile of the papers). Returns
        the node times."""
        N, c = self.N, p[P_C]
        t = tf * (np.linspace(0.0, 1.0, N + 1) if tau is None else np.asarray(tau, float))
        h = np.diff(t)
        g = np.array([0.0, 0.0, -p[P_G]])
        m_wet = p[P_MWET]
        z_lo = np.log(np.maximum(m_wet - p[P_RHO2] * t / c, 1e-3))
        z_hi = np.log(np.maximum(m_wet - p[P_RHO1] * t / c, 1e-3))
        lin = z_lo if z_lin is None else np.clip(z_lin, z_lo, z_hi)
        self.r0.value, self.v0.value = p[0:3], p[3:6]
        self.half_h.value = np.repeat(h[:, None] / 2, 3, axis=1)
        self.h2.value = np.repeat(h[:, None] ** 2, 3, axis=1)
        self.gdt.value, self.gdt2.value = np.outer(h, g), np.outer(h * h / 2, g)
        self.alpha_h.value = h / (2 * c)
        self.z_lin.value = lin
        self.inv_mu1.value = np.exp(lin) / p[P_RHO1]
        self.inv_mu2.value = np.exp(lin) / p[P_RHO2]
        self.z_lo.value, self.z_hi.value = z_lo, z_hi
        self.z_wet.value, self.z_dry.value = np.log(m_wet), np.log(p[P_MDRY])
        self.tan_gs.value = p[P_TAN_GS]
        self.v_max.value = p[P_VMAX]
        self.cos_point.value = p[P_COS_POINT]
        return t

    def solve(self, p: np.ndarray, tf: float, miss_bound: float = 0.0,
              z_lin: np.ndarray | None = None, objective: str = "fuel",
              tau: np.ndarray | None = None) -> SOCPResult | None:
        """The optimum at final time tf on the mesh tau (None: infeasible at this tf)."""
        t = self.set_data(p, tf, z_lin, tau)
        self.miss_bound.value = miss_bound
        problem = self.fuel_problem if objective == "fuel" else self.miss_problem
        try:
            problem.solve(solver=cp.CLARABEL)
        except cp.SolverError:
            return None
        if problem.status not in SOLVED:
            return None
        z = np.asarray(self.z.value)
        return SOCPResult(tf, t, np.asarray(self.r.value), np.asarray(self.v.value), z,
                          np.asarray(self.u.value), np.asarray(self.sigma.value),
                          float(p[P_MWET] - np.exp(z[-1])),
                          float(np.linalg.norm(self.r.value[-1, :2])),
                          float(problem.solver_stats.solve_time or 0.0))


@built_once(maxsize=8)
def descent_socp(n_intervals: int) -> DescentSOCP:
    """The compiled SOCP for this node count (built once, cached)."""
    return DescentSOCP(n_intervals)


@dataclass
class LosslessResult:
    best: SOCPResult
    solves: int
    relinearisations: int
    landing_error: float  # the minimum-landing-error problem's distance (0 for minimum fuel)


def _refine(f, a: float, b: float, tol: float, ctx: SolveContext | None) -> float:
    """Golden-section minimum of f on [a, b] to an interval of width tol."""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    while b - a > tol:
        if ctx is not None:
            ctx.checkpoint()
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
    return 0.5 * (a + b)


def solve_lossless(p: np.ndarray, n_intervals: int, objective: str = "fuel",
                   tf_hint: float | None = None, ctx: SolveContext | None = None,
                   tf_tol: float = 0.1, switches_hint: Sequence[float] = ()
                   ) -> LosslessResult:
    """Minimum fuel (objective "fuel") or minimum landing error ("landing-error") with free
    final time; `tf_hint` (a previous optimum) narrows the search, and with its thrust
    switches (`switches_hint`, s) the search runs on their mesh at once. Raises
    `Infeasible` naming the bound when no final time admits a landing."""
    socp = descent_socp(n_intervals)
    t_lo, t_hi = flight_time_bounds(p)
    count = [0]
    if objective == "landing-error":
        miss, tf_miss = _min_landing_error(socp, p, t_lo, t_hi, count, ctx, tf_tol)
        if miss > REACHED:
            return _fuel_at_landing_error(socp, p, miss, tf_miss, count)
    cache: dict[float, SOCPResult | None] = {}
    mesh = [anchored_mesh(socp.N, switches_hint, tf_hint) if tf_hint and len(switches_hint)
            else equal_mesh]

    def fuel_at(tf: float) -> float:
        if tf not in cache:
            count[0] += 1
            cache[tf] = socp.solve(p, tf, tau=mesh[0](tf))
        res = cache[tf]
        return np.inf if res is None else res.fuel

    tf = _near_hint(fuel_at, t_lo, t_hi, tf_hint, tf_tol, ctx)
    if tf is None:
        mesh[0] = equal_mesh  # the whole range on one mesh: the hint's switches may not fit
        cache.clear()
        try:
            a, b = _bracket(fuel_at, t_lo, t_hi, ctx)
        except _NoLanding:
            closest, tf_miss = _min_landing_error(socp, p, t_lo, t_hi, count, ctx, tf_tol)
            if closest <= REACHED:  # a window of landings narrower than the scan's step
                # (at the papers' example the propellant lasts from 75 s to 81 s only)
                step = (t_hi - t_lo) / (SCAN - 1)
                a, b = _bracket(fuel_at, max(t_lo, tf_miss - step),
                                min(t_hi, tf_miss + step), ctx)
                tf = _refine(fuel_at, a, b, tf_tol, ctx)
                return _finish(socp, p, cache, fuel_at, tf, count, tf_tol, ctx)
            raise Infeasible(
                f"the target is out of reach: with the propellant (m(tf) ≥ m_dry = "
                f"{p[P_MDRY]:g} kg), the thrust bounds and the state constraints the closest "
                f"touchdown is {closest:.0f} m from it — add propellant, or choose minimum "
                "landing error") from None
        tf = _refine(fuel_at, a, b, tf_tol, ctx)
    return _finish(socp, p, cache, fuel_at, tf, count, tf_tol, ctx)


def _finish(socp: DescentSOCP, p: np.ndarray, cache: dict[float, SOCPResult | None],
            fuel_at: Callable[[float], float], tf: float, count: list[int], tf_tol: float,
            ctx: SolveContext | None) -> LosslessResult:
    """The best final time found (`tf`, or a better one the search met): its SOCP optimum
    expanded about its own mass profile and put on a mesh that follows its switches."""
    best = min((r for r in cache.values() if r is not None), key=lambda r: r.fuel)
    if fuel_at(tf) <= best.fuel:
        best = cache[tf]
    best, relin = _relinearise(socp, p, best, 0.0, count)
    best, relin = _follow_switches(socp, p, best, 0.0, count, relin, tf_tol, ctx)
    return LosslessResult(best, count[0], relin, 0.0)


def _fuel_at_landing_error(socp: DescentSOCP, p: np.ndarray, miss: float, tf: float,
                           count: list[int]) -> LosslessResult:
    """Blackmore et al.'s second step: the least fuel at the final time of the least
    touchdown distance, with that distance held (to a millimetre)."""
    bound = miss + 1e-3
    count[0] += 1
    best = socp.solve(p, tf, bound)
    if best is None:
        raise Infeasible("the minimum-fuel landing at the least landing error failed: the "
                         "SOCP solver did not converge")
    best, relin = _relinearise(socp, p, best, bound, count)
    best, relin = _follow_switches(socp, p, best, bound, count, relin, 0.1, None)
    return LosslessResult(best, count[0], relin, best.miss)


class _NoLanding(Exception):
    """No scanned final time lands at the target."""


def _near_hint(fuel_at, t_lo: float, t_hi: float, tf_hint: float | None, tf_tol: float,
               ctx: SolveContext | None) -> float | None:
    """The best final time within 5 % of a previous optimum (a slider moved a little), or
    None when there is no hint or the minimum lies at the edge of that window."""
    if tf_hint is None:
        return None
    a, b = max(0.95 * tf_hint, t_lo), min(1.05 * tf_hint, t_hi)
    if b - a <= 4 * tf_tol:
        return None
    tf = _refine(fuel_at, a, b, tf_tol, ctx)
    inside = a + 2 * tf_tol < tf < b - 2 * tf_tol
    return tf if inside and np.isfinite(fuel_at(tf)) else None


def _bracket(fuel_at, t_lo: float, t_hi: float, ctx: SolveContext | None
             ) -> tuple[float, float]:
    """An interval around the best final time from a scan of the papers' bracket
    [t_min, t_max]; raises `_NoLanding` when no scanned final time lands."""
    grid = np.linspace(t_lo, t_hi, SCAN)
    values = []
    for t in grid:
        if ctx is not None:
            ctx.checkpoint()
        values.append(fuel_at(float(t)))
    k = int(np.argmin(values))
    if not np.isfinite(values[k]):
        raise _NoLanding
    return float(grid[max(k - 1, 0)]), float(grid[min(k + 1, len(grid) - 1)])


def _min_landing_error(socp: DescentSOCP, p: np.ndarray, t_lo: float, t_hi: float,
                       count: list[int], ctx: SolveContext | None, tf_tol: float
                       ) -> tuple[float, float]:
    """Blackmore et al.'s first problem: the least horizontal touchdown distance over tf,
    and that tf."""
    cache: dict[float, float] = {}

    def miss_at(tf: float) -> float:
        if tf not in cache:
            count[0] += 1
            res = socp.solve(p, tf, miss_bound=1e7, objective="landing-error")
            cache[tf] = np.inf if res is None else res.miss
        return cache[tf]

    grid = np.linspace(t_lo, t_hi, SCAN)
    values = [miss_at(float(t)) for t in grid]
    k = int(np.argmin(values))
    if not np.isfinite(values[k]):
        raise Infeasible(
            "no final time admits a touchdown at all: the propellant (m(tf) ≥ m_dry = "
            f"{p[P_MDRY]:g} kg) cannot stop the descent within the thrust bounds and the "
            "state constraints — add propellant or thrust, or start higher or slower")
    tf = _refine(miss_at, float(grid[max(k - 1, 0)]), float(grid[min(k + 1, SCAN - 1)]),
                 tf_tol, ctx)
    if miss_at(tf) > values[k]:
        tf = float(grid[k])
    return miss_at(tf), tf


def _relinearise(socp: DescentSOCP, p: np.ndarray, best: SOCPResult, miss_bound: float,
                 count: list[int], steps: int = 4, tol: float = 1e-6
                 ) -> tuple[SOCPResult, int]:
    """Expand e^{-z} about the last solution's z until z stops moving: the Taylor bounds then
    equal the exact thrust bounds at the answer."""
    tau = best.t / best.tf
    for k in range(1, steps + 1):
        count[0] += 1
        again = socp.solve(p, best.tf, miss_bound, z_lin=best.z, tau=tau)
        if again is None:
            return best, k - 1
        moved = float(np.max(np.abs(again.z - best.z)))
        best = again
        if moved < tol:
            return best, k
    return best, steps


def _follow_switches(socp: DescentSOCP, p: np.ndarray, best: SOCPResult, miss_bound: float,
                     count: list[int], relinearisations: int, tf_tol: float,
                     ctx: SolveContext | None, rounds: int = ROUNDS) -> tuple[SOCPResult, int]:
    """Solve again on a mesh with a short interval at each thrust switch (`switch_mesh`),
    the final time searched again near the last one, until every switch of the answer lies
    in its interval: the fuel error falls several times (tests/missions/
    test_powered_descent.py) where equal steps converge at order 1 to 2 in N."""
    for _ in range(rounds):
        switches = switch_times(best.t, best.sigma * np.exp(best.z), p[P_RHO1], p[P_RHO2])
        mesh = anchored_mesh(socp.N, switches, best.tf)
        tau = mesh(best.tf)
        if tau is None or np.allclose(tau, best.t / best.tf, rtol=0.0,
                                      atol=SHORT / (2 * socp.N)):
            break
        cache: dict[float, SOCPResult | None] = {}

        def fuel_at(tf: float, mesh=mesh, cache: dict = cache) -> float:
            if tf not in cache:
                tau = mesh(tf)
                count[0] += 1
                cache[tf] = None if tau is None else socp.solve(p, tf, miss_bound, tau=tau)
            res = cache[tf]
            return np.inf if res is None else res.fuel

        tf = _refine(fuel_at, 0.98 * best.tf, 1.02 * best.tf, tf_tol, ctx)
        found = [r for r in cache.values() if r is not None]
        if not found:
            break
        again = cache[tf] if np.isfinite(fuel_at(tf)) else min(found, key=lambda r: r.fuel)
        best, steps = _relinearise(socp, p, again, miss_bound, count)
        relinearisations += steps
    return best, relinearisations
