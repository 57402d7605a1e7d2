"""Number fields the page reads itself: lengths and limits typed as text.

viser's number field (Mantine's) drops what is not a digit, a point or a leading minus, and
sends every keystroke: ``1e-3`` typed in it arrived as 1, then 13 (and ``1.5e-2`` as
-1.52), each applied as an edit. A :class:`TypedNumber` is a text field whose text the page
parses: ``1e-3``, ``0.001``, ``-2``, ``.5`` are numbers; what is not one yet (``-``, ``1e``,
an empty field) is left alone until it is. The page never rewrites the text while it reads
as the document's value, nor while it makes the edit the text asked for (the browser may
have sent the next keystrokes meanwhile), so typing is not disturbed; a value outside the
field's range (or a fraction in a field of whole numbers) is refused with a message (the text
stays as typed, to be finished or corrected).

Every number the page takes is typed in one: lengths and limits, which edit the document as
they are typed (:meth:`TypedNumber.on_number`), and the counts and factors a button reads
(:meth:`TypedNumber.take`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from .surface import from_browser

__all__ = ["TypedNumber", "hide_number_box", "parse_typed"]

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


def shown(value: float, *, integer: bool = False) -> str:
    """``value`` as the field shows it: the shortest text that reads back as it (a whole
    number without a point in a field of whole numbers)."""
    if integer and float(value).is_integer():
        return str(int(value))
    return repr(float(value))


def said(value: float | None) -> str:
    """``value`` in a message: whole numbers with thousands separators (1,000,000, not
    1e+06), others as ``:g`` writes them."""
    v = float(value or 0.0)
    return f"{int(v):,}" if v.is_integer() and abs(v) < 1e15 else f"{v:g}"


class TypedNumber:
    """A text field for a number in ``[lo, hi]`` (``unit`` for messages; ``integer``: a whole
    number)."""

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
        integer: bool = False,
    ) -> None:
        self.label = label
        self.lo, self.hi, self.unit, self.integer = lo, hi, unit, integer
        self.box: Any = gui.add_text(label, shown(value, integer=integer), hint=hint)
        #: The page is making the edit this field's text asked for.
        self.typing = False

    def read(self) -> float | None:
        """The number the field holds, None when its text is not one (yet)."""
        return parse_typed(str(self.box.value))

    def show(self, value: float) -> None:
        """Show ``value`` (the document's), unless the field already reads as it or is being
        typed in (its edit under way)."""
        if not self.typing and self.read() != value:
            self.box.value = shown(value, integer=self.integer)

    def refusal(self, value: float) -> str | None:
        """Why ``value`` is outside the field's range (one line), or None."""
        lo, hi = self.lo, self.hi
        if self.integer and not value.is_integer():
            return f"not set: {self.label} takes a whole number, not {value:g}"
        if (lo is None or value >= lo) and (hi is None or value <= hi):
            return None
        span = f"{said(lo)} to {said(hi)}" if lo is not None and hi is not None else ""
        if not span:
            span = f"at least {said(lo)}" if lo is not None else f"at most {said(hi)}"
        return f"not set: {self.label} takes {span}{self.unit}, not {said(value)}"

    def take(self, say: Callable[[str], None]) -> float | None:
        """The number in the field, for a button that reads it; None, with ``say`` hearing
        why, when the field holds no number in its range."""
        value = self.read()
        if value is None:
            say(f"not set: type a number in {self.label}")
            return None
        why = self.refusal(value)
        if why is not None:
            say(why)
            return None
        return value

    def watch(self, say: Callable[[str], None]) -> None:
        """Say as it is typed why a number outside the field's range will not be taken (for
        a field a button reads)."""
        self.on_number(say, lambda _: None)

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


def hide_number_box(gui: Any, slider: Any) -> None:
    """Hide the number box viser draws next to ``slider`` (a style rule for that slider
    alone): the slider is for dragging, its number is typed in a :class:`TypedNumber`. The
    slider's element carries its id; a viser whose slider does not leaves the box shown."""
    uuid = getattr(getattr(slider, "_impl", None), "uuid", None)
    if isinstance(uuid, str) and re.fullmatch(r"[0-9a-f-]+", uuid):
        rule = f'[id="{uuid}"] + .mantine-NumberInput-root {{ display: none; }}'
        gui.add_html(f"<style>{rule}</style>")
