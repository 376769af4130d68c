"""The explorer's solves on a dask.distributed cluster (issue 20: a lecture hall beyond one
machine, `--scheduler`): a session's answer comes from a worker process, its deferred
re-propagation check runs on the worker that holds the answer and reaches the session, a
second solve starts warm, bad input is said in words, and an unreachable scheduler stops
the explorer with a message. The minimum time is Kirk 1970, ex. 5.3-1: T* = 2 sqrt(d / a)."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from test_explorer import Recorder

from solvers import get_mission

distributed = pytest.importorskip("dask.distributed")
PATIENCE = 120.0


@pytest.fixture(scope="module")
def scheduler():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def test_a_session_solves_on_the_cluster_and_hears_the_workers_check(scheduler):
    from explorer.runners import ClusterRunner
    from explorer.session import Session
    from solvers.cluster import connect

    runner = ClusterRunner(connect(scheduler))
    mission = get_mission("bang-bang")
    session = Session(mission, auto=False, runner=runner, time_limit=60.0)
    heard = Recorder()
    session.listeners.append(heard)
    try:
        session.values["distance"] = 4.0
        session.submit()
        assert session.wait_idle(PATIENCE)
        sol = session.latest
        assert sol is not None and sol.status == "optimal", sol and sol.message
        assert sol.cost.value == pytest.approx(2 * math.sqrt(4.0), rel=2e-3)  # Kirk 1970
        assert heard.checks and heard.checks[-1] is sol  # the worker's check reached it
        assert set(mission.tolerances) <= set(sol.check)
        assert sol.cost.error_estimate is not None
        session.values["distance"] = 9.0
        session.submit()
        assert session.wait_idle(PATIENCE)
        warm = session.latest
        assert warm.ok and warm.cost.value == pytest.approx(6.0, rel=2e-3)
        cold = mission.solve({"distance": 9.0})  # here, from the initial guess
        assert warm.stats["iterations"] < cold.stats["iterations"]  # warm from d = 4 m
        session.values["distance"] = 500.0  # outside [0.1, 100] m: refused by the worker
        session.submit()
        assert session.wait_idle(PATIENCE)
        assert heard.errors and "distance" in heard.errors[-1]
        assert session.latest is warm  # the last answer stays
    finally:
        session.close()
        runner.close()


def test_the_explorer_stops_with_a_message_when_the_scheduler_cannot_be_reached():
    done = subprocess.run([sys.executable, "-m", "explorer", "--scheduler", "tcp://127.0.0.1:9",
                           "--port", "0"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "cannot reach the dask scheduler at tcp://127.0.0.1:9" in done.stderr
