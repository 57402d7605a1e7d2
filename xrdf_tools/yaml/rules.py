"""What every YAML reader of :mod:`xrdf_tools.yaml.io` applies, whichever parser produced the
events: the YAML 1.2 core schema for scalars, and the bounds on hostile documents.

Plain scalars are resolved with the YAML 1.2 core schema (``on``/``off``/``yes``/``no``/``y``/
``n`` stay strings, ``1e3`` is a float); explicit tags (``!!int``, ``!degrees``) are converted
by :func:`scalar_value`. :func:`plain_value` is the same resolution as PyYAML's resolver with
:class:`Resolver12`'s table followed by :func:`scalar_value`, in one step.
"""

from __future__ import annotations

import math
import re
from typing import Any

import yaml

from ..util.errors import YamlError
from .tree import Scalar

#: Deepest nesting of sequences and mappings accepted (real XRDF and cuRobo files nest < 10).
MAX_DEPTH = 100
#: Most alias uses (``*name``) in one document.
MAX_ALIASES = 10_000
#: The expanded document may hold ``MAX_EXPANDED_NODES + MAX_AMPLIFICATION * distinct`` nodes.
MAX_EXPANDED_NODES = 100_000
MAX_AMPLIFICATION = 10

NULL_TAG = "tag:yaml.org,2002:null"
BOOL_TAG = "tag:yaml.org,2002:bool"
INT_TAG = "tag:yaml.org,2002:int"
FLOAT_TAG = "tag:yaml.org,2002:float"
STR_TAG = "tag:yaml.org,2002:str"

#: Plain words that YAML 1.1 readers take for booleans and YAML 1.2 (this reader) for strings:
#: PyYAML's (ROS 1's rosparam, MoveIt 2's launch helpers, cuRobo) and ROS 2's parameter
#: parser read them alike.
YAML11_BOOLEANS: dict[str, bool] = {
    word: value
    for value, words in ((True, ("yes", "on")), (False, ("no", "off")))
    for w in words
    for word in (w, w.capitalize(), w.upper())
}

_NULL_RE = re.compile(r"^(?:~|null|Null|NULL|)$")
_BOOL_RE = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
_INT_RE = re.compile(r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$")
_FLOAT_RE = re.compile(
    r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
    r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"
)
# The four patterns in one, in the resolver's order (each only matches text starting with one of
# its resolver's first characters, so one match replaces the per-character tables).
_PLAIN_RE = re.compile(
    "|".join(
        f"(?P<{name}>{pattern.pattern[4:-2]})$"
        for name, pattern in (
            ("null", _NULL_RE),
            ("bool", _BOOL_RE),
            ("int", _INT_RE),
            ("float", _FLOAT_RE),
        )
    )
)
_DIGITS = frozenset("0123456789.")
_NUMBER_CHARS = "0123456789.eE+-"
_NULL_FIRST = frozenset(["~", "n", "N", ""])
_BOOL_FIRST = frozenset("tTfF")
_FLOAT_FIRST = frozenset("-+.0123456789")


class Resolver12(yaml.resolver.Resolver):
    """PyYAML's resolver with the YAML 1.2 core schema table (for PyYAML's composer)."""


Resolver12.yaml_implicit_resolvers = {}
for _tag, _regexp, _first in (
    (NULL_TAG, _NULL_RE, sorted(_NULL_FIRST)),
    (BOOL_TAG, _BOOL_RE, sorted(_BOOL_FIRST)),
    (INT_TAG, _INT_RE, list("-+0123456789")),
    (FLOAT_TAG, _FLOAT_RE, sorted(_FLOAT_FIRST)),
):
    Resolver12.add_implicit_resolver(_tag, _regexp, _first)


def error_at(path: str, mark: Any, problem: str) -> YamlError:
    """A bound exceeded at a PyYAML mark: ``problem; refusing this document``."""
    line = mark.line + 1 if mark is not None else None
    col = mark.column + 1 if mark is not None else None
    return YamlError(f"{problem}; refusing this document", path=path, line=line, col=col)


def plain_value(text: str) -> Scalar:
    """The value of an untagged plain scalar: the same as :class:`Resolver12` then
    :func:`scalar_value`, including its one failure: an integer of more digits than Python
    converts raises ``ValueError`` (``scalar_value`` words it).

    Text made only of ``0-9 . e E + -`` (numbers, mostly) is read by ``int`` / ``float``
    without the patterns: over those characters Python's float syntax is exactly the YAML 1.2
    float pattern, and the int pattern is an optional sign and digits.
    """
    if text and not text.strip(_NUMBER_CHARS):
        if "." in text or "e" in text or "E" in text:
            try:
                return float(text)
            except ValueError:
                return text
        digits = text[1:] if text[0] in "+-" else text
        return int(text) if digits.isdigit() else text
    m = _PLAIN_RE.match(text)
    if m is None:
        return text
    kind = m.lastgroup
    if kind == "float":
        return _float(text)
    if kind == "int":
        return _int(text)
    if kind == "null":
        return None
    return text.lower() == "true"


def _int(text: str) -> int:
    if text.startswith("0o"):
        return int(text[2:], 8)
    if text.startswith("0x"):
        return int(text[2:], 16)
    return int(text)


def _float(text: str) -> float:
    if text[-1] in _DIGITS:  # a plain number (Python reads every such float pattern)
        return float(text)
    low = text.lower().lstrip("+")
    if low == ".inf":
        return math.inf
    if low == "-.inf":
        return -math.inf
    if low == ".nan":
        return math.nan
    return float(text)


def scalar_value(tag: str, text: str, path: str, line: int, col: int) -> Scalar:
    """The value of a scalar with its resolved or explicit ``tag``; :class:`YamlError` at
    ``line:col`` when the text is not what the tag says."""
    if tag == NULL_TAG:
        return None
    if tag == BOOL_TAG:
        if text.lower() in ("true", "false"):
            return text.lower() == "true"
        raise YamlError(f"'{text}' is not a boolean", path=path, line=line, col=col)
    if tag == INT_TAG:
        try:
            return _int(text)
        except ValueError:
            raise YamlError(f"'{text}' is not an integer", path=path, line=line, col=col) from None
    if tag == FLOAT_TAG:
        try:
            return _float(text)
        except ValueError:
            raise YamlError(f"'{text}' is not a number", path=path, line=line, col=col) from None
    if tag in (STR_TAG, "!"):
        return text
    if tag in ("!degrees", "!radians"):
        # xacro / ROS conventions seen in UR descriptions; keep the value in radians.
        try:
            v = float(text)
        except ValueError:
            raise YamlError(f"'{text}' is not a number", path=path, line=line, col=col) from None
        return math.radians(v) if tag == "!degrees" else v
    # Unknown explicit tags: keep the text.
    return text
