"""The YAML reader of :mod:`xrdf_tools.yaml.io`: one pass from parser events to the tree.

:class:`_Builder` turns parser events straight into :class:`~xrdf_tools.yaml.tree.YNode`
objects (no PyYAML node graph, no second walk). It checks, in the order PyYAML's composer
would, so every message and position is the one a plain compose-and-convert reader gives:

* while reading: the nesting bound (at the node that goes too deep), a repeated anchor, the
  alias count (at most ``MAX_ALIASES``), an undefined alias, a second document (PyYAML's own
  wording), and any syntax error of the parser;
* after the last event, the first problem in document order of the conversion: a scalar that
  is not what its tag says, a mapping or list used as a key. Duplicate keys are recorded in
  document order with the same key paths.

An alias is its anchor's node again (shared, not copied); a document that uses one gets the
checks of :mod:`xrdf_tools.yaml.aliases` after its last event: what the aliases expand to is
bounded, an alias inside its own anchor is an error, and the checks above run on the document
as expanded (nesting through aliases, a key that is an alias of a mapping, repeated keys under
each alias).

One builder, two event sources (:mod:`xrdf_tools.yaml.events`): libyaml's C parser when PyYAML
has it, else PyYAML's pure-Python parser, which also reads again the few documents libyaml
reads differently (:class:`Diverges`). The tests compare both event sources with a plain
compose-and-convert reference on edge cases, documents with aliases and 600 mutated documents
(``tests/yaml/test_yaml_readers.py``, ``tests/yaml/test_yaml_aliases.py``).
"""

from __future__ import annotations

import gc
import itertools
import re
from array import array
from collections.abc import Callable
from typing import Any

import yaml
from yaml.composer import ComposerError
from yaml.events import (
    AliasEvent,
    MappingEndEvent,
    MappingStartEvent,
    ScalarEvent,
    SequenceEndEvent,
    SequenceStartEvent,
    StreamEndEvent,
)

from ..util.errors import YamlError
from .aliases import AliasCycle, check_expansion, walk_expanded
from .events import CParser, Diverges, PyParser, flow_risk, libyaml_may_read
from .rules import INT_TAG, MAX_ALIASES, MAX_DEPTH, error_at, plain_value, scalar_value
from .tree import (
    DuplicateKey,
    YamlDocument,
    YNode,
    YScalar,
    new_map,
    new_plain_seq,
    new_scalar,
    new_seq,
)

#: Whether libyaml is available to :func:`read_document` (tests and benchmarks turn it off).
HAVE_LIBYAML = CParser is not None

#: Lists of plain scalars longer than this keep their positions' array (no copy to bytes).
_KEEP_ARRAY = 64

# A key that makes ``a.b`` / ``a[0]`` / ``a#key`` paths ambiguous (see yaml.positions).
_ODD_KEY = re.compile(r"[.\[\]#]")


def _may_repeat(items: list[YNode]) -> bool:
    """Whether a mapping's keys (``items[0::2]``, all scalars) may hold a repeat. Two keys are
    compared as a dict compares them (the same object, or equal), more by a set."""
    if len(items) == 4:
        a, b = items[0].value, items[2].value  # type: ignore[attr-defined]
        return bool(a is b or a == b)
    keys = [k.value for k in items[0::2]]  # type: ignore[attr-defined]
    return len(set(keys)) < len(keys)


class _Frame:
    """A sequence or mapping being read: its children so far (a mapping's keys and values
    alternate) and its index among its parent's children (for key paths).

    A sequence keeps the values and packed positions of its items while they are all unquoted
    scalars (``values`` is not None): it becomes a :class:`YPlainSeq`. The first other item
    turns them into nodes (:meth:`unpack`).
    """

    __slots__ = ("anchor", "col", "flow", "is_map", "items", "line", "positions", "slot", "values")

    def __init__(
        self, line: int, col: int, flow: bool, is_map: bool, slot: int, anchor: str | None
    ) -> None:
        self.items: list[YNode] = []
        self.values: list[Any] | None = None if is_map else []
        # packed positions in an array: no int object kept per item while the list is read
        self.positions: array[int] | None = None if is_map else array("Q")
        self.line = line
        self.col = col
        self.flow = flow
        self.is_map = is_map
        self.slot = slot
        self.anchor = anchor

    def unpack(self) -> None:
        """Keep the items as nodes from now on (the YScalar nodes a YPlainSeq would make)."""
        assert self.values is not None and self.positions is not None
        seq = new_plain_seq(0, 0, tuple(self.values), self.positions.tobytes(), False)
        self.items = list(seq.items)
        self.values = self.positions = None

    def node(self) -> YNode:
        """The finished node."""
        items = self.items
        if self.values:
            assert self.positions is not None
            # bytes are smaller than an array for a short list; a long one keeps its array
            long = len(self.positions) > _KEEP_ARRAY
            positions = self.positions if long else self.positions.tobytes()
            return new_plain_seq(self.line, self.col, tuple(self.values), positions, self.flow)
        if not self.is_map:
            return new_seq(self.line, self.col, tuple(items), self.flow)
        return new_map(
            self.line, self.col, tuple(zip(items[0::2], items[1::2], strict=True)), self.flow
        )


class _Builder:
    """Builds one document from its events (see the module docstring)."""

    def __init__(self, path: str, libyaml: bool) -> None:
        self.path = path
        self.libyaml = libyaml
        self.stack: list[_Frame] = []
        self.root: YNode | None = None
        self.error: YamlError | None = None
        self.dups: list[DuplicateKey] = []
        self.anchors: dict[str, Any] = {}  # name -> the mark of its node
        # name -> its node (None while the node is read); the bad scalars' errors by node id
        self.anchored: dict[str, YNode | None] = {}
        self.bad: dict[int, YamlError] = {}
        self._bad_scalar: YamlError | None = None
        self.aliases = 0
        self.keys: dict[tuple[str, bool], tuple[Any]] = {}
        self.simple_keys = True
        self._mark_line = -1
        self._line = 0
        self.handlers: dict[type, Callable[[Any], None]] = {
            ScalarEvent: self.scalar,
            SequenceStartEvent: self.start_sequence,
            MappingStartEvent: self.start_mapping,
            SequenceEndEvent: self.end,
            MappingEndEvent: self.end,
            AliasEvent: self.alias,
        }

    def read(self, get_event: Callable[[], Any]) -> YamlDocument:
        get_event()  # STREAM-START
        event = get_event()
        if type(event) is StreamEndEvent:
            return YamlDocument(self.path, None, ())
        event = get_event()  # the first event after DOCUMENT-START: the root node
        root_mark = event.start_mark
        handlers = self.handlers
        while True:
            handler = handlers.get(type(event))
            if handler is None:  # DOCUMENT-END: the root is complete
                break
            handler(event)
            event = get_event()
        event = get_event()
        if type(event) is not StreamEndEvent:
            raise ComposerError(
                "expected a single document in the stream",
                root_mark,
                "but found another document",
                event.start_mark,
            )
        if self.aliases:
            return self._expanded()
        if self.error is not None:
            raise self.error
        self.dups.sort(key=lambda d: (d.line, d.col))
        return YamlDocument(self.path, self.root, tuple(self.dups), self.simple_keys)

    def _expanded(self) -> YamlDocument:
        """The document with aliases, checked as :mod:`xrdf_tools.yaml.aliases` says."""
        assert self.root is not None
        check_expansion(self.root, self.path, self.anchored)
        dups = walk_expanded(self.root, self.path, self.bad)
        return YamlDocument(self.path, self.root, dups)

    # --- events --------------------------------------------------------------------------------
    def _enter(self, event: Any) -> tuple[int, int]:
        """The checks made before any node (depth first, then the anchor, as PyYAML's
        composer does) and the node's 1-based position."""
        if len(self.stack) >= MAX_DEPTH:
            raise error_at(self.path, event.start_mark, f"nesting deeper than {MAX_DEPTH} levels")
        mark = event.start_mark
        if event.anchor is not None:
            self._anchor(event.anchor, mark)
        if mark.line != self._mark_line:  # one int per line, shared by the nodes on it
            self._mark_line = mark.line
            self._line = mark.line + 1
        return self._line, mark.column + 1

    def scalar(self, event: Any) -> None:
        stack = self.stack
        top = stack[-1] if stack else None
        text: str = event.value
        style = event.style
        tag = event.tag
        if self.libyaml and (
            tag is not None
            or event.anchor is not None
            or style == "|"
            or style == ">"
            or (top is not None and top.flow and not style and flow_risk(text))
        ):
            raise Diverges
        # _enter, inlined (a big file is mostly scalars)
        mark = event.start_mark
        if len(stack) >= MAX_DEPTH or event.anchor is not None:
            self._enter(event)
        if mark.line != self._mark_line:
            self._mark_line = mark.line
            self._line = mark.line + 1
        line = self._line
        col = mark.column + 1
        value: Any
        quoted = style == "'" or style == '"'
        if top is not None and top.is_map and not len(top.items) & 1:  # a key
            if tag is None or tag == "!":
                value = self._key(text, event.implicit[0], line, col)
            else:
                value = self._tagged(tag, text, line, col)
                self.simple_keys = False
            node = new_scalar(line, col, value, quoted)
            top.items.append(node)
            if event.anchor is not None or self._bad_scalar is not None:
                self._note(node, event.anchor)
            return
        if tag is not None and tag != "!":
            value = self._tagged(tag, text, line, col)
        elif not event.implicit[0]:
            value = text
        else:
            try:
                value = plain_value(text)
            except ValueError:  # an int of more digits than Python converts: as scalar_value
                value = self._tagged(INT_TAG, text, line, col)
        special = event.anchor is not None or self._bad_scalar is not None
        if top is None:
            node = self.root = new_scalar(line, col, value, quoted)
        elif top.values is not None and not quoted and not special:  # plain scalars so far
            top.values.append(value)
            top.positions.append((line << 32) | col)  # type: ignore[union-attr]
            return
        else:
            if top.values is not None:
                top.unpack()
            node = new_scalar(line, col, value, quoted)
            top.items.append(node)
        if special:
            self._note(node, event.anchor)

    def start_sequence(self, event: Any) -> None:
        self._start(event, False)

    def start_mapping(self, event: Any) -> None:
        self._start(event, True)

    def _start(self, event: Any, is_map: bool) -> None:
        if self.libyaml and (event.tag is not None or event.anchor is not None):
            raise Diverges
        line, col = self._enter(event)
        stack = self.stack
        slot = 0
        if stack:
            top = stack[-1]
            if top.values is not None:
                top.unpack()
            slot = len(top.items)
        anchor = event.anchor
        if anchor is not None:
            self.anchored[anchor] = None  # an alias to it from inside is a cycle
        stack.append(_Frame(line, col, bool(event.flow_style), is_map, slot, anchor))

    def end(self, event: Any) -> None:
        frame = self.stack.pop()
        node = frame.node()
        if frame.anchor is not None:
            self.anchored[frame.anchor] = node
        repeats = frame.is_map and len(frame.items) > 2 and self.error is None
        repeats = repeats and not self.aliases  # (an alias's keys: checked at the end)
        if repeats and _may_repeat(frame.items):
            self._find_duplicates(frame, node.pairs)  # type: ignore[attr-defined]
        stack = self.stack
        if not stack:
            self.root = node
            return
        top = stack[-1]
        if top.is_map and not len(top.items) & 1:
            self.simple_keys = False
            if self.error is None and not self.aliases:
                kind = "mapping" if frame.is_map else "list"
                self.error = YamlError(
                    f"a {kind} is used as a mapping key; keys must be names or numbers",
                    path=self.path,
                    line=frame.line,
                    col=frame.col,
                )
        top.items.append(node)

    def alias(self, event: Any) -> None:
        """An alias: its anchor's node again (checked once the document is read)."""
        if self.libyaml:
            raise Diverges  # anchor names and messages: PyYAML's
        mark = event.start_mark
        self.aliases += 1
        if self.aliases > MAX_ALIASES:
            raise error_at(self.path, mark, f"more than {MAX_ALIASES} aliases")
        if len(self.stack) >= MAX_DEPTH:
            raise error_at(self.path, mark, f"nesting deeper than {MAX_DEPTH} levels")
        line, col = mark.line + 1, mark.column + 1
        name: str = event.anchor  # the name the alias refers to
        if name not in self.anchored:
            raise ComposerError(None, None, f"found undefined alias {name!r}", mark)
        node = self.anchored[name]
        if node is None:
            node = AliasCycle(line, col, name)
        self.simple_keys = False
        stack = self.stack
        if not stack:
            self.root = node
            return
        top = stack[-1]
        if top.values is not None:
            top.unpack()
        top.items.append(node)

    # --- helpers -------------------------------------------------------------------------------
    def _note(self, node: YScalar, anchor: str | None) -> None:
        """Record an anchored scalar, and the error of a scalar that is not what its tag says."""
        if anchor is not None:
            self.anchored[anchor] = node
        if self._bad_scalar is not None:
            self.bad[id(node)] = self._bad_scalar
            self._bad_scalar = None

    def _anchor(self, name: str, mark: Any) -> None:
        first = self.anchors.get(name)
        if first is not None:
            raise ComposerError(
                f"found duplicate anchor {name!r}; first occurrence",
                first,
                "second occurrence",
                mark,
            )
        self.anchors[name] = mark

    def _tagged(self, tag: str, text: str, line: int, col: int) -> Any:
        try:
            return scalar_value(tag, text, self.path, line, col)
        except YamlError as e:
            if self.error is None:
                self.error = e
            self._bad_scalar = e
            return text

    def _key(self, text: str, plain: bool, line: int, col: int) -> Any:
        """The value of an untagged mapping key, worked out once per distinct key text (one
        string object per distinct key); notes keys that make key paths ambiguous."""
        known = self.keys.get((text, plain))
        if known is None:
            try:
                value = plain_value(text) if plain else text
            except ValueError:  # as in scalar()
                self.simple_keys = False
                return self._tagged(INT_TAG, text, line, col)
            if type(value) is not str or not value or _ODD_KEY.search(value):
                self.simple_keys = False
            known = self.keys[(text, plain)] = (value,)
        return known[0]

    def _find_duplicates(self, frame: _Frame, pairs: tuple[tuple[YNode, YNode], ...]) -> None:
        keys = [k for k, _ in pairs]
        self.simple_keys = False
        key_path = self._key_path(frame)
        seen: dict[Any, YScalar] = {}
        for k in keys:
            assert isinstance(k, YScalar)
            kv = k.value
            if kv not in seen:
                seen[kv] = k
                continue
            first = seen[kv]
            child_path = f"{key_path}.{kv}" if key_path else str(kv)
            dup = DuplicateKey(str(kv), first.line, first.col, k.line, k.col, child_path)
            self.dups.append(dup)

    def _key_path(self, frame: _Frame) -> str:
        """The key path of the node ``frame`` builds, as :func:`walk_expanded` spells it."""
        frames = [*self.stack, frame]
        key_path = ""
        for parent, child in itertools.pairwise(frames):
            if parent.is_map:
                if not child.slot & 1:  # a key (an error follows): its parent's path
                    continue
                key = parent.items[child.slot - 1]
                kv = key.value if isinstance(key, YScalar) else key
                key_path = f"{key_path}.{kv}" if key_path else str(kv)
            else:
                key_path = f"{key_path}[{child.slot}]"
        return key_path


def read_document(source: str | bytes, path: str, *, libyaml: bool | None = None) -> YamlDocument:
    """Read one document in one pass (libyaml's events when available and safe, else PyYAML's).

    ``source``: the text, or its UTF-8 bytes (already checked: libyaml reads them as they are,
    so a big file is not held twice while it is read).

    Raises PyYAML's errors for syntax errors (and an undefined alias or a repeated anchor) and
    :class:`YamlError` for the bounds and bad scalars. ``libyaml``: None uses it
    when available (:data:`HAVE_LIBYAML`); False forces PyYAML's parser.
    """
    use_c = HAVE_LIBYAML if libyaml is None else libyaml and CParser is not None
    # The tree has no reference cycles (an alias shares an earlier, finished node): the cyclic
    # collector, triggered again and again by millions of new nodes, would only walk them (a
    # third of the time of a big file).
    collecting = gc.isenabled()
    gc.disable()
    try:
        return _read(source, path, use_c)
    finally:
        if collecting:
            gc.enable()


def _read(source: str | bytes, path: str, use_c: bool) -> YamlDocument:
    if use_c and libyaml_may_read(source):
        parser = CParser(source)
        try:
            return _Builder(path, True).read(parser.get_event)
        except (Diverges, yaml.YAMLError):
            pass  # read again with PyYAML's parser: its answer (or message) is the reference
        finally:
            parser.dispose()
    py = PyParser(source if isinstance(source, str) else source.decode("utf-8"))
    try:
        return _Builder(path, False).read(py.get_event)
    finally:
        py.dispose()
