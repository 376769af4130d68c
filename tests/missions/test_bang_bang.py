"""The toy mission `bang-bang`, added as one folder with no edit elsewhere: it appears in
the CLI and the explorer, and every general method reaches the analytic optimum
T* = 2 sqrt(d/a) (Kirk 1970, ex. 5.3-1), more closely as the mesh is refined."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import solvers

MISSION = solvers.get_mission("bang-bang")


def test_it_is_listed_by_the_cli_and_the_registry():
    """(The explorer draws it too: tests/explorer/test_browser.py captures every mission.)"""
    out = subprocess.run([sys.executable, "-m", "solvers", "list"], capture_output=True,
                         text=True, check=True)
    assert any(line.startswith("bang-bang ") for line in out.stdout.splitlines())
    assert MISSION in solvers.list_missions()


@pytest.mark.parametrize("method", [m.key for m in MISSION.methods])
def test_the_error_in_time_falls_with_the_mesh(method):
    lo, default, _ = MISSION.method(method).nodes
    coarse = MISSION.solve(method=method, nodes=max(lo, default // 4))
    fine = MISSION.solve(method=method, nodes=default)
    # Converged; a coarse mesh is "inaccurate" by its cost error estimate (issue 17).
    assert coarse.converged and fine.converged
    assert abs(fine.quantities["T_error"].value) < abs(coarse.quantities["T_error"].value)
    assert fine.quantities["T_analytic"].value == pytest.approx(2.0, abs=1e-15)


def test_the_control_is_bang_bang_with_one_switch_at_half_time(solved):
    sol = solved("bang-bang", "hermite-simpson")
    u, t = sol.node_u[:, 0], sol.node_t
    early, late = u[t < 0.45 * t[-1]], u[t > 0.55 * t[-1]]
    assert np.allclose(early, 1.0, atol=1e-6) and np.allclose(late, -1.0, atol=1e-6)
