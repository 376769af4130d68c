"""The thin-air arc: a necessary condition of the reentry's precheck (issue 17), proved from
the model's equations (`model.rhs`) in SI.

Gravity is central and conservative, so only the aerodynamic force changes the energy
E = v²/2 - μ/r and the angular momentum H = r v cos γ. Above an altitude h* it is at most
a* = (S/m) ρ(h*) v_max² √(C_D,max² + C_L,max²) / 2, so in the T <= T_max of the manoeuvre it
changes E by at most v_max a* T_max and H by at most r_max a* T_max. In any state r lies
between the roots r_p <= r_a of E r² + μ r - H²/2 = 0 (v >= H/r), and at a top of the path
(γ = 0) r is one of them (r_a = ∞ when E >= 0).

A capsule that ends at hf descending (γf < 0) and was ever below hf (it started there, or its
E and H could not have stayed that near the end's in air that thin) came over a top after
it was last below hf: there γ = 0 and r > r_f, all in air no denser than at hf. If r_p < r_f
for every E, H that near the end's, that top is r_a, and when r_a lies above h_max for all
of them, no such path exists.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import model

LU, RE = model.LENGTH_UNIT, model.R_EARTH
MU = model.G * LU * RE**2  # m³/s²: g R² of the model's inverse-square gravity
SCALE_HEIGHT = LU / model.BETA  # m: ρ = ρ0 exp(-h / SCALE_HEIGHT)
KAPPA = model.S_OVER_M * model.RHO0 / LU  # 1/m: (S/m) ρ at h = 0, SI


def drag_factor(h: float | np.ndarray) -> float | np.ndarray:
    """(S/m) ρ(h) in 1/m: the drag deceleration is drag_factor(h) v² C_D / 2."""
    return KAPPA * np.exp(-h / SCALE_HEIGHT)


def energy_momentum(v: float, gamma: float, h: float) -> tuple[float, float]:
    """E = v²/2 - μ/r (J/kg) and H = r v cos γ (m²/s)."""
    r = RE + h
    return v * v / 2 - MU / r, r * v * float(np.cos(gamma))


def apsides(e: float, h: float) -> tuple[float, float]:
    """The radii r_p <= r_a between which a state of energy e and angular momentum h lies
    (r_a = inf for e >= 0; (nan, nan) for no state)."""
    q2 = MU * MU + 2 * e * h * h
    if q2 < 0:
        return float("nan"), float("nan")
    q = float(np.sqrt(q2))
    return h * h / (MU + q), (MU + q) / (-2 * e) if e < 0 else float("inf")


def thin_air_change(values: dict[str, float], h: float) -> tuple[float, float]:
    """How much E and H can change above altitude h within T_max (J/kg, m²/s)."""
    cd = model.C1 - model.C2 * np.cos(values["u_max"])
    cl = model.C3 * np.sin(values["u_max"])
    a = drag_factor(h) * values["v_max"] ** 2 * np.hypot(cd, cl) / 2
    return (float(values["v_max"] * a * values["T_max"]),
            float((RE + values["h_max"]) * a * values["T_max"]))


def top_before_descent(values: dict[str, float]) -> float | None:
    """The lowest altitude of the top a capsule ending at hf with γf < 0 must have come over
    (m), when it lies above h_max (see the module); None when no such proof holds."""
    hf = values["hf"]
    if values["gammaf"] >= 0:
        return None
    e_f, h_f = energy_momentum(values["vf"], values["gammaf"], hf)
    d_e, d_h = thin_air_change(values, hf)
    if values["h0"] >= hf:  # it may have stayed above hf, unless E or H must change more
        e_0, h_0 = energy_momentum(values["v0"], values["gamma0"], values["h0"])
        if abs(e_0 - e_f) <= d_e and abs(h_0 - h_f) <= d_h:
            return None
    # r_p grows and r_a falls with H and with -E: both extremes at (E - dE, H + dH).
    r_p, r_a = apsides(e_f - d_e, h_f + d_h)
    if not (r_p < RE + hf and r_a > RE + values["h_max"]):
        return None
    return r_a - RE


def end_energies(values: dict[str, float]) -> tuple[float, float]:
    """The specific orbital energies (J/kg) of the requested start and end states."""
    return (energy_momentum(values["v0"], 0.0, values["h0"])[0],
            energy_momentum(values["vf"], 0.0, values["hf"])[0])


def dense_air_loss(values: dict[str, float], samples: int = 400) -> tuple[float, float]:
    """(the energy the capsule may lose, E0 - Ef; a lower bound on what drag takes from it
    near its ends within T_min), both J/kg: a request whose bound exceeds the allowance is
    impossible.

    E never rises and ends at Ef, so at altitude h the speed is at least
    v_lo(h) = max(v_min, √(2 (Ef + μ/r))), and C_D >= C1 - C2 > 0: drag takes energy at
    -dE/dt = (S/m) ρ v³ C_D / 2 >= q(h) = (S/m) ρ(h) v_lo(h)³ (C1 - C2) / 2, which falls
    with h. The speed is at most V = min(v_max, √(2 (E0 + μ/R))) (h >= 0), so within
    γ_min <= γ <= γ_max the altitude rises at most V sin γ_max and falls at most
    V sin(-γ_min) per second: h(t) <= h0 + V sin γ_max t after the start and
    h(T - s) <= hf + V sin(-γ_min) s before the end (and h <= h_max). Over disjoint arcs
    [0, a] and [T - b, T], a + b = T_min <= T, drag takes at least ∫₀ᵃ q(h0 + ...) dt +
    ∫₀ᵇ q(hf + ...) ds; the largest over a is the bound (right Riemann sums, q falling)."""
    e_0, e_f = end_energies(values)
    top_speed = min(values["v_max"], float(np.sqrt(2 * (e_0 + MU / RE))))
    climb = top_speed * np.sin(max(0.0, values["gamma_max"]))
    fall = top_speed * np.sin(max(0.0, -values["gamma_min"]))
    cd_min = model.C1 - model.C2

    def q(h: np.ndarray) -> np.ndarray:
        h = np.minimum(h, values["h_max"])
        v_lo = np.maximum(np.sqrt(np.maximum(2 * (e_f + MU / (RE + h)), 0.0)), values["v_min"])
        return drag_factor(h) * v_lo**3 * cd_min / 2

    step = values["T_min"] / samples
    s = step * np.arange(1, samples + 1)  # right ends of the steps
    from_start = np.concatenate([[0.0], np.cumsum(q(values["h0"] + climb * s)) * step])
    to_end = np.concatenate([[0.0], np.cumsum(q(values["hf"] + fall * s)) * step])
    return e_0 - e_f, float(np.max(from_start + to_end[::-1]))


def lift_to_drag(u_max: float, samples: int = 2001) -> float:
    """k = max |C_L| / C_D over |u| <= u_max: the lift is at most k times the drag."""
    u = np.linspace(0.0, u_max, samples)
    return float(np.max(model.C3 * np.sin(u) / (model.C1 - model.C2 * np.cos(u))))


class PullUp(NamedTuple):
    """The lowest altitude (m) a capsule diving at `end` ("start", or "end" backwards in
    time) can be kept above, `after` seconds from that end, when the air changes its
    vertical speed by at most `air` (m/s)."""

    lowest: float
    air: float
    after: float
    end: str


def pull_up_floor(values: dict[str, float], samples: int = 2000) -> PullUp:
    """How high a steep dive at the start (or climb at the end) can be kept: a negative
    altitude proves the request impossible, the capsule hits the ground.

    The radius obeys r̈ = v² cos²γ / r - μ/r² + a_r, a_r = L cos γ - D sin γ (from eq. 8).
    The lift is at most k D (`lift_to_drag`), so |a_r| <= m D with
    m = max over the γ bounds of k cos γ + |sin γ|. Drag takes energy at D v and v >= v_lo
    (v_min, and E >= Ef below h_max), so ∫ D dt <= (E0 - Ef) / v_lo: the air changes the
    radial speed by at most I = m (E0 - Ef) / v_lo over the whole flight. Gravity and the
    turning of the path give at most c = max over R <= r <= R + h_max of (v_hi² - μ/r) / r,
    v_hi² = min(v_max², 2 (E0 + μ/r)) (bounded cell by cell from the safe side). So
    r(t) <= r0 + (ṙ0 + I) t + c t²/2 for t <= T_min (and the same backwards from the end
    with -ṙf): a bound below the ground is impossible."""
    e_0, e_f = end_energies(values)
    gamma = np.linspace(values["gamma_min"], values["gamma_max"], samples)
    k = lift_to_drag(values["u_max"])
    m = float(np.max(k * np.cos(gamma) + np.abs(np.sin(gamma))))
    v_lo = max(values["v_min"],
               float(np.sqrt(max(0.0, 2 * (e_f + MU / (RE + values["h_max"]))))))
    air = m * max(0.0, e_0 - e_f) / v_lo
    r = RE + np.linspace(0.0, values["h_max"], samples)
    lo, hi = r[:-1], r[1:]  # on each cell, the numerator's largest over its smallest radius
    excess = np.minimum(values["v_max"] ** 2, 2 * (e_0 + MU / lo)) - MU / hi
    turn = float(np.max(excess / np.where(excess > 0, lo, hi)))
    t = np.linspace(0.0, values["T_min"], samples)
    ends = []
    for end, h, rate in (("start", values["h0"], values["v0"] * np.sin(values["gamma0"])),
                         ("end", values["hf"], -values["vf"] * np.sin(values["gammaf"]))):
        path = h + (rate + air) * t + turn * t * t / 2
        i = int(np.argmin(path))
        ends.append(PullUp(float(path[i]), air, float(t[i]), end))
    return min(ends)
