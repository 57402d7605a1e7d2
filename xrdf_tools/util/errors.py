"""Exception tree: failures are exceptions, findings are diagnostics.

Every exception message is one line that names the file and position when known and, where
it helps, lists what would have been valid.
"""

from __future__ import annotations

from collections.abc import Iterable


class XrdfToolsError(Exception):
    """Root of every error raised by xrdf-tools.

    ``path``, ``line`` and ``col`` (1-based) locate the problem when known; ``str(err)`` is a
    one-line message prefixed with ``path:line:col:``.
    """

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        line: int | None = None,
        col: int | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.path = path
        self.line = line
        self.col = col

    def location(self) -> str:
        parts = [p for p in (self.path, self.line, self.col) if p is not None]
        return ":".join(str(p) for p in parts)

    def __str__(self) -> str:
        loc = self.location()
        return one_line(f"{loc}: {self.message}" if loc else self.message)


def one_line(text: str) -> str:
    """``text`` safe to print as one line: every character that does not print (newlines,
    tabs, other control characters, invisible format characters such as a byte-order mark)
    shown as its escape (``\\n``, ``\\ufeff``). Values quoted from hostile files cannot
    break the one-line format or hide in it."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


class YamlError(XrdfToolsError):
    """The file is not valid YAML, or it repeats a key."""


class SchemaError(XrdfToolsError):
    """The YAML is well formed but does not describe a valid XRDF (or source config)."""


class GeometryGroupError(SchemaError):
    """A geometry group clone is cyclic or names a group that does not exist."""


class UrdfError(XrdfToolsError):
    """A URDF (or xacro) cannot be read, or does not match what the XRDF refers to."""


class UrdfReadError(UrdfError):
    """The URDF file cannot be read at all (missing, a directory, no permission)."""


class SourceError(XrdfToolsError):
    """An input for conversion (SRDF, cuRobo config, joint limits) cannot be used."""


class ConversionError(XrdfToolsError):
    """A model cannot be expressed in the requested XRDF version or output format."""


class InputError(XrdfToolsError):
    """An input file cannot be read: missing, not a regular file, too large, not UTF-8."""


class OutputError(XrdfToolsError, OSError):
    """An output cannot be written. Also an :class:`OSError` (``errno``, ``strerror`` and
    ``filename`` set, ``filename`` being the path the user asked for, never a temporary file),
    so callers that catch ``OSError`` around a write keep working."""

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        errno: int | None = None,
        strerror: str | None = None,
    ) -> None:
        super().__init__(message, path=path)
        self.errno = errno
        self.strerror = strerror or message
        self.filename = path


class MissingDependencyError(XrdfToolsError):
    """An optional dependency is not installed; the message says which extra provides it."""


def did_you_mean(name: str, choices: Iterable[str]) -> str:
    """Return ``"; did you mean 'x'?"`` for the closest choice, or ``""`` when none is close."""
    import difflib  # here: a message that needs it is rare, every command imports this module

    pool = list(choices)
    for match in [*_swapped(name, pool), *difflib.get_close_matches(name, pool, n=3, cutoff=0.6)]:
        own, other = _without_common_suffix(name, match)
        if own.startswith(other) or other.startswith(own):  # 'left' and 'l': an abbreviation
            return f"; did you mean '{match}'?"
        if difflib.SequenceMatcher(None, own, other).ratio() >= 0.5:
            return f"; did you mean '{match}'?"
    return ""


def _swapped(name: str, pool: list[str]) -> list[str]:
    """The first choice that is ``name`` with two letters swapped (``lr_link1`` for
    ``rl_link1``): two swapped letters, a typo or a prefix written the other way round, is
    closer than one letter changed, which names another part (``rr_link1``, the other arm)."""
    letters = sorted(name)
    return [
        c
        for c in pool
        if len(c) == len(name)
        and sum(x != y for x, y in zip(c, name, strict=True)) == 2
        and sorted(c) == letters
    ][:1]


def _without_common_suffix(a: str, b: str) -> tuple[str, str]:
    """``a`` and ``b`` without the ending they share: 'gripper_joint' is not close to
    'base_joint' for their common '_joint'."""
    n = 0
    while n < min(len(a), len(b)) and a[-1 - n] == b[-1 - n]:
        n += 1
    return a[: len(a) - n], b[: len(b) - n]


def shown_text(text: str, limit: int = 60) -> str:
    """A value from a file, safe for a one-line message: characters that do not print
    (newlines included) escaped, long values cut to ``limit`` characters."""
    out = one_line(text[: limit + 1])
    return out if len(out) <= limit and len(text) <= limit else out[: limit - 3] + "..."
