"""The service's end of its worker processes: one worker's handle, whether a process can
run, and spawning with single-threaded linear algebra."""

from __future__ import annotations

import contextlib
import os
import threading
from multiprocessing.connection import Connection
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import multiprocessing as mp

    from .job import Job

# The workers are the parallelism: a worker's linear algebra runs on one thread, or two
# workers' BLAS thread pools fight over the cores (measured on 2 cores: LGL warm re-solves
# 17-23 ms on one thread, 19-100 ms on the default pool).
SINGLE_THREAD_ENV = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
_ENV_LOCK = threading.Lock()


class WorkerHandle:
    """The service's end of one worker process."""

    def __init__(self, index: int, process: mp.Process, conn: Connection) -> None:
        self.index, self.process, self.conn = index, process, conn
        self.ready = threading.Event()
        self.prebuilt = threading.Event()  # its start-up builds are done
        self.job: Job | None = None  # the solve it runs
        self.acked = False  # it acknowledged `job`
        self.checking: dict[int, Job] = {}  # solves whose check it still owes
        self.kept: dict[str, int] = {}  # session -> the job whose answer it keeps as warm start
        self.rss = 0
        self.alive = True  # False once it is being killed or has died
        self.death: str | None = None  # why the service killed it
        self.replaced = False
        self.send_lock = threading.Lock()

    def send(self, msg: tuple) -> None:
        with self.send_lock, contextlib.suppress(OSError, ValueError):
            self.conn.send(msg)  # if it died, its reader thread handles that


def runnable(pid: int | None) -> bool:
    """Whether process `pid` can run: not stopped (SIGSTOP, a debugger) nor a zombie, by
    Linux's /proc/<pid>/stat (elsewhere: assumed so; the acknowledgement deadline covers)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError, ValueError):
        return True
    return state not in ("T", "t", "Z", "X")


@contextlib.contextmanager
def single_threaded_children():
    """Spawn with the BLAS/OpenMP thread counts at one unless the user has set them (a
    spawned process reads them from the environment when its numpy loads)."""
    with _ENV_LOCK:
        added = [v for v in SINGLE_THREAD_ENV if v not in os.environ]
        for var in added:
            os.environ[var] = "1"
        try:
            yield
        finally:
            for var in added:
                os.environ.pop(var, None)
