"""GLB visual meshes read without trimesh (xrdf_tools.robot.gltf_points): the box trimesh
gives, on scenes with nested, turned and scaled nodes; hostile files refused in kind."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh

from xrdf_tools.robot.gltf_points import GltfNotRead, glb_vertices
from xrdf_tools.robot.mesh_files import load_mesh_parts


def _scene() -> trimesh.Scene:
    """Two parts under a turned, scaled and shifted parent node, one of them turned again."""
    tf = trimesh.transformations
    scene = trimesh.Scene()
    parent = tf.concatenate_matrices(
        tf.translation_matrix((0.1, -0.2, 0.3)),
        tf.rotation_matrix(0.7, (1, 2, 3)),
        np.diag([1.5, 1.5, 1.5, 1.0]),
    )
    scene.graph.update(frame_from="world", frame_to="parent", matrix=parent)
    box = trimesh.creation.box((0.1, 0.05, 0.3))
    cyl = trimesh.creation.cylinder(radius=0.04, height=0.2)
    scene.add_geometry(box, node_name="box", parent_node_name="parent")
    scene.add_geometry(
        cyl,
        node_name="cyl",
        parent_node_name="parent",
        transform=tf.concatenate_matrices(
            tf.translation_matrix((0, 0, 0.25)), tf.rotation_matrix(1.1, (0, 1, 0))
        ),
    )
    return scene


def _box(points: np.ndarray) -> np.ndarray:
    return np.array([points.min(axis=0), points.max(axis=0)])


def test_a_glb_scene_gives_the_box_trimesh_gives(tmp_path: Path) -> None:
    path = tmp_path / "part.glb"
    path.write_bytes(_scene().export(file_type="glb"))
    ours = glb_vertices(path.read_bytes())
    theirs = np.concatenate([np.asarray(p.vertices) for p in load_mesh_parts(path)])
    assert np.allclose(_box(ours), _box(theirs), atol=1e-6)
    # the transforms matter: without them the box is another one
    flat = np.concatenate([np.asarray(g.vertices) for g in _scene().geometry.values()])
    assert not np.allclose(_box(flat), _box(theirs), atol=1e-3)


def _glb(doc: dict[str, object], binary: bytes) -> bytes:
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    body += struct.pack("<II", len(binary), 0x004E4942) + binary
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def _triangle_doc(**node: object) -> dict[str, object]:
    return {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, **node}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "buffers": [{"byteLength": 36}],
    }


_TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0]], dtype="<f4").tobytes()


@pytest.mark.parametrize(
    "change, why",
    [
        (lambda d: d["nodes"][0].update(children=[0]), "deeper than"),  # a node cycle
        (lambda d: d["accessors"][0].update(count=4), "past its buffer"),
        (lambda d: d["accessors"][0].update(componentType=5123), "accessor"),
        (lambda d: d["buffers"][0].update(uri="outside.bin"), "outside the GLB"),
        (
            lambda d: d["meshes"][0]["primitives"][0].update(
                extensions={"KHR_draco_mesh_compression": {}}
            ),
            "extensions",
        ),
        (lambda d: d.update(extensionsRequired=["KHR_draco_mesh_compression"]), "required"),
        (lambda d: d["nodes"][0].update(matrix=[1, 2]), "matrix"),
        (lambda d: d["nodes"][0].update(mesh=7), "mesh 7 is not in the file"),
        (lambda d: d["accessors"][0].update(count=-1), "not an index or a size"),
    ],
)
def test_what_the_reader_does_not_follow_is_refused_in_kind(change: object, why: str) -> None:
    doc = _triangle_doc()
    assert np.allclose(
        glb_vertices(_glb(doc, _TRIANGLE)), np.frombuffer(_TRIANGLE, "<f4").reshape(3, 3)
    )
    change(doc)  # type: ignore[operator]
    with pytest.raises(GltfNotRead, match=why):
        glb_vertices(_glb(doc, _TRIANGLE))


def test_any_damage_to_a_glb_file_reads_or_is_refused_in_kind(tmp_path: Path) -> None:
    """Truncations and flipped bytes of a real GLB: vertices or GltfNotRead, nothing else."""
    data = bytearray(_scene().export(file_type="glb"))
    rng = np.random.default_rng(7)
    for cut in (0, 3, 11, 19, 40, len(data) // 2, len(data) - 1):
        with pytest.raises(GltfNotRead):  # the header's length or a chunk's is past the end
            glb_vertices(bytes(data[:cut]))
    for _ in range(300):
        hurt = bytearray(data)
        for at in rng.integers(0, len(hurt), size=3):
            hurt[at] = int(rng.integers(0, 256))
        try:
            points = glb_vertices(bytes(hurt))
        except GltfNotRead:
            continue
        assert points.ndim == 2 and points.shape[1] == 3
