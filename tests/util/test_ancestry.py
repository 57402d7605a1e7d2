"""util.ancestry: lowest common ancestors and ancestors at a depth against walks up the tree."""

from __future__ import annotations

import numpy as np
import pytest

from xrdf_tools.util.ancestry import Ancestry


def _root_path(parent: list[int], x: int) -> list[int]:
    out = [x]
    while parent[out[-1]] >= 0:
        out.append(parent[out[-1]])
    return out[::-1]  # root first: index = depth


def _trees() -> dict[str, list[int]]:
    rng = np.random.default_rng(7)
    branchy = [-1] + [int(rng.integers(max(0, i - 5), i)) for i in range(1, 120)]
    return {
        "chain": [-1, *range(0, 129)],  # depth 129: eight lifting levels
        "star": [-1] + [0] * 40,
        "branchy": branchy,
        "root only": [-1],
        "two chains": [-1, 0, 1, 2, 0, 4, 5, 6],
    }


@pytest.mark.parametrize("name", list(_trees()))
def test_lca_and_ancestor_equal_walks_up_the_tree(name: str) -> None:
    parent = _trees()[name]
    tree = Ancestry(parent)
    n = len(parent)
    paths = [_root_path(parent, x) for x in range(n)]
    assert tree.depth.tolist() == [len(p) - 1 for p in paths]
    a, b = (g.ravel() for g in np.meshgrid(np.arange(n), np.arange(n)))
    expected = []
    for x, y in zip(a.tolist(), b.tolist(), strict=True):
        common = [u for u, v in zip(paths[x], paths[y], strict=False) if u == v]
        expected.append(common[-1])
    assert tree.lca(a, b).tolist() == expected
    depth = np.array([int(np.random.default_rng(x).integers(0, len(paths[x]))) for x in a])
    assert tree.ancestor(a, depth).tolist() == [paths[x][d] for x, d in zip(a, depth, strict=True)]
