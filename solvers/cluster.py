"""A `dask.distributed` cluster as a place to solve: the connection (`connect`, one clear
error when dask is missing or the scheduler unreachable) and the work units its workers run.

dask is imported only here and only when a scheduler address is given (`pip install
"dask[distributed]"`); the work units are module-level functions (they are pickled to the
workers), and the workers need this package installed (and a mission file's path readable,
for a mission declared in a file).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .registry import get_mission, list_missions, load_mission_files
from .request import SolveRequest
from .service.protocol import CheckUpdate
from .solution import Solution

SCHEDULER_TIMEOUT = "5s"  # an unreachable scheduler is reported after this


def connect(scheduler: str) -> Any:
    """A `dask.distributed.Client` on `scheduler` ("tcp://host:8786"); `RuntimeError` saying
    what to do when dask is not installed or the scheduler does not answer."""
    try:
        from dask.distributed import Client
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise RuntimeError('a scheduler address needs dask: pip install "dask[distributed]"'
                           ) from exc
    try:
        return Client(scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise RuntimeError(f"cannot reach the dask scheduler at {scheduler} within "
                           f"{SCHEDULER_TIMEOUT} ({exc})") from None


def mission_for(key: str, mission_files: Sequence[str] = ()) -> Any:
    """The mission `key` on a worker, loading `mission_files` first when it is not known
    there (a mission declared in a file)."""
    if mission_files and key not in {m.key for m in list_missions()}:
        load_mission_files(list(mission_files))
    return get_mission(key)


def solve_on_worker(request: SolveRequest, warm: Solution | None,
                    mission_files: Sequence[str] = ()) -> Solution:
    """Solve `request` on a worker, its re-propagation check deferred (`check_on_worker`
    runs it on the worker holding this answer: the check's closure stays there)."""
    return request.run(mission_for(request.mission, mission_files), warm=warm, verify=False)


def check_on_worker(sol: Solution) -> CheckUpdate:
    """Run the deferred check of an answer held in this worker's memory; what it adds
    (`CheckUpdate`), for the caller's copy of the answer."""
    if sol.checker is None:  # moved between workers (pickled without its closure)
        raise RuntimeError("the answer's check did not stay on its worker")
    sol.run_check()
    return CheckUpdate.of(sol)
