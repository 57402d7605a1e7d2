"""Positions in a text: the 1-based line and column of a character offset."""

from __future__ import annotations

__all__ = ["line_col"]


def line_col(text: str, offset: int) -> tuple[int, int]:
    """The 1-based line and column of ``text[offset]``."""
    return text.count("\n", 0, offset) + 1, offset - (text.rfind("\n", 0, offset) + 1) + 1
