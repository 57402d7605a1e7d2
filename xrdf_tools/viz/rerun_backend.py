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

The timeline is sent as columns, :data:`BLOCK` samples at a time (``send_columns`` with
``TimeColumn`` and the archetypes' ``columns()``): one batch per entity and block instead of a
``log`` call per entity and sample. Uses only APIs present in rerun-sdk 0.23 … 0.41
(``TimeColumn`` came with 0.23). rerun is imported lazily; without it a
:class:`~xrdf_tools.util.errors.MissingDependencyError` says how to install it.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path
from typing import Any

import numpy as np

from . import DEFAULT_PICTURE, Picture, atomic_path, require
from .meshes import Rgba
from .scene import Progress, Scene

TIMELINE = "sample"
ROOT = "robot"
#: Samples sent as one block of columns.
BLOCK = 128


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

    Every byte is written by our own atomic writer, so a full disk or a refused path is an
    ordinary ``OSError`` naming ``path``, never rerun's file sink failing (or waiting) on its
    own. Where the system names open files in ``/dev/fd`` (Linux, macOS), rerun's file sink
    writes into a pipe that a thread of ours empties into the temporary file as the recording
    is made (:class:`_PipeToFile`): memory does not grow with the samples. Elsewhere the
    recording is encoded into memory (a rerun binary stream) and written at the end."""
    rr = _rerun()
    assert path is not None
    rec = rr.RecordingStream("xrdf_tools", recording_id=f"xrdf-{scene.robot_name}")
    with atomic_path(path) as tmp:
        if _FD_DIR.is_dir():
            _stream_through_pipe(rr, rec, scene, tmp, buffered=buffered, progress=progress)
        else:
            _encode_in_memory(rr, rec, scene, tmp, buffered=buffered, progress=progress)


#: Where the system names a process's open files (``/dev/fd/N``).
_FD_DIR = Path("/dev/fd")


def _stream_through_pipe(
    rr: Any, rec: Any, scene: Scene, tmp: Path, *, buffered: bool, progress: Progress | None
) -> None:
    """Log ``scene`` to ``rec`` with rerun's file sink on a pipe that :class:`_PipeToFile`
    copies into ``tmp``; raises the copy's error (``OSError``) once the recording is closed."""
    read_end, write_end = os.pipe()
    copy = _PipeToFile(read_end, tmp)
    try:
        try:
            rec.save(str(_FD_DIR / str(write_end)))  # rerun opens its own descriptor of it
        finally:
            os.close(write_end)
        copy.start()  # from here on the thread owns the read end
    except BaseException:  # nothing logged yet: the stream's few bytes fit in the pipe
        rec.disconnect()
        os.close(read_end)
        raise
    try:
        _log_scene(rr, rec, scene, buffered=buffered, progress=progress)
        rec.flush()
    finally:
        rec.disconnect()  # rerun writes the stream's end and closes the pipe
        copy.join()
    if copy.error is not None:
        raise copy.error


class _PipeToFile(threading.Thread):
    """Copies a pipe into a file until the pipe's end. A failure (a full disk) is kept in
    :attr:`error` and the rest of the pipe is read and dropped, so the writer on the other end
    never waits."""

    def __init__(self, read_end: int, path: Path) -> None:
        super().__init__(name="rrd writer", daemon=True)
        self.read_end, self.path = read_end, path
        self.error: Exception | None = None

    def run(self) -> None:
        with open(self.read_end, "rb", buffering=0) as pipe:
            try:
                with open(self.path, "wb") as out:
                    while chunk := pipe.read(1 << 20):
                        out.write(chunk)
            except Exception as e:  # kept for the caller; the pipe is still read to its end
                self.error = e
                while pipe.read(1 << 20):
                    pass


def _encode_in_memory(
    rr: Any, rec: Any, scene: Scene, tmp: Path, *, buffered: bool, progress: Progress | None
) -> None:
    """Log ``scene`` into a rerun binary stream in memory, then write it to ``tmp``."""
    stream = rec.binary_stream()
    try:
        _log_scene(rr, rec, scene, buffered=buffered, progress=progress)
        data = stream.read()
    finally:
        rec.disconnect()
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
    rr: Any,
    rec: Any,
    scene: Scene,
    *,
    buffered: bool,
    progress: Progress | None,
) -> None:
    """Log ``scene`` to ``rec``: the static robot, then the timeline in blocks of
    :data:`BLOCK` samples, each sent as columns (one batch per entity)."""
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
    for start in range(0, total, BLOCK):
        stop = min(start + BLOCK, total)
        _send_transforms(rr, rec, scene, start, stop)
        _send_colors(rr, rec, scene, start, stop, previous)
        _send_logs(rr, rec, scene, start, stop)
        if progress is not None:
            progress(stop, total)


def _steps(rr: Any, steps: list[int]) -> list[Any]:
    """The ``sample`` timeline column of ``steps``."""
    return [rr.TimeColumn(TIMELINE, sequence=steps)]


def _send_transforms(rr: Any, rec: Any, scene: Scene, start: int, stop: int) -> None:
    """Every link's pose in the base frame at steps ``start`` to ``stop``: one column each."""
    steps = _steps(rr, list(range(start, stop)))
    poses = scene.poses[start:stop]
    for link in scene.links:
        T = poses[:, link.frame_index]
        columns = rr.Transform3D.columns(translation=T[:, :3, 3], mat3x3=T[:, :3, :3])
        rec.send_columns(link_entity(rr, link.name), indexes=steps, columns=columns)


def _send_colors(
    rr: Any, rec: Any, scene: Scene, start: int, stop: int, previous: dict[str, list[Rgba]]
) -> None:
    """The spheres' colours of each link at the steps where they change (``previous``: the
    colours last sent, updated)."""
    changes: dict[str, tuple[list[int], list[list[int]]]] = {}
    for step in range(start, stop):
        for name, colors in scene.colors(step).items():
            if colors and previous.get(name) != colors:
                steps, rgba = changes.setdefault(name, ([], []))
                steps.append(step)
                rgba.extend(_rgba8(c) for c in colors)
                previous[name] = colors
    for name, (steps, rgba) in changes.items():
        per_step = [len(rgba) // len(steps)] * len(steps)
        columns = rr.Ellipsoids3D.columns(colors=rgba).partition(per_step)
        rec.send_columns(
            f"{link_entity(rr, name)}/spheres", indexes=_steps(rr, steps), columns=columns
        )


def _send_logs(rr: Any, rec: Any, scene: Scene, start: int, stop: int) -> None:
    """The text logs of steps ``start`` to ``stop``: what each step is (``samples``) and one
    line per colliding frame pair (``collisions``)."""
    texts, hits, lines = [], [], []
    for step in range(start, stop):
        sample = scene.samples[step]
        q = ", ".join(f"{v:.4f}" for v in sample.q)
        texts.append(
            f"step {step}: {sample.label}, {len(sample.frame_contacts)} colliding frame "
            f"pair(s), {len(sample.contacts)} sphere pair(s); q = [{q}]"
        )
        for line in sample.describe_contacts():
            hits.append(step)
            lines.append(f"step {step}: {line}")
    columns = rr.TextLog.columns(text=texts, level=["INFO"] * len(texts))
    rec.send_columns("samples", indexes=_steps(rr, list(range(start, stop))), columns=columns)
    if lines:
        columns = rr.TextLog.columns(text=lines, level=["WARN"] * len(lines))
        rec.send_columns("collisions", indexes=_steps(rr, hits), columns=columns)


def _mesh3d(rr: Any, vertices: Any, faces: Any, color: Rgba) -> Any:
    import trimesh

    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    return rr.Mesh3D(
        vertex_positions=np.asarray(vertices, dtype=np.float32),
        triangle_indices=np.asarray(faces, dtype=np.uint32),
        vertex_normals=np.asarray(mesh.vertex_normals, dtype=np.float32),
        albedo_factor=_rgba8(color),
    )
