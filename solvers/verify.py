"""Independent accuracy check: re-propagate an optimal control with a high-accuracy
integrator (scipy `solve_ivp`, DOP853, rtol 1e-10) and measure the terminal miss.

The NLP's own defects say how well the discrete equations are satisfied; this says how far
the continuous dynamics driven by the method's control really end from the target.
"""

from __future__ import annotations

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


_interrupt: list[Callable[[], bool]] = []


@contextmanager
def interruptible(should_stop: Callable[[], bool]) -> Iterator[None]:
    """Integrations inside the block raise `CheckInterrupted` as soon as `should_stop()`."""
    _interrupt.append(should_stop)
    try:
        yield
    finally:
        _interrupt.pop()


def checkpoint() -> None:
    """Raise `CheckInterrupted` when an enclosing `interruptible` block asks to stop (for
    long checks that integrate outside `integrate_piecewise`)."""
    if _interrupt and _interrupt[-1]():
        raise CheckInterrupted


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
    if _interrupt:
        stop, inner = _interrupt[-1], rhs

        def rhs(t: float, y: np.ndarray) -> np.ndarray:
            if stop():
                raise CheckInterrupted
            return inner(t, y)

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
