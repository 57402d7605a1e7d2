"""The one XML parser of xrdf-tools (URDF, SRDF, the SRDF that ``export srdf --merge`` edits).

lxml parses with every guard on, whatever the caller keeps:

* entities are never substituted (``resolve_entities=False``): an entity bomb stays one
  reference, and an external entity (``<!ENTITY e SYSTEM "file:///etc/passwd">``) is never read;
* no DTD is loaded and no attribute default applied from one (``load_dtd=False``,
  ``attribute_defaults=False``), nothing is fetched over the network (``no_network=True``);
* libxml2's default limits stay on (``huge_tree=False``): at most 256 levels of nesting and
  10 MB in one text node, comment or attribute value; the file itself was size-capped when read
  (:func:`xrdf_tools.util.fileio.read_input_bytes`).

A document that is not well-formed raises :class:`XmlSyntaxError` with libxml2's words and
position; each caller words its own one-line message from it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

__all__ = ["XmlSyntaxError", "parse_xml", "utf8_xml_bytes"]

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
) -> Any:
    """The root element of ``data`` (an lxml element), parsed with the guards above.

    Processing instructions stay in the tree; ``keep_comments``: so do comments;
    ``keep_cdata``: CDATA sections stay marked as such (an editor that writes the document
    back), else they are plain text; ``remove_blank_text``: whitespace-only text between
    elements is dropped. Raises :class:`XmlSyntaxError`.
    """
    from lxml import etree

    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        attribute_defaults=False,
        huge_tree=False,
        remove_comments=not keep_comments,
        remove_pis=False,
        strip_cdata=not keep_cdata,
        remove_blank_text=remove_blank_text,
    )
    try:
        return etree.fromstring(data, parser)
    except etree.XMLSyntaxError as e:
        line, col = e.position if e.position else (e.lineno, None)
        verbatim = (e.msg or str(e) or "not well-formed").splitlines()[0]
        reason = _POSITION_SUFFIX.sub("", verbatim)
        raise XmlSyntaxError(verbatim, reason, line, col) from None


def utf8_xml_bytes(data: str | bytes) -> bytes:
    """``data`` as bytes to parse: text is encoded as UTF-8 and an XML declaration naming
    another encoding loses its ``encoding=`` (it would no longer be true); bytes are kept."""
    if isinstance(data, bytes):
        return data
    return _OTHER_ENCODING.sub(rb"\1", data.encode("utf-8"), count=1)
