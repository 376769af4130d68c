"""Heliocentric ecliptic-J2000 ephemerides of the Earth and of asteroid 469219 Kamoʻoalewa.

Dates are Modified Julian Dates in TDB (`mjd`), floats in days; a calendar date string
("2022-11-29") is read as 0h TDB of that day (TT-UTC ≈ 69 s is below a launch date's
resolution). States are SI: metres and metres per second, heliocentric, ecliptic J2000 axes.

Earth: ERFA `epv00` (3.7 km RMS against DE405 over 1900–2100) on equatorial axes, rotated by
the J2000 obliquity about x. Asteroid: osculating elements propagated as a two-body orbit
(paper 003 table 2 gives elements at MJD 58000; the two sets here are the JPL ones in
`reference/asteroid.md`; they drift apart by ~0.017 AU over 2022–2024 because the Kepler
model ignores planetary perturbations).
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass
from functools import cache

import erfa
import numpy as np
from scipy.interpolate import CubicSpline

from .kepler import elements_to_state

AU = 149_597_870_700.0  # m (IAU 2012)
DAY = 86_400.0  # s
GM_SUN = 1.32712440018e20  # m^3/s^2
TU = float(np.sqrt(AU**3 / GM_SUN))  # s, canonical time unit (≈ year/2π, so GM_SUN = 1)
VU = AU / TU  # m/s, canonical speed unit (≈ 29.78 km/s)
OBLIQUITY_J2000 = np.deg2rad(84381.448 / 3600.0)
MJD_J2000 = 51544.5
MJD_2022 = 59580.0  # 2022-01-01 0h: the origin of the mission's date parameters
_MJD_EPOCH = _dt.date(1858, 11, 17)
DEG = np.pi / 180.0


@dataclass(frozen=True)
class ElementSet:
    """Heliocentric osculating elements (ecliptic J2000) at an epoch (MJD TDB)."""

    name: str
    epoch_mjd: float
    a_au: float
    e: float
    i_deg: float
    raan_deg: float
    argp_deg: float
    mean_anomaly_deg: float

    def elements_at(self, mjd: np.ndarray | float) -> np.ndarray:
        """Elements (..., 6) in SI (a in m, angles in rad) with M advanced to `mjd`."""
        mjd = np.asarray(mjd, float)
        a = self.a_au * AU
        n = np.sqrt(GM_SUN / a**3)
        M = self.mean_anomaly_deg * DEG + n * (mjd - self.epoch_mjd) * DAY
        fixed = np.array([a, self.e, self.i_deg * DEG, self.raan_deg * DEG, self.argp_deg * DEG])
        return np.concatenate([np.broadcast_to(fixed, (*mjd.shape, 5)), M[..., None]], axis=-1)


# reference/asteroid.md, set B: JPL Small-Body Database, epoch JD 2460400.5 TDB (2024-03-31).
KAMOOALEWA_B = ElementSet("B: JPL SBDB, epoch 2024-03-31", 60400.0, 1.00094, 0.10269,
                          7.79605, 65.7907, 305.0478, 175.153)
# reference/asteroid.md, set A: JPL Horizons solution of 2025-02-20, epoch JD 2457854.5 TDB.
KAMOOALEWA_A = ElementSet("A: JPL Horizons, epoch 2017-04-11", 57854.0, 1.00102447694204,
                          0.1040534310625292, 7.773894173631178, 66.43991583004482,
                          307.0951007739783, 187.6486415815915)
ELEMENT_SETS = (KAMOOALEWA_B, KAMOOALEWA_A)


def mjd_from_iso(date: str) -> float:
    """MJD TDB of an ISO date or date-time string ("2022-11-29", "2022-11-29T12:00")."""
    stamp = _dt.datetime.fromisoformat(date)
    delta = stamp - _dt.datetime.combine(_MJD_EPOCH, _dt.time())
    return delta.days + delta.seconds / DAY + delta.microseconds / (DAY * 1e6)


def iso_from_mjd(mjd: float, with_time: bool = False) -> str:
    """ISO date (or date-time to the minute) of an MJD TDB."""
    stamp = _dt.datetime.combine(_MJD_EPOCH, _dt.time()) + _dt.timedelta(days=float(mjd))
    if with_time:
        return stamp.strftime("%Y-%m-%dT%H:%M")
    return (stamp + _dt.timedelta(hours=12)).date().isoformat()  # nearest calendar day


def ecliptic_from_equatorial(x: np.ndarray) -> np.ndarray:
    """Rotate vectors (..., 3) from J2000 equatorial to ecliptic axes (about x by ε0)."""
    c, s = np.cos(OBLIQUITY_J2000), np.sin(OBLIQUITY_J2000)
    x = np.asarray(x, float)
    return np.stack([x[..., 0], c * x[..., 1] + s * x[..., 2], -s * x[..., 1] + c * x[..., 2]],
                    axis=-1)


def earth_state(mjd: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
    """Earth's heliocentric ecliptic-J2000 position [m] and velocity [m/s] at `mjd` (TDB)."""
    mjd = np.asarray(mjd, float)
    pvh, _ = erfa.epv00(2400000.5, mjd)
    pos = ecliptic_from_equatorial(pvh["p"]) * AU
    vel = ecliptic_from_equatorial(pvh["v"]) * (AU / DAY)
    return pos, vel


_TABLE_BLOCK = 128  # days per cached block of the Earth table


@cache
def _earth_spline(first_block: int, last_block: int) -> CubicSpline:
    mjd = np.arange(first_block * _TABLE_BLOCK - 4, (last_block + 1) * _TABLE_BLOCK + 5, 1.0)
    r, v = earth_state(mjd)
    return CubicSpline(mjd, np.concatenate([r, v], axis=-1))


def earth_table(mjd_min: float, mjd_max: float) -> CubicSpline:
    """Cubic spline through daily `epv00` samples covering [mjd_min, mjd_max] (cached):
    (r, v) in SI as one 6-vector. Interpolation error < 100 m (the Moon-driven wobble), far
    below epv00's own error, at a fraction of its cost (the particle swarm evaluates
    thousands of dates)."""
    return _earth_spline(int(np.floor(mjd_min / _TABLE_BLOCK)),
                         int(np.floor(mjd_max / _TABLE_BLOCK)))


def earth_state_fast(mjd: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
    """`earth_state` through the cached daily spline (see `earth_table`)."""
    mjd = np.asarray(mjd, float)
    rv = earth_table(float(np.min(mjd)), float(np.max(mjd)))(mjd)
    return rv[..., :3], rv[..., 3:]


def asteroid_state(
    mjd: np.ndarray | float, elements: ElementSet = KAMOOALEWA_B
) -> tuple[np.ndarray, np.ndarray]:
    """The asteroid's heliocentric ecliptic-J2000 position [m] and velocity [m/s] at `mjd`,
    two-body Kepler propagation of the chosen osculating element set."""
    return elements_to_state(elements.elements_at(mjd), GM_SUN)


def earth_longitude(mjd: np.ndarray | float) -> np.ndarray:
    """Earth's heliocentric ecliptic longitude [rad, 0..2π) (node crossings: = Ω or Ω + π)."""
    r, _ = earth_state(mjd)
    return np.remainder(np.arctan2(r[..., 1], r[..., 0]), 2 * np.pi)
