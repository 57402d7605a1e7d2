"""Number fields the page reads itself: lengths and limits typed as text.

viser's number field (Mantine's) drops what is not a digit, a point or a leading minus, and
sends every keystroke: ``1e-3`` typed in it arrived as 1, then 13 (and ``1.5e-2`` as
-1.52), each applied as an edit. A :class:`TypedNumber` is a text field whose text the page
parses: ``1e-3``, ``0.001``, ``-2``, ``.5`` are numbers; what is not one yet (``-``, ``1e``,
an empty field) is left alone until it is. The page never rewrites the text while it reads
as the document's value, nor while it makes the edit the text asked for (the browser may
have sent the next keystrokes meanwhile), so typing is not disturbed; a value outside the
field's range is refused with a message (the text stays as typed, to be finished or
corrected).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from .surface import from_browser

__all__ = ["TypedNumber", "parse_typed"]

#: A decimal number with an optional exponent (what Python's float reads, without its
#: ``inf``, ``nan`` and ``1_000``).
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


def parse_typed(text: str) -> float | None:
    """The number ``text`` spells (spaces around it ignored), None when it spells none."""
    text = text.strip()
    if not _NUMBER.fullmatch(text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def shown(value: float) -> str:
    """``value`` as the field shows it: the shortest text that reads back as it."""
    return repr(float(value))


class TypedNumber:
    """A text field for a number in ``[lo, hi]`` (``unit`` for messages)."""

    def __init__(
        self,
        gui: Any,
        label: str,
        value: float,
        *,
        lo: float | None = None,
        hi: float | None = None,
        unit: str = "",
        hint: str | None = None,
    ) -> None:
        self.label = label
        self.lo, self.hi, self.unit = lo, hi, unit
        self.box: Any = gui.add_text(label, shown(value), hint=hint)
        #: The page is making the edit this field's text asked for.
        self.typing = False

    def read(self) -> float | None:
        """The number the field holds, None when its text is not one (yet)."""
        return parse_typed(str(self.box.value))

    def show(self, value: float) -> None:
        """Show ``value`` (the document's), unless the field already reads as it or is being
        typed in (its edit under way)."""
        if not self.typing and self.read() != value:
            self.box.value = shown(value)

    def refusal(self, value: float) -> str | None:
        """Why ``value`` is outside the field's range (one line), or None."""
        lo, hi = self.lo, self.hi
        if (lo is None or value >= lo) and (hi is None or value <= hi):
            return None
        span = f"{lo:g} to {hi:g}" if lo is not None and hi is not None else ""
        if not span:
            span = f"at least {lo:g}" if lo is not None else f"at most {hi:g}"
        return f"not set: {self.label} takes {span}{self.unit}, not {value:g}"

    def on_number(self, say: Callable[[str], None], act: Callable[[float], None]) -> None:
        """Call ``act(value)`` for each number the browser puts in the field within its
        range; ``say`` hears why one outside it is not taken."""

        def changed(event: Any) -> None:
            if not from_browser(event):
                return
            value = self.read()
            if value is None:
                return
            why = self.refusal(value)
            if why is not None:
                say(why)
                return
            self.typing = True
            try:
                act(value)
            finally:
                self.typing = False

        self.box.on_update(changed)
