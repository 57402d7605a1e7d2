"""rerun back-end: a :class:`~xrdf_tools.viz.scene.Scene` as a rerun recording.

Entities (``<link>`` escaped as a rerun path part)::

    robot                        view coordinates (right-handed, Z up), static
    robot/<link>                 Transform3D: link pose in the base frame (``sample`` timeline)
    robot/<link>/spheres         Ellipsoids3D: centres and true radii (static), colours per sample
    robot/<link>/buffered        Ellipsoids3D wireframe: self-collision buffered radii (optional)
    robot/<link>/mesh/<k>        Mesh3D of the link's visual or collision geometry, static
    collisions                   TextLog: one WARN line per colliding sphere pair and sample
    samples                      TextLog: what each step of the ``sample`` timeline is

Step 0 of the ``sample`` timeline is the default pose; each further step is one
configuration. Spheres of a colliding pair are red at that step, in the link colour otherwise.

Uses only APIs present in rerun-sdk 0.22 … 0.41 (``set_time(..., sequence=)``, not the removed
``set_time_sequence``). rerun is imported lazily; without it a
:class:`~xrdf_tools.util.errors.MissingDependencyError` says how to install it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from . import DEFAULT_PICTURE, Picture, atomic_path, require
from .meshes import Rgba
from .scene import Progress, Scene

TIMELINE = "sample"
ROOT = "robot"


def _rerun() -> Any:
    require("rerun", "rerun-sdk")
    import rerun as rr

    return rr


def _rgba8(c: Rgba) -> list[int]:
    return [round(255 * max(0.0, min(1.0, float(v)))) for v in c]


def link_entity(rr: Any, link: str) -> str:
    """The entity path of a link (its name escaped as one path part)."""
    return f"{ROOT}/{rr.escape_entity_path_part(link)}"


def write_rrd(
    scene: Scene,
    path: Path | None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    picture: Picture = DEFAULT_PICTURE,
) -> None:
    """Write ``scene`` to the rerun file ``path`` (atomically).

    The recording is encoded into memory (a rerun binary stream) and written by our own
    atomic writer: a full disk or a refused path is then an ordinary ``OSError`` naming
    ``path``, never rerun's background file sink failing (or waiting) on its own."""
    rr = _rerun()
    assert path is not None
    rec = rr.RecordingStream("xrdf_tools", recording_id=f"xrdf-{scene.robot_name}")
    stream = rec.binary_stream()
    try:
        _log_scene(rr, rec, scene, buffered=buffered, progress=progress)
        data = stream.read()
    finally:
        rec.disconnect()
    with atomic_path(path) as tmp:
        tmp.write_bytes(data or b"")


def spawn(
    scene: Scene,
    path: Path | None = None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    picture: Picture = DEFAULT_PICTURE,
) -> None:
    """Spawn a rerun viewer and stream ``scene`` to it."""
    rr = _rerun()
    rec = rr.RecordingStream("xrdf_tools")
    rec.spawn()
    try:
        _log_scene(rr, rec, scene, buffered=buffered, progress=progress)
        rec.flush()
    finally:
        rec.disconnect()  # everything is sent before the command exits


def _log_scene(
    rr: Any, rec: Any, scene: Scene, *, buffered: bool, progress: Progress | None
) -> None:
    rec.log(ROOT, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    solid = rr.components.FillMode.Solid
    wire = rr.components.FillMode.MajorWireframe
    for link in scene.links:
        ent = link_entity(rr, link.name)
        if link.n_spheres:
            labels = [f"{link.name}[{i}]" for i in link.sphere_ids]
            rec.log(
                f"{ent}/spheres",
                rr.Ellipsoids3D.from_fields(
                    centers=link.centers,
                    half_sizes=np.repeat(link.radii[:, None], 3, axis=1),
                    labels=labels,
                    show_labels=False,
                    fill_mode=solid,
                ),
                static=True,
            )
            if buffered:
                faint = (*link.color[:3], 0.35)
                rec.log(
                    f"{ent}/buffered",
                    rr.Ellipsoids3D(
                        centers=link.centers,
                        half_sizes=np.repeat(link.buffered_radii[:, None], 3, axis=1),
                        colors=[_rgba8(faint)],
                        fill_mode=wire,
                    ),
                    static=True,
                )
        for k, part in enumerate(link.meshes):
            rec.log(
                f"{ent}/mesh/{k}", _mesh3d(rr, part.vertices, part.faces, part.color), static=True
            )

    previous: dict[str, list[Rgba]] = {}
    total = len(scene.samples)
    for step, sample in enumerate(scene.samples):
        rec.set_time(TIMELINE, sequence=step)
        poses = scene.poses[step]
        for link in scene.links:
            T = poses[link.frame_index]
            rec.log(
                link_entity(rr, link.name),
                rr.Transform3D(translation=T[:3, 3], mat3x3=T[:3, :3]),
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
        if progress is not None:
            progress(step + 1, total)


def _mesh3d(rr: Any, vertices: Any, faces: Any, color: Rgba) -> Any:
    import trimesh

    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    return rr.Mesh3D(
        vertex_positions=np.asarray(vertices, dtype=np.float32),
        triangle_indices=np.asarray(faces, dtype=np.uint32),
        vertex_normals=np.asarray(mesh.vertex_normals, dtype=np.float32),
        albedo_factor=_rgba8(color),
    )
