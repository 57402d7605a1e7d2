"""Equality within a tolerance, and how numbers and names are written in change messages."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TypeVar

K = TypeVar("K")


def close(x: float | None, y: float | None, tol: float) -> bool:
    """``|x - y| ≤ tol``; two NaNs are equal, and ``None`` (a value not given) only to ``None``."""
    if x is None or y is None:
        return x is y
    if x == y or (math.isnan(x) and math.isnan(y)):
        return True
    return abs(x - y) <= tol


def close_all(xs: Sequence[float], ys: Sequence[float], tol: float) -> bool:
    """Same length and :func:`close` component by component (vectors, quaternions)."""
    return len(xs) == len(ys) and all(close(x, y, tol) for x, y in zip(xs, ys, strict=True))


def exact(x: object, y: object, tol: float) -> bool:
    """Plain equality, for names and other non-numeric values (``tol`` is not used)."""
    return x == y


def num(v: float | None) -> str:
    """A number as messages show it: ``repr`` of the float, ``none`` when not given."""
    return "none" if v is None else repr(float(v))


def vec(v: Sequence[float]) -> str:
    return "[" + ", ".join(repr(float(c)) for c in v) + "]"


def plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def names(items: Iterable[str]) -> str:
    return "[" + ", ".join(items) + "]"


def union(a: Iterable[K], b: Iterable[K]) -> list[K]:
    """Keys of ``a`` then the new keys of ``b``, each once (deterministic document order)."""
    out = dict.fromkeys(a)
    out.update(dict.fromkeys(b))
    return list(out)


def relative_order(items: Sequence[K], keep: set[K]) -> list[K]:
    """The items of ``keep`` in the order ``items`` lists them first."""
    seen: set[K] = set()
    out = []
    for n in items:
        if n in keep and n not in seen:
            seen.add(n)
            out.append(n)
    return out
