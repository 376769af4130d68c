"""Checks of an answer beyond its solver's verdict: a direct method's costate estimate
against an indirect (maximum-principle) solution, active state bounds, too few nodes.

A mission that has an indirect solution stores it in `Solution.references` under two keys:
`PMP_TRAJECTORY` (states and control over time, SI) and `PMP_COSTATES` (costates over time,
named like the states, in the same units as `Solution.costates`), and the agreement as the
quantity `costate_error`: the largest difference of estimate and extremal over the path,
relative to the extremal's range, taken over the costate components that do not vanish.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

from .problem import Method
from .solution import Quantity, Series, Solution

PMP_TRAJECTORY = "maximum principle"
PMP_COSTATES = "maximum principle costates"
COSTATE_ERROR = "costate_error"


def costate_error(estimate: Series, reference: Series) -> float:
    """max_i max_t |lambda_i - lambda_i,ref| / max_t |lambda_i,ref| over the components whose
    reference is not identically zero (the reference interpolated at the estimate's times,
    clipped to the reference's span, by a cubic spline)."""
    t_ref = np.asarray(reference.t, float)
    t = np.clip(np.asarray(estimate.t, float), t_ref[0], t_ref[-1])
    worst = 0.0
    ref_all = np.asarray(reference.values, float)
    size = np.max(np.abs(ref_all))
    for i, name in enumerate(estimate.names):
        ref = reference.column(name)
        scale = float(np.max(np.abs(ref)))
        if scale <= 1e-12 * size:
            continue
        diff = np.asarray(estimate.values)[:, i] - CubicSpline(t_ref, ref)(t)
        worst = max(worst, float(np.max(np.abs(diff))) / scale)
    return worst


def record_costate_error(sol: Solution) -> None:
    """Put the agreement of `sol.costates` with its stored extremal into the quantities."""
    ref = sol.references.get(PMP_COSTATES)
    if sol.costates is None or ref is None:
        return
    sol.quantities[COSTATE_ERROR] = Quantity(
        costate_error(sol.costates, ref), "costates vs maximum principle (relative)", "")


def active_state_bounds(X: np.ndarray, lam_x: np.ndarray, lower: np.ndarray,
                        upper: np.ndarray, scale: np.ndarray, names: tuple[str, ...], *,
                        lam_scale: float) -> list[str]:
    """Names of the states whose bound is active at an interior node: the state on it
    (within 1e-7 of its scale) with a multiplier `lam_x` (rows like X) above 1e-3 of
    `lam_scale` (the largest constraint multiplier). A bound merely touched, like a mass
    that stays at m0 on a coast, carries only the interior-point barrier's small multiplier
    and does not count. Where a bound is active the costates may jump and the unconstrained
    maximum principle does not apply as it stands."""
    inner, lam = X[1:-1], np.abs(lam_x[1:-1])
    tol = 1e-7 * np.asarray(scale, float)
    on = (inner <= np.asarray(lower) + tol) | (inner >= np.asarray(upper) - tol)
    pushing = lam > 1e-3 * lam_scale
    return [names[i] for i in np.flatnonzero(np.any(on & pushing, axis=0))]


def too_few_nodes(method: Method, nodes: int, message: str) -> str:
    """The message of a failed solve on a mesh coarser than the method's default."""
    return (f"too few nodes: no converged solution at {method.nodes_label} = {nodes} (the "
            f"default is {method.nodes[1]}): the mesh is probably too coarse to represent the "
            f"trajectory; raise the {method.nodes_label} ({message})")
