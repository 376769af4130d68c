"""The solve service: solves in worker processes, warm starts across the pipe, hard time
limits, crash recovery, isolation between sessions, and the CLI's Ctrl-C.

Published numbers come from the mission records (`Mission.published`, from the papers)."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

import solvers
from solvers.request import SolveRequest
from solvers.service import SolveService


@pytest.fixture(scope="module")
def service():
    svc = SolveService(2, prebuild=False, test_hooks=True)
    assert svc.wait_ready(60.0)
    yield svc
    svc.close()


def _until(condition, seconds: float) -> None:
    """Poll `condition` until it holds; fail after `seconds`."""
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.005)


def _published_ok(sol) -> None:
    mission = solvers.get_mission(sol.mission)
    checked = [p for p in mission.published
               if p.holds and p.checked and p.case is None
               and (not p.methods or sol.method in p.methods)]
    assert checked, sol.mission
    for pub in checked:
        assert pub.agrees(sol.value(pub.name)), (sol.mission, pub.name, sol.value(pub.name))


def test_a_solve_runs_in_a_worker_and_its_check_follows(service):
    job = service.submit(SolveRequest("lunar-landing", "hermite-simpson"), session="a")
    sol = job.result(60.0)
    assert sol.ok and job.worker is not None
    assert service.pids()[job.worker] != os.getpid()
    assert job.check(60.0) and abs(sol.check["altitude_m"]) < 0.1  # filled in afterwards
    _published_ok(sol)
    # A warm re-solve crosses the pipe with its warm start: a few iterations only.
    warm = service.submit(SolveRequest("lunar-landing", "hermite-simpson",
                                       values={"thrust": 2020.0}), session="a", warm=sol)
    again = warm.result(60.0)
    assert again.ok and again.stats["iterations"] < sol.stats["iterations"]
    assert warm.worker == job.worker  # the session stuck to its worker


def test_a_sessions_warm_start_stays_in_its_worker(service, monkeypatch):
    """Issue 18: the warm start made a round trip (worker -> server -> the same worker). Now
    the worker keeps its session's newest converged answer and the service sends its id;
    a warm start the worker does not hold (another session's answer, as when the room puts a
    student's case on the projector) still crosses whole, and both are used."""
    from solvers.service import processes

    sent: list[tuple] = []
    send = processes.WorkerHandle.send
    monkeypatch.setattr(processes.WorkerHandle, "send",
                        lambda w, msg: (sent.append(msg), send(w, msg)))
    first = service.submit(SolveRequest("lunar-landing", "hermite-simpson"), session="keep")
    sol = first.result(60.0)
    assert sol.ok and first.check(60.0)
    cold_iterations = sol.stats["iterations"]
    again = service.submit(SolveRequest("lunar-landing", "hermite-simpson",
                                        values={"thrust": 2020.0}), session="keep", warm=sol)
    assert again.result(60.0).ok and again.worker == first.worker
    solves = [m for m in sent if m[0] == "solve"]
    assert solves[-1][4] == first.id  # the id only: the worker holds the solution
    assert again.solution.stats["iterations"] < cold_iterations  # and it was used
    other = service.submit(SolveRequest("lunar-landing", "hermite-simpson",
                                        values={"thrust": 2030.0}), session="projector",
                           warm=sol)
    assert other.result(60.0).ok
    crossed = [m for m in sent if m[0] == "solve"][-1][4]
    assert crossed is not None and not isinstance(crossed, int) and crossed.history == []
    assert other.solution.stats["iterations"] < cold_iterations
    service.forget("keep")
    assert any(m == ("forget", "keep") for m in sent)


def test_bad_input_is_a_value_error_not_a_crash(service):
    job = service.submit(SolveRequest("lunar-landing", values={"thrust": -5.0}))
    with pytest.raises(ValueError, match="thrust"):
        job.result(60.0)


def test_three_sessions_on_different_missions_at_once_get_published_optima(service):
    requests = [SolveRequest("lunar-landing", "hermite-simpson"),
                SolveRequest("cw-rendezvous", "paper"),
                SolveRequest("elliptic-transfer", "seq-law")]
    jobs = [service.submit(r, session=f"s{i}") for i, r in enumerate(requests)]
    for job in jobs:
        sol = job.result(120.0)
        assert sol.ok, sol.message
        assert job.check(120.0)  # some published numbers are re-propagated misses
        _published_ok(sol)


def _both_workers_solved(service, request, sessions=("warm-1", "warm-2")):
    """One solve on each worker at once (a replacement worker imports the missions and
    builds the NLP first: seconds on a loaded machine), with its check; the two jobs. The
    mission is loaded here too: the service answers a killed solve from its records."""
    solvers.get_mission(request.mission)
    assert service.wait_ready(60.0)
    jobs = [service.submit(request, session=s) for s in sessions]
    for job in jobs:
        assert job.result(120.0).ok and job.check(120.0)
    assert jobs[0].worker != jobs[1].worker
    return jobs


@pytest.mark.parametrize("hook", ["hang", "stop"])
def test_a_solve_stuck_in_native_code_is_stopped_and_others_go_on(service, hook):
    """`hang` sleeps in C inside the worker; `stop` freezes the whole worker (SIGSTOP): the
    service kills it at the time limit plus the grace and starts a new one."""
    _both_workers_solved(service, SolveRequest("lunar-landing", "hermite-simpson"))
    restarts = service.restarts
    started = time.monotonic()
    stuck = service.submit(SolveRequest("lunar-landing", "hermite-simpson", time_limit=1.0),
                           session="stuck", test_hook=hook)
    time.sleep(0.2)
    other = service.submit(SolveRequest("lunar-landing", "hermite-simpson",
                                     values={"thrust": 2100.0}), session="other")
    sol = other.result(30.0)
    assert sol.ok and time.monotonic() - started < 5.0  # the other session did not wait
    answer = stuck.result(30.0)
    elapsed = time.monotonic() - started
    assert answer.status == "time-limit" and "raise the time limit" in answer.message
    assert elapsed < 1.0 + 2.0
    deadline = time.monotonic() + 30.0
    while service.restarts == restarts:
        assert time.monotonic() < deadline, "no replacement worker"
        time.sleep(0.05)
    assert service.submit(SolveRequest("hovercraft")).result(60.0).ok  # the next one solves


def test_the_time_limit_runs_from_the_solves_start_not_from_its_hand_over(service):
    """A worker still in a start-up build (native: it cannot stop mid-way) when a solve
    arrives: the solve's time limit counts from when it begins (an Apollo first solve after
    a mission switch was stopped at 15 s, having spent most of them waiting for a build)."""
    _both_workers_solved(service, SolveRequest("lunar-landing", "hermite-simpson"))
    job = service.submit(SolveRequest("lunar-landing", "hermite-simpson", time_limit=30.0),
                         session="late", test_hook="busy")
    _until(lambda: job.started is not None, 10.0)
    handed_over = job.started
    sol = job.result(60.0)
    assert sol.ok, sol.message
    assert job.started - handed_over >= 0.9  # the busy second is not counted


def test_a_worker_killed_mid_solve_is_reported_and_replaced(service):
    job = service.submit(SolveRequest("lunar-landing", "hermite-simpson", time_limit=60.0),
                         session="victim", test_hook="hang")
    _until(lambda: job.worker is not None, 10.0)
    time.sleep(0.3)
    os.kill(service.pids()[job.worker], signal.SIGKILL)
    sol = job.result(30.0)
    assert sol.status == "failed"
    assert "the solver process stopped unexpectedly" in sol.message
    # The worker's empty answer, sent as the solve began (the service loads no mission):
    # validated values and the cost's own label and unit.
    assert (sol.cost.label, sol.cost.unit) == ("fuel", "kg") and sol.nodes == 30
    assert sol.values["thrust"] == solvers.get_mission("lunar-landing").defaults()["thrust"]
    assert service.submit(SolveRequest("lunar-landing", "hermite-simpson"),
                          session="victim").result(60.0).ok


def test_a_newer_request_cancels_the_running_one(service):
    slow = service.submit(SolveRequest("cw-rendezvous", "multiple-shooting", nodes=300),
                          session="c")
    time.sleep(0.5)
    slow.cancel()
    sol = slow.result(30.0)
    assert sol.status == "cancelled"


def _cpu_seconds_below(pid: int) -> float:
    """CPU time (s) the processes started by `pid` (children, grandchildren) have used."""
    total, todo = 0.0, [pid]
    while todo:
        parent = todo.pop()
        for task in os.listdir(f"/proc/{parent}/task"):
            with contextlib.suppress(OSError), open(
                    f"/proc/{parent}/task/{task}/children", encoding="ascii") as f:
                todo += [int(c) for c in f.read().split()]
        if parent != pid:
            with contextlib.suppress(OSError), open(f"/proc/{parent}/stat",
                                                    encoding="ascii") as f:
                fields = f.read().rsplit(")", 1)[1].split()
                total += (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return total


def test_the_cli_stops_at_once_on_ctrl_c_even_inside_a_native_solve():
    """SQP on a 150-interval hovercraft runs for minutes inside the native solver: once its
    worker has worked 6 s (imports and the NLP's build take about 2), it is in there."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "solvers", "solve", "hovercraft", "--method", "hermite-simpson",
         "--backend", "sqp", "--nodes", "150"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300.0
    while _cpu_seconds_below(proc.pid) < 6.0:
        assert proc.poll() is None, "the solve ended before Ctrl-C"
        assert time.monotonic() < deadline, "the worker never got to work"
        time.sleep(0.1)
    started = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=20.0)
    assert time.monotonic() - started < 3.0
    assert proc.returncode == 130 and "interrupted" in err and "Traceback" not in err


def test_progress_crosses_the_process_boundary(service):
    seen: list[int] = []
    lock = threading.Lock()

    def progress(iteration: int, text: str) -> None:
        with lock:
            seen.append(iteration)

    job = service.submit(SolveRequest("apollo-reentry", "hermite-simpson", nodes=80),
                         progress=progress)
    assert job.result(120.0).ok
    assert seen and max(seen) > 0


@pytest.mark.parametrize("found_by", ["its process state", "the acknowledgement deadline"])
def test_a_worker_stopped_while_idle_gets_no_job_and_is_replaced(service, monkeypatch,
                                                                  found_by):
    """Issue 16: a worker stopped (SIGSTOP) while idle still got jobs, and a 30 ms solve
    waited for its time limit. The service sees the stopped process before dispatch (Linux
    /proc) or, failing that, when the job is not acknowledged, and moves the job."""
    from solvers.service import pool

    runnable = pool.runnable
    if found_by == "the acknowledgement deadline":
        monkeypatch.setattr(pool, "runnable", lambda pid: True)
    # Both workers solve once (imports, built NLP), so the move costs a warm solve only.
    first, second = _both_workers_solved(service, SolveRequest("hovercraft"), ("idle", "2"))
    restarts = service.restarts
    victim = service.pids()[first.worker]
    os.kill(victim, signal.SIGSTOP)
    try:
        deadline = time.monotonic() + 10.0
        while runnable(victim):  # the signal is delivered when the kernel next runs it
            assert time.monotonic() < deadline, "SIGSTOP did not stop the worker"
            time.sleep(0.01)
        job = service.submit(SolveRequest("hovercraft", values={"accel": 3.5}, time_limit=60.0),
                             session="idle")
        sol = job.result(60.0)  # on the stopped worker: "time-limit" after 61 s
        assert sol.ok, sol.message
        assert job.worker == second.worker and victim not in service.pids()
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.kill(victim, signal.SIGCONT)  # in case it was not killed
    deadline = time.monotonic() + 30.0
    while service.restarts == restarts:
        assert time.monotonic() < deadline, "no replacement worker"
        time.sleep(0.05)


def test_the_service_side_loads_no_mission():
    """Issue 18: the service's process neither lists the missions for the workers' start-up
    builds (each worker lists them) nor validates a failed job again (the worker sent its
    empty answer as the solve began): a CLI or server that solves one mission loads one."""
    code = ("import sys\n"
            "from solvers.request import SolveRequest\n"
            "from solvers.service import SolveService\n"
            "service = SolveService(1, prebuild=True, first_mission='bang-bang',\n"
            "                       test_hooks=True)\n"
            "job = service.submit(SolveRequest('bang-bang', time_limit=1.0), test_hook='hang')\n"
            "sol = job.result(60.0)\n"
            "assert sol.status == 'time-limit' and sol.cost.unit == 's', sol\n"
            "loaded = sorted(m for m in sys.modules if m.startswith('solvers.missions.'))\n"
            "service.close()\n"
            "print(loaded)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
