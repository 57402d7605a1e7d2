"""The one XML parser of xrdf-tools (URDF, SRDF, the SRDF that ``export srdf --merge`` edits).

lxml parses with every guard on, whatever the caller keeps:

* entities are never substituted (``resolve_entities=False``): an entity bomb stays one
  reference, and an external entity (``<!ENTITY e SYSTEM "file:///etc/passwd">``) is never read;
* no DTD is loaded and no attribute default applied from one (``load_dtd=False``,
  ``attribute_defaults=False``), nothing is fetched over the network (``no_network=True``);
* libxml2's default limits stay on (``huge_tree=False``): at most 256 levels of nesting and
  10 MB in one text node, comment or attribute value; the file itself was size-capped when read
  (:func:`xrdf_tools.util.fileio.read_input_bytes`). A mesh file (COLLADA) may lift them
  (``huge_tree=True``: one ``<float_array>`` of a large mesh is over 10 MB); entities are still
  not substituted, and the file's own size cap bounds the rest.

A document that is not well-formed raises :class:`XmlSyntaxError` with libxml2's words and
position; each caller words its own one-line message from it. A caller that reads like a
namespace-unaware reader (a URDF: ROS parses it with tinyxml) can accept an undeclared prefix
(``<sensor:camera>`` in a Gazebo block without ``xmlns:sensor``): the document is then read
on, the element keeps its prefixed name, and each such place is handed back.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

__all__ = ["XmlSyntaxError", "parse_xml", "utf8_xml_bytes"]

_UNDECLARED_PREFIX = 201  # libxml2's XML_NS_ERR_UNDEFINED_NAMESPACE
_POSITION_SUFFIX = re.compile(r",? line \d+, column \d+\s*$")
_OTHER_ENCODING = re.compile(
    rb"^(\s*<\?xml[^>]*?)\s+encoding\s*=\s*(['\"])(?!utf-?8\2)[^'\"]*\2", re.I
)


@dataclass(frozen=True)
class XmlSyntaxError(Exception):
    """The bytes are not well-formed XML.

    ``verbatim``: libxml2's first line as it words it (ending with ``, line N, column N``);
    ``reason``: the same without that position, which ``line`` and ``col`` (1-based) give.
    """

    verbatim: str
    reason: str
    line: int | None
    col: int | None

    def __str__(self) -> str:
        return self.verbatim


def parse_xml(
    data: bytes,
    *,
    keep_comments: bool = True,
    keep_cdata: bool = False,
    remove_blank_text: bool = False,
    undeclared_prefixes: list[XmlSyntaxError] | None = None,
    huge_tree: bool = False,
) -> Any:
    """The root element of ``data`` (an lxml element), parsed with the guards above.

    Processing instructions stay in the tree; ``keep_comments``: so do comments;
    ``keep_cdata``: CDATA sections stay marked as such (an editor that writes the document
    back), else they are plain text; ``remove_blank_text``: whitespace-only text between
    elements is dropped. With an ``undeclared_prefixes`` list, a namespace prefix used without
    its ``xmlns:`` declaration is no error: it is appended there (libxml2's words and
    position) and the name keeps its prefix. Raises :class:`XmlSyntaxError`.
    """
    from lxml import etree

    options: dict[str, Any] = {
        "resolve_entities": False,
        "no_network": True,
        "load_dtd": False,
        "dtd_validation": False,
        "attribute_defaults": False,
        "huge_tree": huge_tree,
        "remove_comments": not keep_comments,
        "remove_pis": False,
        "strip_cdata": not keep_cdata,
        "remove_blank_text": remove_blank_text,
    }
    try:
        return etree.fromstring(data, etree.XMLParser(**options))
    except etree.XMLSyntaxError as e:
        if undeclared_prefixes is None or e.code != _UNDECLARED_PREFIX:
            raise _syntax_error(e.msg or str(e), e.position or (e.lineno, None)) from None
    # Read on past the undeclared prefixes alone: the first other error fails.
    parser = etree.XMLParser(recover=True, **options)
    root = etree.fromstring(data, parser)
    errors = [(e, _syntax_error(e.message, (e.line, e.column))) for e in parser.error_log]
    for entry, error in errors:
        if not _is_undeclared_prefix(entry):
            raise error
    undeclared_prefixes.extend(error for _, error in errors)
    return root


def _syntax_error(message: str, position: tuple[int | None, int | None]) -> XmlSyntaxError:
    verbatim = (message or "not well-formed").splitlines()[0]
    reason = _POSITION_SUFFIX.sub("", verbatim)
    line, col = position
    if reason == verbatim and line is not None:
        verbatim = f"{reason}, line {line}, column {col}"
    return XmlSyntaxError(verbatim, reason, line, col)


def _is_undeclared_prefix(entry: Any) -> bool:
    return bool(entry.type == _UNDECLARED_PREFIX)


def utf8_xml_bytes(data: str | bytes) -> bytes:
    """``data`` as bytes to parse: text is encoded as UTF-8 and an XML declaration naming
    another encoding loses its ``encoding=`` (it would no longer be true); bytes are kept."""
    if isinstance(data, bytes):
        return data
    return _OTHER_ENCODING.sub(rb"\1", data.encode("utf-8"), count=1)
