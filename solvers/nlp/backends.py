"""Every NLP back end in one registry: what it solves, where it comes from, how to call it.

`kind` says which problems a back end takes:
- "nlp": min f(z, p) s.t. lbg <= g(z, p) <= ubg, lbx <= z <= ubx, given symbolically; called
  through `casadi_nlp.NLP(..., backend=key).solve(...)` (IPOPT, SQP, exterior penalty; FATROP
  where the transcription also gives the problem in stage order, `fatrop.Stages`);
- "equality": min f(z) s.t. h(z) = 0 from numeric value-and-gradient callbacks; called
  through `multiplier_method.solve_multiplier_method` (paper 002);
- "scp": the same NLP by successive convexification (`transcription.scvx.SCvxSolver`);
- "socp": a second-order cone program (a mission's convex formulation, CVXPY + Clarabel);
- "box": min of a vectorised black-box fitness over a box; called through
  `particle_swarm.particle_swarm` (paper 003).
A `Method` lists the keys of the back ends it can use; unknown keys are refused at import.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Backend:
    key: str
    label: str
    kind: str
    source: str
    summary: str
    # Stops soon after it is cancelled or past the time limit (an iteration callback between
    # iterations that each take a bounded time, or bounded steps); a rescue (`continuation`)
    # calls only those.
    stoppable: bool = True


BACKENDS: dict[str, Backend] = {b.key: b for b in (
    Backend("ipopt", "IPOPT (interior point)", "nlp", "Wächter & Biegler 2006, via CasADi",
            "Primal-dual interior point with exact Hessians; warm-started from the previous "
            "optimum's primal and dual values."),
    Backend("sqp", "SQP (CasADi sqpmethod, BFGS Hessian)", "nlp", "CasADi sqpmethod + qrqp",
            "Sequential quadratic programming with a limited-memory BFGS Hessian: the kind of "
            "solver paper 004 used; slower than IPOPT here.",
            # It stops only between iterations, and one QP of a large NLP can run for
            # minutes (a rescue's SQP seed of a 400-segment asteroid case ran 6 min past a
            # 15 s limit): a rescue does not call it.
            stoppable=False),
    Backend("fatrop", "FATROP (structure-exploiting interior point)", "nlp",
            "Vanroye, Sathya, De Schutter & Decré 2023, via CasADi",
            "An interior point method whose linear algebra is a Riccati recursion over the "
            "stages of an optimal control problem; solves a stage-ordered copy of the NLP "
            "(multiple shooting, Hermite–Simpson); warm-started from the previous optimum's "
            "primal values only (CasADi passes it no multipliers).", stoppable=False),
    Backend("penalty-bfgs", "Exterior penalty + BFGS (paper 000, eq. 12)", "nlp", "paper 000",
            "An increasing quadratic penalty on the constraint violations, each subproblem by "
            "BFGS: slow and inexact, which is the lesson."),
    Backend("multiplier-bfgs", "Generalised multiplier method + BFGS (paper 002)", "equality",
            "paper 002", "Augmented Lagrangian with the paper's penalty and multiplier "
            "updates, BFGS inner solver."),
    Backend("scvx", "SCvx (successive convexification, Clarabel QPs)", "scp",
            "Mao, Szmuk & Açıkmeşe 2016; Clarabel (Goulart & Chen 2024)",
            "Convex subproblems about the last iterate with virtual control and a trust "
            "region; called through `transcription.scvx.SCvxSolver`."),
    Backend("clarabel", "Clarabel (interior-point conic solver) via CVXPY", "socp",
            "Goulart & Chen 2024; CVXPY (Diamond & Boyd 2016)",
            "Second-order cone programs compiled once with CVXPY parameters and re-solved "
            "with new data."),
    Backend("pso", "Particle swarm (paper 003)", "box", "paper 003 eqs. 17-21",
            "A swarm with time-varying inertia and learning factors searching a box of "
            "launch dates and flight times."),
)}


def backend(key: str) -> Backend:
    """The registered back end `key`; `ValueError` names the known ones otherwise."""
    if key not in BACKENDS:
        raise ValueError(f"unknown NLP back end '{key}' (back ends: {', '.join(BACKENDS)})")
    return BACKENDS[key]
