"""Names a list gives more than once (``cspace.joint_names``, ``tool_frames``)."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import TypeVar

P = TypeVar("P")

__all__ = ["repeats"]


def repeats(named: Iterable[tuple[str, P]]) -> Iterator[tuple[str, P, P]]:
    """``(name, entry, first entry)`` for every entry of ``named`` (name, entry) whose name an
    earlier entry already has."""
    first: dict[str, P] = {}
    for n, entry in named:
        if n in first:
            yield n, entry, first[n]
        else:
            first[n] = entry
