"""``--jobs``: the sampling driver, in this process or spread over worker processes.

:func:`count_sampled` cuts a sample stream (:func:`xrdf_tools.selfcollision.sampling.sample_rows`)
into chunks and counts them with one :class:`~xrdf_tools.selfcollision.engine.CountEngine`, here or
in spawned workers that each receive a copy of the engine once and pin BLAS/OpenMP to one thread.
Every chunk's totals are sums and minima, so the result does not depend on the number of workers or
on the order in which chunks come back.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from itertools import islice
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ...util.arrays import FloatArray
from ...util.numbers import MAX_SAMPLES
from ...util.processes import sigint_held
from ..sampling import Method, sample_rows
from .core import CountEngine, EngineTotals

if TYPE_CHECKING:
    from concurrent.futures import Future, ProcessPoolExecutor

__all__ = ["MAX_SAMPLES", "MIN_SAMPLES_PER_JOB", "ProgressFn", "count_sampled", "default_jobs"]

#: Longest wait (s) for a stopped pool's manager thread to end.
_MANAGER_JOIN_S = 0.5
#: Below this many samples per worker, starting a worker process costs more than it saves.
MIN_SAMPLES_PER_JOB = 1_000_000

_BLAS_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")
ProgressFn = Callable[[int, int], None]
_POLL_S = 0.05
_WORKER: dict[str, CountEngine] = {}
#: A worker's smallest exact clearances so far (see :func:`_count_rows`).
_KNOWN: dict[str, FloatArray] = {}
#: The pools of the counts under way in this process.
_LIVE: set[ProcessPoolExecutor] = set()


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

    The sample is cut into chunks of ``chunk`` rows, made one at a time (memory does not grow
    with ``n``, at most :data:`MAX_SAMPLES`); with ``jobs > 1`` the chunks go to worker
    processes (each pinned to one BLAS thread), never more than the cores
    (:func:`default_jobs`) and a few chunks ahead of the results. Totals are sums and minima
    over chunks, so the result is identical for any ``jobs``. Fewer workers are started when
    the sample is small (at least :data:`MIN_SAMPLES_PER_JOB` samples each).

    An interrupt (``KeyboardInterrupt``, or ``SystemExit`` from a SIGTERM handler) stops the
    workers at once: they are killed, no queued chunk runs on.
    """
    if not 0 <= n <= MAX_SAMPLES:
        raise ValueError(f"{n} samples: at most {MAX_SAMPLES:,} can be counted")
    if chunk < 1:
        raise ValueError(f"chunk must be at least 1, got {chunk}")
    n_tasks = -(-n // chunk)
    workers = max(1, min(jobs, default_jobs(), n // MIN_SAMPLES_PER_JOB, n_tasks))
    tasks = ((s0, min(chunk, n - s0)) for s0 in range(0, n, chunk))
    lo, hi = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
    totals = EngineTotals.empty(engine.K)
    if workers == 1:  # progress also from within each chunk (a chunk may be most of n)
        known = np.full(engine.K, np.inf)
        for s0, m in tasks:
            within = None if progress is None else _within(progress, s0, m, n)
            totals.merge(_count_rows(engine, lo, hi, s0, m, method, seed, known, within))
            if progress is not None:
                progress(s0 + m, n)
        return totals
    done = 0
    for part in _in_workers(engine, workers, tasks, (lo, hi, method, seed)):
        totals.merge(part)
        done += part.configurations
        if progress is not None:
            progress(done, n)
    if totals.configurations != n:  # never a silently partial count
        raise RuntimeError(f"{totals.configurations:,} of {n:,} samples were counted")
    return totals


def _within(progress: ProgressFn, start: int, m: int, n: int) -> Callable[[float], None]:
    """``progress`` for a fraction of the chunk of ``m`` rows from ``start`` (before its end)."""

    def step(fraction: float) -> None:
        if fraction < 1.0:
            progress(start + int(fraction * m), n)

    return step


def _in_workers(
    engine: CountEngine,
    workers: int,
    tasks: Iterator[tuple[int, int]],
    stream: tuple[FloatArray, FloatArray, Method, int],
) -> Iterator[EngineTotals]:
    """The totals of each task, counted by ``workers`` spawned processes, in completion order.

    At most two tasks per worker are queued at a time, and results are waited for in short
    steps (Python runs a signal handler only in the main thread, when a wait returns). The
    workers ignore SIGINT from their start: a Ctrl-C at the terminal, which reaches the whole
    process group, interrupts only this process, which then kills them; they print nothing.
    """
    # imported here: a count in this process (most reports) needs no process pool
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
    from multiprocessing import get_context

    lo, hi, method, seed = stream
    ctx = get_context("spawn")
    # The engine reaches each worker through a queue (written by the queue's own thread), not
    # as an initializer argument: those are written to a starting worker by this thread,
    # which then waits, deaf to signals, until the worker has imported numpy.
    engines: Any = ctx.Queue()
    pool = ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_worker_init, initargs=(engines,)
    )
    pending: set[Future[EngineTotals]] = set()
    _LIVE.add(pool)
    try:
        with _one_blas_thread(), sigint_held():
            for _ in range(workers):
                engines.put(engine)
            # the first `workers` submissions start the processes
            for s0, m in islice(tasks, workers):
                pending.add(pool.submit(_worker_rows, lo, hi, s0, m, method, seed))
        while True:
            for s0, m in islice(tasks, 2 * workers - len(pending)):
                pending.add(pool.submit(_worker_rows, lo, hi, s0, m, method, seed))
            if not pending:  # every task submitted and its result given
                break
            # a short timeout: a signal delivered to another thread (BLAS's) does not wake a
            # blocked wait, and Python runs its handler only when the wait returns
            finished, pending = wait(pending, timeout=_POLL_S, return_when=FIRST_COMPLETED)
            for fut in finished:
                yield fut.result()
    except BaseException:
        _kill(pool)
        raise
    finally:
        _LIVE.discard(pool)
        engines.cancel_join_thread()  # what a killed worker did not read is dropped
        engines.close()
    pool.shutdown(wait=True)


def stop_workers() -> None:
    """Kill the worker processes of every count under way (for a process about to exit at once,
    without unwinding)."""
    for pool in list(_LIVE):
        for proc in list((getattr(pool, "_processes", None) or {}).values()):
            with suppress(Exception):
                proc.kill()


def _kill(pool: ProcessPoolExecutor) -> None:
    """Stop ``pool`` now: its processes killed, its queued work dropped."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    # the pool's manager thread closes its wake-up pipe as it ends; it is let end here, or the
    # interpreter's exit may write to that pipe while it is being closed (a traceback)
    manager = getattr(pool, "_executor_manager_thread", None)
    for proc in processes:
        with suppress(Exception):
            proc.kill()
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        with suppress(Exception):
            proc.join(0.2)
    if manager is not None:
        manager.join(_MANAGER_JOIN_S)


def _count_rows(
    engine: CountEngine,
    lo: FloatArray,
    hi: FloatArray,
    start: int,
    m: int,
    method: Method,
    seed: int,
    known: FloatArray,
    on_step: Callable[[float], None] | None = None,
) -> EngineTotals:
    """The totals of rows ``start … start + m`` of the stream. ``known`` [K]: the smallest
    exact clearances this process has found so far (updated here); they narrow the work, not
    the totals' clearances (:meth:`CountEngine.count`), so any split over processes agrees."""
    totals = EngineTotals.empty(engine.K)
    q = sample_rows(lo, hi, start, m, method=method, seed=seed)
    engine.count_totals(q, totals, known=known, on_step=on_step)
    np.minimum(known, totals.min_clearance, out=known)
    return totals


def _worker_init(engines: Any) -> None:
    # the parent stops the workers; a Ctrl-C at the terminal is the parent's to handle
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    engine = engines.get()
    _WORKER["engine"] = engine
    _KNOWN["clearance"] = np.full(engine.K, np.inf)


def _worker_rows(
    lo: FloatArray, hi: FloatArray, start: int, m: int, method: Method, seed: int
) -> EngineTotals:
    return _count_rows(_WORKER["engine"], lo, hi, start, m, method, seed, _KNOWN["clearance"])


class _BlasEnvironment:
    """The BLAS/OpenMP variables set to one thread while any count in this process starts
    workers, and put back as they were when the last one is done: counts started from
    several threads at once share the change instead of restoring each other's values."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.users = 0
        self.saved: dict[str, str | None] = {}

    def enter(self) -> None:
        with self.lock:
            if self.users == 0:
                self.saved = {v: os.environ.get(v) for v in _BLAS_VARS}
                os.environ.update(dict.fromkeys(_BLAS_VARS, "1"))
            self.users += 1

    def leave(self) -> None:
        with self.lock:
            self.users -= 1
            if self.users:
                return
            for v, old in self.saved.items():
                if old is None:
                    os.environ.pop(v, None)
                else:
                    os.environ[v] = old


_BLAS_ENV = _BlasEnvironment()


@contextmanager
def _one_blas_thread() -> Iterator[None]:
    """Worker processes inherit this environment: one BLAS/OpenMP thread each."""
    _BLAS_ENV.enter()
    try:
        yield
    finally:
        _BLAS_ENV.leave()
