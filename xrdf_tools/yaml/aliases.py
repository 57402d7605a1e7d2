"""The checks a document that uses aliases gets once its last event is read.

The one-pass reader (:mod:`xrdf_tools.yaml.build`) reads an alias as a second reference to its
anchor's node (the tree is then a graph whose shared nodes are read once), and an alias inside
its own anchor as an :class:`AliasCycle` standing for that anchor. Then, in this order:

1. :func:`check_expansion`: the document as a tree (every alias expanded) may hold at most
   ``MAX_EXPANDED_NODES + MAX_AMPLIFICATION * distinct`` nodes; the size of each distinct node
   is computed once, as its last child ends, so a "billion laughs" document is refused after a
   few hundred steps. An alias inside its own anchor is an error at the anchor.
2. :func:`walk_expanded`: the document as a tree, in document order: nesting (aliases
   included), a scalar that is not what its tag says, a mapping or list used as a key (an alias
   of one included) are errors, the first one raised; every repeated key is recorded with its
   key path, once per place an alias puts it.

The errors, their positions and the order of the repeated keys are those of PyYAML's composer
bounded the same way (the tests compare both, ``tests/yaml_reference.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..util.errors import YamlError
from .rules import MAX_AMPLIFICATION, MAX_DEPTH, MAX_EXPANDED_NODES
from .tree import DuplicateKey, YMap, YNode, YPlainSeq, YScalar, YSeq


@dataclass(frozen=True, slots=True)
class AliasCycle(YNode):
    """An alias read inside the node its anchor names (an error once the document is read)."""

    anchor: str


def _refuse(node: YNode, path: str, problem: str) -> YamlError:
    return YamlError(f"{problem}; refusing this document", path=path, line=node.line, col=node.col)


def _children(node: YNode, anchored: dict[str, YNode | None]) -> list[YNode]:
    """A node's children, an :class:`AliasCycle` standing for the node of its anchor."""
    if isinstance(node, YMap):
        children = [n for pair in node.pairs for n in pair]
    elif isinstance(node, YSeq):
        children = list(node.items)
    else:
        return []
    for i, child in enumerate(children):
        if isinstance(child, AliasCycle):
            target = anchored[child.anchor]
            assert target is not None  # the anchor's node has ended with the document
            children[i] = target
    return children


def check_expansion(root: YNode, path: str, anchored: dict[str, YNode | None]) -> None:
    """Bound what aliases expand to (see the module docstring). The walk visits the last
    child first, as the bound's figures (distinct nodes so far) were always counted."""
    sizes: dict[int, int] = {}
    open_nodes: set[int] = set()
    distinct = 0
    stack: list[tuple[YNode, bool]] = [(root, False)]
    while stack:
        node, closing = stack.pop()
        key = id(node)
        if closing:
            open_nodes.discard(key)
            if type(node) is YPlainSeq:  # its items: distinct scalars of size 1
                distinct += len(node.values)
                size = 1 + len(node.values)
            else:
                size = 1 + sum(sizes[id(c)] for c in _children(node, anchored))
            sizes[key] = size
            distinct += 1
            allowed = MAX_EXPANDED_NODES + MAX_AMPLIFICATION * distinct
            if size > allowed:
                raise _refuse(node, path, f"aliases expand this document beyond {allowed:,} nodes")
            continue
        if key in sizes:
            continue
        if key in open_nodes:
            raise _refuse(node, path, "an alias refers to a node that contains it")
        open_nodes.add(key)
        stack.append((node, True))
        if type(node) is not YPlainSeq:
            stack.extend((c, False) for c in _children(node, anchored))


class _Expanded:
    """The walk of :func:`walk_expanded`."""

    def __init__(self, path: str, bad: dict[int, YamlError]) -> None:
        self.path = path
        self.bad = bad
        self.dups: list[DuplicateKey] = []

    def walk(self, node: YNode, key_path: str, depth: int) -> None:
        if depth > MAX_DEPTH:
            raise YamlError(
                f"nesting deeper than {MAX_DEPTH} levels (aliases included); refusing this "
                "document",
                path=self.path,
                line=node.line,
                col=node.col,
            )
        if isinstance(node, YScalar):
            error = self.bad.get(id(node))
            if error is not None:
                raise error
        elif isinstance(node, YMap):
            self.walk_map(node, key_path, depth)
        elif isinstance(node, YSeq):
            for i, item in enumerate(node.items):
                self.walk(item, f"{key_path}[{i}]", depth + 1)

    def walk_map(self, node: YMap, key_path: str, depth: int) -> None:
        seen: dict[Any, YScalar] = {}
        for k, v in node.pairs:
            self.walk(k, key_path, depth + 1)
            if not isinstance(k, YScalar):
                kind = "mapping" if isinstance(k, YMap) else "list"
                raise YamlError(
                    f"a {kind} is used as a mapping key; keys must be names or numbers",
                    path=self.path,
                    line=k.line,
                    col=k.col,
                )
            kv = k.value
            child_path = f"{key_path}.{kv}" if key_path else str(kv)
            if kv not in seen:
                seen[kv] = k
            else:
                first = seen[kv]
                dup = DuplicateKey(str(kv), first.line, first.col, k.line, k.col, child_path)
                self.dups.append(dup)
            self.walk(v, child_path, depth + 1)


def walk_expanded(root: YNode, path: str, bad: dict[int, YamlError]) -> tuple[DuplicateKey, ...]:
    """The document's repeated keys in document order, aliases expanded; raises its first error
    (see the module docstring). ``bad``: the error of each scalar that is not what its tag
    says, by the node's ``id``."""
    walker = _Expanded(path, bad)
    walker.walk(root, "", 0)
    return tuple(walker.dups)
