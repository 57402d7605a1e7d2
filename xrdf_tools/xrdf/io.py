"""Read an XRDF document into the model, and write the model back canonically.

Reading is strict about types (one :class:`SchemaError` with file:line:col for the first
problem) and lenient about what the linter judges (missing ``cspace``, a section spelled for the
other version, unknown keys). Writing is canonical: the section order of the spec, floats always
written as floats that both YAML 1.1 and 1.2 readers parse as floats, stable formatting.

This module is the public entry point; the reader lives in :mod:`xrdf_tools.xrdf.read`, the
writer in :mod:`xrdf_tools.xrdf.write`, and the document shape both the reader and lint check
against in :mod:`xrdf_tools.xrdf.shape`.
"""

from __future__ import annotations

from .nodes import describe
from .read import (
    TOP_LEVEL_ORDER,
    load_xrdf,
    parse_xrdf,
    xrdf_from_document,
)
from .shape import MAX_LENGTH, version_string
from .write import dump_xrdf, format_float, format_str

__all__ = [
    "MAX_LENGTH",
    "TOP_LEVEL_ORDER",
    "describe",
    "dump_xrdf",
    "format_float",
    "format_str",
    "load_xrdf",
    "parse_xrdf",
    "version_string",
    "xrdf_from_document",
]
