"""Seeded joint-space sampling: uniform random and scrambled Halton, streamable in chunks.

Both samplers are pure numpy and deterministic for a given integer seed. The Halton sequence
is indexed: ``halton(n, d, start=s)`` gives points ``s … s+n-1`` of one fixed sequence, so a
million samples can be produced chunk by chunk in constant memory and give exactly (bit for
bit) the same points as one call. :func:`iter_samples` does that chunking.

Scrambling is a random digit permutation per base and digit position (the scheme of
``scipy.stats.qmc.Halton(scramble=True)``, seeded differently), computed in exact integer
arithmetic, which keeps the low discrepancy and removes the correlation of plain Halton in
higher dimensions.
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import lru_cache
from typing import Literal

import numpy as np
import numpy.typing as npt

from ..util.arrays import FloatArray, Int64Array

Method = Literal["halton", "uniform"]

__all__ = [
    "first_primes",
    "fresh_seed",
    "halton",
    "iter_samples",
    "sample_halton",
    "sample_rows",
    "sample_uniform",
]

_MAX_INDEX = 1 << 62
_ONE_MINUS = 1.0 - 2.0**-53  # largest float below 1.0


def first_primes(d: int) -> tuple[int, ...]:
    """The first ``d`` primes (the Halton bases)."""
    if d < 0:
        raise ValueError(f"d must be >= 0, got {d}")
    primes: list[int] = []
    candidate = 2
    while len(primes) < d:
        if all(candidate % p for p in primes if p * p <= candidate):
            primes.append(candidate)
        candidate += 1
    return tuple(primes)


def _digits(base: int) -> int:
    """Number of base-``base`` digits K with ``base**K <= 2**62`` (exact int64 arithmetic)."""
    k, power = 0, 1
    while power * base <= _MAX_INDEX:
        power *= base
        k += 1
    return k


@lru_cache(maxsize=32)
def _tables(
    d: int, seed: int | None, scramble: bool
) -> tuple[tuple[int, ...], tuple[npt.NDArray[np.int64], ...], tuple[npt.NDArray[np.int64], ...]]:
    """Per dimension: base, contribution table [K, base], tail sums [K + 1] (all int64).

    ``table[k, digit]`` is the value that digit contributes at position k (its permuted digit
    times ``base**(K-1-k)``); ``tail[k]`` is what the digit 0 contributes at all positions
    from k on (a point whose remaining index is 0 has only zero digits left).
    """
    rng = np.random.default_rng(seed)
    bases = first_primes(d)
    tables: list[npt.NDArray[np.int64]] = []
    tails: list[npt.NDArray[np.int64]] = []
    for base in bases:
        K = _digits(base)
        weights = np.array([base ** (K - 1 - k) for k in range(K)], dtype=np.int64)
        if scramble:
            perms = np.stack([rng.permutation(base) for _ in range(K)]).astype(np.int64)
        else:
            perms = np.tile(np.arange(base, dtype=np.int64), (K, 1))
        table = perms * weights[:, None]
        tail = np.zeros(K + 1, dtype=np.int64)
        tail[:K] = np.cumsum(table[::-1, 0])[::-1]
        table.flags.writeable = False
        tail.flags.writeable = False
        tables.append(table)
        tails.append(tail)
    return bases, tuple(tables), tuple(tails)


def halton(
    n: int,
    d: int,
    start: int = 0,
    *,
    seed: int | None = 0,
    scramble: bool = True,
) -> FloatArray:
    """Points ``start … start+n-1`` of the ``d``-dimensional Halton sequence, in [0, 1)^d.

    Returns an array [n, d]. With ``scramble`` (default) the digits are randomly permuted
    per base and position, drawn from ``seed``; the same ``seed`` always gives the same
    sequence, and chunks (``start=0, 4096, 8192, …``) concatenate to exactly the one-shot
    result. ``seed=None`` draws fresh entropy (then chunks do not match). Unscrambled, index
    0 is the origin (skip it with ``start=1`` if that matters).
    """
    if n < 0 or d < 0 or start < 0:
        raise ValueError(f"n, d and start must be >= 0, got n={n}, d={d}, start={start}")
    if start + n > _MAX_INDEX:
        raise ValueError("Halton index out of range: start + n must be <= 2**62")
    if seed is None and scramble:
        seed = _fresh_seed()
    bases, tables, tails = _tables(d, seed if scramble else None, scramble)
    out = np.empty((n, d))
    for j, base in enumerate(bases):
        table, tail = tables[j], tails[j]
        K = table.shape[0]
        index: Int64Array = np.arange(start, start + n, dtype=np.int64)
        acc = np.zeros(n, dtype=np.int64)
        k = 0
        while k < K and index.any():
            index, digit = np.divmod(index, base)
            acc += table[k][digit]
            k += 1
        acc += tail[k]
        col = out[:, j]
        np.multiply(acc, 1.0 / float(base**K), out=col)
        np.minimum(col, _ONE_MINUS, out=col)
    return out


def _fresh_seed() -> int:
    return int(np.random.SeedSequence().generate_state(1, np.uint64)[0])


def _bounds(lower: npt.ArrayLike, upper: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    lo = np.asarray(lower, dtype=np.float64)
    hi = np.asarray(upper, dtype=np.float64)
    if lo.ndim != 1 or lo.shape != hi.shape:
        raise ValueError(
            f"lower and upper must be 1-D of the same length, got shapes {list(lo.shape)} "
            f"and {list(hi.shape)}"
        )
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise ValueError("lower and upper must be finite (use [-pi, pi] for continuous joints)")
    bad = np.flatnonzero(lo > hi)
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"lower > upper in dimension {i}: {lo[i]} > {hi[i]}")
    return lo, hi


def _scale(unit: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
    unit *= hi - lo
    unit += lo
    np.minimum(unit, hi, out=unit)  # rounding must not step past the upper bound
    return unit


def sample_uniform(
    lower: npt.ArrayLike, upper: npt.ArrayLike, n: int, seed: int | None = 0
) -> FloatArray:
    """``n`` independent uniform samples [n, d] in the box ``[lower, upper]`` (both [d])."""
    lo, hi = _bounds(lower, upper)
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    rng = np.random.default_rng(seed)
    return _scale(rng.random((n, lo.shape[0])), lo, hi)


def sample_halton(
    lower: npt.ArrayLike,
    upper: npt.ArrayLike,
    n: int,
    seed: int | None = 0,
    skip: int = 0,
    *,
    scramble: bool = True,
) -> FloatArray:
    """``n`` scrambled-Halton samples [n, d] in ``[lower, upper]``, from index ``skip`` on.

    ``sample_halton(lo, hi, m, seed, skip=k)`` continues ``sample_halton(lo, hi, k, seed)``
    exactly, so a large sample can be drawn in chunks (see :func:`iter_samples`).
    """
    lo, hi = _bounds(lower, upper)
    return _scale(halton(n, lo.shape[0], skip, seed=seed, scramble=scramble), lo, hi)


def sample_rows(
    lower: npt.ArrayLike,
    upper: npt.ArrayLike,
    start: int,
    m: int,
    *,
    method: Method = "halton",
    seed: int = 0,
) -> FloatArray:
    """Rows ``start … start+m-1`` [m, d] of the stream that :func:`iter_samples` yields.

    Any part of a large sample can be drawn on its own (e.g. by a worker process), bit for bit
    equal to the same rows of the chunked stream: ``uniform`` jumps the PCG64 generator ahead
    by ``start · d`` draws (one 64-bit draw per value), ``halton`` starts at index ``start``.
    ``seed`` must be an integer here (draw one first for a fresh stream).
    """
    lo, hi = _bounds(lower, upper)
    if start < 0 or m < 0:
        raise ValueError(f"start and m must be >= 0, got start={start}, m={m}")
    d = lo.shape[0]
    if method == "halton":
        return _scale(halton(m, d, start, seed=seed), lo, hi)
    if method != "uniform":
        raise ValueError(f"method must be 'halton' or 'uniform', not {method!r}")
    bits = np.random.PCG64(seed)
    bits.advance(start * d)
    return _scale(np.random.Generator(bits).random((m, d)), lo, hi)


def fresh_seed() -> int:
    """A random integer seed (for a stream that is random but must be shared)."""
    return _fresh_seed()


def iter_samples(
    lower: npt.ArrayLike,
    upper: npt.ArrayLike,
    n: int,
    *,
    method: Method = "halton",
    seed: int | None = 0,
    chunk: int = 4096,
    skip: int = 0,
) -> Iterator[FloatArray]:
    """Yield ``n`` samples in chunks of at most ``chunk`` rows, each [m, d].

    The concatenated chunks equal ``sample_halton(lower, upper, n, seed, skip)`` or
    ``sample_uniform(lower, upper, n, seed)`` exactly, whatever ``chunk`` is (``skip`` only
    applies to Halton), while memory stays bounded by one chunk.
    """
    lo, hi = _bounds(lower, upper)
    if chunk <= 0:
        raise ValueError(f"chunk must be > 0, got {chunk}")
    if method not in ("halton", "uniform"):
        raise ValueError(f"method must be 'halton' or 'uniform', not {method!r}")
    rng = np.random.default_rng(seed) if method == "uniform" else None
    if method == "halton" and seed is None:
        seed = _fresh_seed()  # one seed for all chunks
    done = 0
    while done < n:
        m = min(chunk, n - done)
        if rng is not None:
            yield _scale(rng.random((m, lo.shape[0])), lo, hi)
        else:
            yield _scale(halton(m, lo.shape[0], skip + done, seed=seed), lo, hi)
        done += m
