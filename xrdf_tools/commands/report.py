"""`xrdf report` (not implemented yet)."""

from __future__ import annotations

from .common import not_implemented


def command() -> None:
    """Not implemented yet: exits with code 2."""
    not_implemented("report")
