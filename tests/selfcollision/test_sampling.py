"""Seeded uniform and scrambled-Halton sampling."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xrdf_tools.selfcollision.sampling import (
    first_primes,
    halton,
    iter_samples,
    sample_halton,
    sample_uniform,
)

LOWER = np.array([-2.9, -1.8, -math.pi, -3.1, 0.0, 0.05, 0.0])
UPPER = np.array([2.9, 1.8, math.pi, -0.07, 0.04, 0.05, 3.8])  # one zero-width joint


def test_first_primes() -> None:
    assert first_primes(0) == ()
    assert first_primes(10) == (2, 3, 5, 7, 11, 13, 17, 19, 23, 29)
    assert len(first_primes(50)) == 50 and first_primes(50)[-1] == 229


@pytest.mark.parametrize("sampler", [sample_uniform, sample_halton])
def test_bounds_respected(sampler) -> None:
    x = sampler(LOWER, UPPER, 5000, 3)
    assert x.shape == (5000, 7)
    assert np.all(x >= LOWER) and np.all(x <= UPPER)
    assert np.all(x[:, 5] == 0.05)
    span = x.max(axis=0) - x.min(axis=0)
    width = UPPER - LOWER
    np.testing.assert_array_less(width * 0.99 - 1e-12, span + 1e-12)  # the box is covered


@pytest.mark.parametrize("sampler", [sample_uniform, sample_halton])
def test_seeded_determinism(sampler) -> None:
    a = sampler(LOWER, UPPER, 300, 42)
    np.testing.assert_array_equal(a, sampler(LOWER, UPPER, 300, 42))
    assert not np.array_equal(a, sampler(LOWER, UPPER, 300, 43))


def test_halton_unit_cube_and_determinism() -> None:
    x = halton(2048, 12, seed=5)
    assert x.shape == (2048, 12) and x.dtype == np.float64
    assert x.min() >= 0.0 and x.max() < 1.0
    np.testing.assert_array_equal(x, halton(2048, 12, seed=5))
    # fewer dimensions are a prefix of more dimensions
    np.testing.assert_array_equal(halton(100, 3, seed=5), x[:100, :3])


def test_unscrambled_halton_is_the_radical_inverse() -> None:
    x = halton(9, 2, scramble=False)
    np.testing.assert_allclose(
        x[:, 0], [0, 1 / 2, 1 / 4, 3 / 4, 1 / 8, 5 / 8, 3 / 8, 7 / 8, 1 / 16]
    )
    np.testing.assert_allclose(x[:, 1], [0, 1 / 3, 2 / 3, 1 / 9, 4 / 9, 7 / 9, 2 / 9, 5 / 9, 8 / 9])
    qmc = pytest.importorskip("scipy.stats.qmc")
    ref = qmc.Halton(d=9, scramble=False).random(1000)
    np.testing.assert_allclose(halton(1000, 9, scramble=False), ref, rtol=0, atol=1e-15)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.integers(min_value=0, max_value=700), min_size=1, max_size=5),
    st.integers(min_value=0, max_value=10**12),
    st.integers(min_value=1, max_value=9),
    st.integers(min_value=0, max_value=2**31),
)
def test_halton_chunks_equal_one_shot(sizes: list[int], start: int, d: int, seed: int) -> None:
    one = halton(sum(sizes), d, start, seed=seed)
    parts, at = [], start
    for n in sizes:
        parts.append(halton(n, d, at, seed=seed))
        at += n
    np.testing.assert_array_equal(np.concatenate(parts), one)  # bit for bit


@pytest.mark.parametrize("method", ["halton", "uniform"])
def test_iter_samples_streams_the_same_points(method: str) -> None:
    chunks = list(iter_samples(LOWER, UPPER, 10_000, method=method, seed=9, chunk=3000))
    assert [len(c) for c in chunks] == [3000, 3000, 3000, 1000]
    whole = (
        sample_halton(LOWER, UPPER, 10_000, 9)
        if method == "halton"
        else sample_uniform(LOWER, UPPER, 10_000, 9)
    )
    np.testing.assert_array_equal(np.concatenate(chunks), whole)


def test_sample_halton_skip_continues() -> None:
    a = sample_halton(LOWER, UPPER, 1000, 1)
    b = sample_halton(LOWER, UPPER, 400, 1, skip=600)
    np.testing.assert_array_equal(a[600:], b)
    chunks = list(iter_samples(LOWER, UPPER, 400, seed=1, chunk=128, skip=600))
    np.testing.assert_array_equal(np.concatenate(chunks), b)


def test_low_discrepancy() -> None:
    n, d = 4096, 7
    x = halton(n, d, seed=11)
    u = np.random.default_rng(11).random((n, d))
    # the mean of a uniform sample is off by ~0.29/sqrt(n) = 0.0045; Halton does far better
    assert np.abs(x.mean(axis=0) - 0.5).max() < 1e-3
    # each 1-D projection fills 64 equal bins almost exactly evenly
    counts = np.stack([np.histogram(x[:, j], bins=64, range=(0, 1))[0] for j in range(d)])
    assert np.abs(counts - n / 64).max() <= 3
    qmc = pytest.importorskip("scipy.stats.qmc")
    assert qmc.discrepancy(x) < 0.2 * qmc.discrepancy(u)


def test_scrambling_decorrelates_high_dimensions() -> None:
    # plain Halton in bases 43 and 47 (dims 14 and 15) is almost perfectly correlated early on
    plain = halton(40, 15, scramble=False)
    scrambled = halton(40, 15, seed=0)
    assert abs(np.corrcoef(plain[:, 13], plain[:, 14])[0, 1]) > 0.99
    assert abs(np.corrcoef(scrambled[:, 13], scrambled[:, 14])[0, 1]) < 0.3


def test_continuous_joint_range() -> None:
    x = sample_halton([-math.pi], [math.pi], 1000, 0)
    assert x.min() >= -math.pi and x.max() <= math.pi
    assert abs(x.mean()) < 0.01


@pytest.mark.parametrize(
    ("lower", "upper", "match"),
    [
        ([0.0, 1.0], [1.0], "same length"),
        ([[0.0]], [[1.0]], "1-D"),
        ([1.0], [0.0], "lower > upper in dimension 0"),
        ([-np.inf], [0.0], "finite"),
    ],
)
def test_bad_bounds(lower, upper, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        sample_uniform(lower, upper, 3, 0)
    with pytest.raises(ValueError, match=match):
        sample_halton(lower, upper, 3, 0)


def test_bad_arguments() -> None:
    with pytest.raises(ValueError, match="must be >= 0"):
        halton(-1, 2)
    with pytest.raises(ValueError, match="out of range"):
        halton(10, 2, start=2**62)
    with pytest.raises(ValueError, match="chunk"):
        next(iter_samples([0.0], [1.0], 10, chunk=0))
    with pytest.raises(ValueError, match="method"):
        next(iter_samples([0.0], [1.0], 10, method="sobol"))  # type: ignore[arg-type]
    assert sample_uniform([0.0], [1.0], 0, 0).shape == (0, 1)
    assert halton(5, 0).shape == (5, 0)


def test_unseeded_scrambled_stream_is_consistent() -> None:
    chunks = list(iter_samples([0.0, 0.0], [1.0, 1.0], 50, seed=None, chunk=20))
    x = np.concatenate(chunks)
    assert x.shape == (50, 2) and len(np.unique(x[:, 0])) == 50
