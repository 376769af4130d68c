"""Costates and the Hamiltonian from the multipliers of a direct transcription.

Every transcription here writes its dynamics as scaled equality constraints
g = C / x_scale = 0 and minimises J / cost_scale; CasADi's multipliers satisfy
grad(J / cost_scale) + J_g^T lam_g + lam_x = 0, so the multiplier of the unscaled constraint C
in the Lagrangian J + mu^T C is

    mu = cost_scale * lam_g / x_scale                                     (1)

(variable scaling and offsets do not enter: a multiplier belongs to its constraint). Each
method maps mu to the costate lambda(t) = dJ*/dx(t) of the maximum principle (the covector
mapping, see the methods' `costate_points`), in the problem's cost per state unit, and the
Hamiltonian is evaluated along it:

    H = L(x, u) + dPhi/dT + lambda^T f(x, u)                              (2)

with the Mayer term's explicit dependence on the final time moved into the running cost (a
minimum-time cost Phi = T counts as L = 1). For these autonomous problems H is constant, and
zero when T is free and no boundary condition depends on time (transversality,
Bryson & Ho 1975, sec. 2.7).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..ocp import OCP, BoundaryPoint, OCPFunctions
from ..solution import Series, costate_units


@dataclass(frozen=True)
class CostatePoints:
    """Costates `lam` (rows) at times `t` (from t0) and the states and controls there, where
    the Hamiltonian is evaluated."""

    t: np.ndarray
    lam: np.ndarray
    X: np.ndarray
    U: np.ndarray


def defect_multipliers(lam_g: np.ndarray, n_blocks: int, ocp: OCP) -> np.ndarray:
    """(n_blocks, nx) multipliers of the unscaled dynamics constraints, eq. (1); the
    dynamics constraints come first in g, one column of nx per node or interval."""
    nx = ocp.nx
    lam = np.asarray(lam_g[: nx * n_blocks], float).reshape(n_blocks, nx)
    return ocp.cost_scale * lam / np.asarray(ocp.x_scale, float)


@dataclass(frozen=True)
class Endpoints:
    """What the transversality conditions need from a solve: the end states, times and
    static variables, and the multipliers of the terminal and boundary constraints (scaled,
    as the NLP returns them) and of the bounds on the end states (scaled variables)."""

    x0: np.ndarray
    xf: np.ndarray
    t0: float
    T: float
    statics: np.ndarray
    lam_end: np.ndarray
    lam_x0: np.ndarray
    lam_xf: np.ndarray


def transversality(ocp: OCP, ends: Endpoints, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """lambda(t0) = -d(nu^T psi)/dx0 and lambda(tf) = dPhi/dxf + d(nu^T psi)/dxf from the end
    multipliers (Bryson & Ho 1975, eq. 2.7.x; the closure conditions of Gong, Ross, Kang &
    Fahroo 2008); psi are the terminal and boundary constraints and the active bounds on the
    end states, whose multipliers the NLP splits between them when they coincide."""
    g0, phi_x, gf = (np.asarray(a).ravel() for a in _transversality_function(ocp)(
        ends.x0, ends.xf, ends.t0, ends.T, ends.statics, p, ends.lam_end))
    scale = np.asarray(ocp.x_scale, float)
    cs = ocp.cost_scale
    lam0 = -cs * (g0 + ends.lam_x0 / scale)
    lamf = phi_x + cs * (gf + ends.lam_xf / scale)
    return lam0, lamf


_TRANSVERSALITY: weakref.WeakKeyDictionary[OCP, ca.Function] = weakref.WeakKeyDictionary()


def _transversality_function(ocp: OCP) -> ca.Function:
    """(d(nu^T psi)/dx0, dPhi/dxf, d(nu^T psi)/dxf) of (x0, xf, t0, T, s, p, nu), built once
    per OCP."""
    if ocp in _TRANSVERSALITY:
        return _TRANSVERSALITY[ocp]
    nx = ocp.nx
    x0, xf = ca.SX.sym("x0", nx), ca.SX.sym("xf", nx)
    t0, T = ca.SX.sym("t0"), ca.SX.sym("T")
    s, q = ca.SX.sym("s", ocp.ns), ca.SX.sym("p", ocp.n_params)
    parts = []
    if ocp.terminal is not None:
        parts.append(ocp.terminal(xf, q) / ca.DM(ocp.terminal_scale))
    if ocp.boundary is not None:
        scale = (np.ones(len(ocp.boundary_lb)) if ocp.boundary_scale is None
                 else np.asarray(ocp.boundary_scale, float))
        parts.append(ocp.boundary(BoundaryPoint(x0, xf, t0, T, s), q) / ca.DM(scale))
    nu = ca.SX.sym("nu", sum(int(e.numel()) for e in parts))
    psi = ca.dot(nu, ca.vertcat(*parts)) if parts else ca.SX(0)
    phi = ocp.mayer(xf, T, q) if ocp.mayer is not None else ca.SX(0)
    _TRANSVERSALITY[ocp] = ca.Function(
        "transversality", [x0, xf, t0, T, s, q, nu],
        [ca.gradient(psi, x0), ca.gradient(phi, xf), ca.gradient(psi, xf)])
    return _TRANSVERSALITY[ocp]


_MAYER_T: weakref.WeakKeyDictionary[OCP, ca.Function] = weakref.WeakKeyDictionary()


def mayer_time_derivative(ocp: OCP, X_final: np.ndarray, T: float, p: np.ndarray) -> float:
    """dPhi/dT of the Mayer cost at the solution (0 without one)."""
    if ocp.mayer is None:
        return 0.0
    if ocp not in _MAYER_T:
        xf, Ts, ps = ca.SX.sym("xf", ocp.nx), ca.SX.sym("T"), ca.SX.sym("p", ocp.n_params)
        _MAYER_T[ocp] = ca.Function("dphi_dT", [xf, Ts, ps],
                                    [ca.jacobian(ocp.mayer(xf, Ts, ps), Ts)])
    return float(_MAYER_T[ocp](X_final, T, p))


def hamiltonian_values(fn: OCPFunctions, pts: CostatePoints, p: np.ndarray,
                       dphi_dT: float) -> tuple[np.ndarray, float]:
    """H of eq. (2) at every costate point, and the size of its largest term (the scale
    its variation is measured against)."""
    K = len(pts.t)
    P = np.tile(np.asarray(p, float)[:, None], (1, K))
    F = np.asarray(fn.f.map(K)(pts.X.T, pts.U.T, P)).T
    terms = np.column_stack([pts.lam * F, np.full(K, dphi_dT)])
    if fn.lagrange is not None:
        terms = np.column_stack([terms, np.asarray(fn.lagrange.map(K)(pts.X.T, pts.U.T, P)).T])
    return terms.sum(axis=1), float(np.max(np.abs(terms)))


def estimate(ocp: OCP, pts: CostatePoints, p: np.ndarray, X_final: np.ndarray, T: float
             ) -> tuple[Series, Series, float]:
    """The costate and Hamiltonian series of a transcription's costate points (the OCP's
    units; the mission converts to SI with `rescale`), and the Hamiltonian's variation
    (max - min) relative to its largest term."""
    fn = ocp.functions()
    H, size = hamiltonian_values(fn, pts, p, mayer_time_derivative(ocp, X_final, T, p))
    units = ocp.state_units or ("",) * ocp.nx
    costates = Series(pts.t, pts.lam, ocp.states, costate_units("cost", units))
    variation = float(np.ptp(H) / size) if size > 0 else 0.0
    return costates, Series(pts.t, H[:, None], ("value",), ("cost/s",)), variation


def rescale(series: Series | None, *, state_factor: np.ndarray, cost_factor: float,
            time_factor: float, cost_unit: str, state_units: tuple[str, ...],
            names: tuple[str, ...] | None = None) -> Series | None:
    """Costates in other units: x_new = state_factor * x, J_new = cost_factor * J,
    t_new = time_factor * t, so lambda_new = cost_factor / state_factor * lambda."""
    if series is None:
        return None
    lam = np.asarray(series.values) * cost_factor / np.asarray(state_factor, float)
    return Series(np.asarray(series.t) * time_factor, lam, names or series.names,
                  costate_units(cost_unit, state_units))


def rescale_hamiltonian(series: Series | None, *, cost_factor: float, time_factor: float,
                        cost_unit: str) -> Series | None:
    """H (cost per time) in other units."""
    if series is None:
        return None
    return Series(np.asarray(series.t) * time_factor,
                  np.asarray(series.values) * cost_factor / time_factor, series.names,
                  (f"{cost_unit or '1'}/s",))
