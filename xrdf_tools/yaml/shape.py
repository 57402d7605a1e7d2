"""The shape vocabulary of every YAML input, and its first-error walker.

A :class:`Shape` says what a node must be: ``any``; a ``scalar`` (a name or number); a name
(``str``); a finite number (``num``); a ``bool``; a ``list`` of ``values``; a mapping with
known ``fields`` (``fields``; other keys take ``values`` when set) or from names to ``values``
(``dict``); ``one_of`` several shapes; and three kinds only an XRDF has (``groupref``,
``buffers``, ``modifier``: see :mod:`xrdf_tools.xrdf.shape`, which describes the XRDF with this
vocabulary, with required keys, list lengths and versions).

Two walkers read it:

* :func:`check_shape` (here), for readers of foreign YAML (cuRobo configs, lint configuration):
  one walk, without recursion, that raises the caller's error class at the first node that
  departs: ``path:line:col: robot_cfg.kinematics.cspace.joint_names must be a list of names,
  not the number 5``. Readers call it once at their boundary, then read plain data without
  scattering ``isinstance`` checks per key. Keys a ``fields`` shape does not name (and has no
  ``values`` for) are left to the caller.
* :func:`xrdf_tools.lint.schema.walk`, for ``xrdf lint``: every departure of an XRDF, unknown
  keys, missing required keys and list lengths included, each in lint's own words.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

from ..util.errors import XrdfToolsError, shown_text
from .io import YMap, YNode, YScalar, YSeq, describe_node, is_finite

__all__ = [
    "ANY",
    "BOOL",
    "NAME",
    "NUMBER",
    "SCALAR",
    "Shape",
    "check_shape",
    "is_name",
    "is_number",
    "list_of",
    "map_of",
    "one_of",
]

Kind = Literal[
    "any",
    "scalar",
    "str",
    "num",
    "bool",
    "list",
    "fields",
    "dict",
    "one_of",
    "groupref",
    "buffers",
    "modifier",
]

#: The mapping kinds (a ``buffers`` may also be a single number).
MAPPINGS = frozenset({"fields", "dict", "modifier"})


@dataclass(frozen=True)
class Shape:
    """Expected shape of a node (the kinds: see the module docstring).

    ``fields``: the known keys of a ``fields`` mapping, of which ``required`` must be present;
    ``values``: the shape of a list's items, a ``dict``'s values, a ``fields`` mapping's other
    keys or a ``buffers``' lengths; ``length``: a list's fixed length; ``nullable``: null (or an
    empty value) is accepted; ``metres``: a number that is a length or coordinate (within the
    XRDF's bound); ``versions``: the XRDF versions in which the key holding this value exists
    (empty: all); ``length_rule``: the lint rule that reports a list of the wrong length;
    ``options``: the shapes of a ``one_of``; ``what`` overrides the generated description used
    in :func:`check_shape`'s messages ("a list of names").
    """

    kind: Kind
    fields: Mapping[str, Shape] = field(default_factory=dict)
    required: tuple[str, ...] = ()
    values: Shape | None = None
    length: int | None = None
    nullable: bool = True
    metres: bool = False
    versions: tuple[str, ...] = ()
    length_rule: str = "wrong-type"
    options: tuple[Shape, ...] = ()
    what: str = ""

    def describe(self) -> str:
        if self.what:
            return self.what
        if self.kind == "list":
            inner = self.values.describe() if self.values is not None else "anything"
            return "a list" if inner == "anything" else f"a list of {_plural(inner)}"
        if self.kind in MAPPINGS:
            return "a mapping"
        if self.kind == "one_of":
            return " or ".join(o.describe() for o in self.options)
        return _WHAT[self.kind]


_WHAT = {
    "any": "anything",
    "scalar": "a name or a number",
    "str": "a name",
    "num": "a finite number",
    "bool": "true or false",
    "groupref": "a geometry group name",
    "buffers": "a length or a mapping of names to lengths",
}


def _plural(what: str) -> str:
    for article in ("a ", "an "):
        if what.startswith(article):
            word = what[len(article) :]
            return word + ("" if word.endswith("s") else "s")
    return what


ANY = Shape("any")
SCALAR = Shape("scalar", nullable=False)
NAME = Shape("str", nullable=False)
NUMBER = Shape("num", nullable=False)
BOOL = Shape("bool", nullable=False)


def list_of(items: Shape = ANY, *, nullable: bool = True, what: str = "") -> Shape:
    return Shape("list", values=items, nullable=nullable, what=what)


def map_of(
    values: Shape | None = ANY,
    *,
    fields: Mapping[str, Shape] | None = None,
    nullable: bool = True,
    what: str = "",
) -> Shape:
    """A mapping: keys in ``fields`` have their own shape; other keys take ``values`` (None:
    other keys are not checked here — report them as dropped or unknown elsewhere)."""
    kind: Kind = "fields" if fields else "dict"
    return Shape(kind, values=values, fields=dict(fields or {}), nullable=nullable, what=what)


def one_of(*options: Shape, nullable: bool = True, what: str = "") -> Shape:
    return Shape("one_of", options=options, nullable=nullable, what=what)


#: Kinds only the XRDF reader and lint's walker read.
_XRDF_ONLY = frozenset({"groupref", "buffers", "modifier"})


def _is_null(node: YNode) -> bool:
    return isinstance(node, YScalar) and node.value is None


def is_name(node: YNode | None) -> bool:
    """A usable name: a non-empty string, or a number (a frame called ``1`` is legal YAML)."""
    if isinstance(node, YScalar):
        v = node.value
        if isinstance(v, str):
            return v != ""
        return isinstance(v, (int, float)) and not isinstance(v, bool)
    return False


def is_number(node: YNode | None, *, finite: bool = True) -> bool:
    """A YAML number (not a boolean); ``finite``: NaN and infinities are not numbers here."""
    if not isinstance(node, YScalar):
        return False
    v = node.value
    if not isinstance(v, (int, float)) or isinstance(v, bool):
        return False
    return not finite or is_finite(v)


def _scalar_ok(kind: Kind, node: YNode) -> bool:
    if kind == "str":
        return is_name(node)
    if kind == "num":
        return is_number(node)
    if not isinstance(node, YScalar):
        return False
    v = node.value
    if kind == "scalar":
        return v is not None and not isinstance(v, bool)
    return isinstance(v, bool)


def _fits(node: YNode, shape: Shape) -> bool:
    """Whether ``node`` has the outer form of ``shape`` (for choosing a ``one_of`` option)."""
    if shape.kind in _XRDF_ONLY:
        raise ValueError(f"check_shape does not take {shape.kind!r} shapes (the XRDF reader does)")
    if _is_null(node):
        return shape.nullable or shape.kind == "any"
    if shape.kind == "any":
        return True
    if shape.kind == "list":
        return isinstance(node, YSeq)
    if shape.kind in ("fields", "dict"):
        return isinstance(node, YMap)
    if shape.kind == "one_of":
        return any(_fits(node, o) for o in shape.options)
    return _scalar_ok(shape.kind, node)


def _child(key_path: str, key: object) -> str:
    name = shown_text(str(key))
    return f"{key_path}.{name}" if key_path else name


def check_shape(
    node: YNode | None,
    shape: Shape,
    *,
    path: str,
    error: type[XrdfToolsError],
    key_path: str = "",
) -> None:
    """Raise ``error`` at the first node of ``node`` that departs from ``shape``.

    ``key_path`` names ``node`` in messages (``""``: the document).
    """
    stack: list[tuple[YNode, Shape, str]] = [] if node is None else [(node, shape, key_path)]
    while stack:
        cur, want, kp = stack.pop()
        if want.kind == "one_of":
            chosen = next((o for o in want.options if _fits(cur, o)), None)
            if chosen is None and not (want.nullable and _is_null(cur)):
                raise _departure(cur, want, kp, path, error)
            if chosen is not None:
                stack.append((cur, chosen, kp))
            continue
        if not _fits(cur, want):
            raise _departure(cur, want, kp, path, error)
        if isinstance(cur, YSeq) and want.kind == "list" and want.values is not None:
            items = [(item, want.values, f"{kp}[{i}]") for i, item in enumerate(cur.items)]
            stack.extend(reversed(items))  # report the first departure in document order
        elif isinstance(cur, YMap) and want.kind in ("fields", "dict"):
            entries: list[tuple[YNode, Shape, str]] = []
            for k, v in cur.pairs:
                key = k.value if isinstance(k, YScalar) else None
                sub = want.fields.get(str(key)) if key is not None else None
                sub = sub if sub is not None else want.values
                if sub is not None:
                    entries.append((v, sub, _child(kp, key)))
            stack.extend(reversed(entries))


def _departure(
    node: YNode, shape: Shape, key_path: str, path: str, error: type[XrdfToolsError]
) -> XrdfToolsError:
    what = key_path or "the document"
    return error(
        f"{what} must be {shape.describe()}, not {describe_node(node)}",
        path=path,
        line=node.line,
        col=node.col,
    )
