"""Paper 002's integral transformation of the lunar soft-landing problem, solved by the
generalised multiplier method with BFGS.

The independent variable is varpi = -omega, which rises monotonically from -omega0 to 0
while |psi| < 90 deg and the thrust beats the Coriolis term. Dividing eq. 1 by

    d varpi / dt = ((F/m) cos psi + 2 v omega) / r          (omega = -varpi)

gives a fixed-interval problem in varpi with state y = (r, v, theta, m, t): the free final
time becomes the fixed end varpi = 0 and omega(tf) = 0 holds by construction. What remains is
min tf (fuel = F tf / c) subject to h = (r(0) - R_moon, v(0)) = 0.

psi is linear between N + 1 equally spaced nodes in varpi. The trajectory is integrated by a
4th-order Adams-Bashforth-Moulton predictor-corrector (PECE) started with three RK4 steps,
as one CasADi SX graph of (psi nodes, parameters); cost, constraints and their exact
gradients are CasADi Functions built once per (N, steps per segment) and cached.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ...context import SolveContext
from ...nlp.cache import built_once
from ...nlp.multiplier_method import MultiplierResult, solve_multiplier_method
from .model import MU_MOON, R_MOON

# Scaling of the NLP seen by the multiplier method: tf in units of T_SCALE, the altitude miss
# in units of R_SCALE and the radial speed in units of V_SCALE. With these units the paper's
# penalty and multiplier values (sigma0 = 20, lambda0 = (10, 10)) behave as published.
T_SCALE = 100.0  # s
R_SCALE = 1000.0  # m
V_SCALE = 10.0  # m/s

STEPS_PER_SEGMENT = 4
N_PARAMS = 7  # r0, omega0, m0, F, c, mu, R

# Convergence: altitude miss and radial speed (SI), inner gradient (scaled units).
TOL_ALTITUDE = 1e-4  # m
TOL_SPEED = 1e-5  # m/s
INNER_GTOL = 1e-6

PAPER_SIGMA = dict(beta=2.0, gamma=0.5, lam0=(10.0, 10.0))


@dataclass
class IntegralTransformResult:
    varpi_nodes: np.ndarray
    psi_nodes: np.ndarray
    t_nodes: np.ndarray
    x_nodes: np.ndarray  # (N+1, 5): r, v, theta, omega, m
    t_dense: np.ndarray
    x_dense: np.ndarray
    psi_dense: np.ndarray
    tf: float
    fuel: float
    converged: bool
    message: str
    outer_iterations: int
    inner_iterations: int
    integrations: int
    n_variables: int
    n_constraints: int
    constraint_violation: float
    history: list[tuple[int, np.ndarray, np.ndarray]] = field(default_factory=list)
    lam: np.ndarray | None = None
    sigma: float = float("nan")
    steps_per_segment: int = STEPS_PER_SEGMENT


def _transformed_rhs(varpi, y, psi, p):
    """dy/dvarpi for y = (r, v, theta, t) and d varpi / dt (must stay > 0).

    The mass is not a state: with constant thrust m = m0 - F t / c exactly.
    """
    r, v, t = y[0], y[1], y[3]
    m0, thrust, c, mu = p[2], p[3], p[4], p[5]
    acc = thrust / (m0 - thrust / c * t)
    rate = (acc * ca.cos(psi) - 2 * v * varpi) / r  # d varpi / dt
    inv = 1 / rate
    dy = ca.vertcat(
        v * inv,
        (acc * ca.sin(psi) - mu / r**2 + r * varpi**2) * inv,
        -varpi * inv,
        inv,
    )
    return dy, rate


@built_once
def _step_functions() -> tuple[ca.Function, ca.Function, ca.Function]:
    """SX Functions of one right-hand side, one RK4 step and one ABM4-PECE step; calling them
    on SX arguments inlines them, so the whole graph is built with few Python calls."""
    y = ca.SX.sym("y", 4)
    f0, f1, f2, f3 = (ca.SX.sym(f"f{i}", 4) for i in range(4))
    w0, hs = ca.SX.sym("varpi0"), ca.SX.sym("h")
    ps0, psm, ps1 = ca.SX.sym("psi0"), ca.SX.sym("psi_half"), ca.SX.sym("psi1")
    p = ca.SX.sym("p", N_PARAMS)
    dy, rate = _transformed_rhs(w0, y, ps0, p)
    rhs = ca.Function("rhs", [y, w0, ps0, p], [dy, rate])
    # RK4 step from (w0, y) with f0 = f(w0, y) given; returns y1, f(w1, y1), min rate.
    k2, r2 = _transformed_rhs(w0 + hs / 2, y + hs / 2 * f0, psm, p)
    k3, r3 = _transformed_rhs(w0 + hs / 2, y + hs / 2 * k2, psm, p)
    k4, r4 = _transformed_rhs(w0 + hs, y + hs * k3, ps1, p)
    y1 = y + hs / 6 * (f0 + 2 * k2 + 2 * k3 + k4)
    fy1, r5 = _transformed_rhs(w0 + hs, y1, ps1, p)
    rk4 = ca.Function("rk4", [y, f0, w0, hs, psm, ps1, p],
                      [y1, fy1, ca.fmin(ca.fmin(r2, r3), ca.fmin(r4, r5))])
    # ABM4 PECE step; f0..f3 = f at the current and the three previous points.
    yp = y + hs / 24 * (55 * f0 - 59 * f1 + 37 * f2 - 9 * f3)
    fp, rp = _transformed_rhs(w0 + hs, yp, ps1, p)
    yc = y + hs / 24 * (9 * fp + 19 * f0 - 5 * f1 + f2)
    fc, rc = _transformed_rhs(w0 + hs, yc, ps1, p)
    abm = ca.Function("abm4", [y, f0, f1, f2, f3, w0, hs, ps1, p], [yc, fc, ca.fmin(rp, rc)])
    return rhs, rk4, abm


def _integrate(z, p, n_segments: int, steps: int):
    """ABM4-PECE (RK4 start) integration over varpi in [-omega0, 0].

    Returns (Y (4, K+1) rows r, v, theta, t; psi at the K+1 step points; min of
    d varpi / dt over all right-hand-side evaluations).
    """
    rhs, rk4, abm = _step_functions()
    k_steps = n_segments * steps
    omega0 = p[1]
    hstep = omega0 / k_steps

    def psi_at(u: float):
        """psi at step coordinate u (in steps from the start), linear between nodes."""
        j = min(int(u // steps), n_segments - 1)
        frac = (u - j * steps) / steps
        return (1 - frac) * z[j] + frac * z[j + 1] if frac else z[j]

    def varpi_at(u: float):
        return -omega0 + u * hstep

    y = ca.vertcat(p[0], 0, 0, 0)
    f, rate_min = rhs(y, varpi_at(0), psi_at(0), p)
    ys, fs = [y], [f]
    for k in range(k_steps):
        if k < 3:
            y, f, rate = rk4(y, f, varpi_at(k), hstep, psi_at(k + 0.5), psi_at(k + 1), p)
        else:
            y, f, rate = abm(y, fs[-1], fs[-2], fs[-3], fs[-4], varpi_at(k), hstep,
                             psi_at(k + 1), p)
            fs.pop(0)
        rate_min = ca.fmin(rate_min, rate)
        ys.append(y)
        fs.append(f)
    psi_dense = ca.vertcat(*[psi_at(float(k)) for k in range(k_steps + 1)])
    return ca.horzcat(*ys), psi_dense, rate_min


@built_once
def build_functions(n_segments: int, steps: int = STEPS_PER_SEGMENT) -> dict[str, ca.Function]:
    """CasADi Functions of (psi nodes (N+1), p = (r0, omega0, m0, F, c, mu, R)):

    `eval`: (J, dJ/dz, h, dh/dz, min d varpi/dt) with J = tf / T_SCALE and
    h = ((r_f - R) / R_SCALE, v_f / V_SCALE); `traj`: (Y (4, K+1), psi (K+1)).
    """
    z = ca.SX.sym("psi", n_segments + 1)
    p = ca.SX.sym("p", N_PARAMS)
    Y, psi_dense, rate_min = _integrate(z, p, n_segments, steps)
    yf = Y[:, -1]
    J = yf[3] / T_SCALE
    h = ca.vertcat((yf[0] - p[6]) / R_SCALE, yf[1] / V_SCALE)
    ev = ca.Function("it_eval", [z, p], [J, ca.gradient(J, z), h, ca.jacobian(h, z), rate_min],
                     ["psi", "p"], ["J", "dJ", "h", "dh", "rate_min"])
    traj = ca.Function("it_traj", [z, p], [Y, psi_dense], ["psi", "p"], ["Y", "psi_dense"])
    return {"eval": ev, "traj": traj}


class _Evaluator:
    """One trajectory integration per distinct z, shared by the cost and constraint callbacks;
    non-integrable points (d varpi/dt <= 0 or non-finite values) give NaN."""

    def __init__(self, fn: ca.Function, p: np.ndarray):
        self.fn = fn
        self.p = p
        self.count = 0
        self._key: bytes | None = None
        self._val = None

    def __call__(self, z: np.ndarray):
        key = z.tobytes()
        if key != self._key:
            self.count += 1
            J, dJ, h, dh, rmin = self.fn(z, self.p)
            J = float(J)
            dJ = np.asarray(dJ, dtype=float).ravel()
            h = np.asarray(h, dtype=float).ravel()
            dh = np.asarray(dh, dtype=float)
            if not float(rmin) > 0.0 or not np.isfinite(J) or not np.all(np.isfinite(h)):
                J, h = float("nan"), np.full(2, np.nan)
            self._key, self._val = key, (J, dJ, h, dh)
        return self._val

    def f_and_grad(self, z):
        J, dJ, _, _ = self(z)
        return J, dJ

    def h_and_jac(self, z):
        _, _, h, dh = self(z)
        return h, dh


def _params(r0, omega0, m0, thrust, exhaust_speed, mu, radius) -> np.ndarray:
    return np.array([r0, omega0, m0, thrust, exhaust_speed, mu, radius], dtype=float)


def resample_psi(psi, n_segments: int) -> np.ndarray:
    """Re-interpolate psi nodes (equally spaced in varpi) to n_segments + 1 nodes."""
    psi = np.asarray(psi, dtype=float).ravel()
    if psi.size == n_segments + 1:
        return psi.copy()
    if psi.size == 1:
        return np.full(n_segments + 1, psi[0])
    return np.interp(np.linspace(0, 1, n_segments + 1), np.linspace(0, 1, psi.size), psi)


def decode_trajectory(psi_nodes, p: np.ndarray, n_segments: int,
                      steps: int = STEPS_PER_SEGMENT):
    """Dense trajectory of psi nodes: (varpi (K+1), t (K+1), x (K+1, 5), psi (K+1))."""
    fns = build_functions(n_segments, steps)
    Y, psi_dense = fns["traj"](np.asarray(psi_nodes, dtype=float), p)
    Y = np.asarray(Y, dtype=float)
    k_steps = n_segments * steps
    varpi = np.linspace(-p[1], 0.0, k_steps + 1)
    t = Y[3].copy()
    x = np.column_stack([Y[0], Y[1], Y[2], -varpi, p[2] - p[3] / p[4] * t])
    return varpi, t, x, np.asarray(psi_dense, dtype=float).ravel()


def _outcome(converged: bool, integrable: bool, tf: float, miss: np.ndarray,
             res: MultiplierResult, integrations: int) -> str:
    """The solve's message: the optimum's time, or why the multiplier method stopped."""
    if converged:
        return (f"converged: tf = {tf:.6f} s in {res.outer_iterations} multiplier / "
                f"{res.inner_iterations} BFGS iterations, {integrations} integrations")
    if integrable:
        return (f"the multiplier method did not converge: altitude miss {miss[0]:.3g} m, "
                f"radial speed {miss[1]:.3g} m/s after {res.outer_iterations} outer "
                f"iterations ({res.message})")
    return ("the multiplier method did not converge: the trajectory cannot be "
            "integrated in the transformed variable (d varpi/dt <= 0 somewhere: "
            "|psi| >= 90 deg, or the thrust is too weak to brake the orbital rate)"
            + ("" if res.outer_iterations > 1 else " already at the initial guess"))


def solve_integral_transform(
    r0: float,
    omega0: float,
    m0: float,
    thrust: float,
    exhaust_speed: float,
    mu: float = MU_MOON,
    radius: float = R_MOON,
    n_segments: int = 30,
    sigma0: float = 20.0,
    psi_guess: float = 0.0,
    warm_psi=None,
    ctx: SolveContext | None = None,
    steps_per_segment: int = STEPS_PER_SEGMENT,
    max_outer: int = 50,
    warm_lam=None,
) -> IntegralTransformResult:
    """Minimum-fuel (= minimum-time) powered descent from perilune by the integral
    transformation + multiplier method + BFGS (paper 002). Angles in rad, SI units.

    The start is constant `psi_guess` at all nodes, or `warm_psi` (previous nodes,
    re-interpolated if N changed). The multipliers start at the paper's (10, 10) unless
    `warm_lam` (a previous result's `lam`, scaled units) is given.
    """
    n, steps = int(n_segments), int(steps_per_segment)
    if n < 1 or steps < 1:
        raise ValueError("n_segments and steps_per_segment must be >= 1")
    if not omega0 > 0:
        raise ValueError("omega0 must be positive (the transformation needs omega to fall to 0)")
    p = _params(r0, omega0, m0, thrust, exhaust_speed, mu, radius)
    fns = build_functions(n, steps)
    ev = _Evaluator(fns["eval"], p)
    z0 = resample_psi(warm_psi, n) if warm_psi is not None else np.full(n + 1, float(psi_guess))
    tol_h = (TOL_ALTITUDE / R_SCALE, TOL_SPEED / V_SCALE)
    lam0 = PAPER_SIGMA["lam0"] if warm_lam is None else warm_lam
    res = solve_multiplier_method(
        ev.f_and_grad, ev.h_and_jac, z0, sigma0=sigma0, beta=PAPER_SIGMA["beta"],
        gamma=PAPER_SIGMA["gamma"], lam0=lam0, tol_h=tol_h, ctx=ctx,
        max_outer=max_outer, inner_gtol=INNER_GTOL, max_step=0.5,
    )
    z = res.z
    varpi, t_dense, x_dense, psi_dense = decode_trajectory(z, p, n, steps)
    idx = np.arange(0, n * steps + 1, steps)
    h_si = np.array([x_dense[-1, 0] - radius, x_dense[-1, 1]])
    tf = float(t_dense[-1])
    integrable = bool(np.isfinite(ev(z)[0])) and bool(np.all(np.isfinite(x_dense)))
    violation = float(np.max(np.abs(h_si))) if integrable else float("inf")
    converged = bool(res.converged and integrable)
    message = _outcome(converged, integrable, tf, h_si, res, ev.count)
    history = [(it, tk[idx], xk[idx]) for it, zk in res.history
               for _, tk, xk, _ in [decode_trajectory(zk, p, n, steps)]]
    return IntegralTransformResult(
        varpi_nodes=varpi[idx], psi_nodes=z.copy(), t_nodes=t_dense[idx], x_nodes=x_dense[idx],
        t_dense=t_dense, x_dense=x_dense, psi_dense=psi_dense, tf=tf,
        fuel=thrust * tf / exhaust_speed, converged=converged, message=message,
        outer_iterations=res.outer_iterations, inner_iterations=res.inner_iterations,
        integrations=ev.count, n_variables=n + 1, n_constraints=2,
        constraint_violation=violation, history=history, lam=res.lam, sigma=res.sigma,
        steps_per_segment=steps,
    )
