"""Low-thrust heliocentric rendezvous by Hermite–Simpson collocation with free launch and
arrival dates (paper 003 section 2, eqs. 7–16).

N equal segments between the free launch time t0 and arrival t0 + T; cubic Hermite states,
linear controls, midpoint collocation (7N defect equalities); states r, v, m and the thrust
vector U at every node. Departure: r(t0) = Earth's, v(t0) = Earth's + v∞ with |v∞|² <= C3max
(C3max = 0 gives the paper's eq. 13, v(t0) = Earth's velocity); arrival: r, v equal to the
asteroid's at t0 + T (eq. 13); m(t0) = m0 (eq. 14); |U| <= Fmax at every node (eq. 15);
maximise the final mass (eq. 16).

Mass flow: m' = -Γ/(Isp g0) with a slack Γ >= |U| (|U|² <= Γ², Γ <= Fmax) instead of
-|U|/(Isp g0), whose derivative does not exist on coast arcs (U = 0). Burning mass without
thrust never pays, so Γ = |U| at the optimum on burn arcs. Γ has a floor of 1e-4 Fmax: with
Γ = U = 0 on coasts the cone constraint has a zero gradient (no constraint qualification)
and IPOPT crawls for ~150 extra iterations; the floor costs at most 1e-4 Fmax T / c of
propellant (0.02 kg in 700 d for the paper's engine).

Ephemerides inside the NLP: Earth by a CasADi B-spline through daily ERFA epv00 states over
the launch-date range; the asteroid by its elements with a fixed-iteration Newton solve of
Kepler's equation (differentiable). Scaling: AU, TU = sqrt(AU³/GM_sun) ≈ year/2π, m0; the
interface is SI with dates as MJD TDB.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ..dynamics.ephemeris import (
    AU,
    DAY,
    GM_SUN,
    MJD_2022,
    TU,
    VU,
    ElementSet,
    earth_state,
    mjd_from_iso,
)
from ..mission import SolveContext
from ..nlp.casadi_nlp import NLP, built_once, status_of

G0 = 9.80665
ACC = AU / TU**2  # m/s², canonical acceleration unit
EPHEMERIS_FIRST = mjd_from_iso("2020-01-01")  # launch dates the NLP's Earth spline covers
EPHEMERIS_LAST = mjd_from_iso("2028-01-01")
KEPLER_ITERATIONS = 6
GAMMA_MIN = 1e-4  # idle floor of the mass-flow slack, in units of Fmax (see module doc)
# IPOPT's adaptive barrier update: ~50 iterations here instead of ~200 with the monotone one.
IPOPT_EXTRA = {"ipopt.mu_strategy": "adaptive"}
NX, NU = 7, 4  # r, v, m | Ux, Uy, Uz, Γ
# Parameter vector: thrust accel. at m0, mass flow at full thrust, asteroid elements (a, e, i,
# Ω, ω) and its mean anomaly at t = 0 (MJD_2022), all canonical.
NP = 8


def to_tu(mjd: np.ndarray | float) -> np.ndarray:
    """Canonical time (TU since 2022-01-01 0h TDB) of a date."""
    return (np.asarray(mjd, float) - MJD_2022) * DAY / TU


def to_mjd(t_tu: np.ndarray | float) -> np.ndarray:
    return MJD_2022 + np.asarray(t_tu, float) * TU / DAY


@dataclass(frozen=True)
class LowThrustProblem:
    """One request in SI: vehicle, dates (MJD TDB), flight-time and C3 bounds, asteroid."""

    m0: float
    thrust: float
    exhaust_speed: float
    launch_first: float
    launch_last: float
    min_flight_days: float
    max_flight_days: float
    c3_max: float
    elements: ElementSet

    def parameters(self) -> np.ndarray:
        el = self.elements
        a = el.a_au
        M0 = np.deg2rad(el.mean_anomaly_deg) - a**-1.5 * float(to_tu(el.epoch_mjd))
        return np.array([
            self.thrust / self.m0 / ACC,
            self.thrust * TU / (self.exhaust_speed * self.m0),
            a, el.e, np.deg2rad(el.i_deg), np.deg2rad(el.raan_deg), np.deg2rad(el.argp_deg), M0,
        ])


@dataclass
class LowThrustGuess:
    """Starting point in SI: node states (N+1, 7) [m, m/s, kg], controls (N+1, 3) [N],
    launch date (MJD TDB), flight time [s] and launch v∞ [m/s]."""

    X: np.ndarray
    U: np.ndarray
    launch_mjd: float
    flight_time: float
    v_inf: np.ndarray


@dataclass
class LowThrustWarm:
    """NLP primal/dual values for a warm start on the same mesh."""

    n_segments: int
    z: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray


@dataclass
class LowThrustResult:
    """Solution in SI: node times [s from launch], states, thrust vectors [N], slack Γ [N]."""

    launch_mjd: float
    flight_time: float
    t_nodes: np.ndarray
    X: np.ndarray
    U: np.ndarray
    gamma: np.ndarray
    v_inf: np.ndarray
    status: str
    message: str
    iterations: int
    n_variables: int
    n_constraints: int
    max_violation: float
    history: list[tuple[int, np.ndarray]] = field(default_factory=list)
    warm: LowThrustWarm | None = None

    @property
    def arrival_mjd(self) -> float:
        return self.launch_mjd + self.flight_time / DAY


def heliocentric_rhs(x: ca.SX, u: ca.SX, p: ca.SX) -> ca.SX:
    """Paper 003 eq. 1 without perturbations, canonical units (GM_sun = 1):
    r' = v, v' = -r/|r|³ + a_F U/m, m' = -k Γ (U, Γ in units of Fmax, m in m0)."""
    r, v, m = x[0:3], x[3:6], x[6]
    acc = -r / ca.norm_2(r) ** 3 + p[0] * u[0:3] / m
    return ca.vertcat(v, acc, -p[1] * u[3])


def kepler_state(p: ca.SX, t: ca.SX) -> ca.SX:
    """The asteroid's canonical state at canonical time t from the elements in `p`, with a
    fixed number of Newton steps on Kepler's equation (e ~ 0.1: converged to 1e-16)."""
    a, e, inc, raan, argp, M0 = (p[i] for i in range(2, 8))
    M = M0 + a**-1.5 * t
    E = M + e * ca.sin(M)
    for _ in range(KEPLER_ITERATIONS):
        E = E - (E - e * ca.sin(E) - M) / (1 - e * ca.cos(E))
    cE, sE = ca.cos(E), ca.sin(E)
    b = a * ca.sqrt(1 - e * e)
    rad = a * (1 - e * cE)
    xp, yp = a * (cE - e), b * sE
    vxp, vyp = -a * sE / rad / ca.sqrt(a), b * cE / rad / ca.sqrt(a)
    cO, sO, ci, si, cw, sw = (ca.cos(raan), ca.sin(raan), ca.cos(inc), ca.sin(inc),
                              ca.cos(argp), ca.sin(argp))
    P = ca.vertcat(cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si)
    Q = ca.vertcat(-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si)
    return ca.vertcat(xp * P + yp * Q, vxp * P + vyp * Q)


@built_once
def earth_spline() -> ca.Function:
    """CasADi B-spline of Earth's canonical state over the launch-date range (daily epv00)."""
    mjd = np.arange(EPHEMERIS_FIRST - 3, EPHEMERIS_LAST + 4, 1.0)
    r, v = earth_state(mjd)
    values = np.concatenate([r / AU, v / VU], axis=1)
    return ca.interpolant("earth", "bspline", [to_tu(mjd)], values.ravel(order="C"))


class LowThrustTranscription:
    """The NLP for one segment count and back end; built once, solved many times."""

    def __init__(self, n_segments: int, backend: str = "ipopt") -> None:
        N = self.N = int(n_segments)
        self.tau = np.linspace(0.0, 1.0, N + 1)
        Xs = ca.SX.sym("X", NX, N + 1)
        Us = ca.SX.sym("U", NU, N + 1)
        t0 = ca.SX.sym("t0")
        T = ca.SX.sym("T")
        vinf = ca.SX.sym("vinf", 3)
        p = ca.SX.sym("p", NP)
        x_, u_ = ca.SX.sym("x", NX), ca.SX.sym("u", NU)
        f = ca.Function("f", [x_, u_, p], [heliocentric_rhs(x_, u_, p)])
        h = T / N
        P = ca.repmat(p, 1, N + 1)
        F = f.map(N + 1)(Xs, Us, P)
        Xm = (Xs[:, :-1] + Xs[:, 1:]) / 2 + h / 8 * (F[:, :-1] - F[:, 1:])
        Fm = f.map(N)(Xm, (Us[:, :-1] + Us[:, 1:]) / 2, P[:, :-1])
        defects = Xs[:, 1:] - Xs[:, :-1] - h / 6 * (F[:, :-1] + 4 * Fm + F[:, 1:])
        earth = earth_spline()(t0)
        target = kepler_state(p, t0 + T)
        departure = Xs[0:6, 0] - ca.vertcat(earth[0:3], earth[3:6] + vinf)
        arrival = Xs[0:6, N] - target
        cone = ca.sum1(Us[0:3, :] ** 2) - Us[3, :] ** 2
        g = ca.vertcat(ca.vec(defects), departure, arrival, ca.sumsqr(vinf), cone.T)
        z = ca.vertcat(ca.vec(Xs), ca.vec(Us), t0, T, vinf)
        self.n_defects = int(defects.numel())
        self.nlp = NLP(z, -Xs[6, N], g, p, backend, name="low_thrust", ipopt_options=IPOPT_EXTRA)
        self.f = f

    # ---- layout ----------------------------------------------------------------------
    def _pack(self, X: np.ndarray, U: np.ndarray, t0: float, T: float, vinf: np.ndarray):
        return np.concatenate([X.ravel(), U.ravel(), [t0, T], vinf])

    def _unpack(self, z: np.ndarray):
        N = self.N
        nX, nU = NX * (N + 1), NU * (N + 1)
        X = z[:nX].reshape(N + 1, NX)
        U = z[nX:nX + nU].reshape(N + 1, NU)
        return X, U, float(z[nX + nU]), float(z[nX + nU + 1]), z[nX + nU + 2:]

    def _bounds(self, prob: LowThrustProblem):
        N = self.N
        vmax = np.sqrt(max(prob.c3_max, 0.0)) / VU
        x_lb = np.array([-3, -3, -3, -3, -3, -3, 0.02])
        x_ub = np.array([3, 3, 3, 3, 3, 3, 1.0])
        X_lb, X_ub = np.tile(x_lb, (N + 1, 1)), np.tile(x_ub, (N + 1, 1))
        X_lb[0, 6] = 1.0
        U_lb = np.tile([-1.0, -1.0, -1.0, GAMMA_MIN], (N + 1, 1))
        U_ub = np.tile([1.0, 1.0, 1.0, 1.0], (N + 1, 1))
        first = max(prob.launch_first, EPHEMERIS_FIRST)
        last = min(prob.launch_last, EPHEMERIS_LAST)
        lbx = self._pack(X_lb, U_lb, float(to_tu(first)), prob.min_flight_days * DAY / TU,
                         -vmax * np.ones(3))
        ubx = self._pack(X_ub, U_ub, float(to_tu(last)), prob.max_flight_days * DAY / TU,
                         vmax * np.ones(3))
        n_eq = self.n_defects + 12
        lbg = np.concatenate([np.zeros(n_eq), [0.0], -np.inf * np.ones(N + 1)])
        ubg = np.concatenate([np.zeros(n_eq), [vmax**2], np.zeros(N + 1)])
        return lbx, ubx, lbg, ubg

    def scale_guess(self, prob: LowThrustProblem, guess: LowThrustGuess) -> np.ndarray:
        """SI guess -> scaled NLP vector (Γ = |U|, masses in m0)."""
        X = np.column_stack([guess.X[:, 0:3] / AU, guess.X[:, 3:6] / VU, guess.X[:, 6] / prob.m0])
        U = guess.U / prob.thrust
        U = np.column_stack([U, np.linalg.norm(U, axis=1)])
        return self._pack(X, U, float(to_tu(guess.launch_mjd)), guess.flight_time / TU,
                          np.asarray(guess.v_inf) / VU)

    # ---- solve -----------------------------------------------------------------------
    def solve(
        self,
        prob: LowThrustProblem,
        guess: LowThrustGuess | None = None,
        warm: LowThrustWarm | None = None,
        ctx: SolveContext | None = None,
    ) -> LowThrustResult:
        """Solve from an SI guess, or warm from a previous solve on this mesh."""
        p = prob.parameters()
        lbx, ubx, lbg, ubg = self._bounds(prob)
        lam_x = lam_g = None
        if warm is not None and warm.n_segments == self.N:
            z0, lam_x, lam_g = warm.z.copy(), warm.lam_x, warm.lam_g
        elif guess is not None:
            z0 = self.scale_guess(prob, guess)
        else:
            raise ValueError("the low-thrust solve needs a guess or a warm start")
        z0 = np.clip(z0, lbx, ubx)
        res = self.nlp.solve(z0, p, lbx, ubx, lbg, ubg, lam_x, lam_g, ctx)
        status, message = status_of(res)
        X, U, t0, T, vinf = self._unpack(res.x)
        out = self._to_si(prob, X, U, t0, T, vinf)
        out.update(status=status, message=message, iterations=res.iterations,
                   n_variables=self.nlp.n_x, n_constraints=self.nlp.n_g,
                   max_violation=res.max_violation)
        history = []
        for k, z in res.history:
            Xk = self._unpack(z)[0]
            history.append((k, Xk[:, 0:3] * AU))
        return LowThrustResult(**out, history=history,
                               warm=LowThrustWarm(self.N, res.x, res.lam_x, res.lam_g))

    def _to_si(self, prob, X, U, t0, T, vinf) -> dict:
        flight = T * TU
        Xsi = np.column_stack([X[:, 0:3] * AU, X[:, 3:6] * VU, X[:, 6] * prob.m0])
        return dict(launch_mjd=float(to_mjd(t0)), flight_time=flight, t_nodes=self.tau * flight,
                    X=Xsi, U=U[:, 0:3] * prob.thrust, gamma=U[:, 3] * prob.thrust,
                    v_inf=np.asarray(vinf) * VU)


@built_once
def transcription(n_segments: int, backend: str = "ipopt") -> LowThrustTranscription:
    """The cached NLP for a segment count and back end."""
    return LowThrustTranscription(n_segments, backend)


def hermite_dense(
    t_nodes: np.ndarray, X: np.ndarray, F: np.ndarray, per_segment: int
) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Hermite interpolation of node states with their slopes F (same units per s)."""
    s = np.linspace(0.0, 1.0, per_segment + 1)[:-1]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    h = np.diff(t_nodes)
    ts, xs = [], []
    for k in range(len(h)):
        xs.append(np.outer(h00, X[k]) + np.outer(h10 * h[k], F[k]) + np.outer(h01, X[k + 1])
                  + np.outer(h11 * h[k], F[k + 1]))
        ts.append(t_nodes[k] + s * h[k])
    return np.concatenate([*ts, t_nodes[-1:]]), np.vstack([*xs, X[-1:]])


def rhs_si(x: np.ndarray, u: np.ndarray, gamma: np.ndarray, exhaust_speed: float) -> np.ndarray:
    """SI state derivatives (rows) of the same dynamics, for dense output."""
    r, v, m = x[:, 0:3], x[:, 3:6], x[:, 6]
    acc = -GM_SUN * r / np.linalg.norm(r, axis=1, keepdims=True) ** 3 + u / m[:, None]
    return np.column_stack([v, acc, -gamma / exhaust_speed])
