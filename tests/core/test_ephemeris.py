"""Ephemerides and Kepler propagation of the asteroid mission (paper 003, reference/asteroid.md)."""

from __future__ import annotations

import numpy as np
import pytest

from solvers.dynamics.ephemeris import (
    AU,
    GM_SUN,
    KAMOOALEWA_A,
    KAMOOALEWA_B,
    asteroid_state,
    earth_longitude,
    earth_state,
    earth_state_fast,
    iso_from_mjd,
    mjd_from_iso,
)
from solvers.dynamics.kepler import (
    elements_to_state,
    period,
    propagate,
    solve_kepler,
    state_to_elements,
)

DAYS_2022 = mjd_from_iso("2022-01-01") + np.arange(366.0)


def test_iso_and_mjd_round_trip():
    assert mjd_from_iso("2022-01-01") == 59580.0  # MJD 59580 is 2022-01-01 (0h)
    assert mjd_from_iso("2000-01-01T12:00") == 51544.5  # J2000
    assert iso_from_mjd(mjd_from_iso("2022-11-29")) == "2022-11-29"


def test_earth_distance_and_speed_stay_in_their_known_ranges_over_a_year():
    r, v = earth_state(DAYS_2022)
    dist = np.linalg.norm(r, axis=1) / AU
    speed = np.linalg.norm(v, axis=1)
    # Perihelion 0.98329 AU, aphelion 1.01671 AU (a = 1.00000261, e = 0.01671123, Standish).
    assert 0.9830 < dist.min() < 0.9836 and 1.0164 < dist.max() < 1.0170
    # Speeds at aphelion and perihelion: 29.29 and 30.29 km/s.
    assert 29.25e3 < speed.min() < 29.32e3 and 30.26e3 < speed.max() < 30.33e3
    # Ecliptic frame: Earth stays within 1e-4 AU of the ecliptic plane (the Moon's wobble).
    assert np.abs(r[:, 2]).max() / AU < 1e-4


def test_earth_agrees_with_standish_elements():
    """reference/asteroid.md: the EMB elements differ from epv00 by ~5.5e-5 AU (Earth–EMB
    offset) plus their own ~1e-4 AU error."""
    T = (DAYS_2022 - 51544.5) / 36525.0
    L = np.deg2rad(100.46457166 + 35999.37244981 * T)
    varpi = np.deg2rad(102.93768193 + 0.32327364 * T)
    el = np.column_stack([np.full_like(T, 1.00000261 * AU), np.full_like(T, 0.01671123),
                          np.full_like(T, np.deg2rad(-0.00001531)), np.zeros_like(T), varpi,
                          L - varpi])
    r_standish, _ = elements_to_state(el, GM_SUN)
    r, _ = earth_state(DAYS_2022)
    assert np.linalg.norm(r - r_standish, axis=1).max() / AU < 2.5e-4


def test_fast_earth_table_matches_epv00():
    days = mjd_from_iso("2022-01-01") + np.linspace(0.0, 1400.0, 977)
    r, v = earth_state(days)
    rf, vf = earth_state_fast(days)
    assert np.abs(rf - r).max() < 200.0 and np.abs(vf - v).max() < 1e-3


def test_paper_launch_dates_are_node_crossings():
    """SPEC M4: on 2022-11-29 and 2022-05-28 Earth's ecliptic longitude is ≈ Ω and Ω + 180°."""
    lon = np.rad2deg(earth_longitude([mjd_from_iso("2022-11-29"), mjd_from_iso("2022-05-28")]))
    assert lon[0] == pytest.approx(KAMOOALEWA_B.raan_deg, abs=1.5)
    assert lon[1] == pytest.approx(KAMOOALEWA_B.raan_deg + 180.0, abs=1.5)


def test_asteroid_element_sets_drift_apart_as_documented():
    """reference/asteroid.md: the two sets drift apart by about 0.017 AU over 2022–2024, and the
    Earth–asteroid distance is about 0.2 AU."""
    rb, _ = asteroid_state(DAYS_2022, KAMOOALEWA_B)
    ra, _ = asteroid_state(DAYS_2022, KAMOOALEWA_A)
    drift = np.linalg.norm(ra - rb, axis=1).max() / AU
    assert 0.008 < drift < 0.035
    re, _ = earth_state(DAYS_2022)
    assert 0.1 < np.median(np.linalg.norm(rb - re, axis=1)) / AU < 0.3


def test_kepler_equation_and_element_round_trip():
    M = np.linspace(-20.0, 20.0, 101)
    for e in (0.0, 0.1, 0.7, 0.97):
        E = solve_kepler(M, e)
        assert np.abs(E - e * np.sin(E) - np.remainder(M + np.pi, 2 * np.pi) + np.pi).max() < 1e-13
    el = np.array([1.3 * AU, 0.3, 0.4, 2.0, 5.0, 1.0])
    r, v = elements_to_state(el, GM_SUN)
    assert state_to_elements(r, v, GM_SUN) == pytest.approx(el, rel=1e-11)


@pytest.mark.parametrize("elements", [KAMOOALEWA_B, KAMOOALEWA_A])
def test_kepler_propagation_returns_to_its_start_after_one_period(elements):
    r0, v0 = asteroid_state(mjd_from_iso("2022-01-01"), elements)
    T = float(period(r0, v0, GM_SUN))
    # In unequal pieces (a whole period at once would be reduced to zero by the modulo).
    pieces = np.array([0.13, 0.31, 0.07, 0.22, 0.27]) * T
    r, v = r0, v0
    for dt in pieces:
        r, v = propagate(r, v, dt, GM_SUN)
    assert np.linalg.norm(r - r0) / np.linalg.norm(r0) < 1e-10
    assert np.linalg.norm(v - v0) / np.linalg.norm(v0) < 1e-10
    # And propagation agrees with advancing the mean anomaly of the elements.
    r1, v1 = propagate(r0, v0, 40.0 * 86400.0, GM_SUN)
    r2, v2 = asteroid_state(mjd_from_iso("2022-01-01") + 40.0, elements)
    assert np.linalg.norm(r1 - r2) < 1.0 and np.linalg.norm(v1 - v2) < 1e-6


def test_universal_propagation_handles_hyperbolas_and_backwards_time():
    mu = 1.0
    r0, v0 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.6, 0.1])  # hyperbolic
    r1, v1 = propagate(r0, v0, 3.0, mu)
    rb, vb = propagate(r1, v1, -3.0, mu)
    assert np.abs(rb - r0).max() < 1e-10 and np.abs(vb - v0).max() < 1e-10
    energy = lambda r, v: v @ v / 2 - mu / np.linalg.norm(r)  # noqa: E731
    assert energy(r1, v1) == pytest.approx(energy(r0, v0), rel=1e-12)
