"""The numpy array types every module annotates with (one definition each)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["BoolArray", "FloatArray", "Int64Array", "IntArray", "sorted_unique"]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
Int64Array = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


def sorted_unique(a: npt.NDArray[np.integer]) -> npt.NDArray[np.integer]:
    """The distinct values of the 1-D integer array ``a``, sorted: ``np.unique(a)`` without
    its start-up cost (numpy >= 2.3 imports ``numpy.ma`` on the first plain ``np.unique``)."""
    s = np.sort(a, kind="stable")
    if len(s) == 0:
        return s
    keep = np.empty(len(s), dtype=np.bool_)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]
