"""Where each node of a YAML tree starts, by key path (``a.b[0]``, ``a.b#key``).

:func:`node_positions` lists every node of a tree in a dict; :func:`positions_of` gives the
same mapping without building it: a key path is followed down the tree when it is asked for,
so a model read from a file with 300,000 spheres does not carry millions of path strings. A
tree whose keys could make two paths look alike (a key with ``.`` or ``[``, a number key, a
repeated key: ``YamlDocument.simple_keys`` is False) is indexed in full on the first
question, with exactly :func:`node_positions`' answers.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping

from .tree import YamlDocument, YMap, YNode, YScalar, YSeq, key_of

Position = tuple[int, int]

#: Maps with more keys than this get a dict index on their first lookup.
_INDEX_FROM = 8
_NAME = re.compile(r"[^.\[\]#]+")
_INDEX = re.compile(r"\[(0|[1-9][0-9]*)\]")


def node_positions(root: YNode | None) -> dict[str, Position]:
    """``key_path → (line, col)`` for every node of a tree.

    The value of a mapping entry is recorded under its key path (``a.b``) and the key itself
    under ``a.b#key``; sequence items under ``a.b[0]``. The root is recorded under ``""``.
    """
    out: dict[str, Position] = {}
    if root is None:
        return out
    stack: list[tuple[str, YNode]] = [("", root)]
    while stack:
        kp, node = stack.pop()
        out[kp] = (node.line, node.col)
        if isinstance(node, YMap):
            for k, v in node.pairs:
                child = f"{kp}.{key_of(k)}" if kp else str(key_of(k))
                out.setdefault(child + "#key", (k.line, k.col))
                stack.append((child, v))
        elif isinstance(node, YSeq):
            for i, v in enumerate(node.items):
                stack.append((f"{kp}[{i}]", v))
    return out


class NodePositions(Mapping[str, Position]):
    """:func:`node_positions` of a tree as a read-only mapping, answered on demand."""

    __slots__ = ("_full", "_indexes", "_root", "_simple")

    def __init__(self, root: YNode | None, simple: bool) -> None:
        self._root = root
        self._simple = simple and root is not None
        self._full: dict[str, Position] | None = None
        self._indexes: dict[int, dict[str, tuple[YNode, YNode]]] = {}

    def __reduce__(self) -> tuple[object, ...]:
        # The indexes are keyed by id(): never carried to another process or copy.
        return (NodePositions, (self._root, self._simple))

    def _all(self) -> dict[str, Position]:
        if self._full is None:
            self._full = node_positions(self._root)
        return self._full

    def __getitem__(self, key_path: str) -> Position:
        if not self._simple:
            return self._all()[key_path]
        found = self._find(key_path)
        if found is None:
            raise KeyError(key_path)
        return found

    def __contains__(self, key_path: object) -> bool:
        if not isinstance(key_path, str):
            return False
        if not self._simple:
            return key_path in self._all()
        return self._find(key_path) is not None

    def __iter__(self) -> Iterator[str]:
        return iter(self._all())

    def __len__(self) -> int:
        return len(self._all())

    def _entry(self, node: YMap, name: str) -> tuple[YNode, YNode] | None:
        if len(node.pairs) <= _INDEX_FROM:
            for pair in node.pairs:
                k = pair[0]
                if isinstance(k, YScalar) and k.value == name:
                    return pair
            return None
        index = self._indexes.get(id(node))
        if index is None:
            index = {str(key_of(k)): (k, v) for k, v in node.pairs}
            self._indexes[id(node)] = index
        return index.get(name)

    def _find(self, key_path: str) -> Position | None:
        """Follow ``key_path`` down a tree of simple keys (see :class:`YamlDocument`)."""
        node = self._root
        assert node is not None
        i, end = 0, len(key_path)
        while i < end:
            m = _INDEX.match(key_path, i)
            if m is not None:
                if not isinstance(node, YSeq) or int(m.group(1)) >= len(node):
                    return None
                node = node.item(int(m.group(1)))
                i = m.end()
                continue
            if i > 0:
                if key_path[i] != ".":
                    return None
                i += 1
            m = _NAME.match(key_path, i)
            if m is None or not isinstance(node, YMap):
                return None
            pair = self._entry(node, m.group())
            if pair is None:
                return None
            i = m.end()
            if key_path.startswith("#", i):
                return (pair[0].line, pair[0].col) if key_path[i:] == "#key" else None
            node = pair[1]
        return (node.line, node.col)


def positions_of(doc: YamlDocument) -> NodePositions:
    """:func:`node_positions` of ``doc`` as a mapping, computed only for the paths asked."""
    return NodePositions(doc.root, doc.simple_keys and not doc.duplicates)
