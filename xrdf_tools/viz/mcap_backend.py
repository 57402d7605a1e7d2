"""MCAP back-end: a :class:`~xrdf_tools.viz.scene.Scene` as Foxglove messages.

Encoding: JSON messages with JSON Schemas (schema encoding ``jsonschema``, message encoding
``json``). Foxglove opens such files without any setup, and writing them needs nothing beyond
the ``mcap`` package (no compiled protobuf schemas); the chunks are zstd-compressed, which
takes most of the size overhead of JSON away.

Channels (schemas registered under their Foxglove names)::

    /tf               foxglove.FrameTransform  one per non-root frame and sample: parent -> child
    /xrdf/spheres     foxglove.SceneUpdate     one per sample: an entity per link, SpherePrimitive
                                               (size = diameter) in the link frame, red if colliding
    /xrdf/buffered    foxglove.SceneUpdate     once (optional): self-collision buffered radii
    /xrdf/meshes      foxglove.SceneUpdate     once (when meshes are drawn): TriangleListPrimitive
    /xrdf/collisions  foxglove.Log             one per sample: its colliding sphere pairs

Sample ``k`` (0 = default pose) is logged at ``T0 + k * DT`` (1 s + k * 100 ms); entities are
frame-locked with an unlimited lifetime, so the links' spheres and meshes follow ``/tf``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..util.rotations import quats_xyzw_from_matrices
from . import DEFAULT_PICTURE, Picture, atomic_path, require
from .foxglove_schemas import LOG_INFO, LOG_WARNING, schema_bytes
from .meshes import Rgba
from .scene import Progress, Scene

T0_NS = 1_000_000_000
DT_NS = 100_000_000

TOPIC_TF = "/tf"
TOPIC_SPHERES = "/xrdf/spheres"
TOPIC_BUFFERED = "/xrdf/buffered"
TOPIC_MESHES = "/xrdf/meshes"
TOPIC_COLLISIONS = "/xrdf/collisions"

_IDENTITY_POSE = {
    "position": {"x": 0.0, "y": 0.0, "z": 0.0},
    "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
}
_FOREVER = {"sec": 0, "nsec": 0}


def log_time(step: int) -> int:
    """Log time (ns) of sample ``step``."""
    return T0_NS + step * DT_NS


def _stamp(ns: int) -> dict[str, int]:
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


def _color(c: Rgba) -> dict[str, float]:
    return {"r": float(c[0]), "g": float(c[1]), "b": float(c[2]), "a": float(c[3])}


def _vec(v: Any) -> dict[str, float]:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _json(obj: Any) -> bytes:
    return _json_text(obj).encode("utf-8")


def _json_text(obj: Any) -> str:
    return json.dumps(obj, separators=(",", ":"), allow_nan=False)


def _stamp_text(ns: int) -> str:
    """``_json_text(_stamp(ns))``, formatted directly."""
    sec, nsec = divmod(ns, 1_000_000_000)
    return f'{{"sec":{sec},"nsec":{nsec}}}'


def _entity(scene: Scene, link: str, ns: int, kind: str, **prims: Any) -> dict[str, Any]:
    return {"timestamp": _stamp(ns), **_entity_body(scene, link, kind, **prims)}


def _entity_body(scene: Scene, link: str, kind: str, **prims: Any) -> dict[str, Any]:
    """An entity's fields after its timestamp: they do not change from step to step."""
    return {
        "frame_id": link,
        "id": f"{kind}/{link}",
        "lifetime": _FOREVER,
        "frame_locked": True,
        "metadata": [{"key": "group", "value": scene.group}, {"key": "link", "value": link}],
        **prims,
    }


def _spheres(centers: Any, radii: Any, colors: list[Rgba] | Rgba) -> list[dict[str, Any]]:
    out = []
    for k, (c, r) in enumerate(zip(centers, radii, strict=True)):
        d = 2.0 * float(r)
        col = colors[k] if isinstance(colors, list) else colors
        out.append(
            {
                "pose": {"position": _vec(c), "orientation": _IDENTITY_POSE["orientation"]},
                "size": {"x": d, "y": d, "z": d},
                "color": _color(col),
            }
        )
    return out


class _SphereUpdates:
    """The ``/xrdf/spheres`` message of each step. An entity is its timestamp and a body that
    changes only with its colours: each link's body in its own colours is encoded once, a
    link with red spheres is encoded at its step. Same bytes as encoding the whole message."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.plain = {
            link.name: self._body(link.name, link.color) for link in scene.links if link.n_spheres
        }

    def _body(self, name: str, colors: list[Rgba] | Rgba) -> str:
        """The entity's JSON after ``{"timestamp":…``: from its first comma on."""
        link = self.scene.link(name)
        spheres = _spheres(link.centers, link.radii, colors)
        text = _json_text(_entity_body(self.scene, name, "spheres", spheres=spheres))
        return "," + text[1:]

    def message(self, step: int, ns: int) -> bytes:
        red = self.scene.red_spheres(step)
        colors = self.scene.colors(step) if red else {}
        head = '{"timestamp":' + _stamp_text(ns)
        entities = ",".join(
            head + (self._body(name, colors[name]) if name in red else self.plain[name])
            for name in self.plain
        )
        return ('{"deletions":[],"entities":[' + entities + "]}").encode("utf-8")


#: Samples whose transforms are composed together (one batch of arrays per block).
BLOCK = 256


def _transform_templates(scene: Scene) -> list[str]:
    """Per non-root frame, its ``/tf`` message with ``%`` fields for the stamp (``%d``) and
    the translation and rotation (``%r``: a float as ``json`` writes it)."""
    out = []
    for f in range(1, len(scene.frame_names)):
        parent = _json_text(scene.frame_names[scene.parent[f]]).replace("%", "%%")
        child = _json_text(scene.frame_names[f]).replace("%", "%%")
        out.append(
            '{"timestamp":{"sec":%d,"nsec":%d},"parent_frame_id":'
            + parent
            + ',"child_frame_id":'
            + child
            + ',"translation":{"x":%r,"y":%r,"z":%r},"rotation":{"x":%r,"y":%r,"z":%r,"w":%r}}'
        )
    return out


def _transform_messages(
    scene: Scene, templates: list[str], start: int, stop: int
) -> list[list[bytes]]:
    """The ``/tf`` messages of steps ``start`` to ``stop``: per step, one per non-root frame
    (its pose in its parent frame), the poses and quaternions computed for the block at once."""
    relative = scene.relative_poses(start, stop)[:, 1:]
    values = np.concatenate(
        [relative[..., :3, 3], quats_xyzw_from_matrices(relative[..., :3, :3])], axis=-1
    )
    if not np.isfinite(values).all():
        raise ValueError("Out of range float values are not JSON compliant")
    out = []
    for step, rows in enumerate(values.tolist(), start):
        sec_nsec = divmod(log_time(step), 1_000_000_000)
        out.append(
            [
                (t % (*sec_nsec, *row)).encode("utf-8")
                for t, row in zip(templates, rows, strict=True)
            ]
        )
    return out


def write_mcap(
    scene: Scene,
    path: Path | None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    picture: Picture = DEFAULT_PICTURE,
) -> None:
    """Write ``scene`` to the MCAP file ``path`` (atomically). Messages are written as they
    are made (the file holds finished chunks), so memory does not grow with the samples."""
    require("mcap", "mcap")
    from mcap.writer import CompressionType, Writer

    assert path is not None
    with atomic_path(path) as tmp, open(tmp, "wb") as stream:
        writer = Writer(stream, compression=CompressionType.ZSTD)
        writer.start(profile="", library="xrdf-tools")
        schema_ids = {
            name: writer.register_schema(name, "jsonschema", schema_bytes(name))
            for name in ("foxglove.FrameTransform", "foxglove.SceneUpdate", "foxglove.Log")
        }

        def channel(topic: str, schema: str) -> int:
            meta = {"robot": scene.robot_name, "group": scene.group}
            return int(writer.register_channel(topic, "json", schema_ids[schema], meta))

        ch_tf = channel(TOPIC_TF, "foxglove.FrameTransform")
        ch_spheres = channel(TOPIC_SPHERES, "foxglove.SceneUpdate")
        ch_log = channel(TOPIC_COLLISIONS, "foxglove.Log")
        seq: dict[int, int] = {}

        def add(ch: int, ns: int, data: bytes) -> None:
            seq[ch] = seq.get(ch, -1) + 1
            writer.add_message(ch, log_time=ns, data=data, publish_time=ns, sequence=seq[ch])

        t0 = log_time(0)
        if any(link.meshes for link in scene.links):
            ch_meshes = channel(TOPIC_MESHES, "foxglove.SceneUpdate")
            add(ch_meshes, t0, _json({"deletions": [], "entities": _mesh_entities(scene, t0)}))
        if buffered:
            ch_buf = channel(TOPIC_BUFFERED, "foxglove.SceneUpdate")
            entities = [
                _entity(
                    scene,
                    link.name,
                    t0,
                    "buffered",
                    spheres=_spheres(link.centers, link.buffered_radii, (*link.color[:3], 0.25)),
                )
                for link in scene.links
                if link.n_spheres
            ]
            add(ch_buf, t0, _json({"deletions": [], "entities": entities}))

        total = len(scene.samples)
        templates = _transform_templates(scene)
        spheres = _SphereUpdates(scene)
        for start in range(0, total, BLOCK):
            stop = min(start + BLOCK, total)
            transforms = _transform_messages(scene, templates, start, stop)
            for step in range(start, stop):
                ns = log_time(step)
                for data in transforms[step - start]:
                    add(ch_tf, ns, data)
                add(ch_spheres, ns, spheres.message(step, ns))
                add(ch_log, ns, _json(_log_message(scene, step, ns)))
                if progress is not None:
                    progress(step + 1, total)
        writer.finish()  # type: ignore[no-untyped-call]


def _log_message(scene: Scene, step: int, ns: int) -> dict[str, Any]:
    """The ``/xrdf/collisions`` message of ``step``: its colliding pairs, or none."""
    sample = scene.samples[step]
    pairs = sample.describe_contacts()
    text = f"step {step}: {sample.label}: " + ("; ".join(pairs) if pairs else "no self-collision")
    return {
        "timestamp": _stamp(ns),
        "level": LOG_WARNING if pairs else LOG_INFO,
        "message": text,
        "name": "xrdf viz",
        "file": "",
        "line": 0,
    }


def _mesh_entities(scene: Scene, ns: int) -> list[dict[str, Any]]:
    entities = []
    for link in scene.links:
        if not link.meshes:
            continue
        triangles = []
        for part in link.meshes:
            pts = np.round(np.asarray(part.vertices, dtype=np.float64), 6).tolist()
            triangles.append(
                {
                    "pose": _IDENTITY_POSE,
                    "points": [{"x": p[0], "y": p[1], "z": p[2]} for p in pts],
                    "color": _color(part.color),
                    "colors": [],
                    "indices": np.asarray(part.faces, dtype=np.int64).ravel().tolist(),
                }
            )
        entities.append(_entity(scene, link.name, ns, "mesh", triangles=triangles))
    return entities
