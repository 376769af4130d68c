"""The general methods, declared once: each solves any mission's `OCP` with no mission code.

A mission lists the ones it offers, adjusting the node range or back ends with `replace`:

    METHODS = (paper_method, HERMITE_SIMPSON.replace(nodes=(5, 30, 200)), LGL)
"""

from __future__ import annotations

from .problem import Method

HERMITE_SIMPSON = Method(
    "hermite-simpson", "Hermite–Simpson collocation", "direct collocation",
    "Cubic Hermite state, control linear between nodes, one collocation point at each "
    "interval's midpoint; the NLP is built once and re-solved warm.",
    nodes=(5, 30, 200), nodes_label="intervals", backends=("ipopt", "sqp"),
    transcription="hermite-simpson",
    equations=(("Hermite–Simpson defect (compressed form)",
                r"x_{k+1} - x_k - \frac{h}{6}\left(f_k + 4 f_{k+\frac12} + f_{k+1}\right) = 0,"
                r"\quad x_{k+\frac12} = \frac{x_k + x_{k+1}}{2} + \frac{h}{8}(f_k - f_{k+1})"),),
)

MULTIPLE_SHOOTING = Method(
    "multiple-shooting", "Direct multiple shooting (paper 004)", "paper 004",
    "τ ∈ [0, 1] with t = Tτ, T a decision variable; control linear between nodes; RK4 on "
    "each interval; continuity of the node states.",
    nodes=(5, 30, 200), nodes_label="intervals", backends=("ipopt", "sqp"),
    transcription="multiple-shooting",
    equations=(("Continuity of the shooting intervals (paper 004)",
                r"x\left(S_i, \tau_{i+1}\right) - S_{i+1} = 0,\qquad t = T\tau"),),
)

LGL = Method(
    "lgl", "LGL pseudospectral collocation", "paper 001's LGL nodes",
    "One polynomial of degree N through N+1 Legendre–Gauss–Lobatto nodes for the states and "
    "the controls; the dynamics collocated at every node.",
    nodes=(10, 40, 80), nodes_label="LGL degree", backends=("ipopt",),
    transcription="lgl",
    equations=(("LGL collocation (paper 001, eq. 4)",
                r"\sum_j D_{ij} x_j = \frac{T}{2} f(x_i, u_i),\qquad "
                r"J \approx \frac{T}{2}\sum_i w_i L(x_i, u_i)"),),
)

SCVX = Method(
    "scvx", "Successive convexification (SCvx)", "Mao, Szmuk & Açıkmeşe 2016",
    "The Hermite–Simpson NLP solved as a sequence of convex QPs (Clarabel): constraints "
    "linearised about the last iterate with exact CasADi Jacobians, virtual control and "
    "virtual buffers under an L1 penalty, the Lagrangian's curvature made convex in the "
    "cost, a trust region adapted by the ratio of actual to predicted reduction of the "
    "nonlinear penalised cost.",
    nodes=(5, 30, 200), nodes_label="intervals", backends=("scvx",),
    transcription="scvx",
    equations=(("Convex subproblem about the iterate z_k",
                r"\min_d\ \nabla f^T d + \tfrac12 d^T B_k d + \lambda\lVert\nu\rVert_1,\ "
                r"B_k = \nabla^2 L + \delta I \succeq 0"
                r"\quad g_k + J_k d = \nu,\quad \lVert d\rVert_\infty \le \eta"),
               ("Trust-region ratio on the nonlinear penalised cost",
                r"\rho = \frac{\Phi(z_k) - \Phi(z_k + d)}{\Phi(z_k) - L_k(d)},\quad "
                r"\Phi = f + \lambda\,\lVert\text{violation}(g)\rVert_1"),),
)

GENERAL_METHODS = (HERMITE_SIMPSON, MULTIPLE_SHOOTING, LGL, SCVX)
