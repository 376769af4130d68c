"""Relative transfer on an elliptic orbit as a problem (paper 001, SPEC M2): parameters and
view options, published numbers, accuracy targets, presets, the request check and the
quantities every method reports."""

from __future__ import annotations

import numpy as np

from ...context import Infeasible
from ...dynamics.tschauner_hempel import R_EARTH
from ...problem import Consistency, Param, Preset, Published
from ...solution import Label, Quantity
from .laws import LawResult
from .model import Case

DEG = np.pi / 180
PAPER = "Mei, Ma & Yang 2010, J. Harbin Inst. Technol. 42(3) (paper 001)"
MIN_PERIGEE_ALTITUDE = 100e3  # m
COST_LABEL = "J = ½∫|u|²dt"
COST_UNIT = "m^2/s^3"

PARAMS = (
    Param("a", "semi-major axis a", "m", 9500e3, 6600e3, 60000e3, 10e3, group="Target orbit",
          display_unit="km", display_factor=1e-3),
    Param("e", "eccentricity e", "", 0.3, 0.0, 0.8, 0.01, group="Target orbit",
          help="e = 0 is the circular (Clohessy–Wiltshire) limit."),
    Param("inclination", "inclination i", "rad", 30 * DEG, 0.0, np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG,
          help="Orientation only changes the inertial view (the relative problem is the same)."),
    Param("raan", "ascending node Ω", "rad", 30 * DEG, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("argp", "argument of perigee ω", "rad", 10 * DEG, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("f0", "initial true anomaly f0", "rad", 0.0, 0.0, 2 * np.pi, DEG,
          group="Target orbit", display_unit="deg", display_factor=1 / DEG),
    Param("periods", "transfer time", "periods", 3.0, 0.25, 6.0, 0.25, group="Target orbit",
          help="In target orbital periods; the chaser must reach the target (zero relative "
               "position and velocity) at the end."),
    Param("x0", "radial x0", "m", 10000.0, -50e3, 50e3, 100.0, group="Chaser initial state",
          display_unit="km", display_factor=1e-3),
    Param("y0", "along-track y0", "m", 10000.0, -50e3, 50e3, 100.0,
          group="Chaser initial state", display_unit="km", display_factor=1e-3),
    Param("z0", "cross-track z0", "m", 0.0, -50e3, 50e3, 100.0, group="Chaser initial state",
          display_unit="km", display_factor=1e-3),
    Param("vx0", "radial vx0", "m/s", 4.0, -50.0, 50.0, 0.01, group="Chaser initial state"),
    Param("vy0", "along-track vy0", "m/s", -23.485, -100.0, 100.0, 0.001,
          group="Chaser initial state",
          help="The paper's -23.485 m/s is the drift-free value for x0 = 10 km at perigee."),
    Param("vz0", "cross-track vz0", "m/s", 0.0, -50.0, 50.0, 0.01,
          group="Chaser initial state"),
    Param("vy_source", "along-track velocity from", "", 0, 0, 1, 1,
          group="Chaser initial state", options=("given vy0", "drift-free (periodic motion)"),
          help="Drift-free: vy0 is set so that the uncontrolled relative motion is periodic."),
)

VIEW_PARAMS = (
    Param("view", "3D view", "", 0, 0, 1, 1, group="Display",
          options=("LVLH (target-centred)", "inertial (Earth-centred)"),
          help="LVLH: x radial (up), y along-track, z orbit normal. Inertial: the target's "
               "orbit about the Earth (the 10 km relative motion is invisible at that scale)."),
)

_SECTION_4 = "paper 001, section 4"
PUBLISHED = (
    Published("J_f", 2.95e-7, "m^2/s^4", "paper 001, section 4, fig. 4 (SEQ law)",
              rtol=0.0, atol=0.005e-7, methods=("seq-law", "lgl-nlp"),
              note="compared with J_f = k²J, the paper's eq. 5 form of the cost (not J): "
                   "equal to the three printed digits, so the printed unit m²/s is a misprint "
                   "for m²/s⁴"),
    Published("J_f", 1.9e-6, "m^2/s^4", "paper 001, section 4, fig. 1 (STM law)",
              rtol=0.8, holds=False, methods=("stm-law",),
              note="compared with J_f = k²J like the SEQ value (printed in m²/s): ours is more "
                   "than 5 times smaller. At N = 64 the STM law reaches the same optimum as "
                   "the SEQ law (1e-7 relative) and the Gramian, so the paper's 6x gap "
                   "between the laws does not appear; no reading of the units gives 1.9e-6"),
    Published("position_m", 5.0, "m", _SECTION_4, rtol=0.0, relation="at-most",
              methods=("seq-law", "lgl-nlp"),
              note="SEQ law in the linear model: position miss 'within 5 m'"),
    Published("velocity_m_s", 0.01, "m/s", _SECTION_4, rtol=0.0, relation="at-most",
              methods=("seq-law", "lgl-nlp"),
              note="SEQ law in the linear model: velocity miss 'within 0.01 m/s'"),
    Published("position_m", 100.0, "m", _SECTION_4, rtol=0.0, relation="at-least",
              holds=False, methods=("stm-law",),
              note="'the STM method misses by hundreds of metres in both models': in the "
                   "linear model ours misses by 1.5e-4 m, as accurate as the SEQ law"),
    Published("nonlinear_position_m", 100.0, "m", _SECTION_4, rtol=0.0, relation="at-least",
              note="both laws' controls flown in the nonlinear two-body model miss by "
                   "'hundreds of metres' (the linearisation's error over three revolutions)"),
    Published("nonlinear_position_m", 1000.0, "m", _SECTION_4, rtol=0.0,
              relation="at-most", note="... and by less than a kilometre"),
)

# Accuracy targets of the re-propagated (linear model) arrival, SI: 1 m and 1 mm/s, well
# inside the paper's 5 m / 0.01 m/s. At the default N = 64 every method misses by less than
# 2e-4 m and 3e-7 m/s (a margin above 1000); an under-resolved N = 16 misses by kilometres and
# is flagged. The nonlinear two-body miss (393 m) is the model's error, not the method's.
TOLERANCES = {"position_m": 1.0, "velocity_m_s": 1e-3}

CONSISTENCY = (
    Consistency("cost", 1e-6, note="at N = 64 the two laws and the NLP reach the same optimum "
                                   "(STM and SEQ law differ by 1e-7 relative)"),
    Consistency("cost", 1e-8, methods=("seq-law", "lgl-nlp"),
                note="the same collocation, in closed form and by IPOPT"),
)

PRESETS = (
    Preset("Paper 001 case", {}, method="seq-law", nodes=64,
           note="a = 9500 km, e = 0.3, three periods, N = 64."),
    Preset("Paper case, STM law", {}, method="stm-law", nodes=64),
    Preset("Circular limit (e = 0, Clohessy–Wiltshire)", {"e": 0.0, "vy_source": 1},
           method="seq-law", nodes=64,
           note="vy0 drift-free for the circular orbit (-2 n x0)."),
    Preset("Too few nodes (N = 16)", {}, method="stm-law", nodes=16,
           note="The STM law's quadrature is under-resolved: the linear-model miss grows."),
    Preset("Time as independent variable, N = 32", {"variable": 1}, method="seq-law",
           nodes=32, note="Compare J with the true-anomaly version at the same N."),
    Preset("One period", {"periods": 1.0}, method="seq-law", nodes=64),
    Preset("Out-of-plane start (z0 = 5 km)", {"z0": 5000.0}, method="seq-law", nodes=64),
)

EQUATIONS = (
    ("Tschauner–Hempel equations in true anomaly (paper 001, eq. 1), x̃ = (1 + e cos f) x",
     r"\tilde x'' = \frac{3\tilde x}{1 + e\cos f} + 2\tilde y' "
     r"+ \frac{u_x}{k^4(1 + e\cos f)^3},"
     r"\quad \tilde y'' = -2\tilde x' + \frac{u_y}{k^4(1 + e\cos f)^3},"
     r"\quad \tilde z'' = -\tilde z + \frac{u_z}{k^4(1 + e\cos f)^3}"),
    ("Minimum-energy cost: physical (SI) and the paper's true-anomaly form (eq. 5)",
     r"J = \frac12\int_{t_0}^{t_f} \lVert u\rVert^2\,dt,\qquad "
     r"J_f = \frac12\int_{f_0}^{f_T} \frac{u^T u}{(1 + e\cos f)^2}\,df = k^2 J"),
    ("LGL nodes, weights and differentiation matrix (eq. 4)",
     r"w_i = \frac{2}{N(N+1)L_N(t_i)^2},\qquad D_{ij} = \frac{L_N(t_i)}{L_N(t_j)(t_i - t_j)}"
     r"\ (i \ne j)"),
)


def precheck_case(case: Case) -> None:
    """Refuse a target orbit whose perigee is too low, naming the bound."""
    perigee = case.orbit.a * (1 - case.orbit.e)
    if perigee < R_EARTH + MIN_PERIGEE_ALTITUDE:
        raise Infeasible(
            f"the target's perigee radius {perigee / 1e3:.0f} km is less than "
            f"{MIN_PERIGEE_ALTITUDE / 1e3:.0f} km above the Earth's surface "
            f"({R_EARTH / 1e3:.0f} km): lower e or raise a"
        )


def quantities(case: Case, res: LawResult) -> dict[str, Quantity]:
    """J, the paper's J_f = k² J (eq. 5), the transfer time, the vy0 used and the terminal
    position of the law's own states."""
    return {
        "J": Quantity(res.J, COST_LABEL, COST_UNIT),
        "J_f": Quantity(res.J * case.orbit.k2, "J_f (paper eq. 5)", "m^2/s^4"),
        "transfer_time": Quantity(case.duration, "transfer time", "s"),
        "vy0": Quantity(float(case.x0[4]), "initial along-track velocity used", "m/s"),
        "law_terminal_position": Quantity(float(np.linalg.norm(res.X[-1, :3] - case.xT[:3])),
                                          "terminal position of the law's states", "m"),
    }


# Screen names of the states, controls and re-propagation check entries (keys of
# `Solution.check`), with the SI unit of each value.
LABELS = {
    "ux": Label("control acceleration, radial", "m/s²"),
    "uy": Label("control acceleration, along-track", "m/s²"),
    "uz": Label("control acceleration, cross-track", "m/s²"),
    "position_m": Label("arrival position miss", "m"),
    "velocity_m_s": Label("arrival velocity miss", "m/s"),
    "nonlinear_position_m": Label("arrival position miss (nonlinear model)", "m"),
    "nonlinear_velocity_m_s": Label("arrival velocity miss (nonlinear model)", "m/s"),
    "J_gramian_m2_s3": Label("J by the Gramian", "m²/s³"),
    "J_relative_difference": Label("J against the Gramian (relative)"),
}
