"""One typed shape check for foreign YAML (cuRobo configs, lint configuration, joint limits).

A :class:`Shape` says what a node must be: ``any``, a ``scalar`` (a name or number), a
``name``, a ``number``, a ``bool``, a ``list`` of ``items``, a ``map`` (known ``fields`` and,
for other keys, ``values``), or ``one_of`` several shapes. :func:`check_shape` walks the tree
once, without recursion, and raises the caller's error class at the first node that departs:
``path:line:col: robot_cfg.kinematics.cspace.joint_names must be a list of names, not the
number 5``. Readers call it once at their boundary, then read plain data without scattering
``isinstance`` checks per key.
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
    "list_of",
    "map_of",
    "one_of",
]

Kind = Literal["any", "scalar", "name", "number", "bool", "list", "map", "one_of"]


@dataclass(frozen=True)
class Shape:
    """Expected shape of a node; ``nullable``: null (or an empty value) is accepted.

    ``what`` overrides the generated description used in messages ("a list of names").
    """

    kind: Kind
    items: Shape | None = None
    fields: Mapping[str, Shape] = field(default_factory=dict)
    options: tuple[Shape, ...] = ()
    nullable: bool = True
    what: str = ""

    def describe(self) -> str:
        if self.what:
            return self.what
        if self.kind == "list":
            inner = self.items.describe() if self.items is not None else "anything"
            return "a list" if inner == "anything" else f"a list of {_plural(inner)}"
        if self.kind == "map":
            return "a mapping"
        if self.kind == "one_of":
            return " or ".join(o.describe() for o in self.options)
        return _WHAT[self.kind]


_WHAT = {
    "any": "anything",
    "scalar": "a name or a number",
    "name": "a name",
    "number": "a finite number",
    "bool": "true or false",
}


def _plural(what: str) -> str:
    for article in ("a ", "an "):
        if what.startswith(article):
            word = what[len(article) :]
            return word + ("" if word.endswith("s") else "s")
    return what


ANY = Shape("any")
SCALAR = Shape("scalar", nullable=False)
NAME = Shape("name", nullable=False)
NUMBER = Shape("number", nullable=False)
BOOL = Shape("bool", nullable=False)


def list_of(items: Shape = ANY, *, nullable: bool = True, what: str = "") -> Shape:
    return Shape("list", items=items, nullable=nullable, what=what)


def map_of(
    values: Shape | None = ANY,
    *,
    fields: Mapping[str, Shape] | None = None,
    nullable: bool = True,
    what: str = "",
) -> Shape:
    """A mapping: keys in ``fields`` have their own shape; other keys take ``values`` (None:
    other keys are not checked here — report them as dropped or unknown elsewhere)."""
    return Shape("map", items=values, fields=dict(fields or {}), nullable=nullable, what=what)


def one_of(*options: Shape, nullable: bool = True, what: str = "") -> Shape:
    return Shape("one_of", options=options, nullable=nullable, what=what)


def _is_null(node: YNode) -> bool:
    return isinstance(node, YScalar) and node.value is None


def _scalar_ok(kind: Kind, node: YNode) -> bool:
    if not isinstance(node, YScalar):
        return False
    v = node.value
    if kind == "scalar":
        return v is not None and not isinstance(v, bool)
    if kind == "name":
        return (isinstance(v, str) and v != "") or (
            isinstance(v, (int, float)) and not isinstance(v, bool)
        )
    if kind == "number":
        return isinstance(v, (int, float)) and not isinstance(v, bool) and is_finite(v)
    return isinstance(v, bool)


def _fits(node: YNode, shape: Shape) -> bool:
    """Whether ``node`` has the outer form of ``shape`` (for choosing a ``one_of`` option)."""
    if _is_null(node):
        return shape.nullable or shape.kind == "any"
    if shape.kind == "any":
        return True
    if shape.kind == "list":
        return isinstance(node, YSeq)
    if shape.kind == "map":
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
        if isinstance(cur, YSeq) and want.kind == "list" and want.items is not None:
            items = [(item, want.items, f"{kp}[{i}]") for i, item in enumerate(cur.items)]
            stack.extend(reversed(items))  # report the first departure in document order
        elif isinstance(cur, YMap) and want.kind == "map":
            entries: list[tuple[YNode, Shape, str]] = []
            for k, v in cur.pairs:
                key = k.value if isinstance(k, YScalar) else None
                sub = want.fields.get(str(key)) if key is not None else None
                sub = sub if sub is not None else want.items
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
