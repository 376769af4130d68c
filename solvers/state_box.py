"""Does the trajectory the method's control really flies stay inside the state box?

A direct method enforces state bounds at its nodes only. Between nodes the path its own
control produces (each interval integrated from its node state, `interval_error.local_paths`)
may leave the box: a coarse Hermite–Simpson answer whose speed must stay >= 0 can dip below
zero between nodes while every node sits on the bound. That answer is a mesh artefact, not a
trajectory that obeys the problem, so it must not be called `optimal`.

The excursion of state i is measured against the tolerance `BOX_RTOL` x its NLP scale; the
check entry `KEY` is the worst excursion in units of that tolerance (target 1), and the
statistics name the state, the time, the value and the bound (`reason` words them).
"""

from __future__ import annotations

import numpy as np

from .solution import Label, Solution

KEY = "state_box_excursion"
# Tolerance of a state's excursion beyond its bound, relative to its NLP scale: far below
# anything visible, far above the DOP853 re-propagation's error (rtol 1e-10).
BOX_RTOL = 1e-3


def check(sol: Solution, t: np.ndarray, paths: np.ndarray, lb: np.ndarray, ub: np.ndarray,
          scale: np.ndarray, names: tuple[str, ...], units: tuple[str, ...]) -> dict[str, float]:
    """The check entry for the sampled paths (`t`: (m,) times, `paths`: (m, nx) states, in
    the OCP's units); its target and label, and the worst excursion in words, into `sol`."""
    lb, ub = np.asarray(lb, float), np.asarray(ub, float)
    tol = BOX_RTOL * np.abs(np.asarray(scale, float)) * np.ones(paths.shape[1])
    below = np.where(np.isfinite(lb), lb - paths, -np.inf)
    above = np.where(np.isfinite(ub), paths - ub, -np.inf)
    excess = np.maximum(below, above) / tol
    k, i = np.unravel_index(int(np.argmax(excess)), excess.shape)
    worst = float(max(excess[k, i], 0.0))
    sol.targets[KEY] = 1.0
    sol.labels[KEY] = Label("state box excursion between nodes (× tolerance)", "")
    if worst > 0.0:
        bound = lb[i] if below[k, i] >= above[k, i] else ub[i]
        unit = f" {units[i]}" if i < len(units) and units[i] else ""
        sol.reasons[KEY] = (
            f"between nodes the path its control flies leaves the state box ({names[i]} "
            f"reaches {paths[k, i]:.4g}{unit} at t = {t[k]:.4g}, its bound is {bound:.4g}{unit}):"
            " the mesh is too coarse where a bound is active")
    return {KEY: worst}
