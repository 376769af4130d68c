"""`python -m solvers sweep` and `launch-map` through the real command line."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solvers", *args], capture_output=True,
                          text=True, timeout=300)


def test_sweep_solves_every_grid_point_in_worker_processes(tmp_path):
    out = tmp_path / "sweep.json"
    res = _run("sweep", "lunar-landing", "--method", "hermite-simpson", "--grid",
               "thrust=1800,2400", "--grid", "mass0=500,600", "--workers", "2", "--out", str(out))
    assert res.returncode == 0, res.stderr
    rows = json.loads(out.read_text())
    assert len(rows) == 4 and all(r["status"] == "optimal" for r in rows)
    by_point = {(r["values"]["thrust"], r["values"]["mass0"]): r["quantities"]["tf"] for r in rows}
    # Physics, not numbers copied from a run: more thrust or less mass lands sooner.
    assert by_point[(2400, 600)] < by_point[(1800, 600)]
    assert by_point[(1800, 500)] < by_point[(1800, 600)]


def test_sweep_rejects_a_bad_grid_point_before_solving():
    res = _run("sweep", "lunar-landing", "--grid", "thrust=5,2000")
    assert res.returncode == 2
    assert "thrust" in res.stderr and "Traceback" not in res.stderr


def test_launch_map_cli_writes_the_data_file(tmp_path):
    pytest.importorskip("erfa")
    res = _run("launch-map", "--out", str(tmp_path), "--no-png", "--tof", "50", "700", "66")
    assert res.returncode == 0, res.stderr
    data = np.load(tmp_path / "launch_c3.npz")
    c3 = data["c3_km2_s2"]
    assert c3.shape[1] == 66 and np.isfinite(c3).any()
    # Paper 003: C3 <= 20 km^2/s^2 windows exist each year of 2022-2023.
    assert (c3 <= 20).any()
