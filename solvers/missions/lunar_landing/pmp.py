"""The maximum principle for the lunar landing (paper 002's Pontryagin reference): the
extremal by single shooting, started from a direct method's costate estimate.

With the Mayer cost Phi = m0 - m(tf) (fuel) and H = lambda^T f(x, psi) (eq. 1), H is minimised
by the thrust direction

    (sin psi, cos psi) = -(lambda_v, -lambda_omega / r) / |(lambda_v, -lambda_omega / r)|,

lambda' = -dH/dx, and the end conditions are r(tf) = R, v(tf) = 0, omega(tf) = 0 with
lambda_theta = 0 (theta free, H independent of theta), lambda_m(tf) = dPhi/dm = -1 and
H(tf) = 0 (free final time, autonomous). The unknowns are (lambda_r, lambda_v, lambda_omega,
lambda_m)(0) and tf; the state and costate are integrated on tau in [0, 1] (t = tf tau) with
`STEPS` RK4 steps, one CasADi graph, so Newton (MINPACK hybrj) has the exact Jacobian.
Costates are scaled by the OCP's state scales inside the solve so the unknowns are O(1).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np
from scipy.optimize import root

from ...optimality import PMP_COSTATES, PMP_TRAJECTORY, record_costate_error
from ...solution import Quantity, Series, Solution
from .model import R_MOON, STATE_UNITS, STATES, descent_rhs
from .problem import P_C, P_F, P_M0, P_R0, P_W0

STEPS = 1000  # RK4 steps over the descent (about 0.4 s each)
SAMPLES = 201
X_SCALE = np.array([1e4, 100.0, 0.1, 1e-3, 100.0])  # the OCP's state scales
FREE = [0, 1, 3, 4]  # costates solved for: r, v, omega, m (lambda_theta = 0)
_LAST: dict[bytes, LandingExtremal] = {}  # the last few extremals, by parameter vector
KEEP = 8


@dataclass
class LandingExtremal:
    """The extremal: time, states, costates and thrust angle at `SAMPLES` times."""

    tf: float
    t: np.ndarray
    x: np.ndarray
    lam: np.ndarray
    psi: np.ndarray
    converged: bool
    residual: float

    def trajectory(self) -> Series:
        return Series(self.t, np.column_stack([self.x, self.psi]), (*STATES, "psi"),
                      (*STATE_UNITS, "rad"))

    def costates(self) -> Series:
        units = ("kg/m", "kg/(m/s)", "kg/rad", "kg/(rad/s)", "kg/kg")
        return Series(self.t, self.lam, STATES, units)


def _psi(x: ca.SX, lam: ca.SX) -> ca.SX:
    return ca.atan2(-lam[1], lam[3] / x[0])


@cache
def _functions() -> dict[str, ca.Function]:
    """One RK4 step of (x, lambda) in tau, the shooting map and its Jacobian, H and psi."""
    x, lam, q = ca.SX.sym("x", 5), ca.SX.sym("lam", 5), ca.SX.sym("q", 2)  # q = (F, c)
    tf = ca.SX.sym("tf")
    psi = _psi(x, lam)
    f = descent_rhs(x, psi, q[0], q[1])
    H = ca.dot(lam, f)
    u = ca.SX.sym("u")
    H_u = ca.dot(lam, descent_rhs(x, u, q[0], q[1]))
    g = ca.vertcat(f, -ca.substitute(ca.gradient(H_u, x), u, psi))
    y = ca.vertcat(x, lam)
    rhs = ca.Function("rhs", [y, tf, q], [tf * g])
    h = 1.0 / STEPS
    k1 = rhs(y, tf, q)
    k2 = rhs(y + h / 2 * k1, tf, q)
    k3 = rhs(y + h / 2 * k2, tf, q)
    k4 = rhs(y + h * k3, tf, q)
    step = ca.Function("step", [y, tf, q], [y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)])
    path = step.mapaccum(STEPS)
    # Shooting map in the scaled unknowns z = (lambda_free * X_SCALE, tf).
    z, x0 = ca.MX.sym("z", 5), ca.MX.sym("x0", 5)
    qm = ca.MX.sym("q", 2)
    lam0 = ca.MX.zeros(5)
    for k, i in enumerate(FREE):
        lam0[i] = z[k] / X_SCALE[i]
    yN = path(ca.vertcat(x0, lam0), z[4], qm)[:, -1]
    Hf = ca.Function("H", [y, q], [ca.substitute(H, ca.vertcat(x, lam), y)])
    res = ca.vertcat((yN[0] - R_MOON) / X_SCALE[0], yN[1] / X_SCALE[1], yN[3] / X_SCALE[3],
                     yN[9] + 1.0, Hf(yN, qm))
    return {
        "residual": ca.Function("residual", [z, x0, qm], [res]),
        "jacobian": ca.Function("jacobian", [z, x0, qm], [ca.jacobian(res, z)]),
        "path": ca.Function("path", [z, x0, qm], [path(ca.vertcat(x0, lam0), z[4], qm)]),
        "psi": ca.Function("psi", [y], [_psi(y[:5], y[5:])]),
    }


def solve_extremal(x0: np.ndarray, p: np.ndarray, lam0: np.ndarray, tf: float
                   ) -> LandingExtremal:
    """The extremal from the initial state `x0` (SI), OCP parameters `p` and a guess of the
    initial costates `lam0` (kg per state unit) and final time."""
    fn = _functions()
    q = np.array([p[P_F], p[P_C]])
    z0 = np.concatenate([np.asarray(lam0, float)[FREE] * X_SCALE[FREE], [tf]])

    def equations(z: np.ndarray) -> np.ndarray:
        return np.asarray(fn["residual"](z, x0, q)).ravel()

    def jacobian(z: np.ndarray) -> np.ndarray:
        return np.asarray(fn["jacobian"](z, x0, q))

    sol = root(equations, z0, jac=jacobian, method="hybr", options={"xtol": 1e-13})
    residual = float(np.max(np.abs(equations(sol.x))))
    Y = np.column_stack([np.concatenate([x0, np.zeros(5)]), np.asarray(fn["path"](sol.x, x0, q))])
    keep = np.linspace(0, STEPS, SAMPLES).round().astype(int)
    Y = Y[:, keep].T
    tf = float(sol.x[4])
    lam_start = np.zeros(5)
    lam_start[FREE] = sol.x[:4] / X_SCALE[FREE]
    Y[0, 5:] = lam_start
    psi = np.asarray(fn["psi"].map(len(Y))(Y.T)).ravel()
    return LandingExtremal(tf=tf, t=keep / STEPS * tf, x=Y[:, :5], lam=Y[:, 5:], psi=psi,
                           converged=bool(residual < 1e-8 and tf > 0),
                           residual=residual)


def reference_extremal(sol: Solution, p: np.ndarray) -> None:
    """Solve the extremal from `sol`'s costate estimate (extrapolated to t = 0) or, without
    one, from the last extremal of the same parameters; store it in `sol.references` with
    tf_pontryagin and the costate agreement."""
    x0 = np.array([p[P_R0], 0.0, 0.0, p[P_W0], p[P_M0]])
    key = np.asarray(p, float).tobytes()
    if sol.costates is not None:
        est = sol.costates
        lam = np.asarray(est.values)
        lam0 = lam[0] - est.t[0] * (lam[1] - lam[0]) / (est.t[1] - est.t[0])
        ext = solve_extremal(x0, p, lam0, float(sol.node_t[-1]))
    elif key in _LAST:
        ext = _LAST[key]
    else:
        return
    if not ext.converged:
        sol.message += " (the Pontryagin shooting did not converge from the costate estimate)"
        return
    _LAST[key] = ext
    while len(_LAST) > KEEP:
        _LAST.pop(next(iter(_LAST)))
    sol.references[PMP_TRAJECTORY] = ext.trajectory()
    sol.references[PMP_COSTATES] = ext.costates()
    sol.quantities["tf_pontryagin"] = Quantity(ext.tf, "tf (Pontryagin)", "s")
    record_costate_error(sol)
