"""Paper 003's transfer with its burn/coast structure fixed and the switch times free.

A Hermite–Simpson optimum shows the structure (coast, burn, coast, burn at the defaults:
paper 003 fig. 3); this NLP keeps that sequence of phases and makes each phase's duration a
variable. On a burn the engine is at full thrust along a unit direction u (|u|² = 1 at every
collocation point) and the mass falls at the full rate; on a coast thrust and mass flow are
zero, so no bound on the thrust is ever active and a warm re-solve after a small change of
the parameters is a few Newton steps (3–5 IPOPT iterations against 70–250 for the
400-segment Hermite–Simpson NLP, whose interior point crawls through the switches). The
flight ends at the last burn's end: a coast after it, alongside the asteroid, changes
nothing and leaves its length undetermined.

Each phase has equal intervals of Gauss–Legendre collocation of degree 5 (order 10 at the
interval ends, for the smooth arcs between switches, which fall on phase ends): 24 intervals
in all re-propagate to within about 30 m of the asteroid, where 400 Hermite–Simpson segments
miss by 0.6 km. Canonical units (`model.py`).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...context import SolveContext
from ...nlp.cache import built_once
from ...nlp.casadi_nlp import NLP, NLPResult
from .model import (
    N_PARAMS,
    P_ACC,
    P_C3,
    P_FLOW,
    P_T0_LB,
    P_T0_UB,
    P_T_LB,
    P_T_UB,
    earth_spline,
    kepler_state,
)

DEGREE = 5
POINTS = np.asarray(ca.collocation_points(DEGREE, "legendre"))  # in (0, 1)
NX = 7
X_LB, X_UB = np.array([-3.0] * 6 + [0.02]), np.array([3.0] * 6 + [1.5])
# The pivot tolerance of MUMPS (IPOPT's default 1e-6): with it a warm re-solve now and then
# took a first step of size 500 into restoration (69–811 iterations); at 1e-2, 3–5 always.
IPOPT_OPTIONS = {"ipopt.mu_strategy": "adaptive", "ipopt.mumps_pivtol": 1e-2}


def _lagrange(points: np.ndarray) -> list[np.poly1d]:
    """The Lagrange basis polynomials on `points`."""
    basis = []
    for j, pj in enumerate(points):
        poly = np.poly1d([1.0])
        for r, pr in enumerate(points):
            if r != j:
                poly *= np.poly1d([1.0, -pr]) / (pj - pr)
        basis.append(poly)
    return basis


STATE_BASIS = _lagrange(np.concatenate([[0.0], POINTS]))  # interval start + collocation points
CONTROL_BASIS = _lagrange(POINTS)
DERIVATIVE = np.array([[b.deriv()(s) for s in POINTS] for b in STATE_BASIS])  # (d+1, d)
END = np.array([b(1.0) for b in STATE_BASIS])


@dataclass(frozen=True)
class Layout:
    """The phases ("burn" / "coast", in flight order) and each one's interval count."""

    kinds: tuple[str, ...]
    intervals: tuple[int, ...]

    @classmethod
    def share(cls, kinds: tuple[str, ...], durations: np.ndarray, total: int) -> Layout:
        """`total` intervals shared in proportion to the phases' durations, two at least."""
        share = np.maximum(2, np.round(total * np.asarray(durations) / np.sum(durations)))
        share[int(np.argmax(share))] += total - int(share.sum())
        return cls(tuple(kinds), tuple(int(n) for n in np.maximum(share, 2)))


class BurnCoastNLP:
    """The fixed-structure NLP of one layout, built once (`built`) and re-solved warm."""

    def __init__(self, layout: Layout, backend: str) -> None:
        self.layout = layout
        p = ca.SX.sym("p", N_PARAMS)
        x, u = ca.SX.sym("x", NX), ca.SX.sym("u", 3)
        r, v, m = x[0:3], x[3:6], x[6]
        gravity = -r / ca.norm_2(r) ** 3
        self._burn = ca.Function("burn", [x, u, p],
                                 [ca.vertcat(v, gravity + p[P_ACC] * u / m, -p[P_FLOW])])
        self._coast = ca.Function("coast", [x, p], [ca.vertcat(v, gravity, 0)])
        self._parts: list[ca.SX] = []
        self._lb: list[np.ndarray] = []
        self._ub: list[np.ndarray] = []
        self.n_x = 0
        t0, self.i_t0 = self._variable("t0", 1, -np.inf, np.inf)
        s, self.i_s = self._variable("vinf", 3, -np.inf, np.inf)
        tau, self.i_tau = self._variable("tau", len(layout.kinds), 0.0, 10.0)
        eq: list[ca.SX] = []
        # Per phase and interval: the index of its start state, of its collocation states
        # and (burns) of its directions.
        self.i_x: list[list[int]] = []
        self.i_xc: list[list[list[int]]] = []
        self.i_u: list[list[list[int]]] = []
        x_first, ix = self._variable("x0", NX, X_LB, X_UB)
        xk = x_first
        for k, (kind, n) in enumerate(zip(layout.kinds, layout.intervals, strict=True)):
            self.i_x.append([])
            self.i_xc.append([])
            self.i_u.append([])
            for i in range(n):
                self.i_x[k].append(ix)
                xk, ix = self._interval(kind, f"{k}_{i}", tau[k] / n, xk, p, eq)
        self.i_xf = ix
        flight = ca.sum1(tau)
        earth = earth_spline()(t0)
        eq.append(ca.vertcat(x_first[0:3] - earth[0:3], x_first[3:6] - earth[3:6] - s,
                             x_first[6] - 1.0, xk[0:6] - kepler_state(p, t0 + flight)))
        g_eq = ca.vertcat(*eq)
        self.n_eq = int(g_eq.numel())
        g = ca.vertcat(g_eq, ca.sumsqr(s) - p[P_C3], flight)
        self.nlp = NLP(ca.vertcat(*self._parts), -xk[6], g, p, backend,
                       name="asteroid_burn_coast", ipopt_options=IPOPT_OPTIONS)

    def _variable(self, name: str, n: int, lb: np.ndarray | float, ub: np.ndarray | float
                  ) -> tuple[ca.SX, int]:
        """A new block of n variables with its bounds, and its index in the NLP vector."""
        start = self.n_x
        self._parts.append(ca.SX.sym(name, n))
        self._lb.append(np.broadcast_to(lb, (n,)).astype(float))
        self._ub.append(np.broadcast_to(ub, (n,)).astype(float))
        self.n_x += n
        return self._parts[-1], start

    def _interval(self, kind: str, name: str, h: ca.SX, xk: ca.SX, p: ca.SX,
                  eq: list[ca.SX]) -> tuple[ca.SX, int]:
        """One collocation interval from state `xk` (its collocation states, on a burn
        its unit directions, its defects into `eq`); the next interval's start state."""
        xs, us, ixc, iu = [], [], [], []
        for j in range(DEGREE):
            xc, ic = self._variable(f"xc{name}_{j}", NX, X_LB, X_UB)
            xs.append(xc)
            ixc.append(ic)
            if kind == "burn":
                uc, ic = self._variable(f"u{name}_{j}", 3, -1.5, 1.5)
                us.append(uc)
                iu.append(ic)
                eq.append(ca.sumsqr(uc) - 1.0)
        self.i_xc[-1].append(ixc)
        self.i_u[-1].append(iu)
        points = [xk, *xs]
        for j in range(DEGREE):
            slope = sum((DERIVATIVE[r, j] * points[r] for r in range(DEGREE + 1)),
                        ca.SX.zeros(NX))
            rate = self._burn(xs[j], us[j], p) if kind == "burn" else self._coast(xs[j], p)
            eq.append(h * rate - slope)
        end = sum((END[r] * points[r] for r in range(DEGREE + 1)), ca.SX.zeros(NX))
        x_next, ix = self._variable(f"x{name}_end", NX, X_LB, X_UB)
        eq.append(end - x_next)
        return x_next, ix

    def bounds(self, p: np.ndarray) -> tuple[np.ndarray, ...]:
        """(lbx, ubx, lbg, ubg): the launch window, |v∞|² <= C3 and the flight-time range."""
        lbx, ubx = np.concatenate(self._lb), np.concatenate(self._ub)
        lbx[self.i_t0], ubx[self.i_t0] = p[P_T0_LB], p[P_T0_UB]
        vmax = float(np.sqrt(p[P_C3]))
        lbx[self.i_s:self.i_s + 3], ubx[self.i_s:self.i_s + 3] = -vmax, vmax
        lbg = np.concatenate([np.zeros(self.n_eq), [-np.inf, p[P_T_LB]]])
        ubg = np.concatenate([np.zeros(self.n_eq), [0.0, p[P_T_UB]]])
        return lbx, ubx, lbg, ubg

    def solve(self, p: np.ndarray, z0: np.ndarray, lam: tuple[np.ndarray, np.ndarray] | None,
              ctx: SolveContext | None) -> NLPResult:
        lam_x, lam_g = lam if lam is not None else (None, None)
        return self.nlp.solve(z0, p, *self.bounds(p), lam_x, lam_g, ctx)

    # ---- between the NLP vector and trajectories ----------------------------------------
    def times(self, z: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """(launch t0, v∞, phase durations), canonical."""
        k = len(self.layout.kinds)
        return (float(z[self.i_t0]), z[self.i_s:self.i_s + 3].copy(),
                z[self.i_tau:self.i_tau + k].copy())

    def seed(self, t0: float, vinf: np.ndarray, durations: np.ndarray,
             t: np.ndarray, X: np.ndarray, U: np.ndarray) -> np.ndarray:
        """A start from a trajectory (times from launch, states, thrust directions; canonical)
        interpolated onto this layout with the phases lasting `durations`."""
        z = np.zeros(self.n_x)
        z[self.i_t0], z[self.i_s:self.i_s + 3] = t0, vinf
        z[self.i_tau:self.i_tau + len(durations)] = durations

        def at(time: float, values: np.ndarray) -> np.ndarray:
            return np.array([np.interp(time, t, col) for col in values.T])

        start = 0.0
        for k, n in enumerate(self.layout.intervals):
            h = durations[k] / n
            for i in range(n):
                a = start + h * i
                z[self.i_x[k][i]:self.i_x[k][i] + NX] = at(a, X)
                for j, point in enumerate(POINTS):
                    ic = self.i_xc[k][i][j]
                    z[ic:ic + NX] = at(a + h * point, X)
                    if self.i_u[k][i]:
                        u = at(a + h * point, U)
                        iu = self.i_u[k][i][j]
                        z[iu:iu + 3] = u / max(float(np.linalg.norm(u)), 1e-12)
            start += durations[k]
        z[self.i_xf:self.i_xf + NX] = at(start, X)
        return z

    def pieces(self, z: np.ndarray) -> list[tuple[float, float, np.ndarray, np.ndarray | None]]:
        """Every interval as (start, length, states at its start and collocation points,
        directions at its collocation points or None on a coast), times from launch."""
        _, _, durations = self.times(z)
        out, start = [], 0.0
        for k, n in enumerate(self.layout.intervals):
            h = durations[k] / n
            for i in range(n):
                ix = self.i_x[k][i]
                states = np.array([z[ix:ix + NX]] + [z[c:c + NX] for c in self.i_xc[k][i]])
                dirs = (np.array([z[c:c + 3] for c in self.i_u[k][i]])
                        if self.i_u[k][i] else None)
                out.append((start + h * i, h, states, dirs))
            start += durations[k]
        return out


def _coefficients(basis: list[np.poly1d]) -> np.ndarray:
    """The basis polynomials' coefficients as rows (highest power first)."""
    n = len(basis)
    return np.array([np.pad(poly.coeffs, (n - len(poly.coeffs), 0)) for poly in basis])


STATE_COEFFICIENTS = _coefficients(STATE_BASIS)
CONTROL_COEFFICIENTS = _coefficients(CONTROL_BASIS)


def _basis_at(coefficients: np.ndarray, s: float | np.ndarray) -> np.ndarray:
    """Every basis polynomial at fractions `s` of an interval: (len(s), basis size)."""
    return np.vander(np.atleast_1d(s), coefficients.shape[1]) @ coefficients.T


def direction(dirs: np.ndarray, s: float | np.ndarray) -> np.ndarray:
    """The unit thrust direction at fraction `s` of an interval (the collocation points'
    directions, Lagrange-interpolated and normalised)."""
    u = _basis_at(CONTROL_COEFFICIENTS, s) @ dirs
    return u / np.linalg.norm(u, axis=1, keepdims=True)


def state(states: np.ndarray, s: float | np.ndarray) -> np.ndarray:
    """The collocation polynomial's state at fractions `s` of an interval."""
    return _basis_at(STATE_COEFFICIENTS, s) @ states


@built_once(maxsize=8)
def built(layout: Layout, backend: str) -> BurnCoastNLP:
    return BurnCoastNLP(layout, backend)
