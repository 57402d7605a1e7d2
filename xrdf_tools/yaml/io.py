"""YAML loading with source positions, duplicate-key detection and YAML 1.2 scalars.

Every YAML input (XRDF, cuRobo and Lula configs, ``joint_limits.yaml``, lint configuration) is
read here, into a small tree of :class:`YScalar`, :class:`YSeq` and :class:`YMap` that keeps a
1-based line and column for every node (:mod:`xrdf_tools.yaml.tree`). Plain scalars follow the
YAML 1.2 core schema (``on``/``off``/``yes``/``no``/``y``/``n`` stay strings, ``1e3`` is a
float). Repeated mapping keys are recorded (PyYAML silently keeps the last one):
:func:`load_yaml` turns them into an error naming both lines, :func:`parse_yaml` returns them
so a linter can report them as findings.

Hostile input is bounded the way XML parsers bound entity expansion: a control character is an
error at its line and column; nesting deeper than :data:`MAX_DEPTH` is an error (never a
``RecursionError``); aliases are counted (at most :data:`MAX_ALIASES`) and the document as
expanded may hold at most :data:`MAX_EXPANDED_NODES` nodes more than it has distinct nodes
times :data:`MAX_AMPLIFICATION`, so a kilobyte of nested anchors ("billion laughs") fails at
once; an alias inside its own anchor and a mapping used as a key are errors. Files are read
through :mod:`xrdf_tools.util.fileio` (regular files only, size limit).

One reader builds the tree: the one-pass builder of :mod:`xrdf_tools.yaml.build`, fed by
libyaml's C parser when PyYAML has it and by PyYAML's own parser otherwise (and for the few
documents libyaml reads differently); aliases are read there too and checked by
:mod:`xrdf_tools.yaml.aliases`.
"""

from __future__ import annotations

import os
import re
from typing import Any

import yaml

from ..util.errors import YamlError, shown_text
from ..util.fileio import decode_utf8, read_input_bytes, read_input_text
from ..util.fileio import write_atomic as write_atomic
from ..util.textpos import line_col
from .build import read_document
from .hints import XML_NOT_YAML, looks_like_xml, syntax_hint
from .positions import NodePositions, node_positions, positions_of
from .rules import MAX_ALIASES, MAX_AMPLIFICATION, MAX_DEPTH, MAX_EXPANDED_NODES
from .tree import (
    DuplicateKey,
    Scalar,
    YamlDocument,
    YMap,
    YNode,
    YPlainSeq,
    YScalar,
    YSeq,
    describe_node,
    is_finite,
    key_of,
    to_python,
)

__all__ = [
    "MAX_ALIASES",
    "MAX_AMPLIFICATION",
    "MAX_DEPTH",
    "MAX_EXPANDED_NODES",
    "DuplicateKey",
    "NodePositions",
    "Scalar",
    "YMap",
    "YNode",
    "YPlainSeq",
    "YScalar",
    "YSeq",
    "YamlDocument",
    "describe_node",
    "is_finite",
    "key_of",
    "load_plain",
    "load_yaml",
    "node_positions",
    "parse_yaml",
    "positions_of",
    "raise_on_duplicates",
    "read_text",
    "shown_text",
    "to_python",
    "write_atomic",
]

# What YAML allows in a stream (PyYAML's Reader.NON_PRINTABLE, which raises without a position).
_NON_PRINTABLE = re.compile(
    "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"
)


def _check_printable(text: str, path: str) -> None:
    m = _NON_PRINTABLE.search(text)
    if m is None:
        return
    line, col = line_col(text, m.start())
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


def parse_yaml(text: str | bytes, path: str = "<string>") -> YamlDocument:
    """Parse one YAML document, keeping positions and recording duplicate keys.

    ``text``: the document, or the bytes of a file (UTF-8 is checked as :func:`read_text`
    checks it; the text is then not kept while the bytes are read).

    Raises :class:`YamlError` (with line and column) on a syntax error, a second document, or
    a document beyond the bounds in the module docstring.
    """
    source = text
    _check_printable(
        decode_utf8(source, path, "file", YamlError) if isinstance(source, bytes) else source,
        path,
    )
    del text  # a big file's text is not kept while libyaml reads its bytes
    try:
        return read_document(source, path)
    except yaml.MarkedYAMLError as exc:
        if looks_like_xml(source):
            raise YamlError(XML_NOT_YAML, path=path, line=1, col=1) from None
        mark = exc.problem_mark or exc.context_mark
        problem = exc.problem or exc.context or "invalid YAML"
        context = f" ({exc.context})" if exc.context and exc.problem else ""
        hint = syntax_hint(exc)
        raise YamlError(
            f"YAML syntax error: {problem}{context}{'; ' + hint if hint else ''}",
            path=path,
            line=mark.line + 1 if mark else None,
            col=mark.column + 1 if mark else None,
        ) from None
    except yaml.YAMLError as exc:
        raise YamlError(f"YAML error: {' '.join(str(exc).split())}", path=path) from None


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
    """Read a UTF-8 file through :func:`xrdf_tools.util.fileio.read_input_text`; a missing,
    unreadable, non-regular, oversized or non-UTF-8 file is a one-line :class:`YamlError`."""
    return read_input_text(path, what="file", error=YamlError)


def load_yaml(path: str | os.PathLike[str]) -> YamlDocument:
    """Read and parse a YAML file; duplicate keys are an error naming both lines."""
    doc = parse_yaml(read_input_bytes(path, what="file", error=YamlError), str(path))
    raise_on_duplicates(doc)
    return doc


def load_plain(path: str | os.PathLike[str]) -> Any:
    """Plain Python data of a YAML file (YAML 1.2 scalars, duplicate keys rejected)."""
    return to_python(load_yaml(path).root)
