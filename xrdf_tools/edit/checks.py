"""What every edit of ``xrdf edit`` checks: the error it raises and the numbers a saved file
can hold."""

from __future__ import annotations

from ..util.errors import XrdfToolsError
from ..util.numbers import bound_reason

__all__ = ["EditError", "checked_number"]


class EditError(XrdfToolsError):
    """An edit that does not fit the document (unknown sphere, no self_collision section)."""


def checked_number(what: str, value: float, *, metres: bool = True) -> float:
    """``value`` as a float, or :class:`EditError` when a saved file could not hold it
    (not finite, or past the bound every reader applies: see :mod:`xrdf_tools.util.numbers`)."""
    v = float(value)
    reason = bound_reason(v, metres=metres)
    if reason is not None:
        raise EditError(f"{what} {v:g} cannot be saved: {reason}")
    return v
