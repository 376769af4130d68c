"""A landing inside a glide-slope cone: a lander in Mars gravity comes down from 1 km up and
1 km downrange to rest on a target in a given time, with the least ∫|a|²/2 of thrust
acceleration, and must stay above the glide slope z ≥ tan(γ)·|x − x_t| (terrain and sensors
demand it: Açıkmeşe & Ploen 2007). In the explorer the cone is drawn with its apex on the
target: drag the apex along the ground, or steepen γ, and the descent re-shapes live.

    python -m explorer --mission-file examples/glide_slope_landing.py

With the slope flat the cone is out of the way and the answer is analytic: each axis is the
double integrator's cubic, so the cost is the least-energy one per axis (12/T³ (Δ − T v̄)² +
Δv²/T, halved) plus g Δv_z + g² T/2 for holding against gravity. That path dives in at
50 m/s and sinks to 21° above the target's horizon on its way in; at the default 40° slope
the optimum stays higher, rides the cone's surface on a long arc and costs 3.7 % more. The
start sits 45° above the target: a steeper slope, or the target dragged some 190 m further
on at 40°, puts it outside the cone, and the answer is `infeasible`, naming
the glide slope.
"""

import math

from casadi import sqrt, tan

from solvers.problem import Preset
from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Cone,
    Consistency,
    Control,
    Param,
    PathConstraint,
    Plane,
    Published,
    State,
    UserMission,
)

G_MARS = 3.7114  # m/s², the surface gravity of the powered-descent papers
START = {"x": -1000.0, "z": 1000.0, "vx": 10.0, "vz": -50.0}  # m, m/s: diving, 45° up
DURATION = 40.0  # s
SMOOTH = 1.0  # m: |x − x_t| is smoothed within a metre of the target (finite gradient there)
FLAT = Preset("slope flat", {"slope": math.radians(1.0)},
              note="a 1° slope never binds: the analytic least-energy landing")


def _least_energy(delta: float, v0: float, vf: float, duration: float) -> float:
    """min ∫ a²/2 dt of the double integrator moving `delta` from speed v0 to vf."""
    mean = 0.5 * (v0 + vf)
    return 0.5 * (12.0 / duration**3 * (delta - duration * mean)**2 + (vf - v0)**2 / duration)


def analytic_cost(target: float = 0.0, duration: float = DURATION) -> float:
    """The unconstrained optimum: per-axis cubics, and a constant g offset in z."""
    across = _least_energy(target - START["x"], START["vx"], 0.0, duration)
    down = _least_energy(-START["z"], START["vz"], 0.0, duration)
    return across + down + G_MARS * (0.0 - START["vz"]) + 0.5 * G_MARS**2 * duration


def _glide_slope(x, u, p):  # noqa: ARG001 - the path constraint's signature
    """z − tan γ (√((x − x_t)² + ε²) − ε) ≥ 0: the cone, rounded within ε of its axis."""
    return x.z - tan(p.slope) * (sqrt((x.x - p.target)**2 + SMOOTH**2) - SMOOTH)


MISSION = UserMission(
    key="glide-slope-landing",
    title="Landing inside a glide-slope cone",
    summary="Down to rest on a target in Mars gravity, staying above the glide slope.",
    source="glide-slope constraint of Açıkmeşe & Ploen 2007; analytic when it does not bind",
    params=(Param("slope", "glide-slope angle γ", "rad", math.radians(40.0), math.radians(1.0),
                  math.radians(44.0), math.radians(1.0), display_unit="°",
                  display_factor=180.0 / math.pi),
            Param("target", "target downrange x_t", "m", 0.0, -400.0, 400.0, 10.0),
            Param("duration", "flight time T", "s", DURATION, 25.0, 80.0, 1.0)),
    states=(
        State("x", "m", bounds=(-3000, 3000), initial=START["x"], final="target",
              label="downrange x"),
        State("z", "m", bounds=(-10, 3000), initial=START["z"], final=0.0, label="altitude z"),
        State("vx", "m/s", bounds=(-150, 150), initial=START["vx"], final=0.0),
        State("vz", "m/s", bounds=(-150, 150), initial=START["vz"], final=0.0),
    ),
    controls=(Control("ax", "m/s²", bounds=(-15, 15)),
              Control("az", "m/s²", bounds=(-15, 15), guess=G_MARS)),
    dynamics=lambda x, u, p: [x.vx, x.vz, u.ax, u.az - G_MARS],
    lagrange=lambda x, u, p: 0.5 * (u.ax**2 + u.az**2),
    path=(PathConstraint("glide_slope", _glide_slope, lower=0.0, unit="m", scale=100.0),),
    final_time="duration",
    # Downrange across, altitude up the screen: the cone opens up the display z axis.
    position=lambda x, p: (x.x, 0.0 * x.x, x.z),
    shapes=(Cone("cone", "glide slope apex", ("target", 0.0, 0.0), "slope", 1100.0),
            Plane("ground", "ground", (0.0, 0.0, 0.0), 3000.0)),
    cost_unit="m²/s³",
    cost_scale=100.0,
    methods=(HERMITE_SIMPSON.replace(nodes=(10, 40, 300)),
             MULTIPLE_SHOOTING.replace(nodes=(10, 80, 300))),
    presets=(FLAT,),
    published=(Published("cost", analytic_cost(), "m²/s³",
                         "analytic least-energy landing: per-axis cubics, cone not binding",
                         rtol=1e-6, case=FLAT),),
    consistency=(Consistency("cost", 1e-3, note="both methods ride the same slope"),),
    tolerances={"x_miss_m": 1e-3, "z_miss_m": 1e-3, "vx_miss_m_s": 1e-5, "vz_miss_m_s": 1e-5},
)
