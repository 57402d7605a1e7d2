"""JSON Schemas of the Foxglove message types written by the MCAP back-end.

Foxglove recognizes a channel by its schema *name* (``foxglove.SceneUpdate`` …) and uses the
JSON Schema to type the fields (``contentEncoding: base64`` marks bytes). These are compact
hand-written schemas with the documented field names of the Foxglove schemas, limited to the
fields that matter for JSON encoding; unused primitive lists are plain arrays.
"""

from __future__ import annotations

import json
from typing import Any

Schema = dict[str, Any]


def _obj(title: str | None, **props: Any) -> Schema:
    s: Schema = {"type": "object", "properties": props}
    if title:
        s["title"] = title
    return s


_NUM: Schema = {"type": "number"}
_STR: Schema = {"type": "string"}
_BOOL: Schema = {"type": "boolean"}
_TIME = _obj(
    "time",
    sec={"type": "integer", "minimum": 0},
    nsec={"type": "integer", "minimum": 0, "maximum": 999_999_999},
)
_DURATION = _obj(
    "duration",
    sec={"type": "integer"},
    nsec={"type": "integer", "minimum": 0, "maximum": 999_999_999},
)
_VEC3 = _obj("foxglove.Vector3", x=_NUM, y=_NUM, z=_NUM)
_POINT3 = _obj("foxglove.Point3", x=_NUM, y=_NUM, z=_NUM)
_QUAT = _obj("foxglove.Quaternion", x=_NUM, y=_NUM, z=_NUM, w=_NUM)
_COLOR = _obj("foxglove.Color", r=_NUM, g=_NUM, b=_NUM, a=_NUM)
_POSE = _obj("foxglove.Pose", position=_VEC3, orientation=_QUAT)


def _array(items: Schema) -> Schema:
    return {"type": "array", "items": items}


_SPHERE = _obj("foxglove.SpherePrimitive", pose=_POSE, size=_VEC3, color=_COLOR)
_TRIANGLES = _obj(
    "foxglove.TriangleListPrimitive",
    pose=_POSE,
    points=_array(_POINT3),
    color=_COLOR,
    colors=_array(_COLOR),
    indices=_array({"type": "integer", "minimum": 0}),
)
_MODEL = _obj(
    "foxglove.ModelPrimitive",
    pose=_POSE,
    scale=_VEC3,
    color=_COLOR,
    use_embedded_materials=_BOOL,
    url=_STR,
    media_type=_STR,
    data={"type": "string", "contentEncoding": "base64"},
)
_TEXT = _obj(
    "foxglove.TextPrimitive",
    pose=_POSE,
    billboard=_BOOL,
    font_size=_NUM,
    scale_invariant=_BOOL,
    color=_COLOR,
    text=_STR,
)
_ANY_LIST = _array({"type": "object"})
_ENTITY = _obj(
    "foxglove.SceneEntity",
    timestamp=_TIME,
    frame_id=_STR,
    id=_STR,
    lifetime=_DURATION,
    frame_locked=_BOOL,
    metadata=_array(_obj("foxglove.KeyValuePair", key=_STR, value=_STR)),
    arrows=_ANY_LIST,
    cubes=_ANY_LIST,
    spheres=_array(_SPHERE),
    cylinders=_ANY_LIST,
    lines=_ANY_LIST,
    triangles=_array(_TRIANGLES),
    texts=_array(_TEXT),
    models=_array(_MODEL),
)
_DELETION = _obj(
    "foxglove.SceneEntityDeletion",
    timestamp=_TIME,
    type={"type": "integer", "enum": [0, 1]},
    id=_STR,
)

SCENE_UPDATE: Schema = _obj(
    "foxglove.SceneUpdate", deletions=_array(_DELETION), entities=_array(_ENTITY)
)
FRAME_TRANSFORM: Schema = _obj(
    "foxglove.FrameTransform",
    timestamp=_TIME,
    parent_frame_id=_STR,
    child_frame_id=_STR,
    translation=_VEC3,
    rotation=_QUAT,
)
LOG: Schema = _obj(
    "foxglove.Log",
    timestamp=_TIME,
    level={"type": "integer", "enum": [0, 1, 2, 3, 4, 5]},
    message=_STR,
    name=_STR,
    file=_STR,
    line={"type": "integer", "minimum": 0},
)

#: schema name -> JSON Schema
SCHEMAS: dict[str, Schema] = {
    "foxglove.SceneUpdate": SCENE_UPDATE,
    "foxglove.FrameTransform": FRAME_TRANSFORM,
    "foxglove.Log": LOG,
}

#: foxglove.Log levels
LOG_INFO = 2
LOG_WARNING = 3


def schema_bytes(name: str) -> bytes:
    """The schema ``name`` as compact UTF-8 JSON, as registered in the MCAP file."""
    return json.dumps(SCHEMAS[name], separators=(",", ":"), sort_keys=True).encode("utf-8")
