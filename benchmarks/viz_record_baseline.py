"""The ``xrdf viz`` recording writers as they were before they were made to scale, frozen here
as the baseline of ``bench_viz_record.py``:

* MCAP: every message built as a dict and encoded with ``json.dumps`` (the spheres of every
  link at every step), each frame's parent-relative pose and quaternion computed one at a time;
* rerun: one ``log`` call per entity and step (``set_time``), the whole recording encoded into
  a binary stream in memory and written at the end.

Same messages and the same recording content as the tool writes (the benchmark checks the MCAP
bytes are equal).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from xrdf_tools.util.fixed_order import matmul, rigid_inverse
from xrdf_tools.viz.foxglove_schemas import LOG_INFO, LOG_WARNING, schema_bytes
from xrdf_tools.viz.mcap_backend import (
    TOPIC_BUFFERED,
    TOPIC_COLLISIONS,
    TOPIC_MESHES,
    TOPIC_SPHERES,
    TOPIC_TF,
    _entity,
    _json,
    _mesh_entities,
    _spheres,
    _stamp,
    _vec,
    log_time,
)
from xrdf_tools.viz.rerun_backend import ROOT, TIMELINE, _mesh3d, _rgba8, link_entity
from xrdf_tools.viz.scene import Scene


def _relative_pose(scene: Scene, step: int, frame: int) -> Any:
    p = scene.parent[frame]
    T = scene.poses[step, frame]
    if p < 0:
        return np.array(T)
    return matmul(rigid_inverse(scene.poses[step, p]), T)


def _quat_xyzw(m: Any) -> tuple[float, float, float, float]:
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        w, x = 0.25 * s, (m[2, 1] - m[1, 2]) / s
        y, z = (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        w, x = (m[2, 1] - m[1, 2]) / s, 0.25 * s
        y, z = (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        w, x = (m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s
        y, z = 0.25 * s, (m[1, 2] + m[2, 1]) / s
    else:
        s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        w, x = (m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s
        y, z = (m[1, 2] + m[2, 1]) / s, 0.25 * s
    q = np.array([x, y, z, w])
    q /= math.sqrt(sum(float(v) * float(v) for v in q))
    if q[3] < 0:
        q = -q
    return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def write_mcap(scene: Scene, path: Path, buffered: bool = False) -> None:
    """The MCAP writer before: a dict and ``json.dumps`` per message."""
    from mcap.writer import CompressionType, Writer

    with open(path, "wb") as stream:
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

        def add(ch: int, ns: int, message: Any) -> None:
            seq[ch] = seq.get(ch, -1) + 1
            writer.add_message(
                ch, log_time=ns, data=_json(message), publish_time=ns, sequence=seq[ch]
            )

        t0 = log_time(0)
        if any(link.meshes for link in scene.links):
            ch_meshes = channel(TOPIC_MESHES, "foxglove.SceneUpdate")
            add(ch_meshes, t0, {"deletions": [], "entities": _mesh_entities(scene, t0)})
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
            add(ch_buf, t0, {"deletions": [], "entities": entities})
        for step, sample in enumerate(scene.samples):
            ns = log_time(step)
            for f in range(1, len(scene.frame_names)):
                T = _relative_pose(scene, step, f)
                x, y, z, w = _quat_xyzw(T[:3, :3])
                add(
                    ch_tf,
                    ns,
                    {
                        "timestamp": _stamp(ns),
                        "parent_frame_id": scene.frame_names[scene.parent[f]],
                        "child_frame_id": scene.frame_names[f],
                        "translation": _vec(T[:3, 3]),
                        "rotation": {"x": x, "y": y, "z": z, "w": w},
                    },
                )
            colors = scene.colors(step)
            entities = [
                _entity(
                    scene,
                    link.name,
                    ns,
                    "spheres",
                    spheres=_spheres(link.centers, link.radii, colors[link.name]),
                )
                for link in scene.links
                if link.n_spheres
            ]
            add(ch_spheres, ns, {"deletions": [], "entities": entities})
            pairs = sample.describe_contacts()
            text = f"step {step}: {sample.label}: " + (
                "; ".join(pairs) if pairs else "no self-collision"
            )
            message = {
                "timestamp": _stamp(ns),
                "level": LOG_WARNING if pairs else LOG_INFO,
                "message": text,
                "name": "xrdf viz",
                "file": "",
                "line": 0,
            }
            add(ch_log, ns, message)
        writer.finish()


def write_rrd(scene: Scene, path: Path) -> None:
    """The rerun writer before: a ``log`` call per entity and step, into memory."""
    import rerun as rr

    rec = rr.RecordingStream("xrdf_tools", recording_id=f"xrdf-{scene.robot_name}")
    stream = rec.binary_stream()
    try:
        _log_scene(rr, rec, scene)
        data = stream.read()
    finally:
        rec.disconnect()
    path.write_bytes(data or b"")


def _log_scene(rr: Any, rec: Any, scene: Scene) -> None:
    rec.log(ROOT, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    for link in scene.links:
        ent = link_entity(rr, link.name)
        if link.n_spheres:
            rec.log(
                f"{ent}/spheres",
                rr.Ellipsoids3D.from_fields(
                    centers=link.centers,
                    half_sizes=np.repeat(link.radii[:, None], 3, axis=1),
                    labels=[f"{link.name}[{i}]" for i in link.sphere_ids],
                    show_labels=False,
                    fill_mode=rr.components.FillMode.Solid,
                ),
                static=True,
            )
        for k, part in enumerate(link.meshes):
            mesh = _mesh3d(rr, part.vertices, part.faces, part.color)
            rec.log(f"{ent}/mesh/{k}", mesh, static=True)
    previous: dict[str, Any] = {}
    for step, sample in enumerate(scene.samples):
        rec.set_time(TIMELINE, sequence=step)
        poses = scene.poses[step]
        for link in scene.links:
            T = poses[link.frame_index]
            rec.log(
                link_entity(rr, link.name), rr.Transform3D(translation=T[:3, 3], mat3x3=T[:3, :3])
            )
        for name, colors in scene.colors(step).items():
            if colors and previous.get(name) != colors:
                rec.log(
                    f"{link_entity(rr, name)}/spheres",
                    rr.Ellipsoids3D.from_fields(colors=[_rgba8(c) for c in colors]),
                )
                previous[name] = colors
        q = ", ".join(f"{v:.4f}" for v in sample.q)
        rec.log(
            "samples",
            rr.TextLog(
                f"step {step}: {sample.label}, {len(sample.frame_contacts)} colliding frame "
                f"pair(s), {len(sample.contacts)} sphere pair(s); q = [{q}]",
                level="INFO",
            ),
        )
        for line in sample.describe_contacts():
            rec.log("collisions", rr.TextLog(f"step {step}: {line}", level="WARN"))
