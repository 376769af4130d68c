"""Double integrator: push a mass from rest to rest over a distance in a given time with the
least control effort.

    python -m solvers solve double-integrator --mission-file examples/double_integrator.py
    python -m explorer --mission-file examples/double_integrator.py

Analytic optimum (the maximum principle makes the control linear in time):
u(t) = 6 d / T² (1 - 2 t / T), cost = 6 d² / T³ = 6 m²/s³ for d = 1 m, T = 1 s.
"""

from solvers.userproblem import Control, Param, Published, State, UserMission

MISSION = UserMission(
    key="double-integrator",  # the name on the command line and in the mission list
    title="Double integrator, least effort",
    summary="Move a mass from rest to rest over a distance d in a time T with least ∫u²/2.",
    source="analytic: u = 6d/T² (1 - 2t/T), cost 6 d²/T³",
    # Parameters become sliders in the explorer and `--set key=value` on the command line.
    params=(
        Param("distance", "distance d", "m", 1.0, 0.1, 10.0, 0.1),
        Param("duration", "duration T", "s", 1.0, 0.5, 10.0, 0.1),
    ),
    # A state's initial/final value is a number, a parameter key, or None (free).
    states=(
        State("x", "m", bounds=(-20, 20), initial=0.0, final="distance"),
        State("v", "m/s", bounds=(-50, 50), initial=0.0, final=0.0),
    ),
    controls=(Control("a", "m/s²", bounds=(-100, 100)),),
    # x' = v, v' = a: the functions get the states, controls and parameters by name.
    dynamics=lambda x, u, p: [x.v, u.a],
    lagrange=lambda x, u, p: 0.5 * u.a**2,  # running cost; `mayer=lambda xf, p: ...` for x(T)
    final_time="duration",  # a number, a parameter key, or FreeTime(guess) to optimise it
    position=("x",),  # the state(s) drawn as the path in 3D
    cost_unit="m²/s³",
    published=(Published("cost", 6.0, "m²/s³", "analytic optimum 6 d²/T³", rtol=1e-6),),
    tolerances={"x_miss_m": 1e-6, "v_miss_m_s": 1e-6},  # re-propagated misses allowed
)
