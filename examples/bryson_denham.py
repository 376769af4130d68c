"""Bryson–Denham problem: a state bound that becomes active (Bryson, Denham & Dreyfus,
"Optimal programming problems with inequality constraints I", AIAA J. 1(11), 1963;
Bryson & Ho, Applied Optimal Control, 1975, §3.11).

A unit mass arrives at x = 0 with speed 1 and must leave it at t = 1 with speed -1 (x' = v,
v' = u), using the least effort ∫u²/2, without ever going past x = l. Unconstrained, it would
reach x = 1/4 (u ≡ -2, cost 2). For l <= 1/6 the bound is touched along a whole arc
[3l, 1 - 3l] where u = 0, and the optimum is analytic:
    u = -(2 / 3l)(1 - t / 3l) on [0, 3l] (mirrored on [1 - 3l, 1]),   cost = 4 / (9 l),
so cost = 4 exactly for the classic l = 1/9. For 1/6 <= l <= 1/4 the bound is touched at
t = 1/2 only (cost 2.24 for l = 0.2, two cubic arcs).

    python -m solvers solve bryson-denham --mission-file examples/bryson_denham.py
"""

from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Control,
    Param,
    Preset,
    Published,
    State,
    UserMission,
)

MISSION = UserMission(
    key="bryson-denham",
    title="Bryson–Denham: an active state bound",
    summary="Turn a moving mass around with least effort without passing x = l.",
    source="Bryson, Denham & Dreyfus 1963; analytic cost 4/(9 l) for l <= 1/6",
    params=(Param("l", "bound l on x", "m", 1 / 9, 0.05, 0.3, 0.01,
                  help="Active along an arc for l <= 1/6, at one point up to 1/4, "
                       "inactive beyond."),),
    states=(
        State("x", "m", bounds=(-1.0, "l"), initial=0.0, final=0.0),  # the bound is a slider
        State("v", "m/s", bounds=(-10.0, 10.0), initial=1.0, final=-1.0),
    ),
    controls=(Control("u", "m/s²", bounds=(-50.0, 50.0)),),
    dynamics=lambda x, u, p: [x.v, u.u],
    lagrange=lambda x, u, p: 0.5 * u.u**2,
    final_time=1.0,
    position=("x",),
    cost_unit="m²/s³",
    methods=(HERMITE_SIMPSON.replace(nodes=(5, 30, 200)),
             MULTIPLE_SHOOTING.replace(nodes=(5, 30, 200))),
    published=(
        Published("cost", 4.0, "m²/s³", "analytic 4/(9 l), l = 1/9 (Bryson & Ho §3.11)",
                  rtol=1e-6, note="the arc's ends 3l = 1/3 and 2/3 fall on nodes"),
        Published("cost", 2.24, "m²/s³", "analytic touch-point case l = 0.2 (OptimalControl.jl "
                  "documentation, state constraint example)", rtol=1e-6,
                  case=Preset("Touching at one point, l = 0.2", {"l": 0.2})),
    ),
    tolerances={"x_miss_m": 1e-8, "v_miss_m_s": 1e-8},
    presets=(Preset("Bound inactive, l = 0.3 (cost 2)", {"l": 0.3}),
             Preset("Touching at one point, l = 0.2", {"l": 0.2})),
)
