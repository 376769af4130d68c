"""A failed solve rescued (issue 17): continuation from the nearest solved case, a method
seeded by another method of the same mission, and a few other initial guesses.

When a solve from the initial guess (or from the previous answer) fails, the request may
still be solvable: the guess was too far. Three ways are tried in turn, each within the
solve's own time limit, and what found the answer is said in its message:

1. Continuation. From a solved case — the previous answer when there is one, then the
   mission's defaults (solved by every method) — every parameter walks in a straight line to
   the request, each step warm-started from the step before. A step that fails is halved, one
   that converges lets the next double, down to `MIN_STEP` of the way and `MAX_SOLVES` warm
   solves at most; choices and whole numbers switch at the first step, and the guess
   parameters (`Param.guess`: they steer the solver, not the problem) stay at the start's.
2. Seeding. A general method (Hermite–Simpson, LGL, multiple shooting: one OCP) starts from
   another general method of the mission that converges from its own guess, its nodes
   re-interpolated, then from a mission's own method answering the same problem (a paper's),
   its dense samples re-interpolated (`samples_guess`: a paper's nodes may lie on another
   independent variable); any method from its own other back ends that stop at the time limit
   (when the chosen back end does not converge even from there, the other's answer is
   shown, said so).
3. A stand-in. A mission's own method (a paper's) that still fails may be unable to
   represent the optimum at all (lunar landing's integral transformation needs the thrust
   to keep braking the orbital rate, d ϖ/dt > 0, which an optimum with ψ reaching 90° does
   not): a general method's answer to the same problem is shown instead, said so (never for
   a method that answers another problem, `Method.other_problem`).
4. Other guesses. A few cold starts with the guess parameters (`Param.guess`) at their
   defaults, then spread over their ranges (`multistart.guess_values`).

When all fail, the answer stays `failed` and says where continuation stalled and the last
case it solved on the way: a case a student can move toward. A rescue cut short by the time
limit, or with a stage that used up its share of it, ends `time-limit` (it was not
exhausted: a longer limit may find the answer).
`infeasible` is left to the missions' named bounds (`Mission.precheck`).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from .context import SolveContext
from .multistart import guess_values
from .nlp.backends import BACKENDS
from .problem import Method
from .solution import Solution, WarmStart, samples_guess
from .solvable import SolvableMission

RESCUED = ("failed", "iteration-limit")  # the statuses a rescue is tried for
MIN_STEP = 1 / 64  # of the way: a walk needing shorter steps has stalled
MAX_SOLVES = 16  # warm solves of one walk at most
RESTARTS = 4  # cold starts from other guesses
NAMED = 3  # parameters named in the message of a stalled walk
CACHED_DEFAULTS = 16  # solved default cases kept (per mission, method, nodes, back end)
_DEFAULTS: OrderedDict[tuple[object, ...], Solution] = OrderedDict()


@dataclass(frozen=True)
class Case:
    """A validated request, as `SolvableMission.solve_validated` takes it."""

    mission: SolvableMission
    values: dict[str, float]
    method: Method
    nodes: int
    backend: str

    def solve(self, values: dict[str, float], warm: Solution | None, ctx: SolveContext,
              nodes: int | None = None) -> Solution:
        return self.mission.solve_validated(values, self.method, nodes or self.nodes,
                                            self.backend, warm, ctx)


@dataclass
class Walk:
    """How far a continuation got: `t` of the way, with the last case solved there."""

    origin: str
    t: float
    solved: Solution
    steps: int = 0
    solves: int = 0


def rescue(request: Case, warm: Solution | None, failed: Solution, ctx: SolveContext
           ) -> Solution:
    """`failed` itself unless its status is one of RESCUED (and the request is another case
    than `warm`'s: a warm start of the same case that fails, such as a refinement step, is
    the walk's last step already); else the request solved by continuation, a seed or
    another guess (its message says which and how the initial guess had failed), or
    `failed` with what was tried. Continuation may spend half of the time left, a seed half
    of what then remains, a stand-in half of the rest (the general methods are quick: a
    paper's own method may take seconds a start), other guesses what is left."""
    if failed.status not in RESCUED or (warm is not None and warm.converged
                                         and warm.values == request.values):
        return failed
    walk, tried = None, []
    stage = _share(ctx, 0.5)
    for origin, start in _starts(request, warm, stage):
        walk = _walk(request, start, origin, stage)
        if walk.t >= 1.0:
            steps = f"{walk.steps} step{'s' if walk.steps != 1 else ''}"
            return _found(request, walk.solved, failed, f"reached by continuation from "
                          f"{walk.origin} in {steps}", continuation_steps=walk.steps)
    cut = stage.should_stop()  # a stage that used up its share was not exhausted
    for finder, share in ((_seeded, 1 / 2), (_stand_in, 1 / 2), (_restarted, 1.0)):
        stage = _share(ctx, share)
        found = None if ctx.should_stop() else finder(request, stage, tried)
        if found is not None:
            return _found(request, found[0], failed, found[1])
        cut = cut or stage.should_stop()
    return _stalled(request, failed, walk, tried, ctx, cut)


def _share(ctx: SolveContext, share: float) -> SolveContext:
    """A context for one stage of the rescue: `share` of the time `ctx` has left (no limit
    when it has none), its progress reports and its cancellation."""
    left = ctx.remaining()
    return SolveContext(progress=ctx.progress, cancel=ctx.cancel,
                        time_limit=None if left is None else share * left)


def _found(request: Case, sol: Solution, failed: Solution, how: str, **stats: float
           ) -> Solution:
    """`sol` as the answer to the request (its values, whatever guess parameters found it):
    its message says how it was found."""
    sol.values = dict(request.values)
    sol.stats.update(stats)
    sol.message += f" — {how} (from the initial guess: {failed.message})"
    return sol


def _starts(request: Case, warm: Solution | None, ctx: SolveContext
            ) -> Iterator[tuple[str, Solution]]:
    """The solved cases a walk may start from: the previous answer, then the defaults."""
    if warm is not None and warm.converged and warm.warm is not None:
        yield "the previous answer", warm
    start = _defaults(request, ctx)
    if start is not None:
        yield "the defaults", start


def _defaults(request: Case, ctx: SolveContext) -> Solution | None:
    """The mission's defaults solved by the method from its initial guess (at the request's
    node count, or at the method's default when that fails), kept for the next rescue."""
    m = request.method
    key = (id(request.mission), request.mission.key, m.key, request.nodes, request.backend)
    if key in _DEFAULTS:
        _DEFAULTS.move_to_end(key)
        return _DEFAULTS[key]
    values, _, _ = request.mission.validate(None, m.key, None)
    for n in dict.fromkeys((request.nodes, m.nodes[1])):
        if ctx.should_stop():
            break
        if n == request.nodes and values == request.values:
            continue  # that very solve is the one that failed
        sol = request.solve(values, None, ctx, nodes=n)
        if sol.converged and sol.warm is not None:
            _DEFAULTS[key] = sol
            if len(_DEFAULTS) > CACHED_DEFAULTS:
                _DEFAULTS.popitem(last=False)
            return sol
    return None


def _between(request: Case, start: dict[str, float], t: float) -> dict[str, float]:
    """The case `t` of the way from `start` to the request: its physical parameters on the
    straight line (choices and whole numbers at the request's value from the first step),
    the guess parameters at `start`'s (they steer the solver, not the problem)."""
    out = dict(request.values)
    for p in request.mission.all_params(request.method.key):
        if p.key not in start:
            continue
        if p.guess:
            out[p.key] = start[p.key]
        elif not (p.options or p.integer) and t < 1.0:
            out[p.key] = start[p.key] + t * (out[p.key] - start[p.key])
    return out


def _walk(request: Case, start: Solution, origin: str, ctx: SolveContext) -> Walk:
    """Walk from `start`'s case to the request, warm-starting each step (see the module)."""
    walk = Walk(origin, 0.0, start)
    step = 1.0
    while walk.solves < MAX_SOLVES and step >= MIN_STEP and not ctx.should_stop():
        t = min(1.0, walk.t + step)
        walk.solves += 1
        sol = request.solve(_between(request, start.values, t), walk.solved, ctx)
        if not sol.converged:
            step /= 2
            continue
        walk.t, walk.solved, walk.steps = t, sol, walk.steps + 1
        if t >= 1.0:
            break
        step *= 2
    return walk


def _seeded(request: Case, ctx: SolveContext, tried: list[str]
            ) -> tuple[Solution, str] | None:
    """The method warm-started from another general method of the mission (same OCP: its
    nodes re-interpolated), from a mission's own method answering the same problem (its
    samples), or from its own other back ends, that converges from its own initial guess;
    None when none does (what was tried goes to `tried`). Another back end of the method
    that does not converge from its own guess walks from the defaults (`_walked`). A back
    end that does not converge even from another's answer leaves that answer, said so."""
    m = request.method
    general = m.transcription is not None
    seeds = [(o, o.default_backend) for o in request.mission.methods
             if general and o.transcription is not None and o.key != m.key]
    # then a mission's own methods that answer the same problem (a paper's), by their samples
    seeds += [(o, o.default_backend) for o in request.mission.methods
              if general and o.transcription is None and not o.other_problem]
    # Only back ends that stop at the time limit: a FATROP seed of a lunar case ran 19 s
    # past a 15 s limit.
    seeds += [(m, b) for b in m.backends if b != request.backend and BACKENDS[b].stoppable]
    for other, backend in seeds:
        if ctx.should_stop():
            return None
        label = other.label if other is not m else f"the {backend} back end"
        try:  # the other method's own parameters at their defaults
            values = request.mission.validate(request.values, other.key)[0]
        except ValueError:
            continue
        tried.append(f"a seed from {label}")
        seed = request.mission.solve_validated(values, other, request.nodes
                                               if other is m else other.nodes[1], backend,
                                               None, ctx)
        how = "converged from its own guess"
        if other is m and not seed.converged:  # that back end's own walk from the defaults
            walked = _walked(replace(request, backend=backend), ctx)
            if walked is not None:
                seed, how = walked, "reached this case by continuation from the defaults"
        if not seed.converged or seed.warm is None:
            continue
        start = replace(seed, method=m.key, warm=seed.warm.primal_only("seed")
                        if other.transcription is not None else _samples(request, seed))
        sol = request.solve(request.values, start, ctx)
        if sol.converged:
            return sol, f"seeded by {label}, which {how}"
        if other is m:
            return seed, (f"the {request.backend} back end did not converge even from the "
                          f"answer of {label}, which is shown")
    return None


def _walked(request: Case, ctx: SolveContext) -> Solution | None:
    """The request reached by continuation from the defaults (solved by the request's back
    end), or None (a hovercraft case: SQP's walk stalls at 34 %, IPOPT's takes one step)."""
    start = _defaults(request, ctx)
    if start is None:
        return None
    walk = _walk(request, start, "the defaults", ctx)
    return walk.solved if walk.t >= 1.0 else None


def _samples(request: Case, seed: Solution) -> WarmStart:
    """Another method's answer as a guess for the request's transcription: its samples,
    with the controls the request's OCP adds (`OCP.controls_from_shown`)."""
    complete = request.mission.ocp(request.method, request.values).controls_from_shown
    return samples_guess(seed, seed.u if complete is None else complete(seed.u))


def _restarted(request: Case, ctx: SolveContext, tried: list[str]
               ) -> tuple[Solution, str] | None:
    """A cold start from another initial guess that converges, or None: the defaults' guess
    parameters, then the guess parameters spread over their ranges; their number goes to
    `tried`."""
    params = request.mission.all_params(request.method.key)
    guesses = [p for p in params if p.guess]
    default = dict(request.values) | {p.key: p.default for p in guesses}
    points = [x for x in [default] + guess_values(params, request.values, RESTARTS + 1)[1:]
              if guesses and x != request.values]
    for count, point in enumerate(points, start=1):
        if ctx.should_stop():
            count -= 1
            break
        sol = request.solve(point, None, ctx)
        if sol.converged:
            used = ", ".join(f"{p.label} {point[p.key]:.4g} {p.unit}".rstrip()
                             for p in guesses)
            return sol, f"found from another initial guess ({used})"
    if points and count:
        tried.append(f"{count} other initial guess{'es' if count > 1 else ''}")
    return None


def _stand_in(request: Case, ctx: SolveContext, tried: list[str]
              ) -> tuple[Solution, str] | None:
    """For a mission's own method that failed: the first general method of the mission
    that converges on the request from its own guess (at its default node count), or None."""
    m = request.method
    if m.transcription is not None or m.other_problem:
        return None
    for other in request.mission.methods:
        if other.transcription is None or ctx.should_stop():
            continue
        tried.append(f"{other.label} as a stand-in")
        sol = request.mission.solve_validated(request.values, other, other.nodes[1],
                                              other.default_backend, None, ctx)
        if sol.converged:
            return sol, (f"{m.label} did not converge on this case, so the answer of "
                         f"{other.label} to the same problem is shown (its method is named "
                         "in the answer)")
    return None


def _stalled(request: Case, failed: Solution, walk: Walk | None, tried: list[str],
             ctx: SolveContext, cut: bool) -> Solution:
    """`failed` with what the rescue tried, and the last case continuation solved;
    `time-limit` when the limit, or a stage's share of it (`cut`), ended a way not yet
    exhausted (on a slower or busier machine the same request may end so)."""
    if ctx.cancel is not None and ctx.cancel.is_set():
        failed.status = "cancelled"  # a newer request took over: the rescue is moot
        return failed
    if walk is None:
        failed.message += (" — no continuation: the defaults do not converge with this "
                           "method either")
    else:
        failed.message += (f" — continuation from {walk.origin} got {100 * walk.t:.0f} % of "
                           "the way and no further" + _last_case(request, walk))
    if tried:
        failed.message += f"; {', '.join(tried)} did not converge either"
    if ctx.should_stop() or cut:  # cut short, not exhausted: the answer is the time limit's
        failed.status = "time-limit"
        how = "stopped at" if ctx.should_stop() else "ran out of its share of"
        failed.message += (f" (the rescue {how} the time limit of {ctx.time_limit:g} s: a "
                           "longer time limit may find it)")
    return failed


def _last_case(request: Case, walk: Walk) -> str:
    """The parameters in which the last case continuation solved differs most from the
    request, as a case to move toward (empty when it solved none)."""
    if walk.t <= 0:
        return ""
    last, values = walk.solved.values, request.values
    params = {p.key: p for p in request.mission.all_params(request.method.key)
              if not p.guess and p.max > p.min and p.key in last}
    moved = sorted((k for k in params if not np.isclose(values[k], last[k])),
                   key=lambda k: -abs(values[k] - last[k]) / (params[k].max - params[k].min))
    named = ", ".join(f"{params[k].label} {last[k]:.4g} {params[k].unit}".rstrip()
                      for k in moved[:NAMED])
    return (f"; it solved the case with {named}: beyond it toward this request the problem "
            "stops being solvable or the steps get too hard, so try values nearer that case")
