"""An obstacle field to reshape by hand: a mass crosses a floor from rest to rest in a given
time with the least control effort, around three round obstacles whose centres and radius
are parameters. In the explorer each obstacle is a sphere in the 3D view: drag one and the
optimum bends around it live.

    python -m explorer --mission-file examples/obstacle_field.py

With the obstacles off the straight line the answer is the double integrator's analytic
optimum along x: u = 6d/T² (1 - 2t/T), cost 6 d²/T³ = 0.6 m²/s³ for d = 10 m, T = 10 s.
With them in the way the path goes round (to the side the warm start is already on: each
side of an obstacle is a local optimum of its own) and costs more.

The clearances hold at the mesh points only, so between them the path cuts a little into
each obstacle it slides along, and the cost converges like the square of the spacing. At
the live defaults the estimated cost error is about 0.2 % (status `inaccurate` against the
1e-4 target, said on screen); "refine" meets it (40 → 101 → 300 intervals, J = 1.98547,
6 s on a 2-core laptop).
"""

from solvers.problem import Preset
from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Consistency,
    Control,
    Param,
    PathConstraint,
    Published,
    Sphere,
    State,
    UserMission,
)

DISTANCE = 10.0  # m, from the start (0, 0) to the goal (d, 0)
OBSTACLES = ((3.0, 0.4), (5.5, -0.5), (8.0, 0.6))  # default centres (x, y), m
CLEAR = Preset("obstacles aside", {f"o{i}_y": 6.0 for i in range(1, 4)},
               note="every obstacle moved off the line: the analytic double integrator")


def _centre(i: int, x: float, y: float) -> tuple[Param, Param]:
    return (Param(f"o{i}_x", f"obstacle {i} centre x", "m", x, -2.0, 12.0, 0.1),
            Param(f"o{i}_y", f"obstacle {i} centre y", "m", y, -6.0, 6.0, 0.1))


def _clearance(i: int) -> PathConstraint:
    """(x - cx)² + (y - cy)² ≥ r²: the squared form keeps its gradient finite everywhere,
    the centre included (the straight-line cold start passes right through them)."""
    return PathConstraint(
        f"clearance_{i}",
        lambda x, u, p: (x.x - getattr(p, f"o{i}_x"))**2 + (x.y - getattr(p, f"o{i}_y"))**2
        - p.radius**2,
        lower=0.0, unit="m²", scale=1.0)


MISSION = UserMission(
    key="obstacle-field",
    title="Through an obstacle field, least effort",
    summary="Rest to rest across a floor around three obstacles you can drag.",
    source="analytic without obstacles: u = 6d/T² (1 - 2t/T), cost 6 d²/T³",
    params=(*(p for i, (x, y) in enumerate(OBSTACLES, 1) for p in _centre(i, x, y)),
            Param("radius", "obstacle radius", "m", 1.0, 0.2, 2.0, 0.05),
            Param("duration", "duration T", "s", 10.0, 4.0, 30.0, 0.5)),
    states=(
        State("x", "m", bounds=(-5, 15), initial=0.0, final=DISTANCE),
        State("y", "m", bounds=(-8, 8), initial=0.0, final=0.0),
        State("vx", "m/s", bounds=(-10, 10), initial=0.0, final=0.0),
        State("vy", "m/s", bounds=(-10, 10), initial=0.0, final=0.0),
    ),
    controls=(Control("ax", "m/s²", bounds=(-5, 5)), Control("ay", "m/s²", bounds=(-5, 5))),
    dynamics=lambda x, u, p: [x.vx, x.vy, u.ax, u.ay],
    lagrange=lambda x, u, p: 0.5 * (u.ax**2 + u.ay**2),
    path=tuple(_clearance(i) for i in range(1, 4)),
    final_time="duration",
    position=("x", "y"),
    shapes=tuple(Sphere(f"obstacle_{i}", f"obstacle {i}", (f"o{i}_x", f"o{i}_y", 0.0), "radius")
                 for i in range(1, 4)),
    cost_unit="m²/s³",
    # Both hold the clearances at the same 81 points of the path: Hermite–Simpson at the
    # nodes and midpoints of 40 intervals, multiple shooting at the nodes of 80.
    methods=(HERMITE_SIMPSON.replace(
                 nodes=(10, 40, 300), options=(("midpoint_path", 1),),
                 summary=HERMITE_SIMPSON.summary + " The clearances hold at the interval "
                 "midpoints too."),
             MULTIPLE_SHOOTING.replace(nodes=(10, 80, 300))),
    presets=(CLEAR,),
    published=(Published("cost", 6 * DISTANCE**2 / 10.0**3, "m²/s³",
                         "analytic optimum 6 d²/T³ with no obstacle in the way", rtol=1e-6,
                         case=CLEAR),),
    consistency=(Consistency("cost", 1e-3, note="both methods go round the same sides"),),
    tolerances={"x_miss_m": 1e-3, "y_miss_m": 1e-3, "vx_miss_m_s": 1e-5, "vy_miss_m_s": 1e-5},
)
