"""util.arrays.ragged_index: each item's group and place, for groups of given sizes."""

from __future__ import annotations

import numpy as np
import pytest

from xrdf_tools.util.arrays import ragged_index


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ragged_index_equals_a_loop_over_the_groups(seed: int) -> None:
    counts = np.random.default_rng(seed).integers(0, 5, size=12)  # empty groups too
    group, rank = ragged_index(counts)
    expected = [(g, i) for g, n in enumerate(counts.tolist()) for i in range(n)]
    assert list(zip(group.tolist(), rank.tolist(), strict=True)) == expected


def test_no_groups_give_no_items() -> None:
    group, rank = ragged_index(np.zeros(0, dtype=np.intp))
    assert len(group) == 0 and len(rank) == 0
