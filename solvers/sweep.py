"""Grids and Monte-Carlo runs: mission solves on the solve service's worker processes, or on a
`dask.distributed` cluster when given a scheduler address ("tcp://host:8786").

dask is imported only then (`solvers.cluster`; `pip install "dask[distributed]"` to use
it); its work functions must be importable module-level functions (they are pickled to the
workers), and the workers must have this package installed. Vectorised grids (`grid_rows`)
run on a local process pool or the same cluster.

Two shapes of work:
- `grid_rows`: a vectorised function of (row values, column values) -> a 2-D block, split
  into row chunks (the launch-C3 map: one Lambert batch per chunk of launch dates);
- `mission_grid` / `monte_carlo`: one mission solve per value set, returning the
  solutions' JSON summaries.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any, TypedDict, Unpack

import numpy as np

from .cluster import connect, mission_for
from .request import SolveRequest
from .service import SolveService


@contextmanager
def executor(scheduler: str | None = None, workers: int | None = None) -> Iterator[Executor]:
    """A process pool (default: one worker per core) or a dask cluster's executor."""
    if scheduler:
        with connect(scheduler) as client:
            yield client.get_executor()
        return
    with ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
        yield pool


def grid_rows(
    fn: Callable[..., np.ndarray],
    rows: np.ndarray,
    cols: np.ndarray,
    *args: Any,
    scheduler: str | None = None,
    workers: int | None = None,
    chunks: int | None = None,
    pool: Executor | None = None,
) -> np.ndarray:
    """Evaluate fn(rows_chunk, cols, *args) -> (len(chunk), len(cols)) over row chunks and
    stack the blocks. `pool` reuses an open executor; otherwise one is opened for the call
    (`workers=1` with no scheduler runs in this process, no pool at all)."""
    rows = np.asarray(rows)
    if pool is None and not scheduler and workers == 1:
        return np.asarray(fn(rows, cols, *args))
    n_chunks = chunks or 4 * (workers or os.cpu_count() or 1)
    parts = [p for p in np.array_split(rows, min(n_chunks, len(rows))) if len(p)]
    # Sized argument lists: dask's executor needs len() of every iterable.
    extra = [[a] * len(parts) for a in (cols, *args)]
    if pool is not None:
        return np.vstack(list(pool.map(fn, parts, *extra)))
    with executor(scheduler, workers) as ex:
        blocks = list(ex.map(fn, parts, *extra))
    return np.vstack(blocks)


def solve_summary(mission_key: str, values: Mapping[str, float], method: str | None,
                  nodes: int | None, mission_files: Sequence[str] = (),
                  time_limit: float | None = None) -> dict[str, Any]:
    """Solve one request and return its JSON-ready summary (the work unit of mission sweeps
    on a cluster, where the limit is `Mission.solve`'s cooperative one); `mission_files` are
    loaded first when the mission is not known in this process."""
    return mission_for(mission_key, mission_files).solve(dict(values), method=method, nodes=nodes,
                                          time_limit=time_limit).to_dict()


class SweepOptions(TypedDict, total=False):
    """How every solve of a sweep runs: `method` and `nodes` (None: the mission's defaults),
    `scheduler` (a dask address; None: the solve service's worker processes), `workers`,
    `mission_files` (loaded by every worker: a mission declared in a file) and `time_limit`
    (s, bounding each solve and its check; None: no limit)."""

    method: str | None
    nodes: int | None
    scheduler: str | None
    workers: int | None
    mission_files: Sequence[str]
    time_limit: float | None


def mission_grid(mission_key: str, axes: Mapping[str, Sequence[float]],
                 fixed: Mapping[str, float] | None = None, **options: Unpack[SweepOptions]
                 ) -> list[dict[str, Any]]:
    """Solve a mission on the Cartesian product of `axes` (param key -> values), the other
    parameters at `fixed` (or their defaults)."""
    keys = list(axes)
    value_sets = [dict(fixed or {}, **dict(zip(keys, combo, strict=True)))
                  for combo in itertools.product(*(axes[k] for k in keys))]
    return _solve_all(mission_key, value_sets, options)


def monte_carlo(mission_key: str, sampler: Callable[[np.random.Generator], Mapping[str, float]],
                runs: int, seed: int = 0, fixed: Mapping[str, float] | None = None,
                **options: Unpack[SweepOptions]) -> list[dict[str, Any]]:
    """Solve a mission for `runs` value sets drawn by `sampler(rng)` (seeded, repeatable)."""
    rng = np.random.default_rng(seed)
    value_sets = [dict(fixed or {}, **sampler(rng)) for _ in range(runs)]
    return _solve_all(mission_key, value_sets, options)


def _solve_all(mission_key: str, value_sets: list[dict[str, float]], options: SweepOptions
               ) -> list[dict[str, Any]]:
    n = len(value_sets)
    method, nodes = options.get("method"), options.get("nodes")
    files, time_limit = list(options.get("mission_files", ())), options.get("time_limit")
    scheduler, workers = options.get("scheduler"), options.get("workers")
    if scheduler:
        with executor(scheduler, workers) as ex:
            return list(ex.map(solve_summary, [mission_key] * n, value_sets, [method] * n,
                               [nodes] * n, [files] * n, [time_limit] * n))
    with SolveService(workers, prebuild=False, mission_files=files) as service:
        jobs = [service.submit(SolveRequest(mission_key, method, nodes, values=dict(v),
                                            time_limit=time_limit))
                for v in value_sets]
        rows = []
        for job in jobs:  # a check runs when its worker has no solve waiting, bounded by
            sol = job.result()  # what its solve left of the limit (`Mission.solve`)
            job.check()
            rows.append(sol.to_dict())
        return rows
