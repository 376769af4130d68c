"""Maximum-radius orbit raising in a given time (Bryson & Ho, Applied Optimal Control, 1975,
§2.7, pp. 66–69): a spacecraft on a circular orbit thrusts at constant thrust, losing mass
at a constant rate, for a fixed time, and chooses the thrust direction so as to end on the
largest circular orbit it can. Canonical units: μ = 1, r0 = 1, v0 = 1; T = 0.1405 m0,
|ṁ| = 0.0749 m0 per unit time, tf = 3.32 (193 days for an Earth-to-Mars scale).

The thrust angle φ (from the local horizontal, towards the outside) turns through most of a
circle during the transfer, from about 25° to about 311°: a constant cold-start guess does
not seed it, the ramp `guess=(start, end)` on the control does (as would a function of the
normalised time, `guess=lambda tau, p: (25 + 286 * tau) * DEG`). φ is bounded to one turn,
[0, 2π]: bounded to two, it could wind, and the NLP ended on other branches on some meshes
(Hermite–Simpson on 40 nodes: r(tf) = 1.4983; multiple shooting on 25: 1.4900).

    python -m solvers solve orbit-raising --mission-file examples/orbit_raising.py
"""

import math

from casadi import cos, sin

from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Control,
    FinalConstraint,
    Param,
    Published,
    State,
    UserMission,
)

DEG = math.pi / 180


def dynamics(x, u, p):
    """Polar equations of motion (Bryson & Ho eq. 2.7.1) with the mass as a state."""
    a = p.thrust / x.m
    return [x.vr, x.vt / x.r,
            x.vt**2 / x.r - 1.0 / x.r**2 + a * sin(u.phi),
            -x.vr * x.vt / x.r + a * cos(u.phi),
            -p.mass_rate]


MISSION = UserMission(
    key="orbit-raising",
    title="Orbit raising: the largest orbit in a given time",
    summary="Steer a constant thrust to end on the largest circular orbit after a fixed time.",
    source="Bryson & Ho 1975, §2.7: r(tf) = 1.525 r0",
    params=(Param("thrust", "thrust T / m0", "", 0.1405, 0.05, 0.3, 0.005),
            Param("mass_rate", "mass flow |ṁ| / m0", "", 0.0749, 0.03, 0.15, 0.001),
            Param("tf", "transfer time", "", 3.32, 1.0, 6.0, 0.01,
                  help="In units of the initial orbit's period over 2π.")),
    states=(
        State("r", bounds=(0.5, 5.0), initial=1.0, label="radius r"),
        State("theta", bounds=(-1.0, 20.0), initial=0.0, label="polar angle θ"),
        State("vr", bounds=(-2.0, 2.0), initial=0.0, final=0.0, label="radial speed"),
        State("vt", bounds=(0.05, 2.0), initial=1.0, label="tangential speed"),
        State("m", bounds=(0.05, 1.0), initial=1.0, label="mass m"),
    ),
    controls=(Control("phi", "rad", bounds=(0.0, 2 * math.pi),
                      guess=(25 * DEG, 311 * DEG), label="thrust angle φ"),),
    dynamics=dynamics,
    mayer=lambda xf, p: xf.r,
    maximize=True,
    final=(FinalConstraint("circular", lambda xf, p: xf.vt - xf.r**-0.5),),
    final_time="tf",
    position=lambda x, p: (x.r * cos(x.theta), x.r * sin(x.theta)),
    position_unit="r0",  # canonical: the initial orbit's radius
    cost_label="final radius",
    methods=(HERMITE_SIMPSON.replace(nodes=(10, 60, 400)),
             MULTIPLE_SHOOTING.replace(nodes=(10, 60, 400))),
    published=(Published("r_final", 1.525, "", "Bryson & Ho 1975, §2.7, p. 68", rtol=0.0,
                         atol=5e-4, note="printed with 4 digits"),),
    tolerances={"vr_miss": 1e-5, "circular_miss": 1e-5},
)
