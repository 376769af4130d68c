"""Mission `elliptic-transfer`: minimum-energy relative transfer about an elliptic target
orbit, Tschauner–Hempel equations in true anomaly, Legendre–Gauss–Lobatto pseudospectral
(paper 001, SPEC M2).

Three methods solve the same linear-quadratic problem: the paper's two closed-form laws
(`stm-law`, eq. 10; `seq-law`, eq. 16) and the same LGL collocation handed to IPOPT as a
general NLP (`lgl-nlp`), which must agree with `seq-law`. Everything that does not depend on
the chaser's initial state (LGL matrices, STMs, KKT factorisation, interpolation) is cached,
so the laws reduce to a matrix-vector product when a slider moves the initial state.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from ..dynamics.tschauner_hempel import (
    IN_PLANE,
    MU_EARTH,
    OUT_OF_PLANE,
    R_EARTH,
    KeplerOrbit,
    controllability_gramian,
    drift_free_vy,
    lvlh_linear_rhs,
    lvlh_matrix,
    th_matrices,
    th_rhs,
    true_anomaly_clock,
    ya_stm,
)
from ..dynamics.two_body import elements_to_state, lvlh_basis, propagate_relative
from ..mission import Infeasible, Mission, SolveContext
from ..nlp.casadi_nlp import NLP, built_once, status_of
from ..problem import Method, Param, Preset, Published
from ..solution import Body, Curve, Marker, PlotSeries, Quantity, Scene, Solution
from ..transcription.lgl import (
    barycentric_weights,
    interpolate,
    lgl_differentiation,
    lgl_nodes,
    lgl_weights,
)
from ..verify import repropagate

DEG = np.pi / 180
PAPER = "Mei, Ma & Yang 2010, J. Harbin Inst. Technol. 42(3) (paper 001)"
STATES = ("x", "y", "z", "vx", "vy", "vz")
STATE_UNITS = ("m", "m", "m", "m/s", "m/s", "m/s")
CONTROLS = ("ux", "uy", "uz")
CONTROL_UNITS = ("m/s^2",) * 3
MIN_PERIGEE_ALTITUDE = 100e3  # m
PAPER_J_SOURCE = "paper 001 (unverified; units unclear: printed as m^2/s)"

PARAMS = (
    Param("a", "semi-major axis a", "m", 9500e3, 6600e3, 60000e3, 10e3, group="Target orbit",
          display_unit="km", display_factor=1e-3),
    Param("e", "eccentricity e", "", 0.3, 0.0, 0.8, 0.01, group="Target orbit",
          help="e = 0 is the circular (Clohessy–Wiltshire) limit."),
    Param("inclination", "inclination i", "rad", 30 * DEG, 0.0, np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG,
          help="Orientation only changes the inertial view (the relative problem is the same)."),
    Param("raan", "ascending node Ω", "rad", 30 * DEG, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("argp", "argument of perigee ω", "rad", 10 * DEG, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("f0", "initial true anomaly f0", "rad", 0.0, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("periods", "transfer time", "periods", 3.0, 0.25, 6.0, 0.25, group="Target orbit",
          help="In target orbital periods; the chaser must reach the target (zero relative "
               "position and velocity) at the end."),
    Param("x0", "radial x0", "m", 10000.0, -50e3, 50e3, 100.0, group="Chaser initial state"),
    Param("y0", "along-track y0", "m", 10000.0, -50e3, 50e3, 100.0,
          group="Chaser initial state"),
    Param("z0", "cross-track z0", "m", 0.0, -50e3, 50e3, 100.0, group="Chaser initial state"),
    Param("vx0", "radial vx0", "m/s", 4.0, -50.0, 50.0, 0.01, group="Chaser initial state"),
    Param("vy0", "along-track vy0", "m/s", -23.485, -100.0, 100.0, 0.001,
          group="Chaser initial state",
          help="The paper's -23.485 m/s is the drift-free value for x0 = 10 km at perigee."),
    Param("vz0", "cross-track vz0", "m/s", 0.0, -50.0, 50.0, 0.01,
          group="Chaser initial state"),
    Param("vy_source", "along-track velocity from", "", 0, 0, 1, 1,
          group="Chaser initial state", options=("given vy0", "drift-free (periodic motion)"),
          help="Drift-free: vy0 is set so that the uncontrolled relative motion is periodic."),
    Param("view", "3D view", "", 0, 0, 1, 1, group="Display",
          options=("LVLH (target-centred)", "inertial (Earth-centred)"),
          help="LVLH: x radial (up), y along-track, z orbit normal. Inertial: the target's "
               "orbit about the Earth (the 10 km relative motion is invisible at that scale)."),
)

NODES = (8, 64, 128)
METHODS = (
    Method(
        "stm-law", "STM law (closed form, eq. 10)", PAPER,
        "Yamanaka–Ankersen STM maps the control at the LGL nodes to the final state by LGL "
        "quadrature; Lagrange multipliers give the node controls in closed form. Only the "
        "initial and final states constrain the control.",
        nodes=NODES, nodes_label="LGL degree N",
    ),
    Method(
        "seq-law", "SEQ law (collocation + KKT, eq. 16)", PAPER,
        "The TH state equations are collocated at all N+1 LGL nodes, the boundary states "
        "are fixed and the equality-constrained QP is solved from its KKT system.",
        nodes=NODES, nodes_label="LGL degree N",
        params=(
            Param("variable", "independent variable", "", 0, 0, 1, 1, group="Method",
                  options=("true anomaly f (paper)", "time t"),
                  help="Time as independent variable needs more nodes for e = 0.3 over "
                       "three revolutions: the perigee passes are short in time."),
        ),
    ),
    Method(
        "lgl-nlp", "LGL collocation as a general NLP (IPOPT)", "paper 001, solved by IPOPT",
        "The same collocation as the SEQ law written as an NLP (states and controls at the "
        "nodes, defects as constraints) and solved by IPOPT: it must agree with the SEQ law.",
        nodes=NODES, nodes_label="LGL degree N", backends=("ipopt",),
    ),
)

PUBLISHED = (
    Published("J_stm", 1.9e-6, "m^2/s", PAPER_J_SOURCE,
              "section 4, fig. 1: STM-law cost as printed. Not reproduced: our converged "
              "J_f = 2.952e-7 m^2/s^4 (J = 3.7585e-4 m^2/s^3) for both laws (see help)"),
    Published("J_seq", 2.95e-7, "m^2/s", PAPER_J_SOURCE,
              "section 4, fig. 4: SEQ-law cost as printed. Equals our J_f = k^2 J = 2.952e-7 "
              "m^2/s^4 (the paper's eq. 5 form) to the printed digits (see help)"),
    Published("seq_linear_position_miss", 5.0, "m", "paper 001, section 4",
              "upper bound: SEQ law in the linear model 'within 5 m'"),
    Published("seq_linear_velocity_miss", 0.01, "m/s", "paper 001, section 4",
              "upper bound: SEQ law in the linear model 'within 0.01 m/s'"),
)

# J [m²/s³] of the paper case per LGL degree N (measured; `convergence_table` recomputes it
# and tests/test_elliptic_transfer.py checks this documentation against it).
J_REFERENCE = 3.7585390767e-4  # controllability Gramian of the time-domain linear model
CONVERGENCE = (  # N, STM law (f), SEQ law (f), SEQ law (t)
    (8, 2.429883971e-04, 4.792315528e-03, 1.936044790e-02),
    (16, 3.539333351e-04, 1.712691038e-03, 1.761104483e-03),
    (24, 3.737072822e-04, 3.939655655e-04, 1.010934934e-03),
    (32, 3.756286029e-04, 3.760134675e-04, 8.419750315e-04),
    (48, 3.758526862e-04, 3.758560346e-04, 5.674778943e-04),
    (64, 3.758539030e-04, 3.758539376e-04, 4.113071277e-04),
    (96, 3.758539077e-04, 3.758539077e-04, 3.759909324e-04),
    (128, 3.758539077e-04, 3.758539077e-04, 3.758546507e-04),
)


def _convergence_markdown() -> str:
    rows = ["| N | STM law (f) | SEQ law (f) | SEQ law (time t) |", "|---|---|---|---|"]
    for N, *Js in CONVERGENCE:
        rel = [(J - J_REFERENCE) / J_REFERENCE for J in Js]
        cells = [f"{J:.4e} ({r:+.0e})" if abs(r) > 1e-9 else f"{J:.4e} (< 1e-9)"
                 for J, r in zip(Js, rel, strict=True)]
        rows.append(f"| {N} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


HELP = """\
**Minimum-energy rendezvous about an elliptic orbit** (paper 001). The target flies a
9500 km, e = 0.3 orbit; the chaser starts 10 km above and 10 km ahead of it and must reach
it, at rest, after three orbital periods (27 645 s), minimising J = ½ ∫ |u|² dt. With the
true anomaly f as independent variable the linearised (Tschauner–Hempel) equations are simple
and have the closed-form Yamanaka–Ankersen state transition matrix. The paper's cost (eq. 5)
J_f = ½ ∫ |u|² / (1 + e cos f)² df equals k² J exactly (k² = h / p² = 7.8546e-4 /s here), so
both name the same optimum.

*Methods.* **STM law** (eq. 10): control at the LGL nodes, final state by the STM and LGL
quadrature, closed form. **SEQ law** (eq. 16): the state equations collocated at every node,
KKT system, closed form (option: time instead of true anomaly as independent variable).
**LGL-NLP**: the SEQ collocation handed to IPOPT as a general NLP; it agrees with the SEQ law
to solver tolerance, which checks the closed form.

*Cost, ours and the paper's (paper case).* Ours, computed two independent ways that agree to
4e-11: the LGL laws at converged N (96 and up), and the minimum-energy control from the
controllability Gramian of the time-domain linear model (integrated numerically, no STM):

| | J = ½∫\\|u\\|² dt [m²/s³] | J_f = k² J [m²/s⁴] | paper, printed "m²/s" |
|---|---|---|---|
| converged (both laws, Gramian) | 3.75854e-4 | 2.9522e-7 | — |
| STM law, N = 64 | 3.75854e-4 | 2.9522e-7 | 1.9e-6 |
| SEQ law, N = 64 | 3.75854e-4 | 2.9522e-7 | 2.95e-7 |

The paper's SEQ value 2.95e-7 equals our J_f to its three printed digits (so "m²/s" is a
misprint for the eq. 5 form, m²/s⁴). Its STM value 1.9e-6 is not reproduced: at N = 64 both
laws give the same optimum (they differ by 1e-7 relative), so the paper's 6x gap between the
laws does not appear here. Both printed values are kept as published, marked unverified.

*Convergence with N* (J in m²/s³, relative error against the Gramian value in brackets):
with f as independent variable three revolutions are resolved by N ≈ 64; with time as
independent variable the short perigee passes need about twice the nodes (method option
"time t" of the SEQ law).

""" + _convergence_markdown() + """

*Terminal misses (paper case, N = 64)* after re-propagating each law's control (its LGL
polynomial) with solve_ivp, rtol 1e-10. Linear model: STM law 1.5e-4 m / 2.7e-7 m/s, SEQ law
8.7e-5 m / 9.2e-8 m/s (paper: SEQ within 5 m and 0.01 m/s, STM hundreds of metres).
Nonlinear two-body model: 393 m / 0.14 m/s for both laws (paper: hundreds of metres) — the
linearisation error over three revolutions at 14 km separation, not a property of the laws.
At N = 16 the laws are not converged and miss by kilometres even in the linear model.

*Teaching points:* the LGL nodes cluster at both ends of the transfer (see the node markers
and thrust arrows). In true anomaly the motion is a smooth, nearly trigonometric function;
in time it changes fastest during the perigee passes, which are short, so a polynomial in t
needs more nodes for the same accuracy. The paper's initial along-track speed −23.485 m/s
is exactly the drift-free value, so without control the chaser would circle the target
periodically (the dashed curve).
"""


# --- the problem instance -------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    """A validated request in the form the laws use (SI)."""

    orbit: KeplerOrbit
    f0: float
    fT: float
    duration: float
    x0: np.ndarray
    xT: np.ndarray
    inclination: float
    raan: float
    argp: float


def make_case(values: dict[str, float]) -> Case:
    """Case from mission values (vy0 replaced by the drift-free value when asked)."""
    orbit = KeplerOrbit(values["a"], values["e"], MU_EARTH)
    f0 = values["f0"]
    duration = values["periods"] * orbit.period
    x0 = np.array([values[k] for k in ("x0", "y0", "z0", "vx0", "vy0", "vz0")])
    if values["vy_source"] == 1:
        x0[4] = drift_free_vy(orbit, f0, x0)
    fT = float(orbit.true_anomaly_after(duration, f0))
    return Case(orbit, f0, fT, duration, x0, np.zeros(6), values["inclination"],
                values["raan"], values["argp"])


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


def _blocks(A: np.ndarray, B: np.ndarray):
    """The decoupled in-plane and out-of-plane sub-systems (state and control indices)."""
    for states, controls in ((IN_PLANE, (0, 1)), (OUT_OF_PLANE, (2,))):
        s, c = np.array(states), np.array(controls)
        yield s, c, A[:, s][:, :, s], B[:, s][:, :, c]


def _assemble(Np: int, parts) -> tuple[np.ndarray, np.ndarray]:
    """6-state gains from the in-plane and out-of-plane gains (b = (X_0, X_N), 12)."""
    gain_x = np.zeros((Np, 6, 12))
    gain_u = np.zeros((Np, 3, 12))
    for s, c, gx, gu in parts:
        cols = np.concatenate([s, 6 + s])
        gain_x[np.ix_(range(Np), s, cols)] = gx
        gain_u[np.ix_(range(Np), c, cols)] = gu
    return gain_x, gain_u


def _dense_grid(e: float, f0: float, fT: float, variable: str, N: int):
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


def _stm_gain(e: float, f_nodes: np.ndarray, w: np.ndarray, f_eval: np.ndarray):
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
    o = case.orbit
    if variable == "f":
        return o.to_scaled(f, x)
    return np.concatenate([x[:3], x[3:] / o.n])


def _from_law(case: Case, variable: str, f: np.ndarray, X: np.ndarray, U: np.ndarray):
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


def gramian_cost(case: Case) -> float:
    """Minimum energy J = ½ d^T W^-1 d [m²/s³] from the controllability Gramian of the
    time-domain linear model (independent of the STM and of the LGL discretisation)."""
    Phi, W = _gramian(case.orbit.e, case.f0, case.duration * case.orbit.n)
    n = case.orbit.n
    scale = np.array([1, 1, 1, 1 / n, 1 / n, 1 / n])
    d = case.xT * scale - Phi @ (case.x0 * scale)
    return 0.5 * float(d @ np.linalg.solve(W, d)) * n**3


@lru_cache(maxsize=16)
def _gramian(e: float, f0: float, duration_nd: float) -> tuple[np.ndarray, np.ndarray]:
    return controllability_gramian(KeplerOrbit(1.0, e, 1.0), f0, duration_nd)


def convergence_table(
    case: Case, nodes: tuple[int, ...] = (8, 16, 24, 32, 48, 64, 96, 128)
) -> list[dict[str, float]]:
    """J of the STM law (f), the SEQ law (f) and the SEQ law (t) per LGL degree N."""
    return [
        {"N": N, **{law: solve_law(case, law, N).J for law in ("stm-f", "seq-f", "seq-t")}}
        for N in nodes
    ]


# --- LGL collocation as a general NLP ---------------------------------------------------------


@built_once
def _lgl_nlp(N: int, backend: str) -> NLP:
    """The SEQ collocation as an NLP in variables (X, U) at the nodes, built once per N.

    Parameters p = (e, f0, fT, X_0, X_N) with boundary states divided by a scale so the
    variables are O(1). Cost: paper eq. 8 (without the constant k^8).
    """
    tau, w, D = lgl_nodes(N), lgl_weights(N), lgl_differentiation(N)
    X = ca.MX.sym("X", 6, N + 1)
    U = ca.MX.sym("U", 3, N + 1)
    p = ca.MX.sym("p", 15)
    e, f0, fT = p[0], p[1], p[2]
    f = f0 + 0.5 * (ca.DM(tau).T + 1) * (fT - f0)
    defects = ca.mtimes(X, ca.DM(D).T) * (2 / (fT - f0)) - th_rhs(X, U, f, e)
    rho = 1 + e * ca.cos(f)
    cost = 0.25 * (fT - f0) * ca.dot(ca.DM(w).T / rho**2, ca.sum1(U**2))
    g = ca.vertcat(ca.vec(defects), X[:, 0] - p[3:9], X[:, N] - p[9:15])
    return NLP(ca.vertcat(ca.vec(X), ca.vec(U)), cost, g, p, backend, name=f"lgl_nlp_{N}")


# --- the mission ------------------------------------------------------------------------------


LAW_OF_METHOD = {"stm-law": "stm-f", "seq-law": "seq-f", "lgl-nlp": "seq-f"}


class EllipticTransfer(Mission):
    key = "elliptic-transfer"
    title = "Relative transfer on an elliptic orbit"
    summary = ("Minimum-energy rendezvous about a 9500 km, e = 0.3 target orbit: "
               "Tschauner–Hempel equations, Legendre–Gauss–Lobatto pseudospectral laws.")
    source = PAPER
    help = HELP
    params = PARAMS
    methods = METHODS
    published = PUBLISHED
    cost_label = "J = ½∫|u|²dt"
    cost_unit = "m^2/s^3"
    equations = (
        ("Tschauner–Hempel equations in true anomaly (paper 001, eq. 1), x̃ = (1 + e cos f) x",
         r"\tilde x'' = \frac{3\tilde x}{1 + e\cos f} + 2\tilde y' "
         r"+ \frac{u_x}{k^4(1 + e\cos f)^3},"
         r"\quad \tilde y'' = -2\tilde x' + \frac{u_y}{k^4(1 + e\cos f)^3},"
         r"\quad \tilde z'' = -\tilde z + \frac{u_z}{k^4(1 + e\cos f)^3}"),
        ("Minimum-energy cost: physical (SI) and the paper's true-anomaly form (eq. 5)",
         r"J = \frac12\int_{t_0}^{t_f} \lVert u\rVert^2\,dt,\qquad "
         r"J_f = \frac12\int_{f_0}^{f_T} \frac{u^T u}{(1 + e\cos f)^2}\,df = k^2 J"),
        ("LGL nodes, weights and differentiation matrix (eq. 4)",
         r"w_i = \frac{2}{N(N+1)L_N(t_i)^2},\qquad D_{ij} = \frac{L_N(t_i)}{L_N(t_j)(t_i - t_j)}"
         r"\ (i \ne j)"),
    )
    presets = (
        Preset("Paper 001 case", {}, method="seq-law", nodes=64,
               note="a = 9500 km, e = 0.3, three periods, N = 64."),
        Preset("Paper case, STM law", {}, method="stm-law", nodes=64),
        Preset("Circular limit (e = 0, Clohessy–Wiltshire)", {"e": 0.0, "vy_source": 1},
               method="seq-law", nodes=64,
               note="vy0 drift-free for the circular orbit (-2 n x0)."),
        Preset("Too few nodes (N = 16)", {}, method="stm-law", nodes=16,
               note="The STM law's quadrature is under-resolved: the linear-model miss grows."),
        Preset("Time as independent variable, N = 32", {"variable": 1}, method="seq-law",
               nodes=32, note="Compare J with the true-anomaly version at the same N."),
        Preset("One period", {"periods": 1.0}, method="seq-law", nodes=64),
        Preset("Out-of-plane start (z0 = 5 km)", {"z0": 5000.0}, method="seq-law", nodes=64),
    )

    def _solve(
        self,
        values: dict[str, float],
        method: Method,
        nodes: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        case = make_case(values)
        perigee = case.orbit.a * (1 - case.orbit.e)
        if perigee < R_EARTH + MIN_PERIGEE_ALTITUDE:
            raise Infeasible(
                f"the target's perigee radius {perigee / 1e3:.0f} km is less than "
                f"{MIN_PERIGEE_ALTITUDE / 1e3:.0f} km above the Earth's surface "
                f"({R_EARTH / 1e3:.0f} km): lower e or raise a"
            )
        if method.key == "lgl-nlp":
            res, status, message, stats, warm_out, history = self._solve_nlp(
                case, nodes, backend, warm, ctx)
        else:
            law = "seq-t" if method.key == "seq-law" and values["variable"] == 1 else \
                LAW_OF_METHOD[method.key]
            res = solve_law(case, law, nodes)
            status, message, history, warm_out = "optimal", "closed form", [], None
            stats = {"iterations": 0, "nlp_variables": res.plan.n_unknowns,
                     "nlp_constraints": res.plan.n_equations}
        sol = self._record(values, method.key, nodes, backend, case, res, status, message)
        sol.stats.update(stats)
        sol.warm = warm_out
        sol.history = [{"iteration": k, "positions": self._display(case, values, f, Xk)[0]}
                       for k, f, Xk in history]
        sol.checker = lambda: self._check(sol, case, res, values)
        return sol

    def _solve_nlp(self, case: Case, N: int, backend: str, warm: Solution | None,
                   ctx: SolveContext):
        p_plan = plan("seq-f", N, case.orbit.e, case.f0, case.fT)
        b = boundary_vector(case, p_plan)
        scale = max(float(np.max(np.abs(b))), 1.0)
        nlp = _lgl_nlp(N, backend)
        params = np.concatenate([[case.orbit.e, case.f0, case.fT], b / scale])
        lam_x0 = lam_g0 = None
        if warm is not None and warm.ok and warm.warm is not None and warm.nodes == N:
            x_prev, lx, lg, scale_prev = warm.warm
            ratio = scale_prev / scale
            x0, lam_x0, lam_g0 = x_prev * ratio, lx * ratio, lg * ratio
        else:
            # Neutral guess: states linear between the boundary states, no control.
            alpha = 0.5 * (lgl_nodes(N) + 1.0)
            Xg = np.outer(b[:6], 1 - alpha) + np.outer(b[6:], alpha)
            x0 = np.concatenate([Xg.T.ravel() / scale, np.zeros(3 * (N + 1))])
        zeros_g = np.zeros(nlp.n_g)
        inf = np.full(nlp.n_x, np.inf)
        out = nlp.solve(x0, params, -inf, inf, zeros_g, zeros_g, lam_x0, lam_g0, ctx)
        status, message = status_of(out)
        nx = 6 * (N + 1)

        def unpack(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            return (z[:nx].reshape(N + 1, 6) * scale, z[nx:].reshape(N + 1, 3) * scale)

        X_law, U_law = unpack(out.x)
        res = evaluate_law(case, p_plan, X_law, U_law)
        stats = {"iterations": out.iterations, "nlp_variables": nlp.n_x,
                 "nlp_constraints": nlp.n_g, "constraint_violation": out.max_violation}
        history = [(k, p_plan.f_nodes, case.orbit.from_scaled(p_plan.f_nodes, unpack(z)[0]))
                   for k, z in out.history]
        return res, status, message, stats, (out.x, out.lam_x, out.lam_g, scale), history

    # --- Solution assembly ---

    def _display(self, case: Case, values: dict[str, float], f: np.ndarray, X: np.ndarray,
                 vectors: np.ndarray | None = None):
        """Positions (and optional vectors) in the chosen display frame (metres)."""
        if values["view"] == 0:
            return X[:, :3], vectors
        r, v = elements_to_state(case.orbit.a, case.orbit.e, case.inclination, case.raan,
                                 case.argp, f, case.orbit.mu)
        R = lvlh_basis(r, v)
        pos = r + np.einsum("nij,nj->ni", R, X[:, :3])
        vec = None if vectors is None else np.einsum("nij,nj->ni", R, vectors)
        return pos, vec

    def _record(self, values, method, nodes, backend, case: Case, res: LawResult, status,
                message) -> Solution:
        o = case.orbit
        quantities = {
            "J": Quantity(res.J, "J = ½∫|u|²dt", "m^2/s^3"),
            "J_f": Quantity(res.J * o.k2, "J_f (paper eq. 5)", "m^2/s^4"),
            "transfer_time": Quantity(case.duration, "transfer time", "s"),
            "vy0": Quantity(float(case.x0[4]), "initial along-track velocity used", "m/s"),
            "law_terminal_position": Quantity(float(np.linalg.norm(res.X[-1, :3] - case.xT[:3])),
                                              "terminal position of the law's states", "m"),
        }
        sol = Solution(
            mission=self.key, method=method, nodes=nodes, backend=backend, status=status,
            message=message, cost=Quantity(res.J, self.cost_label, self.cost_unit),
            values=values, quantities=quantities, state_names=STATES, state_units=STATE_UNITS,
            control_names=CONTROLS, control_units=CONTROL_UNITS, node_t=res.t_nodes,
            node_x=res.X, node_u=res.U, arcs=[(0.0, case.duration, "burn")], t=res.t,
            x=res.Xd, u=res.Ud,
        )
        umag = np.linalg.norm(res.U, axis=1)
        thrust = res.U / max(float(umag.max()), 1e-300)
        sol.positions, _ = self._display(case, values, res.f, res.Xd)
        sol.node_positions, sol.thrust = self._display(case, values, res.f_nodes, res.X, thrust)
        sol.scene = self._scene(case, values)
        sol.plots = _plots(res)
        return sol

    def _scene(self, case: Case, values: dict[str, float]) -> Scene:
        o = case.orbit
        f_free = np.linspace(case.f0, case.fT, 400)
        X0 = o.to_scaled(case.f0, case.x0)
        free = o.from_scaled(f_free, ya_stm(f_free, case.f0, o.e) @ X0)
        free_pos, _ = self._display(case, values, f_free, free)
        start, _ = self._display(case, values, np.array([case.f0]), case.x0[None])
        curves = [Curve("uncontrolled motion (linear model)", free_pos, (150, 150, 150),
                        dashed=True)]
        if values["view"] == 0:
            return Scene(
                frame="LVLH (target-centred): x radial, y along-track, z orbit normal",
                display_unit="km", display_scale=1e-3,
                bodies=[Body("target", (0.0, 0.0, 0.0), 150.0, (255, 210, 90))],
                curves=curves,
                markers=[Marker("chaser start", tuple(start[0]), (120, 200, 255)),
                         Marker("target", (0.0, 0.0, 0.0), (255, 210, 90))],
                up="+x",
            )
        f_orbit = np.linspace(0.0, 2 * np.pi, 361)
        r_orbit, _ = elements_to_state(o.a, o.e, case.inclination, case.raan, case.argp,
                                       f_orbit, o.mu)
        r_t0, _ = elements_to_state(o.a, o.e, case.inclination, case.raan, case.argp,
                                    case.f0, o.mu)
        r_per, _ = elements_to_state(o.a, o.e, case.inclination, case.raan, case.argp, 0.0,
                                     o.mu)
        return Scene(
            frame="Earth-centred inertial", display_unit="km", display_scale=1e-3,
            bodies=[Body("Earth", (0.0, 0.0, 0.0), R_EARTH, (70, 120, 200))],
            curves=[Curve("target orbit", r_orbit, (255, 210, 90), dashed=True), *curves],
            markers=[Marker("target at start", tuple(r_t0), (255, 210, 90)),
                     Marker("perigee", tuple(r_per), (200, 200, 200))],
            up="+z",
        )

    # --- deferred check ---

    def _check(self, sol: Solution, case: Case, res: LawResult,
               values: dict[str, float]) -> dict[str, float]:
        """Re-propagate the law's control (its LGL polynomial) through the time-domain
        linear model and the nonlinear two-body model; compare J with the Gramian's."""
        o = case.orbit
        p = res.plan
        u_of_s = _polynomial(p.s_nodes, res.U)
        s_of_t = true_anomaly_clock(o.e, o.n, case.f0) if p.variable == "f" else \
            (lambda t: o.n * t)

        f_lin = _linear_function()
        x0 = np.concatenate([case.x0, [case.f0]])
        control_lin = (lambda t, x: u_of_s(x[6])) if p.variable == "f" else \
            (lambda t, x: u_of_s(o.n * t))
        t_lin, X_lin = repropagate(f_lin, np.array([o.e, o.k2]), x0, control_lin, res.t_nodes,
                                   atol=np.array([1e-6] * 3 + [1e-9] * 3 + [1e-12]))
        r_t0, v_t0 = elements_to_state(o.a, o.e, case.inclination, case.raan, case.argp,
                                       case.f0, o.mu)
        t_nl, X_nl, _ = propagate_relative(r_t0, v_t0, case.x0,
                                           lambda t: u_of_s(s_of_t(t)), res.t_nodes,
                                           o.mu, samples_per_piece=3)
        miss_lin, miss_nl = X_lin[-1, :6] - case.xT, X_nl[-1] - case.xT
        J_gram = gramian_cost(case)
        out = {
            "position_m": float(np.linalg.norm(miss_lin[:3])),
            "velocity_m_s": float(np.linalg.norm(miss_lin[3:])),
            "nonlinear_position_m": float(np.linalg.norm(miss_nl[:3])),
            "nonlinear_velocity_m_s": float(np.linalg.norm(miss_nl[3:])),
            "J_gramian_m2_s3": J_gram,
            "J_relative_difference": (res.J - J_gram) / J_gram,
        }
        sol.quantities.update(
            linear_miss_position=Quantity(out["position_m"], "linear-model miss", "m"),
            linear_miss_velocity=Quantity(out["velocity_m_s"], "linear-model miss", "m/s"),
            nonlinear_miss_position=Quantity(out["nonlinear_position_m"],
                                             "nonlinear-model miss", "m"),
            nonlinear_miss_velocity=Quantity(out["nonlinear_velocity_m_s"],
                                             "nonlinear-model miss", "m/s"),
            J_gramian=Quantity(J_gram, "J (Gramian, exact)", "m^2/s^3"),
        )
        f_nl = o.true_anomaly_after(t_nl, case.f0)
        nl_pos, _ = self._display(case, values, f_nl, X_nl)
        if sol.scene is not None:
            sol.scene.curves.append(Curve("nonlinear model (re-propagated)", nl_pos,
                                          (255, 110, 110)))
        sol.plots.extend(_state_plots(t_nl, X_nl, "nonlinear model", "(nonlinear)"))
        return out


def _polynomial(nodes: np.ndarray, values: np.ndarray):
    """Fast scalar evaluation of the LGL polynomial through (nodes, values) (barycentric)."""
    bw = barycentric_weights(nodes)

    def at(s: float) -> np.ndarray:
        d = s - nodes
        k = int(np.argmin(np.abs(d)))
        if d[k] == 0.0:
            return values[k]
        c = bw / d
        return (c @ values) / c.sum()

    return at


@built_once
def _linear_function() -> ca.Function:
    """The time-domain linear model f(x, u, p) for `repropagate` (x includes f)."""
    x, u, p = ca.SX.sym("x", 7), ca.SX.sym("u", 3), ca.SX.sym("p", 2)
    return ca.Function("lvlh_linear", [x, u, p], [lvlh_linear_rhs(x, u, p)])


def _state_plots(t, X, group: str, suffix: str) -> list[PlotSeries]:
    return [
        *[PlotSeries(f"{n} {suffix}".strip(), "km", t, X[:, k] / 1e3, group=group)
          for k, n in enumerate(("x", "y", "z"))],
        *[PlotSeries(f"{n} {suffix}".strip(), "m/s", t, X[:, 3 + k], group=group)
          for k, n in enumerate(("vx", "vy", "vz"))],
    ]


def _plots(res: LawResult) -> list[PlotSeries]:
    mm = 1e3  # m/s^2 -> mm/s^2
    umag = np.linalg.norm(res.Ud, axis=1)
    plots = [PlotSeries("|u| (paper figs. 1, 4)", "mm/s^2", res.t, umag * mm, res.t_nodes,
                        np.linalg.norm(res.U, axis=1) * mm, group="control")]
    for k, n in enumerate(CONTROLS):
        plots.append(PlotSeries(n, "mm/s^2", res.t, res.Ud[:, k] * mm, res.t_nodes,
                                res.U[:, k] * mm, group="control"))
    for k, n in enumerate(STATES):
        unit, factor = ("km", 1e-3) if k < 3 else ("m/s", 1.0)
        plots.append(PlotSeries(f"{n} (linear model)", unit, res.t, res.Xd[:, k] * factor,
                                res.t_nodes, res.X[:, k] * factor))
    return plots


MISSION = EllipticTransfer()
