"""One way to run independent tasks: in this process, in local worker processes, or on a Dask
cluster.

Every executor maps a picklable top-level function over a list of items and returns the results
in the items' order, so the numbers do not depend on which executor ran them (each task is a
deterministic solve with one BLAS thread). Items are sent in chunks — a few per worker — so that
each task is well above the per-task overhead of process pools and schedulers; the function and
its bound arguments (a description, a few points) are what travels, never large arrays.

* ``workers=1`` (default): in this process, on ``threads`` threads (default 1). SciPy's
  sparse LU and LAPACK release the GIL, so the frequencies of a small problem factorise side by
  side on the cores; :func:`frequency_threads` chooses the count the memory allows.
* ``workers=N``: ``N`` local processes (``spawn``: a fresh interpreter each, which inherits the
  one-thread BLAS settings that :func:`updating.cli.main` sets).
* ``scheduler="tcp://host:8786"``: a running ``dask.distributed`` scheduler (the
  ``distributed`` extra); its workers need vtcr installed.
"""

from __future__ import annotations

import ctypes
import math
import multiprocessing
import os
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from typing import TYPE_CHECKING, Literal, Self, TypeVar

from updating.errors import InputError

if TYPE_CHECKING:
    from distributed import Client

_T = TypeVar("_T")
_R = TypeVar("_R")

__all__ = ["Executor", "CHUNKS_PER_WORKER", "frequency_threads", "thread_map", "usable_cores"]

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc mallopt parameters (malloc.h)

CONNECT_TIMEOUT = "20s"
"""How long to try reaching a scheduler before saying it cannot be reached."""

CHUNKS_PER_WORKER = 4
"""Chunks per worker and per map: enough to balance uneven tasks, few enough that each chunk
holds several solves."""


def _keep_freed_memory() -> None:
    """Let a worker keep the memory it frees, where the C library is glibc.

    A solve allocates and frees arrays of a few MB; by default glibc hands freed memory back
    to the system (Dask's nanny even sets ``MALLOC_TRIM_THRESHOLD_=65536`` for its workers),
    and every page taken again is a page fault, about 2.5 us each on a virtual machine. That
    made the tasks of Dask workers 25 % slower than the same solves in one process; raising
    the trim and mmap thresholds (the latter to glibc's 32 MB cap) removes the difference.
    """
    if _keep_freed_memory.done:
        return
    _keep_freed_memory.done = True
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(M_TRIM_THRESHOLD, 1 << 30)
        libc.mallopt(M_MMAP_THRESHOLD, 1 << 25)
    except (OSError, AttributeError):  # not glibc: its own allocator policy stands
        pass


_keep_freed_memory.done = False


def usable_cores() -> int:
    """Cores this process may run on (its CPU affinity, which job schedulers and ``taskset``
    restrict), else the machine's."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def frequency_threads(tasks: int, task_bytes: float, available_bytes: float | None) -> int:
    """Threads for ``tasks`` independent per-frequency solves of ``task_bytes`` peak memory each:
    one per usable core and per task, as many as fit in half the ``available_bytes`` (None:
    unknown, then one)."""
    if available_bytes is None or task_bytes <= 0:
        return 1
    fit = int(0.5 * available_bytes // task_bytes)
    return max(1, min(usable_cores(), tasks, fit))


def thread_map(function: Callable[[_T], _R], items: Iterable[_T], threads: int) -> list[_R]:
    """``[function(item) for item in items]`` on up to ``threads`` threads, in order.

    For tasks that spend their time in compiled code releasing the GIL (sparse and dense
    factorisations); each task is deterministic, so the results do not depend on ``threads``.
    """
    items = list(items)
    if threads <= 1 or len(items) <= 1:
        return [function(item) for item in items]
    with ThreadPoolExecutor(min(threads, len(items))) as pool:
        return list(pool.map(function, items))


def _run_chunk(function: Callable[[_T], _R], chunk: Iterable[_T]) -> list[_R]:
    _keep_freed_memory()
    return [function(item) for item in chunk]


def _chunks(items: Sequence[_T], count: int) -> list[Sequence[_T]]:
    size = max(1, math.ceil(len(items) / max(count, 1)))
    return [items[i:i + size] for i in range(0, len(items), size)]


class Executor:
    """``map(function, items) -> list`` on one of the three back-ends (see the module docstring).

    Use as a context manager: the worker processes or the cluster connection are closed on exit.
    """

    _pool: ProcessPoolExecutor | None
    _client: Client | None

    def __init__(self, workers: int = 1, scheduler: str | None = None, threads: int = 1) -> None:
        if workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        self.workers, self.scheduler, self.threads = workers, scheduler, threads
        self._pool = self._client = None

    def __enter__(self) -> Self:
        if self.scheduler is not None:
            try:
                from distributed import Client
            except ImportError:
                raise InputError(f"scheduler {self.scheduler}: a Dask scheduler needs "
                                 "dask.distributed: pip install 'distributed>=2024.1' (the "
                                 "extra distributed of vtcr)") from None
            try:
                self._client = Client(self.scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as err:
                raise InputError(f"scheduler {self.scheduler}: cannot connect ({err}); start "
                                 "a scheduler there (dask scheduler) or give the address it "
                                 "prints, e.g. tcp://node1:8786") from None
            self.workers = max(1, len(self._client.scheduler_info()["workers"]))
        elif self.workers > 1:
            self._pool = ProcessPoolExecutor(self.workers,
                                             mp_context=multiprocessing.get_context("spawn"))
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
        if self._client is not None:
            self._client.close()
        self._pool = self._client = None
        return False

    @property
    def description(self) -> str:
        if self.scheduler is not None:
            return f"Dask scheduler {self.scheduler} ({self.workers} workers)"
        if self.workers > 1:
            return f"{self.workers} local processes"
        return f"this process ({self.threads} threads)" if self.threads > 1 else "this process"

    def map(self, function: Callable[[_T], _R], items: Iterable[_T]) -> list[_R]:
        """``[function(item) for item in items]``, possibly in parallel, in order."""
        items = list(items)
        if self._pool is None and self._client is None or len(items) <= 1:
            return thread_map(function, items, self.threads)
        chunks = _chunks(items, CHUNKS_PER_WORKER * self.workers)
        if self._client is not None:
            futures = self._client.map(_run_chunk, [function] * len(chunks), chunks, pure=False)
            results = self._client.gather(futures)
        else:
            results = list(self._pool.map(_run_chunk, [function] * len(chunks), chunks))
        return [value for chunk in results for value in chunk]

