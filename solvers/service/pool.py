"""The solve service: a pool of worker processes that every front end (explorer, CLI, sweeps)
hands its solves to.

A solve runs in a worker process, never in the caller's: a slow, stuck or crashing solve
cannot hold or take down anyone else. A session sticks to the worker that solved its last
request (its built NLPs are there, and the warm start it made: only its id crosses the pipe);
when that worker is busy, an idle one takes the request (the warm start travels with it). A
solve still running at its time limit plus `grace` is killed with its worker; a worker that
dies is replaced; either way only that solve's caller hears of it, with a status that says
so. Jobs wait in one queue, first come, first served.
"""

from __future__ import annotations

import collections
import dataclasses
import itertools
import multiprocessing as mp
import os
import threading
import time
import weakref
from collections.abc import Sequence

from ..request import SolveRequest
from ..solution import Quantity, Solution
from .job import Job, Progress
from .processes import WorkerHandle, runnable, single_threaded_children
from .protocol import CheckUpdate, light_warm
from .worker import Prebuild, resident_bytes, worker_main

GRACE = 1.0  # s past a solve's time limit before its worker is killed
# s a worker has to acknowledge a solve (its reader thread answers at once; the longest wait
# for the GIL measured in a native NLP build or solve: 0.3 s). A worker that does not is
# stopped or stuck: its job goes to another worker and it is replaced.
ACK_TIMEOUT = 2.0
MAX_EARLY_DEATHS = 3  # workers dying before they are ready, in a row, before giving up
RSS_BUDGET = 700 * 2**20  # bytes per worker before it empties its NLP cache or retires
# Whether an older answer stays on screen is the caller's to say (it knows whether it has one).
CRASHED = ("the solver process stopped unexpectedly ({why}) — try again, or another method or "
           "node count")


class SolveService:
    """`workers` processes (default: one per core); `prebuild` pairs (mission, method) whose
    default NLPs every worker builds in the background (True: all, the first mission first);
    `mission_files` are loaded by every worker; `test_hooks` lets tests make a worker hang or
    crash on purpose."""

    def __init__(self, workers: int | None = None, *, prebuild: bool | Sequence[tuple[str, str]]
                 = True, mission_files: Sequence[str] = (), grace: float = GRACE,
                 rss_budget: int = RSS_BUDGET, test_hooks: bool = False,
                 first_mission: str | None = None) -> None:
        self.n_workers = max(1, workers or os.cpu_count() or 1)
        self.grace = grace
        self.rss_budget = rss_budget
        self.test_hooks = test_hooks
        self.mission_files = list(mission_files)
        # every worker lists the (mission, method) pairs itself for True: all, first first
        self.prebuild: Prebuild = (list(prebuild) if not isinstance(prebuild, bool)
                                   else (first_mission or "") if prebuild else [])
        self.restarts = 0
        self._early_deaths = 0  # consecutive workers that died before they were ready
        self._broken: str | None = None
        self.mission_errors: dict[str, str] = {}
        self._ctx = mp.get_context("spawn")
        self._ids = itertools.count(1)
        self._lock = threading.RLock()
        self._queue: collections.deque[Job] = collections.deque()
        self._affinity: dict[str, int] = {}
        # The answers workers keep as warm starts, while a caller still holds them.
        self._answers: weakref.WeakValueDictionary[int, Solution] = weakref.WeakValueDictionary()
        self._closed = False
        self._workers: list[WorkerHandle] = [self._spawn(i) for i in range(self.n_workers)]
        self._monitor = threading.Thread(target=self._watch, daemon=True, name="service-watch")
        self._monitor.start()

    # ---- workers ----------------------------------------------------------------------------
    def _spawn(self, index: int) -> WorkerHandle:
        parent, child = self._ctx.Pipe(duplex=True)
        process = self._ctx.Process(
            target=worker_main, name=f"solve-worker-{index}", daemon=True,
            args=(child, self.mission_files, self.prebuild, self.rss_budget, self.test_hooks))
        with single_threaded_children():
            process.start()
        child.close()
        worker = WorkerHandle(index, process, parent)
        threading.Thread(target=self._read, args=(worker,), daemon=True,
                         name=f"service-read-{index}").start()
        return worker

    def _read(self, w: WorkerHandle) -> None:
        """Messages of one worker, until its pipe closes (the worker died or retired)."""
        while True:
            try:
                msg = w.conn.recv()
            except (EOFError, OSError):
                break
            self._handle(w, msg)
        self._died(w)

    def _handle(self, w: WorkerHandle, msg: tuple) -> None:
        kind = msg[0]
        if kind == "ready":
            w.ready.set()
            with self._lock:
                self._dispatch()
        elif kind == "ack":
            with self._lock:
                if w.job is not None and w.job.id == msg[1]:
                    w.acked = True
        elif kind == "begin":  # the time limit counts from here (not from the hand-over)
            with self._lock:
                if w.job is not None and w.job.id == msg[1]:
                    w.job.started, w.job.blank = time.monotonic(), msg[2]
        elif kind == "progress":
            job = w.job
            if job is not None and job.id == msg[1] and job.progress is not None:
                job.progress(msg[2], msg[3])
        elif kind in ("result", "error"):
            with self._lock:
                job = w.job
                if job is None or job.id != msg[1]:
                    return
                w.job = None
                if kind == "error":
                    job._finish(error=msg[2])
                else:
                    sol: Solution = msg[2]
                    if job.session and sol.converged:  # the worker keeps it (`Worker.solve`)
                        w.kept[job.session] = job.id
                        self._answers[job.id] = sol
                    will_check = job.verify and sol.ok and sol.has_trajectory
                    if will_check:
                        w.checking[job.id] = job
                    job._finish(msg[2], checked=not will_check)
                self._dispatch()
        elif kind == "check":
            with self._lock:
                job = w.checking.pop(msg[1], None)
            if job is not None and job.solution is not None:
                update: CheckUpdate = msg[2]
                update.apply(job.solution)
                job.checked.set()
        elif kind == "rss":
            w.rss = msg[1]
        elif kind == "prebuilt":
            w.prebuilt.set()
        elif kind == "mission-errors":
            self.mission_errors.update(msg[1])

    def _died(self, w: WorkerHandle) -> None:
        """The pipe of `w` closed: replace the worker; its running solve fails, its owed
        checks are dropped."""
        with self._lock:
            if w.replaced:
                return
            w.replaced, w.alive = True, False
            job, w.job = w.job, None
            owed, w.checking = list(w.checking.values()), {}
        if w.process.is_alive():
            w.process.kill()
        w.process.join(timeout=5.0)
        with self._lock:
            if job is not None:
                reason = w.death or f"exit code {w.process.exitcode}"
                self._fail(job, "failed", CRASHED.format(why=reason))
            for owed_job in owed:
                owed_job.checked.set()
            if self._closed:
                return
            self._early_deaths = 0 if w.ready.is_set() else self._early_deaths + 1
            if self._early_deaths > MAX_EARLY_DEATHS:
                self._broken = (f"the solver processes die as they start (exit code "
                                f"{w.process.exitcode}); see the terminal for the error")
                for queued in self._queue:
                    queued._finish(error=self._broken)
                self._queue.clear()
                return
            self.restarts += 1
            self._workers[w.index] = self._spawn(w.index)
            self._dispatch()

    def _kill(self, w: WorkerHandle, why: str) -> None:
        """Stop a worker now; its reader thread sees the pipe close and replaces it."""
        w.alive, w.death = False, why
        if w.process.is_alive():
            w.process.kill()

    def _watch(self) -> None:
        """Move a job its worker did not acknowledge in time to another worker; kill a
        solve still running past its time limit plus the grace."""
        while not self._closed:
            time.sleep(0.05)
            now = time.monotonic()
            with self._lock:
                for w in self._workers:
                    job = w.job
                    if (w.alive and job is not None and not w.acked and job.started is not None
                            and now > job.started + ACK_TIMEOUT):
                        self._requeue(w, "it did not acknowledge a solve")
                late = [w for w in self._workers if w.alive and w.job is not None
                        and w.job.deadline is not None and now > w.job.deadline]
                expired = []
                for w in late:
                    expired.append(w.job)
                    w.job = None
                    self._kill(w, "stopped at its time limit")
            for job in expired:  # outside the lock: answering may import the mission
                self._fail(job, "time-limit",
                           f"stopped at the time limit of {job.request.time_limit:g} s (the solver "
                           "did not return, so its process was stopped): raise the time "
                           "limit, or use fewer nodes or another method")

    def _requeue(self, w: WorkerHandle, why: str) -> None:
        """`w` does not answer: its job goes back to the head of the queue, for another
        worker, and `w` is killed (and replaced)."""
        job, w.job = w.job, None
        if job is not None:
            job.worker = job.started = None
            self._queue.appendleft(job)
        self._kill(w, why)
        self._dispatch()

    def _fail(self, job: Job, status: str, message: str) -> None:
        """Answer a job the worker could not answer: its worker's empty solution (sent when
        the solve began: validated values, the cost's label and unit) with `status`, or,
        before it began, one made of the request itself (no mission is loaded here)."""
        if job.blank is not None:
            sol = dataclasses.replace(job.blank, status=status, message=message, stats={})
        else:
            sol = _unanswered(job.request, status, message)
        if job.started is not None:
            sol.stats["wall_s"] = time.monotonic() - job.started
        job._finish(sol)

    # ---- jobs -------------------------------------------------------------------------------
    def submit(self, request: SolveRequest, session: str = "",
               progress: Progress | None = None, *, warm: Solution | None = None,
               verify: bool = True, test_hook: str | None = None) -> Job:
        """Queue a solve, warm from `warm` (an earlier answer of this service or any
        `Solution`); `verify`: run the re-propagation check after the answer; `test_hook`:
        "hang" / "crash" / "stop", honoured only with `test_hooks`."""
        if self._closed:
            raise RuntimeError("the solve service is closed")
        if self._broken:
            raise RuntimeError(self._broken)
        job = Job(next(self._ids), request, session, progress, self.grace, self.cancel,
                  warm=warm, verify=verify, test_hook=test_hook)
        with self._lock:
            self._queue.append(job)
            self._dispatch()
        return job

    def cancel(self, job: Job) -> None:
        """Stop a job: dropped from the queue, or its worker told to stop it (and to drop
        its check)."""
        with self._lock:
            if job in self._queue:
                self._queue.remove(job)
                self._fail(job, "cancelled", "cancelled by a newer request")
                return
            for w in self._workers:
                if (w.job is job or job.id in w.checking) and w.alive:
                    w.send(("cancel", job.id))
                    if w.checking.pop(job.id, None) is not None:
                        job.checked.set()

    def _idle(self) -> list[WorkerHandle]:
        """Workers ready for a solve; one found stopped (SIGSTOP) or dead is replaced."""
        for w in self._workers:
            if w.alive and w.job is None and not runnable(w.process.pid):
                self._kill(w, "it was stopped and did not answer")
        return [w for w in self._workers if w.alive and w.ready.is_set() and w.job is None]

    def _dispatch(self) -> None:
        """Hand queued jobs to idle workers, each to its session's worker if that one is
        idle, else to any idle worker (which becomes the session's)."""
        while self._queue:
            idle = self._idle()
            if not idle:
                return
            job = self._queue.popleft()
            preferred = self._affinity.get(job.session)
            worker = next((w for w in idle if w.index == preferred), idle[0])
            if job.session:
                self._affinity[job.session] = worker.index
            worker.job, job.worker, job.started = job, worker.index, time.monotonic()
            worker.acked = False
            worker.send(("solve", job.id, job.request, job.session, self._warm_for(worker, job),
                         job.verify, job.test_hook))

    def _warm_for(self, w: WorkerHandle, job: Job) -> Solution | int | None:
        """What `w` is sent as the warm start: the id of the answer it keeps for the job's
        session when that is the one asked for (nothing crosses the pipe), else the solution
        stripped of what the solve never reads."""
        kept = w.kept.get(job.session)
        if job.warm is not None and kept is not None and self._answers.get(kept) is job.warm:
            return kept
        return light_warm(job.warm)

    # ---- state ------------------------------------------------------------------------------
    def wait_ready(self, timeout: float = 60.0) -> bool:
        """Block until every worker has started (tests, benchmarks)."""
        deadline = time.monotonic() + timeout
        return all(w.ready.wait(max(deadline - time.monotonic(), 0.0)) for w in self._workers)

    def wait_prebuilt(self, timeout: float = 300.0) -> bool:
        """Block until every worker has built its start-up NLPs (benchmarks measure after)."""
        if not self.prebuild:
            return self.wait_ready(timeout)
        deadline = time.monotonic() + timeout
        return all(w.prebuilt.wait(max(deadline - time.monotonic(), 0.0))
                   for w in list(self._workers))

    def pids(self) -> list[int]:
        return [w.process.pid for w in self._workers if w.alive and w.process.pid]

    def resident(self) -> dict[str, float]:
        """Resident memory (MB) of this process and of each worker (as last reported)."""
        out = {"server": resident_bytes() / 2**20}
        for w in self._workers:
            out[f"worker {w.index}"] = w.rss / 2**20
        return out

    def forget(self, session: str) -> None:
        """A session closed: drop its worker affinity and the warm starts kept for it."""
        with self._lock:
            self._affinity.pop(session, None)
            for w in self._workers:
                if w.kept.pop(session, None) is not None and w.alive:
                    w.send(("forget", session))

    def reload_mission_files(self, mission_files: Sequence[str]) -> None:
        """Every worker loads the mission files again before its next solve (running solves
        finish undisturbed); workers started later load them too."""
        self.mission_files = list(mission_files)
        with self._lock:
            for w in self._workers:
                if w.alive:
                    w.send(("reload", self.mission_files))

    def close(self) -> None:
        """Stop every worker (one running a solve or owing a check is killed at once)."""
        with self._lock:
            self._closed = True
            workers = list(self._workers)
            for job in self._queue:
                job._finish(error="the solve service closed")
            self._queue.clear()
        for w in workers:
            if w.job is not None or w.checking:  # busy: it would read "stop" only after
                self._kill(w, "the solve service closed")
            else:
                w.send(("stop",))
        deadline = time.monotonic() + 2.0
        for w in workers:
            w.process.join(timeout=max(deadline - time.monotonic(), 0.0))
            if w.process.is_alive():
                w.process.kill()
                w.process.join(timeout=2.0)

    def __enter__(self) -> SolveService:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _unanswered(r: SolveRequest, status: str, message: str) -> Solution:
    """An answer made of the request alone, for a job that ended before its solve began (a
    worker that died in a start-up build, a cancel while queued): the mission's cost label
    and unit are the worker's to know, so the cost is a bare NaN."""
    return Solution(mission=r.mission, method=r.method or "",
                    nodes=r.nodes if isinstance(r.nodes, int) else 0, status=status,
                    message=message, cost=Quantity(float("nan"), "cost", ""),
                    values=dict(r.values), backend=r.backend or "")
