"""One browser's state (mission, method, values, view options, last solution) and its
newest-request-wins queue.

The session knows nothing about viser: views subscribe as `SessionListener`s, so one session
can drive one browser tab (the default) or every tab (`--shared`), and tests can drive it
without a browser. Requests are handed to a `Runner` (the solve service's worker processes in
the app) from one thread per session; submitting cancels the running solve and replaces any
request still waiting. A request is one solve of the current state (warm from the last good
solution, or `cold` from the method's initial guess) or a comparison of several methods on
the same values. View options (frame, magnification...) never trigger a solve: the view
redraws from the solution it has.
"""

from __future__ import annotations

import itertools
import traceback
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Protocol

from solvers.mission import Mission
from solvers.problem import Preset
from solvers.request import SolveRequest
from solvers.solution import Solution

from .request_queue import RequestQueue
from .requests import Request
from .runners import LocalRunner, Pending, Runner

__all__ = ["COLD_FACTOR", "DEFAULT_TIME_LIMIT", "Request", "Session", "SessionListener"]

DEFAULT_TIME_LIMIT = 5.0  # s per solve: a slider move never hangs the session
COLD_FACTOR = 3.0  # a cold solve (no warm start of that method: it may also build the NLP)


class SessionListener(Protocol):
    """What a view hears from its session; every call comes from the session's thread,
    except `on_config` and `on_view`, which come from whoever changed the state."""

    def on_config(self, session: Session) -> None:
        """Mission, method or preset changed: rebuild the controls."""

    def on_view(self, session: Session) -> None:
        """A view option changed: redraw the solution on screen (no solve)."""

    def on_submit(self, request: Request) -> None:
        """A request was queued (it supersedes every older one)."""

    def on_progress(self, request: Request, iteration: int, message: str) -> None:
        """The running solve reached `iteration`."""

    def on_result(self, request: Request, solution: Solution) -> None:
        """A solve finished (any status); `session.last_good` is already updated."""

    def on_check(self, request: Request, solution: Solution) -> None:
        """The re-propagation check of the solution just delivered has run."""

    def on_error(self, request: Request, message: str) -> None:
        """The request was rejected (bad input): nothing was solved."""

    def on_compare(self, request: Request, solutions: list[Solution]) -> None:
        """A comparison finished: one solution per method, checks already run."""


class Session:
    """Mission/method/node/value/view state of one view plus a newest-request-wins solver.

    `auto=True` submits a solve after every change (the live explorer); with `auto=False`
    call `submit()` yourself. `last_good` is the newest optimal solution: the warm start of
    the next solve and what the view keeps on screen when a request fails. With `patience`
    > 0 a newer request lets a running solve younger than that finish (it is drawn, so a
    slider drag shows intermediate optima) and only waits for it; older ones are cancelled.
    """

    _ids = itertools.count(1)

    def __init__(self, mission: Mission, *, method: str | None = None,
                 nodes: int | None = None, auto: bool = True,
                 time_limit: float | None = DEFAULT_TIME_LIMIT,
                 runner: Runner | None = None, patience: float = 0.0) -> None:
        self.id = f"session-{next(Session._ids)}"
        self.auto = auto
        self.time_limit = time_limit
        self.runner: Runner = runner or LocalRunner()
        self.listeners: list[SessionListener] = []
        self.last_good: Solution | None = None
        self.latest: Solution | None = None
        self.error: str | None = None
        self.preset: str | None = None
        self._seq = itertools.count(1)
        self._configure(mission, method, nodes, {})
        self.view = mission.view_defaults()
        self._queue = RequestQueue(self._run, patience)

    # ---- configuration ----------------------------------------------------------------
    def _configure(self, mission: Mission, method: str | None, nodes: int | None,
                   values: Mapping[str, float]) -> None:
        m = mission.method(method if method is not None else mission.live_method)
        self.mission = mission
        self.method = m.key
        self.nodes = m.nodes[1] if nodes is None else int(nodes)
        self.backend = m.backends[0] if m.backends else None
        known = mission.defaults(m.key)
        self.values = known | {k: float(v) for k, v in values.items() if k in known}

    def _emit(self, event: str, *args: object) -> None:
        """Call every listener; a failing view is logged and never stops the session."""
        Session._deliver(list(self.listeners), event, args)

    @staticmethod
    def _deliver(listeners: list[object], event: str, args: tuple) -> None:
        for listener in listeners:
            handler = getattr(listener, event, None)
            if handler is None:
                continue
            try:
                handler(*args)
            except Exception:  # noqa: BLE001 - one broken view must not break the session
                traceback.print_exc()

    def _changed(self, config: bool, cold: bool = False) -> None:
        if config:
            self._emit("on_config", self)
        if self.auto:
            self.submit(cold=cold)

    def select_mission(self, mission: Mission) -> None:
        """Switch mission: its live method, default nodes, values and view options."""
        self.preset = None
        self.last_good = self.latest = None
        self._configure(mission, None, None, {})
        self.view = mission.view_defaults()
        self._changed(config=True)

    def select_method(self, key: str) -> None:
        """Switch method, keeping the mission's values (the new method's own params reset)."""
        self.preset = None
        shared = {p.key: self.values[p.key] for p in self.mission.params}
        self._configure(self.mission, key, None, shared)
        self._changed(config=True)

    def apply_preset(self, preset: Preset) -> None:
        """Defaults overridden by the preset's values (and its method, node count and view
        options); a preset about guesses solves cold."""
        self.preset = preset.name
        self._configure(self.mission, preset.method or self.method, preset.nodes,
                        dict(preset.values))
        self.view = self.mission.view_defaults() | {k: float(v) for k, v in preset.view.items()}
        self._changed(config=True, cold=preset.cold)

    def reload_mission(self, mission: Mission) -> None:
        """A new version of the mission on screen (a saved mission file): keep the method,
        nodes, values and view options that still fit, then solve again (the last good
        picture stays until the new answer is in)."""
        method = self.method if any(m.key == self.method for m in mission.methods) else None
        lo, _, hi = mission.method(method).nodes
        nodes = self.nodes if method is not None and lo <= self.nodes <= hi else None
        ranges = {p.key: p for p in mission.all_params(method)}
        kept = {k: v for k, v in self.values.items()
                if k in ranges and ranges[k].min <= v <= ranges[k].max}
        self._configure(mission, method, nodes, kept)
        view_defaults = mission.view_defaults()
        self.view = view_defaults | {k: v for k, v in self.view.items() if k in view_defaults}
        self._changed(config=True)

    def restore(self, mission: Mission, method: str | None, nodes: int | None,
                values: Mapping[str, float], view: Mapping[str, float],
                backend: str | None = None) -> None:
        """Set a whole case at once (a shared link); bad entries raise `ValueError` and
        change nothing."""
        vals, m, n = mission.validate(
            values, method if method is not None else mission.live_method, nodes)
        checked_view = mission.validate_view(view)
        if backend is not None and backend not in m.backends:
            raise ValueError(f"method '{m.key}' has no back end '{backend}'")
        if mission is not self.mission:
            self.last_good = self.latest = None
        self._configure(mission, m.key, n, vals)
        if backend is not None:
            self.backend = backend
        self.view = checked_view
        self.preset = None
        self._changed(config=True)

    def set_value(self, key: str, value: float) -> None:
        """Change one value (SI); an unchanged value is ignored (no re-solve). A parameter of
        the initial guess solves from the initial guess."""
        if key not in self.values:
            raise KeyError(f"'{key}' is not a parameter of {self.mission.key}/{self.method}")
        if self.values[key] == float(value):
            return
        self.values[key] = float(value)
        guess = any(p.key == key and p.guess for p in self.mission.all_params(self.method))
        self._changed(config=False, cold=guess)

    def set_values(self, values: Mapping[str, float]) -> None:
        """Change several values at once (a handle dragged in 3D moves x and y): one solve,
        not one per value; unchanged values are ignored."""
        unknown = sorted(set(values) - set(self.values))
        if unknown:
            raise KeyError(f"{unknown} are not parameters of {self.mission.key}/{self.method}")
        changed = {k: float(v) for k, v in values.items() if self.values[k] != float(v)}
        if not changed:
            return
        self.values.update(changed)
        guess = any(p.key in changed and p.guess for p in self.mission.all_params(self.method))
        self._changed(config=False, cold=guess)

    def set_view(self, key: str, value: float) -> None:
        """Change one view option: listeners redraw, nothing is solved."""
        if key not in self.view:
            raise KeyError(f"'{key}' is not a view option of {self.mission.key}")
        if self.view[key] == float(value):
            return
        self.view = self.mission.validate_view({**self.view, key: float(value)})
        self._emit("on_view", self)

    def set_nodes(self, nodes: int) -> None:
        if self.nodes == int(nodes):
            return
        self.nodes = int(nodes)
        self._changed(config=False)

    def set_backend(self, backend: str) -> None:
        if self.backend == backend:
            return
        self.backend = backend
        self._changed(config=False)

    def set_time_limit(self, seconds: float | None) -> None:
        """Time limit of later solves (None: no limit); the running solve keeps its own."""
        self.time_limit = None if seconds is None or seconds <= 0 else float(seconds)

    # ---- solving ----------------------------------------------------------------------
    def submit(self, cold: bool = False, refine: bool = False, starts: int = 1) -> Request:
        """Queue a solve of the current state (`cold`: from the method's initial guess, not
        from the last good solution; `refine`: with as many nodes as the accuracy targets
        need; `starts` > 1: from several initial guesses, keeping the best); cancels the
        running and waiting ones."""
        return self._request((), cold or starts > 1, refine, starts)

    def compare(self, methods: Sequence[str]) -> Request:
        """Queue a comparison: every method in `methods` on the current values (the current
        method with the current node count, the others with their default), each from its
        initial guess; cancels the running and waiting requests like `submit`."""
        pairs = tuple((key, self.nodes if key == self.method else self.mission.method(key).nodes[1])
                      for key in methods)
        if not pairs:
            raise ValueError("choose at least one method to compare")
        return self._request(pairs, cold=True)

    def check_from_cold(self) -> Request:
        """Solve the current case again from the initial guess, as a comparison of one, so
        the view can set it beside the answer on screen (does the answer depend on the
        path that led to it?)."""
        return self._request(((self.method, self.nodes),), cold=True)

    def request_time_limit(self, compare: bool = False, cold: bool = False) -> float | None:
        """The limit of the next solve: `time_limit`, times `COLD_FACTOR` when it cannot be
        warm-started (first solve of this mission and method, a cold solve or a
        comparison), and then never below `COLD_FACTOR` times the mission's stated cold time
        (`Mission.cold_seconds`: the asteroid's first solve takes 10 s by nature, and a
        limit made for slider moves must not cut it off)."""
        good = self.last_good
        warm = (good is not None and good.mission == self.mission.key
                and good.method == self.method and good.converged)
        if self.time_limit is None or (warm and not compare and not cold):
            return self.time_limit
        return COLD_FACTOR * max(self.time_limit, self.mission.cold_seconds)

    def case(self) -> SolveRequest:
        """The current state as the record a runner solves."""
        return SolveRequest(self.mission.key, self.method, self.nodes, self.backend,
                            dict(self.values), self.time_limit)

    def _request(self, compare: tuple[tuple[str, int], ...], cold: bool, refine: bool = False,
               starts: int = 1) -> Request:
        limit = self.request_time_limit(bool(compare), cold)
        if limit is not None and (refine or starts > 1):
            limit *= max(starts, 1) * (COLD_FACTOR if refine else 1.0)
        solve = replace(self.case(), nodes="auto" if refine else self.nodes, time_limit=limit,
                        cold=cold, starts=starts)
        methods = tuple(replace(solve, method=key, nodes=nodes,
                                backend=self.backend if key == self.method else None)
                        for key, nodes in compare)
        request = Request(next(self._seq), self.mission, solve, methods)
        self._queue.put(request)
        self._emit("on_submit", request)
        return request

    @property
    def busy(self) -> bool:
        return self._queue.busy

    def wait_idle(self, timeout: float | None = None) -> bool:
        """Block until the newest request has been delivered (result, check or error)."""
        return self._queue.wait_idle(timeout)

    def close(self) -> None:
        """Stop the session's thread (cancelling any solve); the session cannot be used
        afterwards. Listeners and solutions are dropped so a closed tab frees its memory."""
        self._queue.close()
        self.listeners.clear()
        self.last_good = self.latest = None

    def _stale(self, request: Request) -> bool:
        return self._queue.stale(request)

    def _start(self, request: Request, solve: SolveRequest, warm: Solution | None,
               label: str = "") -> Pending:
        def progress(iteration: int, message: str) -> None:
            if not self._stale(request):
                self._emit("on_progress", request, iteration, label or message)

        return self.runner.start(request.mission, solve, warm=warm, session=self.id,
                                 cancel=request.cancel, progress=progress)

    def _run(self, request: Request) -> None:
        if request.compare:
            self._run_compare(request)
            return
        warm = None if request.solve.cold else self.last_good
        pending = self._start(request, request.solve, warm)
        sol = self._answer(request, pending)
        if sol is None:
            return
        if self._stale(request):
            pending.cancel()
            return
        self.error = None
        self.latest = sol
        if sol.converged:
            self.last_good = sol
            if request.refine:
                self.nodes = sol.nodes  # the mesh the refinement settled on
        self._emit("on_result", request, sol)
        request.answered.set()  # from now a newer request cancels this one's check at once
        if not (sol.converged and sol.has_trajectory) or self._stale(request) \
                or request.superseded.is_set():  # a newer one came in before
            pending.discard()
            return
        pending.check()
        if not self._stale(request):
            self._emit("on_check", request, sol)

    def _answer(self, request: Request, pending: Pending) -> Solution | None:
        """The solve's answer; None after bad input, which is said (unless a newer request
        already replaced this one)."""
        try:
            return pending.result()
        except ValueError as exc:
            if not self._stale(request):
                self.error = str(exc)
                self._emit("on_error", request, str(exc))
            return None

    def _run_compare(self, request: Request) -> None:
        """Start every method of the comparison (in parallel where the runner can), then
        collect the answers and their checks."""
        pendings = []
        for solve in request.compare:
            pendings.append((solve.method, self._start(request, solve, None,
                                                       label=f"comparing: {solve.method}")))
        solutions = []
        for _key, pending in pendings:
            sol = self._answer(request, pending)
            if sol is None or self._stale(request):
                return
            solutions.append((sol, pending))
        for sol, pending in solutions:
            if sol.converged and sol.has_trajectory and not self._stale(request):
                pending.check()
        if not self._stale(request):
            self._emit("on_compare", request, [sol for sol, _ in solutions])
