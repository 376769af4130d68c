"""Brachistochrone: the curve of fastest descent between two points (Johann Bernoulli, 1696).

A bead slides without friction from (0, 10) m to (10, 5) m; the control is the angle θ of
its path from the downward vertical. The optimum is a cycloid through both points; its time
follows from one equation in the cycloid's turning angle φ (solved below):
    Δx / Δy = (φ - sin φ) / (1 - cos φ),   R = Δy / (1 - cos φ),   T = φ √(R / g)
giving T = 1.801603 s for this case, the 1.8016 s that the dymos test suite checks its
collocation against (OpenMDAO/dymos, examples/brachistochrone/test/
test_doc_brachistochrone_polynomial_controls.py, tolerance 1e-3).

    python -m solvers solve brachistochrone --mission-file examples/brachistochrone.py
"""

import math

from casadi import cos, sin
from scipy.optimize import brentq

from solvers.userproblem import (
    HERMITE_SIMPSON,
    LGL,
    Control,
    FreeTime,
    Param,
    Preset,
    Published,
    State,
    UserMission,
)

G = 9.80665  # m/s², the value dymos uses


def cycloid_time(dx: float, dy: float, g: float = G) -> float:
    """Descent time along the cycloid from rest through a drop dy over a distance dx."""
    def shape(phi: float) -> float:
        return (phi - math.sin(phi)) / (1 - math.cos(phi)) - dx / dy

    phi = brentq(shape, 1e-6, 2 * math.pi - 1e-6)
    return phi * math.sqrt(dy / (1 - math.cos(phi)) / g)


MISSION = UserMission(
    key="brachistochrone",
    title="Brachistochrone",
    summary="The fastest frictionless slide between two points: a cycloid.",
    source="Johann Bernoulli 1696; the cycloid's time (analytic) and dymos' 1.8016 s",
    params=(Param("x_end", "end point x", "m", 10.0, 1.0, 20.0, 0.5),
            Param("y_end", "end point y", "m", 5.0, 0.0, 9.0, 0.5)),
    states=(
        State("x", "m", bounds=(0, 30), initial=0.0, final="x_end"),
        State("y", "m", bounds=(-10, 10), initial=10.0, final="y_end"),
        State("v", "m/s", bounds=(0, 30), initial=0.0, guess=10.0),
    ),
    controls=(Control("theta", "rad", bounds=(0, math.pi), guess=1.0,
                      label="angle from the vertical θ"),),
    dynamics=lambda x, u, p: [x.v * sin(u.theta), -x.v * cos(u.theta), G * cos(u.theta)],
    final_time=FreeTime(2.0, bounds=(0.5, 10.0)),
    minimum_time=True,
    position=("x", "y"),
    cost_label="descent time", cost_unit="s",
    methods=(HERMITE_SIMPSON.replace(nodes=(5, 40, 200)), LGL.replace(nodes=(10, 30, 80))),
    published=(
        Published("tf", cycloid_time(10.0, 5.0), "s", "the cycloid (analytic)", rtol=1e-6),
        Published("tf", 1.8016, "s", "dymos test suite (OpenMDAO), brachistochrone",
                  rtol=1e-3),
    ),
    tolerances={"x_miss_m": 1e-4, "y_miss_m": 1e-4},
    presets=(Preset("A steep drop to (2, 1)", {"x_end": 2.0, "y_end": 1.0}),),
)
