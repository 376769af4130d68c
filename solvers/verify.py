"""Independent accuracy check: re-propagate an optimal control with a high-accuracy
integrator (scipy `solve_ivp`, DOP853, rtol 1e-10) and measure the terminal miss.

The NLP's own defects say how well the discrete equations are satisfied; this says how far
the continuous dynamics driven by the method's control really end from the target.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import cache

import casadi as ca
import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-10

Control = Callable[[float, np.ndarray], np.ndarray]


class CheckInterrupted(BaseException):
    """A waiting solve pre-empts the running check (the solve service runs it again later).
    A BaseException, so a check's own error handling does not swallow it."""


class CheckTimeLimit(Exception):
    """The check ran out of its time budget (what its solve's time limit left for it)."""


_interrupt: list[Callable[[], bool]] = []
_deadlines: list[float] = []  # time.monotonic() by which the enclosing checks must stop


@contextmanager
def interruptible(should_stop: Callable[[], bool]) -> Iterator[None]:
    """Integrations inside the block raise `CheckInterrupted` as soon as `should_stop()`."""
    _interrupt.append(should_stop)
    try:
        yield
    finally:
        _interrupt.pop()


@contextmanager
def time_budget(seconds: float | None) -> Iterator[None]:
    """Integrations inside the block raise `CheckTimeLimit` once `seconds` have passed
    (None: no budget; nested budgets: the earliest deadline holds)."""
    if seconds is None:
        yield
        return
    _deadlines.append(time.monotonic() + max(float(seconds), 0.0))
    try:
        yield
    finally:
        _deadlines.pop()


def remaining_budget() -> float | None:
    """Seconds left of the enclosing `time_budget` blocks (None: no budget)."""
    return max(min(_deadlines) - time.monotonic(), 1e-3) if _deadlines else None


def stop_requested() -> bool:
    """An enclosing `interruptible` block asks to stop."""
    return bool(_interrupt) and _interrupt[-1]()


def checkpoint() -> None:
    """Raise `CheckInterrupted` when an enclosing `interruptible` block asks to stop, and
    `CheckTimeLimit` when an enclosing `time_budget` has run out (called by every
    integration's right-hand side, and by long checks between their own steps)."""
    if _interrupt and _interrupt[-1]():
        raise CheckInterrupted
    if _deadlines and time.monotonic() > min(_deadlines):
        raise CheckTimeLimit("the check stopped at the time limit")


def bounded(rhs: Callable[..., np.ndarray]) -> Callable[..., np.ndarray]:
    """`rhs` calling `checkpoint()` first, when a check is interruptible or has a budget
    (a check integrates through Python right-hand sides, so this bounds it finely)."""
    if not (_interrupt or _deadlines):
        return rhs

    def checked_rhs(*args: object) -> np.ndarray:
        checkpoint()
        return rhs(*args)

    return checked_rhs


@cache
def _flat(f: ca.Function) -> ca.Function:
    """f(x, u, p) as a function of one stacked vector: a third of the call overhead."""
    args = [ca.SX.sym(f.name_in(i), f.size1_in(i)) for i in range(f.n_in())]
    return ca.Function(f"{f.name()}_flat", [ca.vertcat(*args)], [f(*args)])


def repropagate(
    f: ca.Function,
    p: np.ndarray,
    x0: np.ndarray,
    control: Control,
    breakpoints: np.ndarray,
    atol: np.ndarray | float = 1e-12,
    samples_per_piece: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Integrate x' = f(x, control(t, x), p) from breakpoints[0] to breakpoints[-1].

    The integration restarts at every breakpoint (node times, where a piecewise control has
    kinks) so the step control never straddles a kink. Returns (t, X): the breakpoints and
    the states there, or denser samples when `samples_per_piece` > 0.
    """
    p = np.asarray(p, float)
    flat = _flat(f)

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        return np.asarray(flat.call([np.concatenate([x, control(t, x), p])])[0]).ravel()

    return integrate_piecewise(rhs, x0, breakpoints, RTOL, atol, samples_per_piece)


def integrate_piecewise(
    rhs: Callable[[float, np.ndarray], np.ndarray],
    y0: np.ndarray,
    breakpoints: np.ndarray,
    rtol: float,
    atol: np.ndarray | float,
    samples_per_piece: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """DOP853 from breakpoints[0] to breakpoints[-1], restarted at every breakpoint (where a
    piecewise control has kinks, so no step straddles one). Returns (t, Y) at the
    breakpoints, or `samples_per_piece` more samples inside each piece."""
    rhs = bounded(rhs)
    ts, ys = [float(breakpoints[0])], [np.asarray(y0, float)]
    y = np.asarray(y0, float)
    for t0, t1 in zip(breakpoints[:-1], breakpoints[1:], strict=True):
        if t1 - t0 <= 1e-12 * max(1.0, abs(t1)):  # empty, or a round-off sliver
            continue
        t_eval = np.linspace(t0, t1, samples_per_piece + 2)[1:] if samples_per_piece else [t1]
        sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval)
        if not sol.success:
            raise RuntimeError(f"propagation failed on [{t0:.6g}, {t1:.6g}] s: {sol.message}")
        ts.extend(sol.t)
        ys.extend(sol.y.T)
        y = sol.y[:, -1]
    return np.asarray(ts), np.vstack(ys)
