"""`python -m solvers solve` with --nodes auto, --tol, --cold and --multistart; the JSON's
costates, Hamiltonian, mesh, switching function and interval errors (issue 12)."""

from __future__ import annotations

import json
import subprocess
import sys


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solvers", *args], capture_output=True,
                          text=True, timeout=300)


def test_auto_nodes_to_a_tolerance_as_json():
    res = _run("solve", "lunar-landing", "--method", "hermite-simpson", "--nodes", "auto",
               "--tol", "0.001", "--cold", "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["status"] == "optimal" and abs(out["check"]["altitude_m"]) <= 1e-3
    assert out["mesh"]["nodes"] == out["nodes"] and len(out["mesh"]["steps"]) >= 2
    assert set(out["costates"]) == {"t", *out["state_names"]}
    assert set(out["hamiltonian"]) == {"t", "value"}
    assert len(out["interval_error"]["t"]) == out["nodes"]
    assert out["targets"]["altitude_m"] == 1e-3


def test_switching_function_of_a_bang_bang_mission():
    res = _run("solve", "cw-rendezvous", "--method", "hermite-simpson", "--json")
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert len(out["switching_function"]["S"]) == len(out["switching_function"]["t"]) > 0


def test_multistart_and_text_output():
    res = _run("solve", "hovercraft", "--multistart", "2")
    assert res.returncode == 0, res.stderr
    assert "2 cold starts" in res.stdout and "(target" in res.stdout


def test_bad_nodes_and_tol_are_refused_in_one_line():
    for args in (("--nodes", "lots"), ("--nodes", "auto", "--tol", "-1"),
                 ("--multistart", "0")):
        res = _run("solve", "lunar-landing", *args)
        assert res.returncode == 2 and "Traceback" not in res.stderr
        assert len(res.stderr.strip().splitlines()) == 1
