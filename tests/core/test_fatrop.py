"""FATROP (issue 17): the stage-ordered copy of a transcription's NLP has the same optimum,
and its multipliers map back onto the original constraints; what has no stage order is
refused by name."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from core_ocps import double_integrator

import solvers
from solvers.context import Cancelled, SolveContext
from solvers.nlp.backends import backend
from solvers.transcription import HermiteSimpson, LGLPseudospectral, MultipleShooting


def test_fatrop_is_a_registered_nlp_back_end():
    assert backend("fatrop").kind == "nlp"


@pytest.mark.parametrize("cls", [HermiteSimpson, MultipleShooting])
def test_min_energy_analytic_optimum(cls):
    res = cls(double_integrator(), 10, "fatrop").solve(np.zeros(1))
    assert res.status == "optimal", res.message
    assert res.cost == pytest.approx(6.0, rel=1e-8)
    assert np.allclose(res.U[:, 0], 6 - 12 * res.t_nodes, atol=1e-6)


@pytest.mark.parametrize(("cls", "options"), [(HermiteSimpson, {}),
                                              (HermiteSimpson, {"midpoint_path": 1}),
                                              (HermiteSimpson, {"variable_mesh": 1}),
                                              (MultipleShooting, {})])
def test_active_path_bound_and_multipliers_match_ipopt(cls, options):
    """The speed bound binds mid-way: the path rows (and, for Hermite–Simpson with
    `midpoint_path`, the midpoint rows) come back in the original order, so every
    multiplier and the costates equal IPOPT's on the same NLP. FATROP keeps its relaxation
    of inequality bounds (1e-8, relative): the bound holds to 1.2e-8 where IPOPT's holds to
    1e-9, and the cost (multipliers 19 in all) is 2e-7 lower."""
    ocp = double_integrator(v_max=1.2)
    ipopt = cls(ocp, 12, "ipopt", **options).solve(np.zeros(1))
    fatrop = cls(ocp, 12, "fatrop", **options).solve(np.zeros(1))
    assert ipopt.status == fatrop.status == "optimal", fatrop.message
    assert fatrop.cost > 6.0 + 1e-3  # the bound costs something: it is active
    assert fatrop.max_violation < 2e-8
    assert fatrop.cost == pytest.approx(ipopt.cost, rel=1e-7)
    np.testing.assert_allclose(fatrop.X, ipopt.X, atol=1e-7)
    scale = np.max(np.abs(ipopt.warm.lam_g))
    np.testing.assert_allclose(fatrop.warm.lam_g, ipopt.warm.lam_g, atol=1e-6 * scale)
    np.testing.assert_allclose(fatrop.costates.values, ipopt.costates.values,
                               atol=1e-6 * np.max(np.abs(ipopt.costates.values)))


@pytest.mark.parametrize("cls", [HermiteSimpson, MultipleShooting])
def test_min_time_and_warm_restart(cls):
    """Free final time (copied into every stage) and active control bounds; a warm
    re-solve from the optimum takes a few iterations and returns it."""
    ocp = double_integrator(min_time=True)
    ipopt = cls(ocp, 20, "ipopt").solve(np.zeros(1))
    res = cls(ocp, 20, "fatrop").solve(np.zeros(1))
    assert res.status == "optimal", res.message
    assert res.T == pytest.approx(ipopt.T, rel=1e-8)
    again = cls(ocp, 20, "fatrop").solve(np.zeros(1), warm=res.warm)
    assert again.status == "optimal" and again.iterations <= 5
    assert again.T == pytest.approx(res.T, rel=1e-9)


def test_a_method_without_stage_structure_is_refused():
    with pytest.raises(ValueError, match="'fatrop' needs the NLP in stage order"):
        LGLPseudospectral(double_integrator(), 10, "fatrop")


def test_boundary_conditions_coupling_the_ends_are_refused():
    ocp = double_integrator(boundary=True)
    assert HermiteSimpson(ocp, 10, "ipopt").solve(np.zeros(1)).cost == pytest.approx(6.0)
    with pytest.raises(ValueError, match="boundary conditions tie the first node to the last"):
        HermiteSimpson(ocp, 10, "fatrop")


@pytest.mark.parametrize(("mission", "method"), [("lunar-landing", "paper"),
                                                 ("hovercraft", "multiple-shooting"),
                                                 ("apollo-reentry", "lgl")])
def test_a_method_that_does_not_offer_fatrop_refuses_it(mission, method):
    with pytest.raises(ValueError, match=f"method '{method}' has no back end 'fatrop'"):
        solvers.get_mission(mission).solve(method=method, backend="fatrop")


def test_a_cancelled_request_does_not_start_fatrop():
    """FATROP calls back no iterate, so a stop is checked before it starts (and after)."""
    event = threading.Event()
    event.set()
    with pytest.raises(Cancelled):
        HermiteSimpson(double_integrator(), 10, "fatrop").solve(
            np.zeros(1), ctx=SolveContext(cancel=event))
