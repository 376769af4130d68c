"""Heliocentric low-thrust dynamics and the ephemerides inside the NLP (paper 003 section 2,
eqs. 1 and 7-16), in canonical units.

Units: AU, TU = sqrt(AU³/GM_sun) ≈ year/2π (so GM_sun = 1), VU = AU/TU, masses in m0,
thrust in Fmax; times count TU from 2022-01-01 0h TDB (MJD 59580).

State x = (r, v, m); control u = (U, Γ): the thrust vector U in units of Fmax and a mass-flow
slack Γ >= |U| (the thrust cone |U|² <= Γ², Γ <= 1). The mass falls as m' = -k Γ instead of
-k |U|, whose derivative does not exist on coast arcs (U = 0); burning mass without thrust
never pays, so Γ = |U| at the optimum on burn arcs. Γ has a floor of 1e-4 (`GAMMA_MIN`):
with Γ = U = 0 on coasts the cone constraint has a zero gradient (no constraint
qualification) and IPOPT crawls for ~150 extra iterations; the floor costs at most
1e-4 Fmax T / c of propellant (0.02 kg in 700 d for the paper's engine).

Earth is a CasADi B-spline through daily ERFA epv00 states over the launch-date range; the
asteroid is its osculating elements with a fixed-iteration Newton solve of Kepler's equation
(differentiable in the arrival date).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...dynamics.ephemeris import AU, DAY, MJD_2022, TU, VU, earth_state, mjd_from_iso
from ...nlp.cache import built_once

G0 = 9.80665
ACC = AU / TU**2  # m/s², canonical acceleration unit
EPHEMERIS_FIRST = mjd_from_iso("2020-01-01")  # launch dates the NLP's Earth spline covers
EPHEMERIS_LAST = mjd_from_iso("2028-01-01")
KEPLER_ITERATIONS = 6
GAMMA_MIN = 1e-4  # idle floor of the mass-flow slack, in units of Fmax (see module doc)

STATES = ("x", "y", "z", "vx", "vy", "vz", "m")
CANONICAL_UNITS = ("AU",) * 3 + ("AU/TU",) * 3 + ("m0",)
SI_UNITS = ("m",) * 3 + ("m/s",) * 3 + ("kg",)
CONTROLS = ("Ux", "Uy", "Uz", "Γ")

# The OCP's parameter vector (canonical): thrust acceleration at m0, mass flow at full thrust,
# the asteroid's elements (a, e, i, Ω, ω) and mean anomaly at t = 0, the launch C3 bound (VU²),
# and the launch-date and flight-time bounds (TU) that only the numeric bounds read.
P_ACC, P_FLOW = 0, 1
P_ELEMENTS = slice(2, 8)
P_C3, P_T0_LB, P_T0_UB, P_T_LB, P_T_UB = range(8, 13)
N_PARAMS = 13


def to_tu(mjd: np.ndarray | float) -> np.ndarray:
    """Canonical time (TU since 2022-01-01 0h TDB) of a date."""
    return (np.asarray(mjd, float) - MJD_2022) * DAY / TU


def to_mjd(t_tu: np.ndarray | float) -> np.ndarray:
    """The date (MJD TDB) of a canonical time."""
    return MJD_2022 + np.asarray(t_tu, float) * TU / DAY


def heliocentric_rhs(x: ca.SX, u: ca.SX, p: ca.SX) -> ca.SX:
    """Paper 003 eq. 1 without perturbations, canonical units (GM_sun = 1):
    r' = v, v' = -r/|r|³ + a_F U/m, m' = -k Γ."""
    r, v, m = x[0:3], x[3:6], x[6]
    acc = -r / ca.norm_2(r) ** 3 + p[P_ACC] * u[0:3] / m
    return ca.vertcat(v, acc, -p[P_FLOW] * u[3])


def kepler_state(p: ca.SX, t: ca.SX) -> ca.SX:
    """The asteroid's canonical state at canonical time t from the elements in `p`, with a
    fixed number of Newton steps on Kepler's equation (e ~ 0.1: converged to 1e-16)."""
    a, e, inc, raan, argp, M0 = (p[i] for i in range(P_ELEMENTS.start, P_ELEMENTS.stop))
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


# Earth's ephemeris samples for the spline: every 6 h. Daily samples left 58 m and 1.5e-4 m/s
# of interpolation error between them, which 400 days of flight turn into a 2-5 km arrival
# miss on re-propagation from the true ephemeris (the floor mesh refinement could not pass);
# at 6 h it is 0.2 m and 6e-7 m/s.
EARTH_SAMPLE_DAYS = 0.25


@built_once
def earth_spline() -> ca.Function:
    """CasADi B-spline of Earth's canonical state over the launch-date range (epv00 every
    `EARTH_SAMPLE_DAYS`)."""
    mjd = np.arange(EPHEMERIS_FIRST - 3, EPHEMERIS_LAST + 4, EARTH_SAMPLE_DAYS)
    r, v = earth_state(mjd)
    values = np.concatenate([r / AU, v / VU], axis=1)
    return ca.interpolant("earth", "bspline", [to_tu(mjd)], values.ravel(order="C"))


def to_si(X: np.ndarray, m0: float) -> np.ndarray:
    """Canonical states (rows) to SI: m, m/s, kg."""
    return np.column_stack([X[:, 0:3] * AU, X[:, 3:6] * VU, X[:, 6] * m0])


@built_once
def si_rhs() -> ca.Function:
    """f(x, u, p) in SI for the re-propagation: x = (r, v, m), u = (U [N], Γ [N]),
    p = (GM_sun, exhaust speed)."""
    x, u, p = ca.SX.sym("x", 7), ca.SX.sym("u", 4), ca.SX.sym("p", 2)
    r, v, m = x[0:3], x[3:6], x[6]
    acc = -p[0] * r / ca.norm_2(r) ** 3 + u[0:3] / m
    return ca.Function("asteroid_rhs", [x, u, p], [ca.vertcat(v, acc, -u[3] / p[1])])

