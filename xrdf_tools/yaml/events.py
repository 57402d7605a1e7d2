"""The two event sources of the YAML reader (:mod:`xrdf_tools.yaml.build`), and where they differ.

The builder's events come from libyaml's C parser when PyYAML has it
(``yaml.__with_libyaml__``), else from PyYAML's pure-Python parser. The two parsers (both YAML
1.1, written apart) disagree on a few inputs: a tab between tokens (PyYAML refuses it), a
byte-order mark after the start (libyaml skips it, shifting columns), a text without a line
break at its end (libyaml adds one, moving an empty value read there), a plain scalar holding
``:`` or ``?`` or an empty value inside ``[]``/``{}`` (libyaml reads one scalar where PyYAML
reads two nodes or an error; the column of the empty value differs by one), block scalar
headers (libyaml takes ``>#``), tags (PyYAML's tag takes a following ``,``), anchor and alias
names, and every error message. PyYAML's answer is the reference one, so libyaml's events feed
the builder only for a document without these (:func:`libyaml_may_read` before reading,
:class:`Diverges` at the first such event: a tag, an anchor, an alias, a block scalar, a risky
flow scalar); otherwise, or on any libyaml error, the same builder is fed PyYAML's events for
that document. Those inputs are rare in robot descriptions (a big file is read by libyaml).
The tests compare both event sources with a plain compose-and-convert reference on these edge
cases above, documents with aliases and 600 mutated documents (``tests/yaml/test_yaml_readers.py``,
``tests/yaml/test_yaml_aliases.py``).
"""

from __future__ import annotations

import importlib
from typing import Any

import yaml


def _libyaml_parser() -> Any:
    """libyaml's parser class, or None when PyYAML was built without libyaml (PyYAML's own
    parser then reads everything)."""
    try:
        return importlib.import_module("yaml._yaml").CParser
    except ImportError:
        return None


CParser: Any = _libyaml_parser()


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


def flow_risk(text: str) -> bool:
    """An untagged plain scalar inside ``[]``/``{}`` that libyaml and PyYAML may read apart."""
    return not text or ":" in text or "?" in text
