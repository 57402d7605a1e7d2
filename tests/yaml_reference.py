"""The reference YAML reader of the tests: PyYAML's pure-Python composer, bounded, then
converted to the tree of :mod:`xrdf_tools.yaml.tree`.

This is how every document was read before the one-pass reader of
:mod:`xrdf_tools.yaml.build`; ``tests/yaml/test_yaml_readers.py`` and
``tests/yaml/test_yaml_aliases.py`` compare the two on the same inputs. It composes PyYAML's
node graph (an alias is a second reference to its anchor's node), bounds nesting and alias uses
while composing, bounds what the aliases expand to, then converts the graph to a tree of
:class:`~xrdf_tools.yaml.tree.YNode` with duplicate keys recorded.
"""

from __future__ import annotations

from typing import Any

import yaml

from xrdf_tools.util.errors import YamlError
from xrdf_tools.yaml.rules import (
    MAX_ALIASES,
    MAX_AMPLIFICATION,
    MAX_DEPTH,
    MAX_EXPANDED_NODES,
    Resolver12,
    error_at,
    scalar_value,
)
from xrdf_tools.yaml.tree import DuplicateKey, YamlDocument, YMap, YNode, YScalar, YSeq


class _Composer12(
    yaml.reader.Reader,
    yaml.scanner.Scanner,
    yaml.parser.Parser,
    yaml.composer.Composer,
    Resolver12,
):
    def __init__(self, stream: str, path: str) -> None:
        yaml.reader.Reader.__init__(self, stream)
        yaml.scanner.Scanner.__init__(self)
        yaml.parser.Parser.__init__(self)
        yaml.composer.Composer.__init__(self)
        Resolver12.__init__(self)
        self._path = path
        self._depth = 0
        self._aliases = 0

    def compose_node(self, parent: yaml.Node | None, index: Any) -> yaml.Node:
        """PyYAML's recursive composer, with the nesting depth and alias uses bounded."""
        event = self.peek_event()  # type: ignore[no-untyped-call]
        if isinstance(event, yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                raise error_at(self._path, event.start_mark, f"more than {MAX_ALIASES} aliases")
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise error_at(
                    self._path, event.start_mark, f"nesting deeper than {MAX_DEPTH} levels"
                )
            node: yaml.Node | None = super().compose_node(parent, index)
            assert node is not None
            return node
        finally:
            self._depth -= 1


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def _check_expansion(root: yaml.Node, path: str) -> None:
    """Bound what aliases expand to: the node count of the document as a tree, computed once
    per distinct node (so a "billion laughs" document is refused after a few hundred steps);
    an alias inside its own anchor is an error."""
    sizes: dict[int, int] = {}
    open_nodes: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    limit = MAX_EXPANDED_NODES
    while stack:
        node, closing = stack.pop()
        key = id(node)
        if closing:
            open_nodes.discard(key)
            sizes[key] = 1 + sum(sizes[id(c)] for c in _children(node))
            allowed = limit + MAX_AMPLIFICATION * len(sizes)
            if sizes[key] > allowed:
                raise error_at(
                    path, node.start_mark, f"aliases expand this document beyond {allowed:,} nodes"
                )
            continue
        if key in sizes:
            continue
        if key in open_nodes:
            raise error_at(path, node.start_mark, "an alias refers to a node that contains it")
        open_nodes.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node))


def _convert(
    node: yaml.Node, path: str, key_path: str, dups: list[DuplicateKey], depth: int = 0
) -> YNode:
    line, col = node.start_mark.line + 1, node.start_mark.column + 1
    if depth > MAX_DEPTH:
        raise YamlError(
            f"nesting deeper than {MAX_DEPTH} levels (aliases included); refusing this document",
            path=path,
            line=line,
            col=col,
        )
    if isinstance(node, yaml.ScalarNode):
        value = scalar_value(node.tag, str(node.value), path, line, col)
        return YScalar(line, col, value, quoted=node.style in ("'", '"'))
    if isinstance(node, yaml.SequenceNode):
        items = tuple(
            _convert(n, path, f"{key_path}[{i}]", dups, depth + 1) for i, n in enumerate(node.value)
        )
        return YSeq(line, col, items, flow=bool(node.flow_style))
    if isinstance(node, yaml.MappingNode):
        pairs: list[tuple[YNode, YNode]] = []
        seen: dict[Any, YNode] = {}
        for knode, vnode in node.value:
            k = _convert(knode, path, key_path, dups, depth + 1)
            if not isinstance(k, YScalar):
                kind = "mapping" if isinstance(k, YMap) else "list"
                raise YamlError(
                    f"a {kind} is used as a mapping key; keys must be names or numbers",
                    path=path,
                    line=k.line,
                    col=k.col,
                )
            kv = k.value
            child_path = f"{key_path}.{kv}" if key_path else str(kv)
            if kv in seen:
                first = seen[kv]
                dups.append(DuplicateKey(str(kv), first.line, first.col, k.line, k.col, child_path))
            else:
                seen[kv] = k
            pairs.append((k, _convert(vnode, path, child_path, dups, depth + 1)))
        return YMap(line, col, tuple(pairs), flow=bool(node.flow_style))
    raise YamlError(f"unsupported YAML node {type(node).__name__}", path=path, line=line, col=col)


def compose_document(text: str, path: str) -> YamlDocument:
    """Read one document the reference way. Raises PyYAML's errors for syntax errors (the
    caller words them) and :class:`YamlError` for the bounds and bad scalars."""
    loader = _Composer12(text, path)
    try:
        node = loader.get_single_node()
        if node is not None:
            _check_expansion(node, path)
    finally:
        loader.dispose()
    if node is None:
        return YamlDocument(path, None, ())
    dups: list[DuplicateKey] = []
    root = _convert(node, path, "", dups)
    return YamlDocument(path, root, tuple(dups))
