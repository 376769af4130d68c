"""A solve worker: one process that solves requests one at a time with its own cache of built
NLPs (no lock shared with anyone), reports progress, runs the re-propagation checks when it has
nothing better to do, and builds the default NLPs in the background.

Priorities: a solve first; then the deferred checks (pre-empted as soon as a solve arrives and
run again later; dropped when their session has moved on); then the start-up builds (a default
solve per mission and method, cancelled when a real solve arrives and taken up again later).
A reader thread takes messages off the pipe while the main thread solves, so a cancel reaches
a running solve. Past its memory budget the worker empties its NLP cache, and if that is not
enough it retires (the service starts a fresh one).
"""

from __future__ import annotations

import collections
import os
import queue
import signal
import threading
import time
import warnings
from multiprocessing.connection import Connection
from typing import Any

from ..nlp.cache import clear_built
from ..registry import get_mission, list_missions, load_mission_files
from ..request import SolveRequest
from ..solution import Solution
from ..verify import CheckInterrupted, interruptible
from .protocol import CheckUpdate, light_warm

# What a worker builds at start-up: (mission, method) pairs, or a mission key for every
# mission's every method, that one's first (the worker lists them: the service loads none).
Prebuild = list[tuple[str, str]] | str
PROGRESS_INTERVAL = 0.05  # s between progress messages of one solve


def resident_bytes() -> int:
    """This process's resident set size (Linux /proc; 0 elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


class Worker:
    """The state of one worker process (see the module docstring)."""

    def __init__(self, conn: Connection, prebuild: list[tuple[str, str]], rss_budget: int,
                 test_hooks: bool) -> None:
        self.conn = conn
        self.inbox: queue.Queue[tuple] = queue.Queue()
        self.checks: collections.deque[tuple[int, Solution]] = collections.deque()
        self.prebuild = collections.deque(prebuild)
        self.rss_budget = rss_budget
        self.test_hooks = test_hooks
        self.solve_waiting = threading.Event()  # pre-empts checks and start-up builds
        self.current: tuple[int, threading.Event] | None = None
        self.dropped: set[int] = set()
        # session -> (job id, answer): its newest converged answer, the warm start of its next
        # solve here (the service mirrors this in `_Worker.kept` and sends just the id).
        self.kept: dict[str, tuple[int, Solution]] = {}
        self.lock = threading.Lock()
        self.send_lock = threading.Lock()  # the reader thread sends too (acknowledgements)

    def send(self, msg: tuple) -> None:
        """One message to the service (from either thread)."""
        with self.send_lock:
            self.conn.send(msg)

    # ---- the reader thread ---------------------------------------------------------------
    def read(self) -> None:
        while True:
            try:
                msg = self.conn.recv()
            except (EOFError, OSError):
                os._exit(0)  # the service is gone
            kind = msg[0]
            if kind == "solve":
                self.send(("ack", msg[1]))  # at once: the service knows this worker runs
                self.solve_waiting.set()
                self.inbox.put(msg)
            elif kind == "cancel":
                with self.lock:
                    self.dropped.add(msg[1])
                    if self.current is not None and self.current[0] == msg[1]:
                        self.current[1].set()
            elif kind in ("stop", "reload", "forget"):
                self.inbox.put(msg)

    # ---- the main thread -----------------------------------------------------------------
    def run(self) -> None:
        self.send(("ready", os.getpid()))
        while True:
            try:
                msg = self.inbox.get(block=not (self.checks or self.prebuild))
            except queue.Empty:
                msg = None
            if msg is not None:
                if msg[0] == "stop":
                    return
                if msg[0] == "forget":
                    self.kept.pop(msg[1], None)
                    continue
                if msg[0] == "reload":
                    errors = _load_quietly(msg[1])
                    if errors:
                        self.send(("mission-errors", errors))
                    continue
                self.solve(*msg[1:])
                if self.inbox.empty():
                    self.solve_waiting.clear()
                self.mind_memory()
            elif self.checks:
                self.check_one()
            elif self.prebuild:
                self.build_one()

    def solve(self, job_id: int, request: SolveRequest, session: str,
              warm: Solution | int | None, verify: bool, test_hook: str | None) -> None:
        """Solve; `warm` is a solution, or the id of the one kept for `session`."""
        if isinstance(warm, int):
            kept = self.kept.get(session)
            warm = kept[1] if kept is not None and kept[0] == warm else None
        cancel = threading.Event()
        with self.lock:
            self.current = (job_id, cancel)
            if job_id in self.dropped:
                cancel.set()
        if test_hook == "busy" and self.test_hooks:
            self.misbehave(test_hook)
        try:  # the answer the service gives if this solve gives none (killed, crashed)
            mission = get_mission(request.mission)
            blank = request.unanswered(mission, "failed", "")
        except ValueError as exc:
            with self.lock:
                self.current = None
            self.send(("error", job_id, str(exc)))
            return
        # Its time limit runs from now: a start-up build this worker was in (native, it
        # cannot stop mid-way) is not the solve's time.
        self.send(("begin", job_id, blank))
        last = [0.0]

        def progress(iteration: int, text: str) -> None:
            now = time.monotonic()
            if now - last[0] >= PROGRESS_INTERVAL:
                last[0] = now
                self.send(("progress", job_id, iteration, text))

        if test_hook and test_hook != "busy" and self.test_hooks:
            self.misbehave(test_hook)
        try:
            sol = request.run(mission, warm=warm, progress=progress,
                              cancel=cancel, verify=False)
        except ValueError as exc:
            self.send(("error", job_id, str(exc)))
            return
        finally:
            with self.lock:
                self.current = None
        if session and sol.converged:  # before the answer goes: the service counts on it
            self.kept[session] = (job_id, light_warm(sol))
        self.send(("result", job_id, sol))
        if verify and sol.checker is not None:
            self.checks.append((job_id, sol))
        elif verify:  # checked already (an "auto" or multi-start solve), or no check
            self.send(("check", job_id, CheckUpdate.of(sol)))

    def check_one(self) -> None:
        job_id, sol = self.checks.popleft()
        with self.lock:
            if job_id in self.dropped:
                return
        try:
            with interruptible(self.solve_waiting.is_set):
                sol.run_check()
        except CheckInterrupted:
            self.checks.appendleft((job_id, sol))
            return
        self.send(("check", job_id, CheckUpdate.of(sol)))

    def build_one(self) -> None:
        """One start-up build: solve a mission's default case with a method, cold and then
        warm (which builds IPOPT's warm-start solver too); a solve arriving cancels it."""
        key, method = self.prebuild.popleft()
        cancel = threading.Event()
        watcher = threading.Thread(target=lambda: self.solve_waiting.wait() or cancel.set(),
                                   daemon=True)
        watcher.start()
        try:
            mission = get_mission(key)
            first = mission.solve(method=method, cancel=cancel, verify=False)
            if first.ok and not cancel.is_set():
                mission.solve(method=method, warm=first, cancel=cancel, verify=False)
        except Exception:  # noqa: BLE001 - a failed pre-build only costs time later
            return
        if cancel.is_set():
            self.prebuild.appendleft((key, method))
        elif not self.prebuild:
            self.send(("prebuilt",))

    def mind_memory(self) -> None:
        rss = resident_bytes()
        if rss > self.rss_budget:
            clear_built()
            rss = resident_bytes()
            if rss > self.rss_budget:
                self.send(("retire", f"memory {rss / 2**20:.0f} MB over the budget"))
                os._exit(0)
        self.send(("rss", rss))

    def misbehave(self, hook: str) -> None:
        """Test-only faults: hang in native code (SIGSTOP: nothing of the process runs, not
        even its reader thread), die as from a segfault (SIGKILL), sleep in C, or be busy
        for a second before the solve begins (as in a start-up build that cannot stop)."""
        if hook == "busy":
            import ctypes

            ctypes.CDLL(None).sleep(1)
        elif hook == "stop":
            os.kill(os.getpid(), signal.SIGSTOP)
        elif hook == "crash":
            os.kill(os.getpid(), signal.SIGKILL)
        elif hook == "hang":
            import ctypes

            ctypes.CDLL(None).sleep(3600)


def prebuild_pairs(prebuild: Prebuild) -> list[tuple[str, str]]:
    """The (mission, method) pairs to build at start-up: given, or (a mission key) every
    mission's every method, that mission's first."""
    if not isinstance(prebuild, str):
        return list(prebuild)
    missions = sorted(list_missions(), key=lambda m: m.key != prebuild)
    return [(m.key, meth.key) for m in missions for meth in m.methods]


def _load_quietly(paths: list[str]) -> dict[str, Any]:
    """Load mission files without their warnings: the process that started the service
    loaded the same files and showed them once (a worker repeating them printed each
    warning once more per worker)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return load_mission_files(paths)


def worker_main(conn: Connection, mission_files: list[str], prebuild: Prebuild,
                rss_budget: int, test_hooks: bool) -> None:
    """Entry point of a worker process."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the service's to handle
    errors: dict[str, Any] = _load_quietly(mission_files)
    if errors:
        conn.send(("mission-errors", errors))
    worker = Worker(conn, prebuild_pairs(prebuild), rss_budget, test_hooks)
    threading.Thread(target=worker.read, daemon=True, name="worker-reader").start()
    worker.run()
