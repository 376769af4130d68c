"""How the asteroid rendezvous is drawn: heliocentric ecliptic J2000 in AU, the Sun, both
orbits, Earth and the asteroid moving with the spacecraft, launch and arrival dates, the path
coloured by thrust, paper 003's figures (thrust, mass, elements; fig. 2's launch-C3 map with
this solution marked). Times in days."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache

import numpy as np

from ... import palette
from ...dynamics.ephemeris import (
    AU,
    DAY,
    ELEMENT_SETS,
    GM_SUN,
    MJD_2022,
    asteroid_state,
    earth_state,
    iso_from_mjd,
)
from ...dynamics.kepler import state_to_elements
from ...presentation import Body, ColorBy, Curve, GridMap, Marker, PlotSeries, Presentation
from ...solution import Solution
from .launch_map import LaunchMap, compute_launch_map
from .methods import BURN_FRACTION

DEG = np.pi / 180
SUN_RADIUS_DRAWN = 0.03 * AU  # ~6.5 solar radii: enlarged so the Sun is visible at 1 AU
PLANET_RADIUS_DRAWN = 0.008 * AU  # Earth and asteroid drawn ~190x Earth's radius
EARTH = "Earth (enlarged)"
ASTEROID = "Kamoʻoalewa (enlarged)"
# Launch and arrival closer than this share one label: a date label is about a quarter of
# the 2 AU picture long in the default framing.
ONE_LABEL = 0.5 * AU


def present(sol: Solution, view: Mapping[str, float]) -> Presentation:
    """The transfer among the Sun, Earth and the asteroid (this mission has no view
    options)."""
    launch = MJD_2022 + sol.quantities["launch_date"].value
    arrival = MJD_2022 + sol.quantities["arrival_date"].value
    impulsive = sol.method == "impulsive"
    if impulsive:
        sizes = np.linalg.norm(sol.node_u, axis=1)
        thrust = sol.node_u / max(float(sizes.max()), 1e-9)
        color_by, plots = None, impulsive_plots(sol)
    else:
        thrust = sol.node_u / sol.values["thrust"]
        color_by = ColorBy("thrust magnitude", "mN", np.linalg.norm(sol.u, axis=1) * 1e3)
        plots = low_thrust_plots(sol)
    tracks = body_tracks(sol)
    return Presentation(
        frame="heliocentric ecliptic J2000",
        path=sol.x[:, 0:3],
        nodes=sol.node_x[:, 0:3],
        thrust=thrust,
        display_unit="AU",
        display_scale=1.0 / AU,
        bodies=[
            Body("Sun (enlarged)", (0.0, 0.0, 0.0), SUN_RADIUS_DRAWN, palette.SUN),
            Body(EARTH, tuple(tracks["Earth"][0]), PLANET_RADIUS_DRAWN, palette.EARTH,
                 track=tracks["Earth"]),
            Body(ASTEROID, tuple(tracks["Kamoʻoalewa"][-1]), 0.6 * PLANET_RADIUS_DRAWN,
                 palette.ASTEROID, track=tracks["Kamoʻoalewa"]),
        ],
        curves=orbits(launch, int(sol.values["elements"])),
        markers=date_markers(sol, tracks, launch, arrival),
        color_by=color_by,
        plots=plots,
        maps=[launch_c3_map(sol, launch, arrival - launch)],
        iterates=[(it.iteration, it.x[:, 0:3]) for it in sol.history],
        time_unit="d",
        time_scale=1.0 / DAY,
        arrow_name="impulse direction" if impulsive else "thrust direction",
    )


def body_tracks(sol: Solution) -> dict[str, np.ndarray]:
    """Earth's and the asteroid's positions [m] at the Solution's dense times `sol.t`, so
    both bodies move with the spacecraft in the animation."""
    launch = MJD_2022 + sol.quantities["launch_date"].value
    dates = launch + np.asarray(sol.t) / DAY
    elements = ELEMENT_SETS[int(sol.values["elements"])]
    return {"Earth": earth_state(dates)[0], "Kamoʻoalewa": asteroid_state(dates, elements)[0]}


def orbits(launch_mjd: float, elements: int) -> list[Curve]:
    """Earth's and the asteroid's orbits, one revolution from launch."""
    el = ELEMENT_SETS[elements]
    r_earth, _ = earth_state(launch_mjd + np.linspace(0.0, 365.25, 367))
    period = 2 * np.pi * np.sqrt((el.a_au * AU) ** 3 / GM_SUN) / DAY
    r_ast, _ = asteroid_state(launch_mjd + np.linspace(0.0, period, 367), el)
    return [Curve("Earth's orbit", r_earth, palette.EARTH_ORBIT, dashed=True),
            Curve("Kamoʻoalewa's orbit", r_ast, palette.ASTEROID, dashed=True)]


def date_markers(sol: Solution, tracks: Mapping[str, np.ndarray], launch: float,
                 arrival: float) -> list[Marker]:
    """Launch (at Earth) and arrival (at the asteroid) labelled with their dates, and the
    impulsive method's mid-course impulses. Kamoʻoalewa is Earth's quasi-satellite, so a
    year's flight ends close to where it began: closer than a label's length, the two
    dates share one label at the launch point (two labels there cover each other)."""
    at_launch, at_arrival = tracks["Earth"][0], tracks["Kamoʻoalewa"][-1]
    launch_text, arrival_text = f"launch {iso_from_mjd(launch)}", f"arrival {iso_from_mjd(arrival)}"
    if np.linalg.norm(at_arrival - at_launch) < ONE_LABEL:
        markers = [Marker(f"{launch_text} · {arrival_text}", tuple(at_launch), palette.START),
                   Marker("", tuple(at_arrival), palette.TARGET)]
    else:
        markers = [Marker(launch_text, tuple(at_launch), palette.START),
                   Marker(arrival_text, tuple(at_arrival), palette.TARGET, anchor="top-left")]
    if sol.method == "impulsive":
        for t, x in zip(sol.node_t[1:-1], sol.node_x[1:-1], strict=True):
            markers.append(Marker(f"impulse {iso_from_mjd(launch + t / DAY)}", tuple(x[0:3]),
                                  palette.LABEL))
    return markers


@cache
def _launch_map(elements: int) -> LaunchMap:
    """Paper 003 fig. 2 on a display grid (3-day launch steps, 10-day flight steps): about
    0.1 s once per element set."""
    return compute_launch_map(elements=ELEMENT_SETS[elements], tof=(50.0, 700.0, 66),
                              workers=1, step_days=3.0)


def launch_c3_map(sol: Solution, launch_mjd: float, flight_days: float) -> GridMap:
    """The launch-C3 map with this solution's (launch date, flight time) marked."""
    m = _launch_map(int(sol.values["elements"]))
    return GridMap(
        "launch C3 (paper 003 fig. 2): set a date pair with 'first guess: Lambert arc at "
        "chosen dates'", "launch date [days since 2022-01-01]", m.launch_mjd - MJD_2022,
        "flight time [d]", m.tof_days, "C3 [km²/s²]", m.c3, sol.values["c3_max"] / 1e6,
        marker=(launch_mjd - MJD_2022, flight_days),
    )


def element_plots(t: np.ndarray, x: np.ndarray, t_nodes: np.ndarray, x_nodes: np.ndarray
                  ) -> list[PlotSeries]:
    """Semi-major axis, eccentricity and inclination along the transfer (paper 003 fig. 4)."""
    el = state_to_elements(x[:, 0:3], x[:, 3:6], GM_SUN)
    eln = state_to_elements(x_nodes[:, 0:3], x_nodes[:, 3:6], GM_SUN)
    return [
        PlotSeries("semi-major axis", "AU", t, el[:, 0] / AU, t_nodes, eln[:, 0] / AU),
        PlotSeries("eccentricity", "", t, el[:, 1], t_nodes, eln[:, 1]),
        PlotSeries("inclination", "deg", t, el[:, 2] / DEG, t_nodes, eln[:, 2] / DEG),
    ]


def thrust_angles(U: np.ndarray, fmax: float) -> tuple[np.ndarray, np.ndarray]:
    """Ecliptic longitude [0, 360) and latitude of the thrust [deg]; NaN on coasts."""
    mag = np.linalg.norm(U, axis=1)
    on = mag > BURN_FRACTION * fmax
    lon = np.where(on, np.remainder(np.arctan2(U[:, 1], U[:, 0]) / DEG, 360.0), np.nan)
    lat = np.where(on, np.arcsin(np.clip(U[:, 2] / np.maximum(mag, 1e-30), -1, 1)) / DEG,
                   np.nan)
    return lon, lat


def low_thrust_plots(sol: Solution) -> list[PlotSeries]:
    """Thrust magnitude and direction, mass and elements (paper 003 figs. 3-4)."""
    t, X, U, tn, Xn, Un = sol.t, sol.x, sol.u, sol.node_t, sol.node_x, sol.node_u
    fmax = sol.values["thrust"]
    lon, lat = thrust_angles(U, fmax)
    lon_n, lat_n = thrust_angles(Un, fmax)
    return [
        PlotSeries("thrust magnitude", "mN", t, np.linalg.norm(U, axis=1) * 1e3, tn,
                   np.linalg.norm(Un, axis=1) * 1e3, "control"),
        PlotSeries("thrust ecliptic longitude", "deg", t, lon, tn, lon_n, "control"),
        PlotSeries("thrust ecliptic latitude", "deg", t, lat, tn, lat_n, "control"),
        PlotSeries("mass", "kg", t, X[:, 6], tn, Xn[:, 6]),
        *element_plots(t, X, tn, Xn),
    ]


def impulsive_plots(sol: Solution) -> list[PlotSeries]:
    """Speed, impulse sizes and elements of the impulsive transfer."""
    speed = np.linalg.norm(sol.x[:, 3:6], axis=1)
    sizes = np.linalg.norm(sol.node_u, axis=1)
    return [
        PlotSeries("heliocentric speed", "km/s", sol.t, speed / 1e3, sol.node_t, None),
        PlotSeries("impulse size", "m/s", sol.node_t, sizes, sol.node_t, sizes, "control"),
        *element_plots(sol.t, sol.x, sol.node_t, sol.node_x),
    ]
