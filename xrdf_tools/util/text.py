"""Names in a one-line message: a robot can have thousands, a message shows a few."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["name_list", "pair_text"]


def name_list(names: Iterable[object], limit: int = 8, sep: str = ", ") -> str:
    """``a, b, c and 5 more``: the first ``limit`` names, then how many were left out
    (``sep`` between them: ``"; "`` for items that hold commas themselves)."""
    shown = [str(n) for n in names]
    if len(shown) <= limit:
        return sep.join(shown)
    return sep.join(shown[:limit]) + f" and {len(shown) - limit} more"


def pair_text(a: object, b: object) -> str:
    """A frame or link pair in a message: ``a/b``; ``a <-> b`` when a name holds a ``/``
    itself (a prefixed robot's ``locobot/ar_tag_link``), where ``a/b`` could not be read."""
    if "/" in f"{a}{b}":
        return f"{a} <-> {b}"
    return f"{a}/{b}"
