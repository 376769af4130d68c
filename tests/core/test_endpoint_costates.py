"""Costates at t0 and tf for every general method (issue 17), where a textbook states them:
Hermite–Simpson's come from the closure (transversality) conditions, the others' nodes
include both ends; units in the JSON."""

from __future__ import annotations

import numpy as np
import pytest

from solvers.optimality import PMP_COSTATES


@pytest.mark.parametrize("method", ["hermite-simpson", "multiple-shooting", "lgl"])
def test_bang_bang_end_costates_are_the_analytic_ones(solved, method: str) -> None:
    """Minimum time x'' = a u, |u| <= 1, rest to rest over d (Bryson & Ho 1975, sec. 7.3):
    H = 1 + lambda_x v + lambda_v a u = 0 with v = 0 and u = +1 at t0, -1 at tf gives
    lambda_v(t0) = -1/a, lambda_v(tf) = 1/a and, lambda_v being linear,
    lambda_x = -2/(a T)."""
    sol = solved("bang-bang", method, None, {})
    a, T = sol.values["accel"], 2.0 * np.sqrt(sol.values["distance"] / sol.values["accel"])
    lam = sol.costates
    assert lam.t[0] == 0.0 and lam.t[-1] == pytest.approx(sol.cost.value, rel=1e-12)
    rtol = 5e-3  # LGL's 40 nodes resolve the switch to 1e-3 in T (measured)
    assert lam.column("v")[0] == pytest.approx(-1.0 / a, rel=rtol)
    assert lam.column("v")[-1] == pytest.approx(1.0 / a, rel=rtol)
    assert lam.column("x")[[0, -1]] == pytest.approx(-2.0 / (a * T), rel=rtol)
    units = sol.to_dict()["costates_units"]
    assert units == {"x": "s/m", "v": "s/(m/s)"}


@pytest.mark.parametrize("method", ["hermite-simpson", "multiple-shooting"])
def test_lunar_end_costates_match_the_pontryagin_extremal(solved, method: str) -> None:
    """Paper 002's indirect solution (`lunar_landing/pmp.py`), shot from the estimate: the
    estimate's first and last values are its values at t0 and tf."""
    sol = solved("lunar-landing", method, None, {})
    lam, ref = sol.costates, sol.references[PMP_COSTATES]
    assert lam.t[0] == 0.0 and lam.t[-1] == pytest.approx(ref.t[-1], rel=1e-6)
    for name in lam.names:
        scale = np.max(np.abs(ref.column(name))) or 1.0
        for end in (0, -1):
            assert abs(lam.column(name)[end] - ref.column(name)[end]) <= 1e-4 * scale, name
    assert sol.to_dict()["costates_units"]["m"] == "kg/kg"
