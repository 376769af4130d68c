"""The two closed-form laws of paper 001 on Legendre–Gauss–Lobatto nodes: the STM law
(eq. 10) and the SEQ law (eqs. 12–16), in true anomaly (the paper) or in time.

Everything that does not depend on the chaser's initial state (LGL matrices, STMs, the KKT
factorisation, the interpolation to dense samples) is a cached `Plan`: a law is linear in the
boundary states, so a slider move on the initial state costs a matrix-vector product.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...dynamics.tschauner_hempel import (
    IN_PLANE,
    OUT_OF_PLANE,
    KeplerOrbit,
    lvlh_matrix,
    th_matrices,
    ya_stm,
)
from ...lgl import interpolate, lgl_differentiation, lgl_nodes, lgl_weights
from .model import Case

# --- cached discretisations (everything independent of the boundary states) ------------------


@dataclass(frozen=True, eq=False)
class Plan:
    """One law on one LGL grid, for a canonical orbit (a = mu = 1, so n = 1).

    The law is linear in the boundary states b = (X(s0), X(sT)) in its own variables:
    node states = gain_x @ b (N+1, 6, 12), node controls = gain_u @ b (N+1, 3, 12), and
    likewise at the dense samples (uniform in time); `interp` maps node values to the dense
    samples (the LGL polynomial).
    `variable` is "f" (TH scaled state, control u / k^4) or "t" (state (x, v / n),
    control u / n^2, s = n t). `f_nodes` are the true anomalies at the nodes.
    """

    variable: str
    s_nodes: np.ndarray
    f_nodes: np.ndarray
    weights: np.ndarray
    gain_x: np.ndarray
    gain_u: np.ndarray
    s_dense: np.ndarray
    f_dense: np.ndarray
    interp: np.ndarray
    dense_gain_x: np.ndarray
    dense_gain_u: np.ndarray
    n_unknowns: int
    n_equations: int


def _collocation_gain(
    Ds: np.ndarray, A: np.ndarray, B: np.ndarray, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray, int, int]:
    """SEQ law (paper eqs. 12–16) for X' = A_i X + B_i U collocated at all nodes:
    min ½ Σ q_i |U_i|² with X_0, X_N fixed, solved from the KKT system
    [[H, Aeq^T], [Aeq, 0]]. Returns the gains (N+1, n, 2n) and (N+1, m, 2n) from
    b = (X_0, X_N), the number of unknowns and of equations.
    """
    Np, n, m = A.shape[0], A.shape[1], B.shape[2]
    # Variables ordered component-major: index (state k, node i) -> k * Np + i.
    CX = np.kron(np.eye(n), Ds)
    CU = np.zeros((n * Np, m * Np))
    idx = np.arange(Np)
    for r in range(n):
        for k in range(n):
            CX[r * Np + idx, k * Np + idx] -= A[:, r, k]
        for k in range(m):
            CU[r * Np + idx, k * Np + idx] = -B[:, r, k]
    boundary = np.array([k * Np for k in range(n)] + [k * Np + Np - 1 for k in range(n)])
    interior = np.setdiff1d(np.arange(n * Np), boundary)
    Aeq = np.hstack([CU, CX[:, interior]])
    nz, ne = Aeq.shape[1], Aeq.shape[0]
    kkt = np.zeros((nz + ne, nz + ne))
    kkt[: m * Np, : m * Np] = np.diag(np.tile(q, m))
    kkt[:nz, nz:] = Aeq.T
    kkt[nz:, :nz] = Aeq
    rhs = np.zeros((nz + ne, 2 * n))
    rhs[nz:] = -CX[:, boundary]
    z = np.linalg.solve(kkt, rhs)[:nz]
    gx = np.zeros((n * Np, 2 * n))
    gx[boundary] = np.eye(2 * n)
    gx[interior] = z[m * Np:]
    gain_x = gx.reshape(n, Np, 2 * n).transpose(1, 0, 2)
    gain_u = z[: m * Np].reshape(m, Np, 2 * n).transpose(1, 0, 2)
    return gain_x, gain_u, nz, ne


def _blocks(A: np.ndarray, B: np.ndarray
            ) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """The decoupled in-plane and out-of-plane sub-systems (state and control indices)."""
    for states, controls in ((IN_PLANE, (0, 1)), (OUT_OF_PLANE, (2,))):
        s, c = np.array(states), np.array(controls)
        yield s, c, A[:, s][:, :, s], B[:, s][:, :, c]


def _assemble(Np: int, parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]
              ) -> tuple[np.ndarray, np.ndarray]:
    """6-state gains from the in-plane and out-of-plane gains (b = (X_0, X_N), 12)."""
    gain_x = np.zeros((Np, 6, 12))
    gain_u = np.zeros((Np, 3, 12))
    for s, c, gx, gu in parts:
        cols = np.concatenate([s, 6 + s])
        gain_x[np.ix_(range(Np), s, cols)] = gx
        gain_u[np.ix_(range(Np), c, cols)] = gu
    return gain_x, gain_u


def _dense_grid(e: float, f0: float, fT: float, variable: str, N: int
                ) -> tuple[np.ndarray, np.ndarray]:
    """Dense samples uniform in time (s values and true anomalies)."""
    canonical = KeplerOrbit(1.0, e, 1.0)
    n_dense = max(401, 4 * N + 1)
    tau = np.linspace(0.0, float(canonical.time_since(fT, f0)), n_dense)
    f_dense = canonical.true_anomaly_after(tau, f0)
    return (f_dense if variable == "f" else tau), f_dense


@lru_cache(maxsize=32)
def plan(law: str, N: int, e: float, f0: float, fT: float) -> Plan:
    """The cached discretisation of `law` ("stm-f", "seq-f", "seq-t") on N+1 LGL nodes."""
    tau, w, D = lgl_nodes(N), lgl_weights(N), lgl_differentiation(N)
    canonical = KeplerOrbit(1.0, e, 1.0)
    if law.endswith("-f"):
        variable, s0, sT = "f", f0, fT
        s_nodes = f0 + 0.5 * (tau + 1.0) * (fT - f0)
        f_nodes = s_nodes
        A, B = th_matrices(f_nodes, e)
        rho = 1.0 + e * np.cos(f_nodes)
        q = 0.5 * (fT - f0) * w / rho**2  # paper eq. 8 without the constant k^8
    else:
        variable, s0, sT = "t", 0.0, float(canonical.time_since(fT, f0))
        s_nodes = 0.5 * (tau + 1.0) * sT
        f_nodes = canonical.true_anomaly_after(s_nodes, f0)
        A = lvlh_matrix(f_nodes, canonical, 1.0)
        B = np.zeros((N + 1, 6, 3))
        B[:, 3:, :] = np.eye(3)
        q = 0.5 * sT * w
    s_dense, f_dense = _dense_grid(e, f0, fT, variable, N)
    interp = interpolate(s_nodes, np.eye(N + 1), s_dense)
    if law.startswith("seq"):
        Ds = D * 2.0 / (sT - s0)
        parts = []
        n_unknowns = n_equations = 0
        for s, c, As, Bs in _blocks(A, B):
            gx, gu, nz, ne = _collocation_gain(Ds, As, Bs, q)
            parts.append((s, c, gx, gu))
            n_unknowns += nz
            n_equations += ne
        gain_x, gain_u = _assemble(N + 1, parts)
        dense_gain_x = np.einsum("di,ikb->dkb", interp, gain_x)
    else:
        f_all = np.concatenate([f_nodes, f_dense])
        order = np.argsort(f_all, kind="stable")
        gain_u, gx_sorted = _stm_gain(e, f_nodes, w, f_all[order])
        gx_all = np.empty_like(gx_sorted)
        gx_all[order] = gx_sorted
        gain_x, dense_gain_x = gx_all[: N + 1], gx_all[N + 1:]
        n_unknowns, n_equations = 3 * (N + 1), 6
    dense_gain_u = np.einsum("di,ikb->dkb", interp, gain_u)
    arrays = (s_nodes, f_nodes, q, gain_x, gain_u, s_dense, f_dense, interp, dense_gain_x,
              dense_gain_u)
    for arr in arrays:
        arr.setflags(write=False)
    return Plan(variable, *arrays, n_unknowns, n_equations)


def _stm_gain(e: float, f_nodes: np.ndarray, w: np.ndarray, f_eval: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """STM law (paper eq. 10): U_i = 2 rho_i² / (fT - f0) Ψ_i^T G^-1 (X_N - Φ_N X_0),
    Ψ_i = Φ(fT, f_i) B(f_i), G = Σ Ψ_i Ψ_i^T rho_i² w_i (Lagrange multipliers on eq. 9).

    The law gives controls only; its states at the (sorted) true anomalies `f_eval` are the
    linear model's exact response to the LGL polynomial control, by variation of constants
    with the YA STM, X(f) = Φ(f, f0) [X_0 + ∫ Φ(f0, σ) B(σ) U(σ) dσ], the integral by
    4-point Gauss–Legendre on every gap between the `f_eval` points. So the law's own
    terminal miss (its quadrature error in eq. 9) shows. Returns the node-control gain
    (N+1, 3, 12) and the state gain at `f_eval` (n, 6, 12).
    """
    f0, fT = f_nodes[0], f_nodes[-1]
    rho = 1.0 + e * np.cos(f_nodes)
    _, B = th_matrices(f_nodes, e)
    Psi = ya_stm(fT, f_nodes, e) @ B  # (N+1, 6, 3)
    G = np.einsum("i,ijk,ilk->jl", rho**2 * w, Psi, Psi)
    d_of_b = np.hstack([-ya_stm(fT, f0, e)[0], np.eye(6)])  # X_N - Φ_N X_0 from b
    gain_u = (2.0 * rho**2 / (fT - f0))[:, None, None] * np.einsum(
        "ijk,jl->ikl", Psi, np.linalg.solve(G, d_of_b))
    gx, gw = np.polynomial.legendre.leggauss(4)
    lo, hi = f_eval[:-1], f_eval[1:]
    sigma = (0.5 * (hi - lo)[:, None] * (gx + 1.0) + lo[:, None]).ravel()
    weight = (0.5 * (hi - lo)[:, None] * gw).ravel()
    _, Bs = th_matrices(sigma, e)
    U_sigma = np.einsum("qi,ikb->qkb", interpolate(f_nodes, np.eye(len(f_nodes)), sigma),
                        gain_u)
    integrand = weight[:, None, None] * (ya_stm(f0, sigma, e) @ Bs @ U_sigma)
    partial = integrand.reshape(len(lo), 4, 6, 12).sum(axis=1)
    cumulative = np.concatenate([np.zeros((1, 6, 12)), np.cumsum(partial, axis=0)])
    cumulative[:, :, :6] += np.eye(6)
    return gain_u, ya_stm(f_eval, f0, e) @ cumulative


# --- law evaluation in physical units --------------------------------------------------------


@dataclass
class LawResult:
    """A law's node and dense values in SI (LVLH), with its cost."""

    t_nodes: np.ndarray
    f_nodes: np.ndarray
    X: np.ndarray
    U: np.ndarray
    t: np.ndarray
    f: np.ndarray
    Xd: np.ndarray
    Ud: np.ndarray
    J: float
    plan: Plan


def _to_law(case: Case, variable: str, f: float, x: np.ndarray) -> np.ndarray:
    """An SI LVLH state in the law's variables (TH scaled, or (x, v / n) in time)."""
    o = case.orbit
    if variable == "f":
        return o.to_scaled(f, x)
    return np.concatenate([x[:3], x[3:] / o.n])


def _from_law(case: Case, variable: str, f: np.ndarray, X: np.ndarray, U: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Law variables to SI (LVLH states, accelerations)."""
    o = case.orbit
    if variable == "f":
        return o.from_scaled(f, X), U * o.k2**2
    return np.concatenate([X[..., :3], X[..., 3:] * o.n], axis=-1), U * o.n**2


def boundary_vector(case: Case, p: Plan) -> np.ndarray:
    """b = (X(s0), X(sT)) in the law's variables."""
    return np.concatenate([_to_law(case, p.variable, case.f0, case.x0),
                           _to_law(case, p.variable, case.fT, case.xT)])


def evaluate_law(
    case: Case, p: Plan, X_law: np.ndarray, U_law: np.ndarray,
    Xd_law: np.ndarray | None = None, Ud_law: np.ndarray | None = None,
) -> LawResult:
    """Node values in law variables (N+1, 6), (N+1, 3) -> SI nodes, dense samples and J.
    Dense values default to the LGL polynomial through the node values."""
    o = case.orbit
    Xd_law = p.interp @ X_law if Xd_law is None else Xd_law
    Ud_law = p.interp @ U_law if Ud_law is None else Ud_law
    X, U = _from_law(case, p.variable, p.f_nodes, X_law, U_law)
    Xd, Ud = _from_law(case, p.variable, p.f_dense, Xd_law, Ud_law)
    # J = ½ Σ q_i |u_i|² in SI: q is per canonical variable (f: dt = df / (k² rho²)).
    time_factor = 1.0 / o.k2 if p.variable == "f" else 1.0 / o.n
    J = 0.5 * time_factor * float(np.sum(p.weights * np.sum(U**2, axis=1)))
    t_nodes = o.time_since(p.f_nodes, case.f0) if p.variable == "f" else p.s_nodes / o.n
    t_dense = o.time_since(p.f_dense, case.f0) if p.variable == "f" else p.s_dense / o.n
    return LawResult(t_nodes, p.f_nodes, X, U, t_dense, p.f_dense, Xd, Ud, J, p)


def solve_law(case: Case, law: str, N: int) -> LawResult:
    """Closed-form law ("stm-f", "seq-f", "seq-t") for this case."""
    p = plan(law, N, case.orbit.e, case.f0, case.fT)
    b = boundary_vector(case, p)
    return evaluate_law(case, p, p.gain_x @ b, p.gain_u @ b, p.dense_gain_x @ b,
                        p.dense_gain_u @ b)




def convergence_table(
    case: Case, nodes: tuple[int, ...] = (8, 16, 24, 32, 48, 64, 96, 128)
) -> list[dict[str, float]]:
    """J of the STM law (f), the SEQ law (f) and the SEQ law (t) per LGL degree N."""
    return [
        {"N": N, **{law: solve_law(case, law, N).J for law in ("stm-f", "seq-f", "seq-t")}}
        for N in nodes
    ]

