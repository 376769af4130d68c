"""The mission contract: data (params, methods, published numbers) plus one solve call."""

from __future__ import annotations

import threading
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from .problem import Method, Param, Preset, Published, validate_values
from .solution import Quantity, Solution

ProgressCallback = Callable[[int, str], None]


class Infeasible(Exception):
    """The request has no solution (physically or by the model); the message says why."""


class Cancelled(Exception):
    """A newer request or the user stopped the solve."""


class TimeLimit(Exception):
    """The solve ran past its time limit."""


@dataclass
class SolveContext:
    """What a running solve may consult: progress reporting, cancellation and a deadline."""

    progress: ProgressCallback | None = None
    cancel: threading.Event | None = None
    time_limit: float | None = None
    started: float = field(default_factory=time.perf_counter)
    iterations: int = 0

    def report(self, iteration: int, message: str = "") -> None:
        """Record progress; raise `Cancelled`/`TimeLimit` when the solve must stop."""
        self.iterations = iteration
        if self.progress is not None:
            self.progress(iteration, message)
        self.checkpoint()

    def checkpoint(self) -> None:
        if self.cancel is not None and self.cancel.is_set():
            raise Cancelled("cancelled by a newer request")
        if self.time_limit is not None and self.elapsed() > self.time_limit:
            raise TimeLimit(f"stopped at the time limit of {self.time_limit:g} s")

    def should_stop(self) -> bool:
        try:
            self.checkpoint()
        except (Cancelled, TimeLimit):
            return True
        return False

    def remaining(self) -> float | None:
        return None if self.time_limit is None else max(self.time_limit - self.elapsed(), 1e-3)

    def elapsed(self) -> float:
        return time.perf_counter() - self.started


class Mission(ABC):
    """A mission is data plus `solve`; subclasses implement `_solve`.

    Class attributes: `key`, `title`, `summary`, `source` (paper), `params`, `methods`,
    `published`, `presets`, `help` (markdown shown in the explorer).
    """

    key: str
    title: str
    summary: str
    source: str
    help: str = ""
    params: tuple[Param, ...] = ()
    methods: tuple[Method, ...] = ()
    published: tuple[Published, ...] = ()
    presets: tuple[Preset, ...] = ()
    # (caption, LaTeX) pairs for the mission's About panel: the model in the paper's notation.
    equations: tuple[tuple[str, str], ...] = ()

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

    def validate(
        self,
        values: Mapping[str, float] | None,
        method: str | None = None,
        nodes: int | None = None,
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
        if int(n) != n or not lo <= n <= hi:
            raise ValueError(f"{m.nodes_label} = {n} is outside the allowed range [{lo}, {hi}]")
        self.check_values(vals)
        return vals, m, int(n)

    def check_values(self, values: dict[str, float]) -> None:  # noqa: B027 - optional hook
        """Cross-parameter consistency checks; raise `ValueError` with a message."""

    def solve(
        self,
        values: Mapping[str, float] | None = None,
        method: str | None = None,
        nodes: int | None = None,
        *,
        backend: str | None = None,
        warm: Solution | None = None,
        progress: ProgressCallback | None = None,
        cancel: threading.Event | None = None,
        time_limit: float | None = None,
        verify: bool = True,
    ) -> Solution:
        """Solve one request. Bad input raises `ValueError`; everything else returns a
        `Solution` whose `status` and `message` say what happened.

        `verify=False` defers the re-propagation check (`Solution.run_check()`), so a live
        view can draw the new optimum before the high-accuracy integration has run.
        """
        vals, m, n = self.validate(values, method, nodes)
        if backend is not None and m.backends and backend not in m.backends:
            raise ValueError(
                f"method '{m.key}' has no back end '{backend}' (back ends: {', '.join(m.backends)})"
            )
        chosen_backend = backend or (m.backends[0] if m.backends else "")
        ctx = SolveContext(progress=progress, cancel=cancel, time_limit=time_limit)
        if warm is not None and (warm.mission != self.key or warm.method != m.key):
            warm = None
        try:
            sol = self._solve(vals, m, n, chosen_backend, warm, ctx)
        except Infeasible as exc:
            sol = self._empty(vals, m, n, chosen_backend, "infeasible", str(exc))
        except Cancelled as exc:
            sol = self._empty(vals, m, n, chosen_backend, "cancelled", str(exc))
        except TimeLimit as exc:
            sol = self._empty(vals, m, n, chosen_backend, "time-limit", str(exc))
        except Exception as exc:  # noqa: BLE001 - a solver failure must never crash a caller
            sol = self._empty(vals, m, n, chosen_backend, "failed", f"solver failure: {exc}")
        sol.stats["wall_s"] = ctx.elapsed()
        sol.stats.setdefault("iterations", ctx.iterations)
        if verify and sol.has_trajectory:
            sol.run_check()
        return sol

    def _empty(
        self, vals: dict[str, float], m: Method, n: int, backend: str, status: str, message: str
    ) -> Solution:
        return Solution(
            mission=self.key,
            method=m.key,
            nodes=n,
            status=status,
            message=message,
            cost=Quantity(float("nan"), self.cost_label, self.cost_unit),
            values=vals,
            backend=backend,
        )

    cost_label: str = "cost"
    cost_unit: str = ""

    @abstractmethod
    def _solve(
        self,
        values: dict[str, float],
        method: Method,
        nodes: int,
        backend: str,
        warm: Solution | None,
        ctx: SolveContext,
    ) -> Solution:
        """Solve a validated request."""
