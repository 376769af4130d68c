"""Bounded caches of built NLPs and CasADi functions.

Building an NLP (symbolic graph, derivatives, solver instance) costs 10 ms to seconds and tens
of megabytes, so each is built once per (mission, method, node count, back end) and re-solved
with new parameters. The caches are bounded (least recently used out) so a process that sees
many node counts does not grow without end; `clear_built()` empties them all (a worker
recycled for memory starts afresh anyway). Builds take `BUILD_LOCK`: CasADi's solver
construction is not thread-safe, and a library user may solve from several threads.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from functools import lru_cache, wraps
from typing import Any, TypeVar

T = TypeVar("T")

# In-process thread safety for library users; the solve service runs one solve per process.
BUILD_LOCK = threading.RLock()
DEFAULT_MAXSIZE = int(os.environ.get("TRAJ_NLP_CACHE", "24"))
_CACHES: list[Any] = []


def built_once(fn: Callable[..., T] | None = None, *, maxsize: int | None = DEFAULT_MAXSIZE
               ) -> Any:
    """Memoise a builder (LRU, `maxsize` entries; None: unbounded), building under
    `BUILD_LOCK`. Usable bare (`@built_once`) or with a size (`@built_once(maxsize=4)`)."""

    def decorate(builder: Callable[..., T]) -> Callable[..., T]:
        cached = lru_cache(maxsize=maxsize)(builder)
        _CACHES.append(cached)

        @wraps(builder)
        def wrapper(*args: Any, **kwargs: Any) -> T:
            with BUILD_LOCK:
                return cached(*args, **kwargs)

        wrapper.cache_info = cached.cache_info  # type: ignore[attr-defined]
        wrapper.cache_clear = cached.cache_clear  # type: ignore[attr-defined]
        return wrapper

    return decorate(fn) if fn is not None else decorate


def clear_built() -> None:
    """Forget every built NLP and function (memory is returned as the objects are freed)."""
    with BUILD_LOCK:
        for cache in _CACHES:
            cache.cache_clear()
