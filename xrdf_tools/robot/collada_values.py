"""The small parts of a COLLADA document as pycollada reads them, for
:mod:`~xrdf_tools.robot.collada_points`: its errors, ``#id`` references, number lists and
node transforms (``<translate>``, ``<rotate>``, ``<scale>``, ``<matrix>``, composed in single
precision)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..util.arrays import AnyArray
from ..util.errors import XrdfToolsError

__all__ = ["TRANSFORMS", "ColladaNotRead", "ColladaTooBig", "composed", "fail", "numbers", "ref"]


class ColladaNotRead(XrdfToolsError):
    """The file holds something this reader does not handle (the message says what)."""


class ColladaTooBig(ColladaNotRead):
    """The scene expands past a bound of :func:`check_collada_bounds`: too deep, too many
    nodes or geometry instances, or an ``<instance_node>`` cycle. No reader should walk it."""


def fail(message: str, element: Any = None, kind: type[ColladaNotRead] = ColladaNotRead) -> Any:
    line = getattr(element, "sourceline", None)
    return kind(message, line=line or None)


def ref(element: Any, attribute: str) -> str | None:
    """The id a ``#id`` attribute refers to (None: none, or not local to the file)."""
    value = None if element is None else element.get(attribute)
    return value[1:] if value and value.startswith("#") else None


def numbers(element: Any, dtype: type) -> AnyArray:
    """The numbers of ``element``'s text; a child (an entity reference) or a word that is not
    a number raises."""
    if len(element):
        raise fail(f"<{element.tag.rpartition('}')[2]}> with child nodes", element)
    text = element.text
    if text is None or text.isspace():
        return np.zeros(0, dtype=dtype)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            values: AnyArray = np.fromstring(text, dtype=dtype, sep=" ")
        except (ValueError, DeprecationWarning):
            raise fail("a number that does not parse", element) from None
    return values


def _translate(v: AnyArray, element: Any) -> AnyArray:
    _count(v, 3, element)
    m = np.identity(4, dtype=np.float32)
    m[:3, 3] = v
    return m


def _scale(v: AnyArray, element: Any) -> AnyArray:
    _count(v, 3, element)
    m = np.identity(4, dtype=np.float32)
    m[0, 0], m[1, 1], m[2, 2] = v
    return m


def _rotate(v: AnyArray, element: Any) -> AnyArray:
    """pycollada's ``makeRotationMatrix`` (the axis taken as written, not normalised)."""
    _count(v, 4, element)
    x, y, z = v[0], v[1], v[2]
    angle = v[3] * np.pi / 180.0
    c, s = np.cos(angle), np.sin(angle)
    t = 1 - c
    rows = [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
        [0, 0, 0, 1],
    ]
    return np.array(rows, dtype=np.float32)


def _matrix(v: AnyArray, element: Any) -> AnyArray:
    _count(v, 16, element)
    return v.reshape(4, 4)


def _count(values: AnyArray, count: int, element: Any) -> None:
    if len(values) != count or not np.all(np.isfinite(values)):
        raise fail(f"a transform of {len(values)} numbers, not {count} finite", element)


TRANSFORMS = {"translate": _translate, "scale": _scale, "rotate": _rotate, "matrix": _matrix}


def composed(transforms: list[AnyArray]) -> AnyArray:
    """A node's transforms composed as pycollada composes them (single precision)."""
    if not transforms:
        return np.identity(4)
    matrix: AnyArray = transforms[0].copy()
    for transform in transforms[1:]:
        matrix = np.dot(matrix, transform)
    return matrix
