"""GLB visual meshes read without trimesh (xrdf_tools.robot.gltf_points): the box trimesh
gives, on scenes with nested, turned and scaled nodes; hostile files refused in kind."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh

from xrdf_tools.robot import gltf_points
from xrdf_tools.robot.gltf_points import GltfNotRead, GltfTooBig, glb_vertices
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


def _shared_children(levels: int, leaf: dict[str, object]) -> dict[str, object]:
    """A node holding the next one twice, ``levels`` deep: 2^levels instances of ``leaf``."""
    doc = _triangle_doc()
    doc["nodes"] = [{"children": [i + 1, i + 1]} for i in range(levels)] + [leaf]
    return doc


@pytest.mark.parametrize(
    "doc, why",
    [
        (_shared_children(60, {}), "more than 1000 nodes"),  # no mesh: walked for ever
        (_shared_children(60, {"mesh": 0}), "over 10000 mesh instances"),
        (_triangle_doc(children=[0]), "deeper than"),  # a node cycle
    ],
)
def test_a_scene_past_the_bounds_is_too_big(
    doc: dict[str, object], why: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Shared children are counted each time they are reached (a 2 kB file of 2^60 nodes
    without a mesh was walked for ever), and such a file is too big for any reader (not
    handed to trimesh). The node bound (100,000) is lowered to 1,000 here; the real one:
    tests/spheres/test_big_meshes.py."""
    if "nodes" in why:
        monkeypatch.setattr(gltf_points, "MAX_NODES", 1000)
    with pytest.raises(GltfTooBig, match=why):
        glb_vertices(_glb(doc, _TRIANGLE))


def test_instanced_vertices_are_bounded_before_they_are_copied(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """5,000 nodes drawing a 3 MB mesh were 36 GB of vertices (a MemoryError, or the machine's
    memory): the instanced vertices are counted first (the bound lowered to 100 here)."""
    monkeypatch.setattr(gltf_points, "MAX_POINTS", 100)
    doc = _triangle_doc()
    doc["nodes"] = [{"mesh": 0} for _ in range(33)]
    doc["scenes"] = [{"nodes": list(range(33))}]
    assert glb_vertices(_glb(doc, _TRIANGLE)).shape == (99, 3)
    doc["nodes"] = [{"mesh": 0} for _ in range(34)]
    doc["scenes"] = [{"nodes": list(range(34))}]
    with pytest.raises(GltfTooBig, match="over 100 vertices"):
        glb_vertices(_glb(doc, _TRIANGLE))


@pytest.mark.parametrize(
    "node",
    [
        {"rotation": [1e200, 1e200, 0, 1]},  # overflow in the quaternion's products
        {"matrix": [1e308] * 16, "children": [1]},  # and in the composed transforms
    ],
)
def test_transforms_that_overflow_give_non_finite_points_without_a_warning(
    node: dict[str, object],
) -> None:
    """numpy printed 'RuntimeWarning: overflow encountered' on stderr (an error in the tests);
    the points are not finite, which the visual check reports."""
    doc = _triangle_doc(**node)
    if "children" in node:
        doc["nodes"].append({"mesh": 0, "matrix": [1e308] * 16})  # type: ignore[attr-defined]
    assert not np.isfinite(glb_vertices(_glb(doc, _TRIANGLE))).all()


@pytest.mark.parametrize(
    "change, why",
    [
        (lambda d: d["nodes"][0].update(translation=[10**400, 0, 0]), "past float range"),
        (lambda d: d["bufferViews"][0].update(byteStride=2**70), "past its buffer"),
        (lambda d: d["bufferViews"][0].update(byteStride=256), "past its buffer"),
    ],
)
def test_numbers_past_their_range_are_refused_in_kind(change: object, why: str) -> None:
    """A JSON integer past float range was an OverflowError, a stride past 2^63 numpy's
    'Maximum allowed dimension exceeded' (glTF allows strides up to 252)."""
    doc = _triangle_doc()
    doc["accessors"][0]["count"] = 1  # type: ignore[index]
    change(doc)  # type: ignore[operator]
    with pytest.raises(GltfNotRead, match=why):
        glb_vertices(_glb(doc, _TRIANGLE))
