"""Names in a one-line message: a robot can have thousands, a message shows a few."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["name_list"]


def name_list(names: Iterable[object], limit: int = 8) -> str:
    """``a, b, c and 5 more``: the first ``limit`` names, then how many were left out."""
    shown = [str(n) for n in names]
    if len(shown) <= limit:
        return ", ".join(shown)
    return ", ".join(shown[:limit]) + f" and {len(shown) - limit} more"
