"""A fly-around that must stay out of a keep-out zone: path constraints in a rendezvous.

The chaser holds 1 km behind its target on the V-bar and must move to a hold 1 km above it
on the R-bar in 20 minutes with the least ∫|a|²/2, in the target's orbital frame
(Clohessy–Wiltshire equations, circular 400 km orbit; x radial, y along-track):
    x'' = 3n²x + 2n y' + a_x,   y'' = -2n x' + a_y.
Left to itself the least-effort path cuts the corner, 422 m from the target; safety rules
keep the chaser outside a sphere around it (800 m by default, a slider), so the optimal
path bends around the sphere and slides along its surface: the clearance constraint is
active on an arc, and the effort rises by half. In the explorer the sphere is drawn and its
centre is dragged by hand (the zone's centre is two parameters): the path re-solves around it.

    python -m solvers solve keep-out-rendezvous --mission-file examples/keep_out_rendezvous.py
"""

import math

from casadi import sqrt

from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Consistency,
    Control,
    Param,
    PathConstraint,
    Sphere,
    State,
    UserMission,
)

MU_EARTH = 3.986004418e14  # m³/s²
N = math.sqrt(MU_EARTH / (6378.137e3 + 400e3) ** 3)  # mean motion of the target, rad/s

MISSION = UserMission(
    key="keep-out-rendezvous",
    title="Fly-around outside a keep-out sphere",
    summary="From the V-bar to the R-bar of a target without entering its keep-out zone.",
    source="Clohessy–Wiltshire relative motion; keep-out zone as a path constraint",
    params=(Param("keep_out", "keep-out radius", "m", 800.0, 100.0, 950.0, 10.0),
            Param("zone_x", "keep-out centre, radial x", "m", 0.0, -1000.0, 1000.0, 10.0),
            Param("zone_y", "keep-out centre, along-track y", "m", 0.0, -1000.0, 1000.0, 10.0),
            Param("duration", "transfer time", "s", 1200.0, 600.0, 3000.0, 60.0,
                  display_unit="min", display_factor=1 / 60)),
    states=(
        State("x", "m", bounds=(-3000, 3000), initial=0.0, final=1000.0, label="radial x"),
        State("y", "m", bounds=(-3000, 3000), initial=-1000.0, final=0.0,
              label="along-track y"),
        State("vx", "m/s", bounds=(-10, 10), initial=0.0, final=0.0),
        State("vy", "m/s", bounds=(-10, 10), initial=0.0, final=0.0),
    ),
    controls=(Control("ax", "m/s²", bounds=(-0.05, 0.05)),
              Control("ay", "m/s²", bounds=(-0.05, 0.05))),
    dynamics=lambda x, u, p: [x.vx, x.vy,
                              3 * N**2 * x.x + 2 * N * x.vy + u.ax,
                              -2 * N * x.vx + u.ay],
    lagrange=lambda x, u, p: 0.5 * (u.ax**2 + u.ay**2),
    path=(PathConstraint("clearance",
                         lambda x, u, p: sqrt((x.x - p.zone_x)**2 + (x.y - p.zone_y)**2)
                         - p.keep_out, lower=0.0, unit="m", scale=100.0),),
    final_time="duration",
    position=("y", "x"),  # drawn with along-track across and radial up the screen
    # The zone in the same display frame (along-track, radial, 0): drag its centre.
    shapes=(Sphere("keep-out", "keep-out zone", ("zone_y", "zone_x", 0.0), "keep_out"),),
    cost_unit="m²/s³",
    cost_scale=1e-4,
    methods=(HERMITE_SIMPSON.replace(nodes=(10, 60, 300)),
             MULTIPLE_SHOOTING.replace(nodes=(10, 60, 300))),
    consistency=(Consistency("cost", 1e-3, note="both methods find the same detour"),),
    tolerances={"x_miss_m": 1e-3, "y_miss_m": 1e-3, "vx_miss_m_s": 1e-6, "vy_miss_m_s": 1e-6},
)
