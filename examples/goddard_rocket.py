"""Goddard rocket, maximum altitude: how to throttle a sounding rocket through the drag of
the lower atmosphere to coast highest (R. H. Goddard 1919; the COPS benchmark).

Nondimensional model of COPS 3.0 (Dolan, Moré & Munson, "Benchmarking optimization
software with COPS 3.0", Argonne report ANL/MCS-TM-273, 2004, problem "rocket"):
    h' = v,  v' = (T - D)/m - g,  m' = -T/c,
    D = D_c v² exp(-h_c (h - h0)/h0),  g = g0 (h0/h)²,  c = 0.5 √(g0 h0),
    h(0) = h0 = 1, v(0) = 0, m(0) = 1, m(tf) = 0.6, 0 <= T <= 3.5, tf free,
    D_c = 310, h_c = 500, g0 = 1.
COPS reports the final altitude 1.01283 (nh = 400); the JuMP port of the same model
("Rocket Control with JuMP", JuliaCon 2015, n = 800 steps) prints 1.0128340615. Here
Hermite–Simpson and multiple shooting reach 1.0128369 at 100 intervals. The optimal thrust
is bang-singular-bang: full thrust, a singular arc where thrust balances drag, a coast.

    python -m solvers solve goddard-rocket --mission-file examples/goddard_rocket.py
"""

from casadi import exp

from solvers.userproblem import (
    HERMITE_SIMPSON,
    MULTIPLE_SHOOTING,
    Control,
    FreeTime,
    Param,
    Published,
    State,
    UserMission,
)

H_C, V_C = 500.0, 620.0  # drag altitude scale and drag speed scale (COPS)
D_C = 0.5 * V_C  # drag coefficient D_c = 0.5 v_c m0 / g0
C = 0.5  # exhaust speed 0.5 √(g0 h0)


def dynamics(x, u, p):
    drag = D_C * x.v**2 * exp(-H_C * (x.h - 1.0))
    return [x.v, (u.T - drag) / x.m - 1.0 / x.h**2, -u.T / C]


MISSION = UserMission(
    key="goddard-rocket",
    title="Goddard rocket, maximum altitude",
    summary="Throttle a vertical rocket through drag to reach the greatest altitude.",
    source="COPS 3.0 (Dolan, Moré & Munson 2004), problem 'rocket': h(tf) = 1.01283",
    params=(Param("thrust_max", "maximum thrust T_max", "", 3.5, 2.0, 6.0, 0.1,
                  help="In units of the initial weight m0 g0."),
            Param("mass_final", "final (dry) mass", "", 0.6, 0.3, 0.9, 0.05,
                  help="Fraction of the initial mass left when the propellant is spent.")),
    states=(
        State("h", bounds=(1.0, 2.0), initial=1.0, guess=1.01, label="altitude h"),
        State("v", bounds=(0.0, 1.0), initial=0.0, guess=0.05, label="speed v"),
        State("m", bounds=(0.2, 1.0), initial=1.0, final="mass_final", label="mass m"),
    ),
    controls=(Control("T", bounds=(0.0, "thrust_max"), label="thrust T"),),
    dynamics=dynamics,
    mayer=lambda xf, p: xf.h,
    maximize=True,
    final_time=FreeTime(0.2, bounds=(0.01, 1.0)),
    position=("h",),
    cost_label="final altitude",
    methods=(HERMITE_SIMPSON.replace(nodes=(10, 100, 400)),
             MULTIPLE_SHOOTING.replace(nodes=(10, 100, 400))),
    published=(Published("h_final", 1.01283, "", "COPS 3.0 (ANL/MCS-TM-273), rocket, nh=400",
                         rtol=0.0, atol=1e-5, note="COPS prints 6 digits"),),
    tolerances={"m_miss": 1e-8},
)
