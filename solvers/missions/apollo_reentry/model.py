"""Apollo-type lifting reentry (paper 004, eq. 8; Stoer & Bulirsch §7.3.7; SPEC M5 case 2):
the model in its published units and its maximum-principle solution by indirect multiple
shooting.

State (v, gamma, xi): speed [1e5 ft/s], flight-path angle [rad], normalised altitude
xi = h/R; control u [rad], the bank/cone angle with C_D = c1 - c2 cos u, C_L = c3 sin u.
Lengths are in units of 1e5 ft and time in seconds, the units of the published numbers; the
mission converts to SI at its interface (`to_si`, `to_model`; `FT = 0.3048 m`).

    v'     = -(S/m) rho v^2 C_D / 2 - g sin(gamma) / (1 + xi)^2
    gamma' =  (S/m) rho v C_L / 2 + v cos(gamma) / (R (1 + xi)) - g cos(gamma) / (v (1 + xi)^2)
    xi'    =  v sin(gamma) / R
    rho    =  rho0 exp(-beta R xi)

Running cost (convective heating rate at the stagnation point): 10 v^3 sqrt(rho).

Maximum principle with H = 10 v^3 sqrt(rho) + lam·f(x, u): the u-dependent part of H is
(S/m) rho v / 2 · (c2 v lam_v cos u + c3 lam_gamma sin u), minimal at
u* = atan2(-c3 lam_gamma, -c2 v lam_v) (tan u = 0.6 lam_gamma / (0.9 v lam_v), S&B's law);
lam' = -dH/dx at u*. With T free and H autonomous, H(T) = 0. On tau in [0, 1] (t = T tau)
the boundary value problem in y = (x, lam) is solved by multiple shooting: node values y_k
and T are the unknowns; the equations are the boundary values, the continuity of y at every
interior node and H(T) = 0. Each segment is integrated by scipy's DOP853 together with its
variational equations, which give the exact block Jacobian for Newton (MINPACK hybrj).

The costate starting guess comes from a direct solution: along its trajectory the costate
ODE is linear in lam, and H = 0, H_u = 0 hold at every instant; one sparse least-squares
problem over the samples gives lam(t) without any NLP-multiplier conventions.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root
from scipy.sparse import coo_matrix
from scipy.sparse.linalg import spsolve

from ...verify import checkpoint

# Stoer & Bulirsch's constants (SPEC M5), units of 1e5 ft and s.
R = 209.0
BETA = 4.26
RHO0 = 2.704e-3
G = 3.2172e-4
S_OVER_M = 53200.0
C1, C2, C3 = 1.174, 0.9, 0.6

FT = 0.3048  # m per ft
LENGTH_UNIT = 1e5 * FT  # m per model length unit (1e5 ft)
R_EARTH = R * LENGTH_UNIT  # m

STATES = ("v", "gamma", "h")
STATE_UNITS = ("m/s", "rad", "m")
NX = 3
RTOL = 1e-12


def rhs(x: ca.SX, u: ca.SX) -> ca.SX:
    """(v, gamma, xi)' for the model (paper 004, eq. 8; CasADi symbols)."""
    v, gamma, xi = x[0], x[1], x[2]
    rho = RHO0 * ca.exp(-BETA * R * xi)
    cd = C1 - C2 * ca.cos(u)
    cl = C3 * ca.sin(u)
    return ca.vertcat(
        -S_OVER_M * rho * v**2 * cd / 2 - G * ca.sin(gamma) / (1 + xi) ** 2,
        S_OVER_M * rho * v * cl / 2 + v * ca.cos(gamma) / (R * (1 + xi))
        - G * ca.cos(gamma) / (v * (1 + xi) ** 2),
        v * ca.sin(gamma) / R,
    )


def heating_rate(x: ca.SX | np.ndarray) -> ca.SX | np.ndarray:
    """10 v^3 sqrt(rho): the integrand of the cost (S&B units); symbols or arrays (..., 3)."""
    if not isinstance(x, ca.SX | ca.MX | ca.DM):
        x = np.asarray(x, float)
        return 10 * x[..., 0] ** 3 * np.sqrt(RHO0) * np.exp(-BETA * R * x[..., 2] / 2)
    return 10 * x[0] ** 3 * ca.sqrt(RHO0) * ca.exp(-BETA * R * x[2] / 2)


def drag_deceleration(x: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Drag deceleration (S/m) rho v^2 C_D / 2 in m/s^2 for rows of (v, gamma, xi)."""
    rho = RHO0 * np.exp(-BETA * R * x[:, 2])
    return S_OVER_M * rho * x[:, 0] ** 2 * (C1 - C2 * np.cos(u)) / 2 * LENGTH_UNIT


def downrange(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Central angle travelled [rad], the integral of v cos(gamma) / (R_E + h) (trapezoid on
    the samples; rows of SI (v, gamma, h))."""
    rate = x[:, 0] * np.cos(x[:, 1]) / (R_EARTH + x[:, 2])
    return np.concatenate([[0.0], np.cumsum(np.diff(t) * (rate[1:] + rate[:-1]) / 2)])


def to_si(x: np.ndarray) -> np.ndarray:
    """Rows of (v, gamma, xi) in model units to (v [m/s], gamma [rad], h [m])."""
    x = np.atleast_2d(x)
    return np.column_stack([x[:, 0] * LENGTH_UNIT, x[:, 1], x[:, 2] * R_EARTH])


def to_model(x: np.ndarray) -> np.ndarray:
    """Rows of (v [m/s], gamma [rad], h [m]) to the model's (v, gamma, xi)."""
    x = np.atleast_2d(x)
    return np.column_stack([x[:, 0] / LENGTH_UNIT, x[:, 1], x[:, 2] / R_EARTH])


@dataclass
class ReentryExtremal:
    """Result of the indirect solve, in the model's units (1e5 ft, s)."""

    T: float
    cost: float
    tau_nodes: np.ndarray
    Y_nodes: np.ndarray
    t: np.ndarray
    Y: np.ndarray
    u: np.ndarray
    converged: bool
    residual: float
    newton_evaluations: int
    message: str


@cache
def _functions() -> dict[str, ca.Function]:
    """Augmented right-hand side (state, costate, running cost) in tau, its Jacobian, u* and
    H, all derived symbolically from the model so they are exact."""
    x = ca.SX.sym("x", NX)
    lam = ca.SX.sym("lam", NX)
    u = ca.SX.sym("u")
    T = ca.SX.sym("T")
    f = rhs(x, u)
    L = heating_rate(x)
    H = L + ca.dot(lam, f)
    u_star = ca.atan2(-C3 * lam[1], -C2 * x[0] * lam[0])
    Hx = ca.substitute(ca.gradient(H, x), u, u_star)
    y = ca.vertcat(x, lam)
    g = ca.vertcat(ca.substitute(f, u, u_star), -Hx)
    return {
        "rhs": ca.Function("rhs", [y, T], [T * ca.vertcat(g, ca.substitute(L, u, u_star))]),
        "var": ca.Function("var", [y], [ca.jacobian(g, y), g]),
        "u": ca.Function("u", [y], [u_star]),
        "H": ca.Function("H", [y], [ca.substitute(H, u, u_star)]),
        # For the costate estimate: A = df/dx, fu = df/du, Lx = dL/dx at a given (x, u).
        "lin": ca.Function("lin", [x, u], [ca.jacobian(f, x), ca.jacobian(f, u), f,
                                           ca.gradient(L, x), L]),
    }


def _segment(y0: np.ndarray, T: float, tau0: float, tau1: float
             ) -> tuple[np.ndarray, np.ndarray, bool]:
    """Integrate one segment with its variational equations: y_end and d y_end / d(y0, T)."""
    fn = _functions()
    n = 2 * NX

    def rhs_var(_: float, z: np.ndarray) -> np.ndarray:
        checkpoint()
        J, g = (np.asarray(a) for a in fn["var"](z[:n]))
        S = z[n:].reshape(n, n + 1)  # [dy/dy0, dy/dT]
        dS = T * (J @ S)
        dS[:, n] += g.ravel()
        return np.concatenate([T * g.ravel(), dS.ravel()])

    z0 = np.concatenate([y0, np.hstack([np.eye(n), np.zeros((n, 1))]).ravel()])
    # A Newton iterate far from any extremal overflows the variational equations (and the
    # step control's norms): the segment then fails (`ok` False), which the caller reports.
    with np.errstate(over="ignore", invalid="ignore"):
        sol = solve_ivp(rhs_var, (tau0, tau1), z0, method="DOP853", rtol=RTOL, atol=1e-13)
    zend = sol.y[:, -1]
    return zend[:n], zend[n:].reshape(n, n + 1), sol.success


def _equations(z: np.ndarray, tau: np.ndarray, x0: np.ndarray, xf: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Shooting residual and its exact Jacobian."""
    n, m = 2 * NX, len(tau) - 1
    Y = z[:-1].reshape(m, n)
    T = z[-1]
    res = np.zeros(n * m + 1)
    jac = np.zeros((n * m + 1, n * m + 1))
    res[:NX] = Y[0, :NX] - x0
    jac[:NX, :NX] = np.eye(NX)
    row = NX
    for k in range(m):
        yend, S, ok = _segment(Y[k], T, tau[k], tau[k + 1])
        if not ok:
            raise FloatingPointError("segment integration failed")
        cols = slice(k * n, (k + 1) * n)
        if k < m - 1:
            res[row : row + n] = yend - Y[k + 1]
            jac[row : row + n, cols] = S[:, :n]
            jac[row : row + n, (k + 1) * n : (k + 2) * n] = -np.eye(n)
            jac[row : row + n, -1] = S[:, n]
            row += n
        else:
            res[row : row + NX] = yend[:NX] - xf
            jac[row : row + NX, cols] = S[:NX, :n]
            jac[row : row + NX, -1] = S[:NX, n]
            row += NX
            res[row] = float(_functions()["H"](yend))
            g = np.asarray(_grad_H()(yend)).ravel()
            jac[row, cols] = g @ S[:, :n]
            jac[row, -1] = g @ S[:, n]
    return res, jac


def hamiltonian(Y: np.ndarray) -> np.ndarray:
    """H at u* along rows of (x, lam); zero on an extremal with free final time."""
    Y = np.atleast_2d(Y)
    return np.asarray(_functions()["H"].map(len(Y))(Y.T)).ravel()


@cache
def _grad_H() -> ca.Function:
    y = ca.SX.sym("y", 2 * NX)
    return ca.Function("gH", [y], [ca.gradient(_functions()["H"](y), y)])


def estimate_costates(t: np.ndarray, X: np.ndarray, U: np.ndarray) -> np.ndarray:
    """Costates (len(t), 3) along a direct solution (dense samples, model units).

    Unknowns lam_k at every sample; equations H = 0 and H_u = 0 at every sample and the
    trapezoidal costate ODE lam' = -A^T lam - L_x between samples, solved in the
    least-squares sense (the direct solution only approximately satisfies them).
    """
    K = len(t)
    A, fu, f, Lx, L = (np.asarray(a) for a in _functions()["lin"].map(K)(X.T, U[None, :]))
    A = A.reshape(NX, K, NX).transpose(1, 0, 2)  # (K, 3, 3): A[k] = df/dx at sample k
    fu, f, Lx, L = fu.T, f.T, Lx.T, L.ravel()
    # The algebraic rows are weighted like the ODE rows (per unit of lam and time).
    w_alg = 1.0 / np.mean(np.abs(f))
    rows, cols, vals = [], [], []
    k = np.arange(K)
    for i in range(NX):
        rows += [2 * k, 2 * k + 1]
        cols += [NX * k + i, NX * k + i]
        vals += [w_alg * f[:, i], w_alg * fu[:, i]]
    b = [-w_alg * np.column_stack([L, np.zeros(K)]).ravel()]
    # (lam_k+1 - lam_k)/h + (A_k^T lam_k + A_k+1^T lam_k+1)/2 = -(Lx_k + Lx_k+1)/2
    h = np.diff(t)
    k = np.arange(K - 1)
    eye = np.eye(NX)
    for i in range(NX):
        row = 2 * K + NX * k + i
        for j in range(NX):
            rows += [row, row]
            cols += [NX * k + j, NX * (k + 1) + j]
            vals += [-eye[i, j] / h + A[:-1, j, i] / 2, eye[i, j] / h + A[1:, j, i] / 2]
    b.append((-(Lx[:-1] + Lx[1:]) / 2).ravel())
    M = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(2 * K + NX * (K - 1), NX * K)).tocsr()
    # Normal equations of a banded system: sparse, small and accurate enough for a start.
    lam = spsolve((M.T @ M).tocsc(), M.T @ np.concatenate(b))
    return lam.reshape(K, NX)


def solve_indirect(
    t: np.ndarray, X: np.ndarray, U: np.ndarray, x0: np.ndarray, xf: np.ndarray, *,
    n_segments: int = 10, dense: int = 40, lam: np.ndarray | None = None,
) -> ReentryExtremal:
    """Indirect multiple shooting started from a direct solution (model units).

    `t`, `X`, `U` are dense samples of the direct solution (states (K, 3), control (K,));
    `lam` its costates at those samples (the multiplier estimate), or None to fit them
    (`estimate_costates`); the shooting nodes are `n_segments` equal intervals in tau.
    Raises `FloatingPointError` when a segment cannot be integrated (a start too far from
    any extremal).
    """
    T0 = float(t[-1])
    lam = estimate_costates(t, X, U) if lam is None else np.asarray(lam, float)
    tau = np.linspace(0.0, 1.0, n_segments + 1)
    Y0 = np.column_stack([X, lam])
    guess = np.column_stack([np.interp(tau[:-1], t / T0, Y0[:, j]) for j in range(2 * NX)])
    z0 = np.concatenate([guess.ravel(), [T0]])
    count = [0]

    def fun(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        count[0] += 1
        return _equations(z, tau, np.asarray(x0, float), np.asarray(xf, float))

    sol = root(fun, z0, jac=True, method="hybr", options={"xtol": 1e-13})
    z = sol.x
    res = float(np.max(np.abs(sol.fun)))
    n = 2 * NX
    Ynodes = z[:-1].reshape(n_segments, n)
    T = float(z[-1])
    # Dense output and the cost (the running cost rides along as the 7th component).
    fn = _functions()

    def augmented_rhs(_: float, w: np.ndarray) -> np.ndarray:
        checkpoint()
        return np.asarray(fn["rhs"](w[:n], T)).ravel()

    ts, Ys, cost = [], [], 0.0
    for k in range(n_segments):
        s = np.linspace(tau[k], tau[k + 1], dense + 1)
        with np.errstate(over="ignore", invalid="ignore"):  # an unconverged end point
            seg = solve_ivp(augmented_rhs, (tau[k], tau[k + 1]),
                            np.concatenate([Ynodes[k], [0.0]]), method="DOP853", rtol=RTOL,
                            atol=1e-13, t_eval=s)
        keep = slice(None) if k == n_segments - 1 else slice(None, -1)
        ts.append(seg.t[keep] * T)
        Ys.append(seg.y[:n, keep].T)
        cost += seg.y[n, -1]
    t_dense = np.concatenate(ts)
    Y_dense = np.vstack(Ys)
    u_dense = np.array([float(fn["u"](y)) for y in Y_dense])
    converged = bool(sol.success and res < 1e-8)
    message = "extremal found" if converged else f"indirect shooting failed ({sol.message})"
    return ReentryExtremal(
        T=T, cost=float(cost), tau_nodes=tau, Y_nodes=Ynodes, t=t_dense, Y=Y_dense, u=u_dense,
        converged=converged, residual=res, newton_evaluations=count[0], message=message,
    )
