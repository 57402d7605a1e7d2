"""util.arrays.sorted_unique: np.unique's values without its start-up cost."""

from __future__ import annotations

import numpy as np
import pytest

from xrdf_tools.util.arrays import sorted_unique


@pytest.mark.parametrize("n", [0, 1, 2, 7, 1000])
def test_sorted_unique_is_the_sorted_set(n: int) -> None:
    rng = np.random.default_rng(n)
    for dtype in (np.intp, np.int64, np.int32):
        a = rng.integers(-5, 5 + n // 10, size=n).astype(dtype)
        got = sorted_unique(a)
        assert got.dtype == a.dtype
        assert got.tolist() == sorted(set(a.tolist()))
