"""``--jobs``: the sampling driver, in this process or spread over worker processes.

:func:`count_sampled` cuts a sample stream (:func:`xrdf_tools.selfcollision.sampling.sample_rows`)
into chunks and counts them with one :class:`~xrdf_tools.selfcollision.engine.CountEngine`, here or
in spawned workers that each receive a copy of the engine once and pin BLAS/OpenMP to one thread.
Every chunk's totals are sums and minima, so the result does not depend on the number of workers or
on the order in which chunks come back.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from multiprocessing import get_context

import numpy as np
import numpy.typing as npt

from ...util.errors import XrdfToolsError
from ..sampling import Method, sample_rows
from .core import CountEngine, EngineTotals

FloatArray = npt.NDArray[np.float64]

__all__ = ["MAX_SAMPLES", "MIN_SAMPLES_PER_JOB", "ProgressFn", "count_sampled", "default_jobs"]

#: Ceiling on one report's samples (docs/security.md): the chunk list stays small.
MAX_SAMPLES = 10**10
#: Below this many samples per worker, starting a worker process costs more than it saves.
MIN_SAMPLES_PER_JOB = 1_000_000
_BLAS_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")
ProgressFn = Callable[[int, int], None]
_WORKER: dict[str, CountEngine] = {}


def default_jobs() -> int:
    """The CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def count_sampled(
    engine: CountEngine,
    lower: npt.ArrayLike,
    upper: npt.ArrayLike,
    n: int,
    *,
    method: Method,
    seed: int,
    chunk: int,
    jobs: int = 1,
    progress: ProgressFn | None = None,
) -> EngineTotals:
    """Count ``n`` samples of the stream ``sample_rows(lower, upper, …, method, seed)``.

    The sample is cut into chunks of ``chunk`` rows; with ``jobs > 1`` the chunks go to worker
    processes (each pinned to one BLAS thread). Totals are sums and minima over chunks, so the
    result is identical for any ``jobs``. Fewer workers are started when the sample is small
    (at least :data:`MIN_SAMPLES_PER_JOB` samples each).
    """
    if n > MAX_SAMPLES:
        raise XrdfToolsError(f"--samples {n:,} is above the ceiling of {MAX_SAMPLES:,}")
    tasks = [(s0, min(chunk, n - s0)) for s0 in range(0, n, chunk)]
    workers = max(1, min(jobs, n // MIN_SAMPLES_PER_JOB, len(tasks)))
    totals = EngineTotals.empty(engine.K)
    lo, hi = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
    done = 0
    if workers == 1:
        parts: Iterator[EngineTotals] = (
            _count_rows(engine, lo, hi, s0, m, method, seed) for s0, m in tasks
        )
        for part in parts:
            totals.merge(part)
            done += part.configurations
            if progress is not None:
                progress(done, n)
        return totals
    with (
        _one_blas_thread(),
        ProcessPoolExecutor(
            max_workers=workers,
            mp_context=get_context("spawn"),
            initializer=_worker_init,
            initargs=(engine,),
        ) as pool,
    ):
        futures = [pool.submit(_worker_rows, lo, hi, s0, m, method, seed) for s0, m in tasks]
        for fut in as_completed(futures):
            part = fut.result()
            totals.merge(part)
            done += part.configurations
            if progress is not None:
                progress(done, n)
    return totals


def _count_rows(
    engine: CountEngine,
    lo: FloatArray,
    hi: FloatArray,
    start: int,
    m: int,
    method: Method,
    seed: int,
) -> EngineTotals:
    totals = EngineTotals.empty(engine.K)
    engine.count(sample_rows(lo, hi, start, m, method=method, seed=seed), totals)
    return totals


def _worker_init(engine: CountEngine) -> None:
    _WORKER["engine"] = engine


def _worker_rows(
    lo: FloatArray, hi: FloatArray, start: int, m: int, method: Method, seed: int
) -> EngineTotals:
    return _count_rows(_WORKER["engine"], lo, hi, start, m, method, seed)


@contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Worker processes inherit this environment: one BLAS/OpenMP thread each."""
    saved = {v: os.environ.get(v) for v in _BLAS_VARS}
    os.environ.update(dict.fromkeys(_BLAS_VARS, "1"))
    try:
        yield
    finally:
        for v, old in saved.items():
            if old is None:
                os.environ.pop(v, None)
            else:
                os.environ[v] = old
