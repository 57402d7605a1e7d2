"""An XML document (an SRDF) edited with lxml and written back with the original bytes kept.

The document is parsed by :func:`xrdf_tools.util.safe_xml.parse_xml` (no entity resolved, no
DTD loaded, no network), keeping comments, processing instructions, CDATA and entity
references. Writing back:

* the bytes before ``<robot`` (XML declaration, comments, DOCTYPE with its internal subset,
  blank lines) and after ``</robot>`` are copied verbatim — lxml would rewrite the declaration
  and drop the whitespace between top-level nodes;
* ``<robot>`` is serialized by lxml (text and indentation inside it are kept by lxml), then the
  start tag of every original element whose attributes did not change is replaced by its
  original bytes: lxml would otherwise rewrite ``<a  x='1' />`` as ``<a x="1"/>``;
* new elements follow the file's majority style for empty tags (``<a/>`` or ``<a />``), and
  LF becomes CRLF in a file with CRLF line ends.

When the prolog or the end of ``<robot>`` cannot be located for sure, or the tags found in the
bytes do not match the parsed elements, the whole document is written by lxml (declaration
kept) — valid, but formatted the lxml way. End tags are always written ``</name>``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

from ..util.errors import SourceError
from ..util.safe_xml import XmlSyntaxError, parse_xml, utf8_xml_bytes

__all__ = ["XmlDocument", "fill_empty", "insert_after", "last_child", "remove_element"]

_DECL = re.compile(rb"^(\xef\xbb\xbf)?<\?xml[^>]*\?>")
#: Markup inside an element: comments, PIs, CDATA and end tags are matched so that their
#: content is never taken for a start tag; text never contains a raw "<".
_MARKUP = re.compile(
    rb"<!--.*?-->|<\?.*?\?>|<!\[CDATA\[.*?\]\]>|</[^>]*>"
    rb"|<(?P<name>[^\s/>!?]+)(?:[^>\"']|\"[^\"]*\"|'[^']*')*>",
    re.S,
)
_MAX_CANDIDATES = 50

Attrs = tuple[tuple[str, str], ...]


def _try_parse(data: bytes) -> Any | None:
    try:
        return parse_xml(data, keep_cdata=True).getroottree()
    except XmlSyntaxError:
        return None


def _start_tags(data: bytes) -> list[tuple[str, int, int]]:
    """(local name, start, end) of every start tag in ``data``, in document order."""
    out = []
    for m in _MARKUP.finditer(data):
        name = m.group("name")
        if name is not None:
            out.append((name.decode("utf-8", "replace").rsplit(":", 1)[-1], m.start(), m.end()))
    return out


def _elements(root: Any) -> list[Any]:
    return [el for el in root.iter() if isinstance(el.tag, str)]


def _local(el: Any) -> str:
    tag: str = el.tag
    return tag.rsplit("}", 1)[-1]


def _attrs(el: Any) -> Attrs:
    return tuple((str(k), str(v)) for k, v in el.attrib.items())


@dataclass
class XmlDocument:
    """A parsed document; edit :attr:`root` in place, then :meth:`serialize`."""

    raw: bytes
    tree: Any
    prolog: bytes | None = None
    epilog: bytes | None = None
    #: original element → (its start tag bytes, its attributes then)
    original: dict[Any, tuple[bytes, Attrs]] = field(default_factory=dict)

    @property
    def root(self) -> Any:
        return self.tree.getroot()

    @property
    def encoding(self) -> str:
        return str(self.tree.docinfo.encoding or "UTF-8")

    @classmethod
    def parse(
        cls,
        data: str | bytes,
        path: str,
        root_tag: str = "robot",
        what: str = "SRDF",
        *,
        undeclared_prefixes: bool = False,
    ) -> XmlDocument:
        """Parse ``data``; :class:`SourceError` (one line) when it is not XML with
        ``<root_tag>`` as root (``what`` names the format in messages). With
        ``undeclared_prefixes`` a prefix without its ``xmlns:`` declaration is read as part of
        the name (as ROS reads a URDF's ``<sensor:camera>``), and every start tag is then
        written the lxml way."""
        raw = utf8_xml_bytes(data)
        try:
            root = parse_xml(
                raw, keep_cdata=True, undeclared_prefixes=[] if undeclared_prefixes else None
            )
        except XmlSyntaxError as e:
            msg = f"malformed {what} XML: {e.verbatim}"
            raise SourceError(msg, path=path, line=e.line) from None
        if root is None or root.tag != root_tag:
            raise SourceError(
                f"the root element of an {what} must be <{root_tag}>", path=path, line=1
            )
        doc = cls(raw, root.getroottree())
        doc.prolog = doc._find_prolog()
        doc.epilog = doc._find_epilog()
        doc.original = doc._original_tags()
        return doc

    # --- locating the original bytes ---------------------------------------------------------
    def _find_prolog(self) -> bytes | None:
        """The bytes before the root start tag: the first candidate that parses as a prolog
        with as many nodes as the document's."""
        root = self.root
        n_before = len(list(root.itersiblings(preceding=True)))
        pattern = re.compile(rb"<" + re.escape(_local(root).encode()) + rb"[\s/>]")
        for i, m in enumerate(pattern.finditer(self.raw)):
            if i >= _MAX_CANDIDATES:
                break
            head = self.raw[: m.start()]
            t = _try_parse(head + b"<x/>")
            if t is not None and len(list(t.getroot().itersiblings(preceding=True))) == n_before:
                return head
        return None

    def _find_epilog(self) -> bytes | None:
        """The bytes after the root element, verified the same way."""
        n_after = len(list(self.root.itersiblings()))
        ends = [m.end() for m in re.finditer(rb"</[^>]*>|/>", self.raw)]
        for end in reversed(ends[-_MAX_CANDIDATES:]):
            tail = self.raw[end:]
            t = _try_parse(b"<x/>" + tail)
            if t is not None and len(list(t.getroot().itersiblings())) == n_after:
                return tail
        return None

    def _original_tags(self) -> dict[Any, tuple[bytes, Attrs]]:
        if self.prolog is None or self.epilog is None:
            return {}
        body = self.raw[len(self.prolog) : len(self.raw) - len(self.epilog)]
        tags = _start_tags(body)
        els = _elements(self.root)
        if [t[0] for t in tags] != [_local(el) for el in els]:
            return {}
        return {el: (body[s:e], _attrs(el)) for el, (_, s, e) in zip(els, tags, strict=True)}

    # --- writing -----------------------------------------------------------------------------
    def serialize(self) -> bytes:
        from lxml import etree

        if self.prolog is None or self.epilog is None:
            return self._whole_document()
        body = etree.tostring(
            self.root, encoding=self.encoding, xml_declaration=False, with_tail=False
        )
        return self.prolog + self._line_ends(self._restore_tags(body)) + self.epilog

    def _restore_tags(self, body: bytes) -> bytes:
        """Original start tags for unchanged elements, the file's empty-tag style for others."""
        tags = _start_tags(body)
        els = _elements(self.root)
        if [t[0] for t in tags] != [_local(el) for el in els]:
            return body
        spaced = self._spaced_empty_tags()
        out, pos = [], 0
        for el, (_, s, e) in zip(els, tags, strict=True):
            tag = body[s:e]
            orig = self.original.get(el)
            same_shape = orig is not None and orig[0].endswith(b"/>") == tag.endswith(b"/>")
            if orig is not None and same_shape and orig[1] == _attrs(el):
                tag = orig[0]
            elif spaced and tag.endswith(b"/>") and not tag.endswith(b" />"):
                tag = tag[:-2] + b" />"
            out += [body[pos:s], tag]
            pos = e
        out.append(body[pos:])
        return b"".join(out)

    def _spaced_empty_tags(self) -> bool:
        """Whether most original empty-element tags are written ``<a />``."""
        empty = [t for t, _ in self.original.values() if t.endswith(b"/>")]
        return sum(1 for t in empty if t[-3:-2].isspace()) * 2 > len(empty)

    def _line_ends(self, body: bytes) -> bytes:
        crlf = self.raw.count(b"\r\n")
        if crlf and crlf == self.raw.count(b"\n"):
            return re.sub(rb"(?<!\r)\n", b"\r\n", body)
        return body

    def _whole_document(self) -> bytes:
        """Fallback: lxml's serialization of the whole document, the declaration kept."""
        from lxml import etree

        doc = etree.tostring(self.tree, encoding=self.encoding, xml_declaration=False)
        m = _DECL.match(self.raw)
        decl = m.group(0) if m else f'<?xml version="1.0" encoding="{self.encoding}"?>'.encode()
        return decl + b"\n" + self._line_ends(doc) + b"\n"


# ------------------------------------------------------------------------------------------
# Whitespace-preserving edits of the element tree
# ------------------------------------------------------------------------------------------
def last_child(root: Any, tag: str) -> Any | None:
    found = None
    for el in root.iterchildren(tag):
        found = el
    return found


def _ws_before(el: Any) -> str:
    prev = el.getprevious()
    text = prev.tail if prev is not None else el.getparent().text
    return str(text or "")


def _set_ws_before(parent: Any, prev: Any | None, value: str) -> None:
    if prev is not None:
        prev.tail = value
    else:
        parent.text = value


def _indent(ws: str) -> str | None:
    """The indentation after the last newline of ``ws``, or None when ``ws`` has none."""
    return ws.rsplit("\n", 1)[1] if "\n" in ws and not ws.strip() else None


def _child_indent(root: Any) -> str:
    for el in reversed(root):
        ind = _indent(_ws_before(el))
        if ind is not None:
            return ind
    return "  "


def insert_after(root: Any, anchor: Any | None, new: list[Any]) -> None:
    """Insert ``new`` after ``anchor`` (else after ``<robot>``'s last child), one per line,
    indented like the file (a blank line first when the file separates its sections so)."""
    if not new:
        return
    if anchor is None and not len(root):
        fill_empty(root, new)
        return
    if anchor is None:
        anchor = root[-1]
        before = _ws_before(anchor)
        sep = "\n" + _child_indent(root)
        first = ("\n" if before.count("\n") >= 2 and not before.strip() else "") + sep
    else:
        ind = _indent(_ws_before(anchor))
        first = sep = "\n" + (ind if ind is not None else _child_indent(root))
    tail = anchor.tail
    prev = anchor
    for i, el in enumerate(new):
        prev.tail = first if i == 0 else sep
        prev.addnext(el)
        prev = el
    prev.tail = tail


def fill_empty(root: Any, new: list[Any]) -> None:
    text = root.text or ""
    keep = text if text.strip() else ""
    close = text if "\n" in text and not text.strip() else "\n"
    root.text = keep + "\n  "
    for i, el in enumerate(new):
        root.append(el)
        el.tail = "\n  " if i < len(new) - 1 else close


def remove_element(el: Any) -> None:
    """Remove ``el``, keeping the layout: the larger of the blank-line gaps around it and the
    indentation of what follows (for the last child: what precedes the parent's end tag)."""
    parent, prev = el.getparent(), el.getprevious()
    before, after = _ws_before(el), el.tail or ""
    if el.getnext() is None and not before.strip():  # the end tag of <robot> keeps its place
        merged = after
    elif not before.strip() and not after.strip():
        nl = max(before.count("\n"), after.count("\n"))
        merged = "\n" * nl + after.rsplit("\n", 1)[-1] if nl else (after or before)
    else:
        merged = before + after
    parent.remove(el)
    _set_ws_before(parent, prev, merged)
