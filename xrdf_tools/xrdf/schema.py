"""A JSON Schema of the XRDF, generated from the one shape description (:mod:`.shape`).

For editors and ``check-jsonschema``: ``python -m xrdf_tools.xrdf.schema > docs/xrdf.schema.json``
(a test keeps the file up to date). Each XRDF version gets its own document schema (the
version-specific keys exist in one only), chosen by ``format_version``. Unknown keys are not
allowed, as ``unknown-key`` warns of them. What the shape does not say (joint names that exist
in the URDF, limits per joint, clone cycles) is left to ``xrdf lint``.
"""

from __future__ import annotations

import json
from typing import Any

from .shape import DOCUMENT, MAX_LENGTH, MODIFIERS, SUPPORTED_VERSIONS, Shape

__all__ = ["json_schema", "render"]

Schema = dict[str, Any]

NAME: Schema = {"type": ["string", "number"], "minLength": 1}


def _nullable(schema: Schema, shape: Shape) -> Schema:
    return {"anyOf": [{"type": "null"}, schema]} if shape.nullable else schema


def _of(shape: Shape, version: str) -> Schema:
    """The schema of a node of ``shape`` in XRDF ``version``."""
    return _nullable(_bare(shape, version), shape)


def _num(shape: Shape) -> Schema:
    if shape.metres:
        return {"type": "number", "minimum": -MAX_LENGTH, "maximum": MAX_LENGTH}
    return {"type": "number"}


def _list(shape: Shape, version: str) -> Schema:
    out: Schema = {"type": "array"}
    if shape.values is not None:
        out["items"] = _of(shape.values, version)
    if shape.length is not None:
        out["minItems"] = out["maxItems"] = shape.length
    return out


def _fields(shape: Shape, version: str) -> Schema:
    keys = {
        k: _of(sub, version)
        for k, sub in shape.fields.items()
        if not sub.versions or version in sub.versions
    }
    out: Schema = {"type": "object", "properties": keys, "additionalProperties": False}
    if shape.required:
        out["required"] = list(shape.required)
    return out


def _modifier(version: str) -> Schema:
    return {
        "oneOf": [
            {
                "type": "object",
                "properties": {key: _of(sub, version)},
                "required": [key],
                "additionalProperties": False,
            }
            for key, sub in MODIFIERS.items()
            if not sub.versions or version in sub.versions
        ]
    }


def _bare(shape: Shape, version: str) -> Schema:
    """The schema of ``shape`` without null."""
    k = shape.kind
    if k == "any":
        return {}
    if k == "num":
        return _num(shape)
    if k == "str":
        return dict(NAME)
    if k == "groupref":
        return {"anyOf": [NAME, {"type": "array", "items": NAME, "minItems": 1, "maxItems": 1}]}
    if k == "list":
        return _list(shape, version)
    if k == "modifier":
        return _modifier(version)
    values = _of(shape.values, version) if shape.values is not None else {}
    if k == "buffers":
        return {"anyOf": [values, {"type": "object", "additionalProperties": values}]}
    if k == "dict":
        return {"type": "object", "additionalProperties": values}
    return _fields(shape, version)


def _version_values(version: str) -> list[Any]:
    """How ``format_version`` may spell ``version`` (``1.0``, ``1``, ``"1.0"``)."""
    f = float(version)
    return [f, int(f), version] if f.is_integer() else [f, version]


def json_schema() -> Schema:
    """The JSON Schema (draft 2020-12) of an XRDF document, 1.0 or 2.0."""
    defs = {f"xrdf-{v}": _of(DOCUMENT, v) for v in SUPPORTED_VERSIONS}
    for v in SUPPORTED_VERSIONS:
        props = defs[f"xrdf-{v}"]["properties"]
        props["format"] = {"const": "xrdf"}
        props["format_version"] = {"enum": _version_values(v)}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "XRDF robot description (generated from xrdf_tools.xrdf.shape)",
        "oneOf": [{"$ref": f"#/$defs/xrdf-{v}"} for v in SUPPORTED_VERSIONS],
        "$defs": defs,
    }


def render() -> str:
    """The schema as the text of ``docs/xrdf.schema.json``."""
    return json.dumps(json_schema(), indent=2) + "\n"


if __name__ == "__main__":
    print(render(), end="")
