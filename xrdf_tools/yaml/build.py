"""One pass from parser events to the tree: the fast YAML reader of :mod:`xrdf_tools.yaml.io`.

The events come from libyaml's C parser when PyYAML has it (``yaml.__with_libyaml__``), else
from PyYAML's pure-Python parser. :class:`_Builder` turns them straight into
:class:`~xrdf_tools.yaml.tree.YNode` objects (no PyYAML node graph, no second walk), applying
what the reference reader (:mod:`xrdf_tools.yaml.compose`) applies, in the same order, so the
result and every message are the same:

* while reading: the nesting bound (at the node that goes too deep), a repeated anchor, a
  second document (PyYAML's own wording), and any syntax error of the parser;
* after the last event, the first problem in document order of the conversion: a scalar that
  is not what its tag says, a mapping or list used as a key. Duplicate keys are recorded in
  document order with the same key paths.

A document that uses an alias is handed to the reference reader (:class:`UsesAliases`): the
alias bounds and the expansion count are defined on its node graph.

libyaml and PyYAML's scanner disagree on a few inputs (both are YAML 1.1 parsers, written
apart): a tab between tokens (PyYAML refuses it), a byte-order mark after the start (libyaml
skips it, shifting columns), a text without a line break at its end (libyaml adds one, moving
an empty value read there), a plain scalar holding ``:`` or ``?`` or an empty value inside
``[]``/``{}`` (libyaml reads one scalar where PyYAML reads two nodes or an error; the column of
the empty value differs by one), block scalar headers (libyaml takes ``>#``), tags (PyYAML's
tag takes a following ``,``), anchor names, and every error message. So libyaml reads a
document only when it has none of these (:func:`libyaml_may_read`, and :class:`Diverges`
raised at the first such event); otherwise, or on any libyaml error, the document is read again
with PyYAML's parser, whose answer is the reference one. The tests compare the three ways on
the edge cases above and 600 mutated documents (``tests/test_yaml_readers.py``).
"""

from __future__ import annotations

import gc
import importlib
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
from .rules import INT_TAG, MAX_DEPTH, error_at, plain_value, scalar_value
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


def _libyaml_parser() -> Any:
    """libyaml's parser class, or None when PyYAML was built without libyaml (PyYAML's own
    parser then reads everything)."""
    try:
        return importlib.import_module("yaml._yaml").CParser
    except ImportError:
        return None


CParser: Any = _libyaml_parser()

#: Whether libyaml is available to :func:`read_document` (tests and benchmarks turn it off).
HAVE_LIBYAML = CParser is not None

#: Lists of plain scalars longer than this keep their positions' array (no copy to bytes).
_KEEP_ARRAY = 64

# A key that makes ``a.b`` / ``a[0]`` / ``a#key`` paths ambiguous (see yaml.positions).
_ODD_KEY = re.compile(r"[.\[\]#]")


class UsesAliases(Exception):
    """The document uses an alias: the reference reader reads it."""


class Diverges(Exception):
    """libyaml may read this document differently from PyYAML's parser."""


class PyParser(yaml.reader.Reader, yaml.scanner.Scanner, yaml.parser.Parser):
    """PyYAML's pure-Python reader, scanner and parser: the reference events."""

    def __init__(self, stream: str) -> None:
        yaml.reader.Reader.__init__(self, stream)
        yaml.scanner.Scanner.__init__(self)
        yaml.parser.Parser.__init__(self)


#: Line breaks (libyaml moves the end of a text that does not end with one to a new line,
#: which moves an empty value read there).
_BREAKS = ("\n", "\r", "\x85", "\u2028", "\u2029")
_BREAKS_UTF8 = tuple(b.encode() for b in _BREAKS)
_BOM_UTF8 = "\ufeff".encode()


def libyaml_may_read(source: str | bytes) -> bool:
    """False when the document (text, or its UTF-8 bytes) has a tab, a byte-order mark past
    the start or no line break at its end, where libyaml and PyYAML read differently (the
    other differences are found in the events)."""
    if isinstance(source, bytes):
        ends, tab, bom = source.endswith(_BREAKS_UTF8), b"\t" in source, source.find(_BOM_UTF8, 1)
    else:
        ends, tab, bom = source.endswith(_BREAKS), "\t" in source, source.find("\ufeff", 1)
    return ends and not tab and bom < 0


def _flow_risk(text: str) -> bool:
    """An untagged plain scalar inside ``[]``/``{}`` that libyaml and PyYAML may read apart."""
    return not text or ":" in text or "?" in text


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

    __slots__ = ("col", "flow", "is_map", "items", "line", "positions", "slot", "values")

    def __init__(self, line: int, col: int, flow: bool, is_map: bool, slot: int) -> None:
        self.items: list[YNode] = []
        self.values: list[Any] | None = None if is_map else []
        # packed positions in an array: no int object kept per item while the list is read
        self.positions: array[int] | None = None if is_map else array("Q")
        self.line = line
        self.col = col
        self.flow = flow
        self.is_map = is_map
        self.slot = slot

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
        self.anchors: dict[str, Any] = {}
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
        if self.error is not None:
            raise self.error
        self.dups.sort(key=lambda d: (d.line, d.col))
        return YamlDocument(self.path, self.root, tuple(self.dups), self.simple_keys)

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
            or (top is not None and top.flow and not style and _flow_risk(text))
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
            top.items.append(new_scalar(line, col, value, quoted))
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
        if top is None:
            self.root = new_scalar(line, col, value, quoted)
        elif top.values is not None and not quoted:  # a sequence of plain scalars so far
            top.values.append(value)
            top.positions.append((line << 32) | col)  # type: ignore[union-attr]
        else:
            if top.values is not None:
                top.unpack()
            top.items.append(new_scalar(line, col, value, quoted))

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
        stack.append(_Frame(line, col, bool(event.flow_style), is_map, slot))

    def end(self, event: Any) -> None:
        frame = self.stack.pop()
        node = frame.node()
        repeats = frame.is_map and len(frame.items) > 2 and self.error is None
        if repeats and _may_repeat(frame.items):
            self._find_duplicates(frame, node.pairs)  # type: ignore[attr-defined]
        stack = self.stack
        if not stack:
            self.root = node
            return
        top = stack[-1]
        if top.is_map and not len(top.items) & 1:
            self.simple_keys = False
            if self.error is None:
                kind = "mapping" if frame.is_map else "list"
                self.error = YamlError(
                    f"a {kind} is used as a mapping key; keys must be names or numbers",
                    path=self.path,
                    line=frame.line,
                    col=frame.col,
                )
        top.items.append(node)

    def alias(self, event: Any) -> None:
        raise UsesAliases

    # --- helpers -------------------------------------------------------------------------------
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
        """The key path of the node ``frame`` builds, as the reference reader spells it."""
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

    Raises :class:`UsesAliases` for a document with an alias, PyYAML's errors for syntax
    errors and :class:`YamlError` for the bounds and bad scalars. ``libyaml``: None uses it
    when available (:data:`HAVE_LIBYAML`); False forces PyYAML's parser.
    """
    use_c = HAVE_LIBYAML if libyaml is None else libyaml and CParser is not None
    # The tree has no reference cycles: the cyclic collector, triggered again and again by
    # millions of new nodes, would only walk them (a third of the time of a big file).
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
