"""YAML loading with source positions, duplicate-key detection and YAML 1.2 scalars.

PyYAML composes the node graph (with marks); we resolve plain scalars with the YAML 1.2 core
schema (``on``/``off``/``yes``/``no``/``y``/``n`` stay strings, ``1e3`` is a float) and build a
small tree of :class:`YScalar`, :class:`YSeq` and :class:`YMap` that keeps a 1-based line and
column for every node. Repeated mapping keys are recorded (PyYAML silently keeps the last one);
:func:`load_yaml` turns them into an error naming both lines, :func:`parse_yaml` returns them so
a linter can report them as findings.

Hostile input is bounded the way XML parsers bound entity expansion: a control character is an
error at its line and column; nesting deeper than :data:`MAX_DEPTH` is an error (never a
``RecursionError``); aliases are counted (at most :data:`MAX_ALIASES`) and the document as
expanded may hold at most :data:`MAX_EXPANDED_NODES` nodes more than it has distinct nodes
times :data:`MAX_AMPLIFICATION`, so a kilobyte of nested anchors ("billion laughs") fails at
once; an alias inside its own anchor and a mapping used as a key are errors. Files are read
through :mod:`xrdf_tools.fileio` (regular files only, size limit).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import yaml

from .errors import YamlError, shown_text
from .fileio import read_input_text
from .fileio import write_atomic as write_atomic

Scalar = str | int | float | bool | None


@dataclass(frozen=True)
class YNode:
    """Base class: every node knows where it starts (1-based line and column)."""

    line: int
    col: int


@dataclass(frozen=True)
class YScalar(YNode):
    value: Scalar
    quoted: bool = False

    def to_python(self) -> Any:
        return self.value


@dataclass(frozen=True)
class YSeq(YNode):
    items: tuple[YNode, ...] = ()
    flow: bool = False

    def __iter__(self) -> Iterator[YNode]:
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)

    def to_python(self) -> list[Any]:
        return [to_python(i) for i in self.items]


@dataclass(frozen=True)
class YMap(YNode):
    """A mapping. ``pairs`` keeps every key in file order, repeated ones included."""

    pairs: tuple[tuple[YNode, YNode], ...] = ()
    flow: bool = False

    def keys(self) -> list[Any]:
        return [key_of(k) for k, _ in self.pairs]

    def get(self, key: str) -> YNode | None:
        """The value of the *last* occurrence of ``key`` (PyYAML semantics), or None."""
        found: YNode | None = None
        for k, v in self.pairs:
            if key_of(k) == key:
                found = v
        return found

    def key_node(self, key: str) -> YNode | None:
        for k, _ in self.pairs:
            if key_of(k) == key:
                return k
        return None

    def __contains__(self, key: object) -> bool:
        return any(key_of(k) == key for k, _ in self.pairs)

    def items(self) -> list[tuple[Any, YNode]]:
        return [(key_of(k), v) for k, v in self.pairs]

    def to_python(self) -> dict[Any, Any]:
        out: dict[Any, Any] = {}
        for k, v in self.pairs:
            key = key_of(k)
            if isinstance(key, list):
                key = tuple(key)
            out[key] = to_python(v)
        return out


def key_of(node: YNode) -> Any:
    """The Python value of a mapping key (scalars only in practice)."""
    if isinstance(node, YScalar):
        return node.value
    return to_python(node)


def describe_node(node: YNode | None) -> str:
    """Human name of a node's type: 'a mapping', 'a list', 'the number 0.1', 'null' …"""
    if node is None:
        return "missing"
    if isinstance(node, YMap):
        return "a mapping"
    if isinstance(node, YSeq):
        return "a list"
    assert isinstance(node, YScalar)
    v = node.value
    if v is None:
        return "null"
    if isinstance(v, bool):
        return f"the boolean {str(v).lower()}"
    if isinstance(v, (int, float)):
        return f"the number {shown_text(str(v))}"
    return f"the string '{shown_text(v)}'"


def to_python(node: YNode | None) -> Any:
    """Plain Python data (dicts, lists, scalars) for a node tree."""
    if node is None:
        return None
    if isinstance(node, (YScalar, YSeq, YMap)):
        return node.to_python()
    raise TypeError(type(node))


@dataclass(frozen=True)
class DuplicateKey:
    key: str
    first_line: int
    first_col: int
    line: int
    col: int
    key_path: str


@dataclass(frozen=True)
class YamlDocument:
    """A parsed file: its root node (None for an empty file) and any repeated keys."""

    path: str
    root: YNode | None
    duplicates: tuple[DuplicateKey, ...] = field(default=())


# --- YAML 1.2 core schema resolver -----------------------------------------------------------

_NULL_RE = re.compile(r"^(?:~|null|Null|NULL|)$")
_BOOL_RE = re.compile(r"^(?:true|True|TRUE|false|False|FALSE)$")
_INT_RE = re.compile(r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$")
_FLOAT_RE = re.compile(
    r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
    r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"
)


class _Resolver12(yaml.resolver.Resolver):
    pass


_Resolver12.yaml_implicit_resolvers = {}
for _tag, _regexp, _first in (
    ("tag:yaml.org,2002:null", _NULL_RE, ["~", "n", "N", ""]),
    ("tag:yaml.org,2002:bool", _BOOL_RE, list("tTfF")),
    ("tag:yaml.org,2002:int", _INT_RE, list("-+0123456789")),
    ("tag:yaml.org,2002:float", _FLOAT_RE, list("-+.0123456789")),
):
    _Resolver12.add_implicit_resolver(_tag, _regexp, _first)


#: Deepest nesting of sequences and mappings accepted (real XRDF and cuRobo files nest < 10).
MAX_DEPTH = 100
#: Most alias uses (``*name``) in one document.
MAX_ALIASES = 10_000
#: The expanded document may hold ``MAX_EXPANDED_NODES + MAX_AMPLIFICATION * distinct`` nodes.
MAX_EXPANDED_NODES = 100_000
MAX_AMPLIFICATION = 10

# What YAML does not allow in a stream (the complement of PyYAML's Reader.NON_PRINTABLE, which
# raises without a position). Written as the few characters it excludes: the negated class of
# what it allows takes Python ~10 ms to compile, paid by every command at start-up.
_NON_PRINTABLE = re.compile(
    "[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x84\x86-\x9f\ud800-\udfff\ufffe\uffff]"
)


class _Composer12(
    yaml.reader.Reader,
    yaml.scanner.Scanner,
    yaml.parser.Parser,
    yaml.composer.Composer,
    _Resolver12,
):
    def __init__(self, stream: str, path: str) -> None:
        yaml.reader.Reader.__init__(self, stream)
        yaml.scanner.Scanner.__init__(self)
        yaml.parser.Parser.__init__(self)
        yaml.composer.Composer.__init__(self)
        _Resolver12.__init__(self)
        self._path = path
        self._depth = 0
        self._aliases = 0

    def compose_node(self, parent: yaml.Node | None, index: Any) -> yaml.Node:
        """PyYAML's recursive composer, with the nesting depth and alias uses bounded."""
        event = self.peek_event()  # type: ignore[no-untyped-call]
        if isinstance(event, yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                raise _error_at(self._path, event.start_mark, f"more than {MAX_ALIASES} aliases")
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _error_at(
                    self._path, event.start_mark, f"nesting deeper than {MAX_DEPTH} levels"
                )
            node: yaml.Node | None = super().compose_node(parent, index)
            assert node is not None
            return node
        finally:
            self._depth -= 1


def _error_at(path: str, mark: Any, problem: str) -> YamlError:
    line = mark.line + 1 if mark is not None else None
    col = mark.column + 1 if mark is not None else None
    return YamlError(f"{problem}; refusing this document", path=path, line=line, col=col)


def _check_printable(text: str, path: str) -> None:
    m = _NON_PRINTABLE.search(text)
    if m is None:
        return
    start = m.start()
    line = text.count("\n", 0, start) + 1
    col = start - (text.rfind("\n", 0, start) + 1) + 1
    code = ord(m.group())
    raise YamlError(
        f"control character U+{code:04X} is not allowed in YAML (write it as an escape such "
        f'as "\\x{code:02x}" inside double quotes)'
        if code < 0x100
        else f"character U+{code:04X} is not allowed in YAML",
        path=path,
        line=line,
        col=col,
    )


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
                raise _error_at(
                    path, node.start_mark, f"aliases expand this document beyond {allowed:,} nodes"
                )
            continue
        if key in sizes:
            continue
        if key in open_nodes:
            raise _error_at(path, node.start_mark, "an alias refers to a node that contains it")
        open_nodes.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node))


def _scalar_value(node: yaml.ScalarNode, path: str) -> Scalar:
    tag = node.tag
    text: str = str(node.value)
    line, col = node.start_mark.line + 1, node.start_mark.column + 1
    if tag == "tag:yaml.org,2002:null":
        return None
    if tag == "tag:yaml.org,2002:bool":
        if text.lower() in ("true", "false"):
            return text.lower() == "true"
        raise YamlError(f"'{text}' is not a boolean", path=path, line=line, col=col)
    if tag == "tag:yaml.org,2002:int":
        try:
            if text.startswith("0o"):
                return int(text[2:], 8)
            if text.startswith("0x"):
                return int(text[2:], 16)
            return int(text)
        except ValueError:
            raise YamlError(f"'{text}' is not an integer", path=path, line=line, col=col) from None
    if tag == "tag:yaml.org,2002:float":
        low = text.lower().lstrip("+")
        if low in (".inf",):
            return math.inf
        if low == "-.inf":
            return -math.inf
        if low == ".nan":
            return math.nan
        try:
            return float(text)
        except ValueError:
            raise YamlError(f"'{text}' is not a number", path=path, line=line, col=col) from None
    if tag in ("tag:yaml.org,2002:str", "!"):
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
        return YScalar(line, col, _scalar_value(node, path), quoted=node.style in ("'", '"'))
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


def parse_yaml(text: str, path: str = "<string>") -> YamlDocument:
    """Parse one YAML document, keeping positions and recording duplicate keys.

    Raises :class:`YamlError` (with line and column) on a syntax error, a second document, or
    a document beyond the bounds in the module docstring.
    """
    _check_printable(text, path)
    loader = _Composer12(text, path)
    try:
        node = loader.get_single_node()
        if node is not None:
            _check_expansion(node, path)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        problem = exc.problem or exc.context or "invalid YAML"
        context = f" ({exc.context})" if exc.context and exc.problem else ""
        raise YamlError(
            f"YAML syntax error: {problem}{context}",
            path=path,
            line=mark.line + 1 if mark else None,
            col=mark.column + 1 if mark else None,
        ) from None
    except yaml.YAMLError as exc:
        raise YamlError(f"YAML error: {' '.join(str(exc).split())}", path=path) from None
    finally:
        loader.dispose()
    if node is None:
        return YamlDocument(path, None, ())
    dups: list[DuplicateKey] = []
    root = _convert(node, path, "", dups)
    return YamlDocument(path, root, tuple(dups))


def raise_on_duplicates(doc: YamlDocument) -> None:
    if doc.duplicates:
        d = doc.duplicates[0]
        raise YamlError(
            f"duplicate key '{d.key}' (first defined on line {d.first_line}, again on line "
            f"{d.line}); YAML keys must be unique",
            path=doc.path,
            line=d.line,
            col=d.col,
        )


def read_text(path: str | os.PathLike[str]) -> str:
    """Read a UTF-8 file through :func:`xrdf_tools.fileio.read_input_text`; a missing,
    unreadable, non-regular, oversized or non-UTF-8 file is a one-line :class:`YamlError`."""
    return read_input_text(path, what="file", error=YamlError)


def load_yaml(path: str | os.PathLike[str]) -> YamlDocument:
    """Read and parse a YAML file; duplicate keys are an error naming both lines."""
    doc = parse_yaml(read_text(path), str(path))
    raise_on_duplicates(doc)
    return doc


def load_plain(path: str | os.PathLike[str]) -> Any:
    """Plain Python data of a YAML file (YAML 1.2 scalars, duplicate keys rejected)."""
    return to_python(load_yaml(path).root)


def node_positions(root: YNode | None) -> dict[str, tuple[int, int]]:
    """``key_path → (line, col)`` for every node of a tree.

    The value of a mapping entry is recorded under its key path (``a.b``) and the key itself
    under ``a.b#key``; sequence items under ``a.b[0]``. The root is recorded under ``""``.
    """
    out: dict[str, tuple[int, int]] = {}
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
