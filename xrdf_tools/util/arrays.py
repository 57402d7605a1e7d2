"""The numpy array types every module annotates with (one definition each)."""

from __future__ import annotations

from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt

__all__ = [
    "AnyArray",
    "BoolArray",
    "FloatArray",
    "Int64Array",
    "IntArray",
    "ragged_index",
    "sorted_unique",
]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
Int64Array = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]
#: an array of any dtype (what a bare ``np.ndarray`` means; numpy < 2.3 stubs need the argument)
AnyArray = npt.NDArray[Any]


_Integer = TypeVar("_Integer", bound=np.integer)


def sorted_unique(a: npt.NDArray[_Integer]) -> npt.NDArray[_Integer]:
    """The distinct values of the 1-D integer array ``a``, sorted: ``np.unique(a)`` without
    its start-up cost (numpy >= 2.3 imports ``numpy.ma`` on the first plain ``np.unique``)."""
    s = np.sort(a, kind="stable")
    if len(s) == 0:
        return s
    keep = np.empty(len(s), dtype=np.bool_)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def ragged_index(counts: npt.NDArray[np.integer]) -> tuple[IntArray, IntArray]:
    """For groups of ``counts[g]`` consecutive items: each item's group and its place in the
    group (``[0, 0, 1, 1, 1]`` and ``[0, 1, 0, 1, 2]`` for counts ``[2, 3]``)."""
    n = np.asarray(counts, dtype=np.intp)
    group = np.repeat(np.arange(len(n), dtype=np.intp), n)
    rank: IntArray = np.arange(len(group), dtype=np.intp) - np.repeat(np.cumsum(n) - n, n)
    return group, rank
