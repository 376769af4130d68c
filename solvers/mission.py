"""The mission contract: data (params, methods, published numbers, presets) plus one solve
call and one presentation call.

A mission package (`solvers/missions/<key>/`) subclasses `Mission` with its records; methods
with a general `transcription` are solved here from the mission's `OCP` (`ocp`,
`parameter_vector`, and the optional hooks `precheck`, `record`, `terminal_miss`,
`interval_error_norm`, `indirect_reference`), and a paper's own methods by the mission's
`_solve`. `present` turns a numeric `Solution` into what the explorer draws.
"""

from __future__ import annotations

import re
import sys
import threading
from collections.abc import Mapping
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

from . import cost_error, interval_error
from .context import (
    DEFAULT_TIME_LIMIT,
    Cancelled,
    Infeasible,
    ProgressCallback,
    SolveContext,
    TimeLimit,
)
from .continuation import Case, rescue
from .handles import AnyHandle
from .optimality import too_few_nodes
from .presentation import Presentation
from .problem import Consistency, Method, Param, Preset, Published, validate_values
from .problem_module import adopt
from .refine import solve_auto
from .shapes import Shape
from .solution import Label, Quantity, Solution, WarmStart
from .transcription import Transcription, direct_transcription
from .verify import repropagate

if TYPE_CHECKING:
    from .ocp import OCP, OCPResult

class Mission:
    """A mission is data plus `solve` and `present`.

    Class attributes: `key`, `title`, `summary`, `source` (paper), `params` (solve inputs),
    `view_params` (display options: changing one redraws without re-solving), `methods`,
    `published`, `presets`, `equations`, `tolerances` (the accuracy target of each
    re-propagated miss, SI, keyed like `Solution.check`), `consistency` (what its methods must
    agree on), `vehicle` (mesh name), `live_method` (the method a live view opens with;
    None: the first). The help text is the package's `help.md`, `{{name}}` from `help_tables()`.
    """

    key: str
    title: str
    summary: str
    source: str
    params: tuple[Param, ...] = ()
    view_params: tuple[Param, ...] = ()
    methods: tuple[Method, ...] = ()
    live_method: str | None = None  # the fastest whose default is `optimal`, if not the first
    published: tuple[Published, ...] = ()
    presets: tuple[Preset, ...] = ()
    # (caption, LaTeX) pairs for the mission's About panel: the model in the paper's notation.
    equations: tuple[tuple[str, str], ...] = ()
    tolerances: Mapping[str, float] = {}
    cost_rtol: float = 1e-4  # target of the cost error estimate, relative (`cost_error`)
    consistency: tuple[Consistency, ...] = ()
    cost_label: str = "cost"
    cost_unit: str = ""
    vehicle: str = "default"
    # s: the default case's cold solve on a 2-core laptop (bench_missions), for a mission
    # whose first solve is slow by nature; a live session's cold limit allows for it.
    cold_seconds: float = 0.0
    labels: Mapping[str, Label] = {}  # screen names of states, controls and check entries
    handles: tuple[AnyHandle, ...] = ()  # points dragged in the 3D view, bound to params
    shapes: tuple[Shape, ...] = ()  # obstacles and surfaces drawn in the 3D view

    def __init_subclass__(cls, records: ModuleType | None = None, **kwargs: Any) -> None:
        """`class M(Mission, records=problem)` takes the records (`PARAMS` -> `params`, ...)
        and the hooks (`precheck`, `ocp`, ...) the mission's `problem` module defines and the
        class body does not (`solvers.problem_module`)."""
        super().__init_subclass__(**kwargs)
        if records is not None:
            adopt(cls, records)

    # ---- records ------------------------------------------------------------------------
    @property
    def help(self) -> str:
        """Markdown help: the package's help.md with its generated tables filled in."""
        module = sys.modules.get(type(self).__module__)
        path = Path(module.__file__).with_name("help.md") if module and module.__file__ else None
        if path is None or not path.exists():
            return ""
        tables = self.help_tables()
        return re.sub(r"\{\{(\w+)\}\}", lambda m: tables.get(m.group(1), m.group(0)),
                      path.read_text(encoding="utf-8"))

    def help_tables(self) -> dict[str, str]:
        """Markdown fragments generated from code for `{{name}}` in help.md; `published`
        lists the published numbers with their expected agreement."""
        return {"published": published_markdown(self.published)}

    def method(self, key: str | None) -> Method:
        if key is None:
            return self.methods[0]
        for m in self.methods:
            if m.key == key:
                return m
        known = ", ".join(m.key for m in self.methods)
        raise ValueError(f"mission '{self.key}' has no method '{key}' (methods: {known})")

    def all_params(self, method: str | None = None) -> tuple[Param, ...]:
        """Mission params followed by the chosen method's own params."""
        return self.params + self.method(method).params

    def defaults(self, method: str | None = None) -> dict[str, float]:
        return {p.key: p.default for p in self.all_params(method)}

    def view_defaults(self) -> dict[str, float]:
        return {p.key: p.default for p in self.view_params}

    def validate_view(self, view: Mapping[str, float] | None) -> dict[str, float]:
        """Complete and check view options (same rules as solve values)."""
        return validate_values(self.view_params, view)

    def validate(
        self,
        values: Mapping[str, float] | None,
        method: str | None = None,
        nodes: int | str | None = None,
    ) -> tuple[dict[str, float], Method, int]:
        """Complete and check a request; raise `ValueError` naming what is wrong."""
        m = self.method(method)
        # Params of the mission's other methods are accepted and ignored, so one value set
        # can be replayed across methods (comparison, sweeps).
        other = {p.key for meth in self.methods if meth.key != m.key for p in meth.params}
        own = {k: v for k, v in (values or {}).items() if k not in other}
        vals = validate_values(self.all_params(m.key), own)
        lo, default, hi = m.nodes
        n = default if nodes is None else nodes
        if isinstance(n, str):
            raise ValueError(f"{m.nodes_label} must be a whole number or 'auto', not {n!r}")
        if int(n) != n or not lo <= n <= hi:
            raise ValueError(f"{m.nodes_label} = {n} is outside the allowed range [{lo}, {hi}]")
        self.check_values(vals)
        return vals, m, int(n)

    def check_values(self, values: dict[str, float]) -> None:
        """Cross-parameter consistency checks; raise `ValueError` with a message."""

    # ---- solving ------------------------------------------------------------------------
    def accuracy_targets(self, tol: float | None = None) -> dict[str, float]:
        """The re-propagated miss targets (`tolerances`); `tol` replaces the headline (first)
        target, in its unit, and scales the others by the same factor."""
        targets = dict(self.tolerances)
        if tol is None or not targets:
            return targets
        if not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"tol must be a positive number, not {tol}")
        factor = float(tol) / next(iter(targets.values()))
        return {k: v * factor for k, v in targets.items()}

    def solve(
        self,
        values: Mapping[str, float] | None = None,
        method: str | None = None,
        nodes: int | str | None = None,
        *,
        tol: float | None = None,
        backend: str | None = None,
        warm: Solution | None = None,
        cold: bool = False,
        progress: ProgressCallback | None = None,
        cancel: threading.Event | None = None,
        time_limit: float | None = DEFAULT_TIME_LIMIT,
        verify: bool = True,
    ) -> Solution:
        """Solve one request. Bad input raises `ValueError`; everything else returns a
        `Solution` whose `status` and `message` say what happened.

        `nodes="auto"` refines the mesh until the re-propagated miss meets the accuracy
        targets (`solvers.refine`; `tol` sets the headline target, see `accuracy_targets`).
        `warm` is a previous solution to start from (None: the method's initial guess); a
        failure from there is rescued (`solvers.continuation`). `cold=True` ignores `warm`,
        tries no rescue and, with "auto", starts every refinement step from the initial
        guess too (what the initial guess alone does).
        `verify=False` defers the re-propagation check (`Solution.run_check()`), so a live
        view can draw the new optimum before the high-accuracy integration has run (an
        "auto" solve always checks: refinement needs the miss).

        `time_limit` (s; default `DEFAULT_TIME_LIMIT`, None or 0: none) bounds the solve and
        its check together (the check gets what is left). In this process the limit is
        cooperative, consulted between solver iterations and at every integration step;
        for a hard limit solve through `solvers.service` (the CLI and the explorer do): a
        solve still running 1 s past its limit is killed with its worker.
        """
        time_limit = time_limit or None
        if nodes == "auto":
            return solve_auto(self, values, method, tol=tol, backend=backend,
                              warm=None if cold else warm, cold=cold, progress=progress,
                              cancel=cancel, time_limit=time_limit)
        if cold:
            warm = None
        targets = self.accuracy_targets(tol)
        vals, m, n = self.validate(values, method, nodes)
        warm = self._usable_warm(m, backend, warm)
        ctx = SolveContext(progress=progress, cancel=cancel, time_limit=time_limit)
        backend = backend or m.default_backend
        sol = self.solve_validated(vals, m, n, backend, warm, ctx)
        if not cold:  # a failure rescued by continuation or another method's seed
            sol = rescue(Case(self, vals, m, n, backend), warm, sol, ctx)
        return self._finish(sol, m, targets, ctx, verify)

    def _finish(self, sol: Solution, m: Method, targets: dict[str, float],
                ctx: SolveContext, verify: bool) -> Solution:
        """An answer's stats, targets and labels; its cost error estimate attached and its
        check bounded by what is left of the time limit (run now when `verify`)."""
        sol.stats["wall_s"] = ctx.elapsed()
        if ctx.iterations:  # a closed form has no iteration count (not "0 iterations")
            sol.stats.setdefault("iterations", ctx.iterations)
        sol.targets, sol.labels = targets, dict(self.labels)
        # A stand-in's answer (continuation._stand_in) is estimated by its own method.
        cost_error.attach(self, sol, m if sol.method == m.key else self.method(sol.method))
        ctx.bound_check(sol)
        if verify and sol.has_trajectory:
            sol.run_check()
        return sol

    def _usable_warm(self, m: Method, backend: str | None, warm: object) -> Solution | None:
        """Refuse an unknown back end or a warm start that is no `Solution`; a warm start
        of another mission or method is dropped (the method's initial guess is used)."""
        if backend is not None and backend not in m.backends:
            known = ", ".join(m.backends) or "none: this method has no choice of back end"
            raise ValueError(f"method '{m.key}' has no back end '{backend}' (back ends: {known})")
        if warm is not None and not isinstance(warm, Solution):
            raise ValueError(f"a warm start must be a Solution, not {type(warm).__name__}")
        if warm is not None and (warm.mission != self.key or warm.method != m.key):
            return None
        return warm

    def solve_validated(self, vals: dict[str, float], m: Method, n: int, backend: str,
                          warm: Solution | None, ctx: SolveContext) -> Solution:
        """Solve a validated request; an early end becomes a solution without a trajectory
        whose status says which (infeasible, cancelled, time-limit, failed)."""
        try:
            if m.transcription is not None and not self.solves_itself(m):
                return self.solve_direct(vals, m, n, backend, warm, ctx)
            return self._solve(vals, m, n, backend, warm, ctx)
        except Infeasible as exc:
            return self.empty(vals, m, n, backend, "infeasible", str(exc))
        except Cancelled as exc:
            return self.empty(vals, m, n, backend, "cancelled", str(exc))
        except TimeLimit as exc:
            return self.empty(vals, m, n, backend, "time-limit", str(exc))
        except Exception as exc:  # noqa: BLE001 - a solver failure must never crash a caller
            return self.empty(vals, m, n, backend, "failed", f"solver failure: {exc}")

    def empty(
        self, vals: dict[str, float], m: Method, n: int, backend: str, status: str, message: str
    ) -> Solution:
        """A solution without a trajectory: what a failed or refused request returns."""
        return Solution(
            mission=self.key, method=m.key, nodes=n, status=status, message=message,
            cost=Quantity(float("nan"), self.cost_label, self.cost_unit), values=vals,
            backend=backend,
        )

    def solves_itself(self, method: Method) -> bool:
        """Whether the mission's `_solve` handles this general method itself (e.g. a
        two-stage solve); False: `solve_direct` does."""
        return False

    def _solve(
        self, values: dict[str, float], method: Method, nodes: int, backend: str,
        warm: Solution | None, ctx: SolveContext,
    ) -> Solution:
        """Solve a validated request with one of the mission's own methods."""
        raise NotImplementedError(f"{self.key}: method '{method.key}' has no solver")

    # ---- the general direct path ---------------------------------------------------------
    def ocp(self, method: Method, values: dict[str, float]) -> OCP:
        """The optimal control problem the general transcriptions solve."""
        raise NotImplementedError(f"{self.key} has no OCP for the general methods")

    def parameter_vector(self, values: dict[str, float]) -> np.ndarray:
        """The OCP's numeric parameters from validated mission values."""
        raise NotImplementedError

    def precheck(self, values: dict[str, float], p: np.ndarray) -> None:
        """Raise `Infeasible` (naming the bound) for requests that cannot be solved."""

    def record(self, sol: Solution, res: OCPResult, p: np.ndarray) -> None:
        """Fill the mission's quantities (and arcs, units) into a direct method's solution."""

    def terminal_miss(self, p: np.ndarray, x_final: np.ndarray) -> dict[str, float]:
        """The re-propagated miss of each terminal condition, SI, keyed "<name>_<unit>"."""
        return {}

    def interval_error_norm(self, dx: np.ndarray) -> tuple[np.ndarray, str] | None:
        """Each interval's local error (rows of state differences, the OCP's units) in the
        unit of the headline miss, and that unit; None: the mission reports none."""
        return None

    def indirect_reference(self, sol: Solution, p: np.ndarray) -> None:
        """Solve the maximum principle from `sol`'s costates (if the mission has it): the
        extremal into `sol.references`, the agreement into `sol.quantities` (deferred)."""

    def check_atol(self, ocp: OCP) -> np.ndarray:
        """Absolute tolerances of the re-propagation (per state, the OCP's units)."""
        return 1e-11 * np.asarray(ocp.x_scale, float)

    def solve_direct(
        self, values: dict[str, float], method: Method, nodes: int, backend: str,
        warm: Solution | None, ctx: SolveContext,
    ) -> Solution:
        """Solve with a general transcription of `self.ocp(...)` (no mission code); the
        deferred check adds the interval errors and the indirect reference
        (`interval_error.checked`)."""
        p = self.parameter_vector(values)
        self.precheck(values, p)
        problem = self.ocp(method, values)
        transcription = direct_transcription(method.transcription, problem, nodes, backend,
                                             **dict(method.options))
        start = warm.warm if warm is not None and warm.converged else None
        res = self.solve_transcription(transcription, p, start, ctx)
        if res.status != "optimal" and nodes < method.nodes[1]:
            res.message = too_few_nodes(method, nodes, res.message)
        sol = self.direct_solution(values, method, nodes, backend, problem, res)
        self.record(sol, res, p)
        if res.status == "optimal":
            sol.checker = lambda: interval_error.checked(self, sol, problem, p, res)
        elif res.defects is not None:  # where the answer fails: its constraint violation
            interval_error.record_defects(self, sol, *res.defects)
        return sol

    def solve_transcription(self, transcription: Transcription, p: np.ndarray,
                            warm: WarmStart | None, ctx: SolveContext) -> OCPResult:
        """One solve of the built transcription; a mission overrides it to choose the mesh
        (e.g. nodes at the thrust switches of a bang–bang answer)."""
        return transcription.solve(p, warm, ctx)

    def direct_solution(
        self, values: dict[str, float], method: Method, nodes: int, backend: str,
        problem: OCP, res: OCPResult,
    ) -> Solution:
        """The numeric record of a general transcription's result."""
        sol = Solution(
            mission=self.key, method=method.key, nodes=nodes, backend=backend,
            status=res.status, message=res.message,
            cost=Quantity(float(res.cost), self.cost_label, self.cost_unit), values=values,
            state_names=problem.states,
            state_units=problem.state_units or ("",) * problem.nx,
            control_names=problem.controls,
            control_units=problem.control_units or ("",) * problem.nu,
            node_t=res.t_nodes, node_x=res.X, node_u=res.U, arcs=[(0.0, res.T, "burn")],
            t=res.t_dense, x=res.X_dense, u=res.U_dense, history=res.history,
        )
        res.record_nlp(sol)
        return sol

    def check_direct(self, problem: OCP, p: np.ndarray, res: OCPResult) -> dict[str, float]:
        """Re-propagate the method's own control with DOP853 (rtol 1e-10) from the first
        node's state; the terminal miss by `terminal_miss`."""
        _, X = repropagate(problem.functions().f, p, res.X[0], res.control, res.t_nodes,
                           atol=self.check_atol(problem))
        return self.terminal_miss(p, X[-1])

    # ---- presentation -------------------------------------------------------------------
    def present(self, sol: Solution, view: Mapping[str, float] | None = None) -> Presentation:
        """What the explorer draws for `sol` with view options `view` (defaults filled in,
        bad values refused like solve values)."""
        return self._present(sol, self.validate_view(view))

    def _present(self, sol: Solution, view: dict[str, float]) -> Presentation:
        """The mission's view (its view.py); this default draws the first three states."""
        def first3(x: np.ndarray) -> np.ndarray:
            out = np.zeros((len(x), 3))
            k = min(3, x.shape[1]) if x.ndim == 2 else 0
            out[:, :k] = x[:, :k]
            return out

        return Presentation(frame="the first three states", path=first3(sol.x),
                            nodes=first3(sol.node_x), vehicle=sol.mission)


def published_markdown(published: tuple[Published, ...]) -> str:
    """Published numbers as a markdown list, with what holds and what does not."""
    if not published:
        return ""
    lines = ["*Published numbers:*"]
    for pub in published:
        verdict = "" if pub.holds else " — does not hold here"
        lines.append(f"- {pub.name} = {pub.value:.10g} {pub.unit} ({pub.source}){verdict}"
                     + (f": {pub.note}" if pub.note else ""))
    return "\n".join(lines)
