"""Mesh files whose scene draws far more than the file holds: a glTF node graph that shares
its children (2^60 nodes in 2 kB), or one mesh drawn from thousands of nodes (a 4 MB file that
``trimesh.Scene.dump`` would copy into 36 GB). Through ``xrdf spheres``: counted before they
are walked or copied, refused in one line."""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest
import trimesh
from typer.testing import CliRunner

from xrdf_tools.cli import app

ROBOT = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm"><{kind}><geometry><mesh filename="{mesh}"/></geometry></{kind}>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _robot(tmp_path: Path, mesh: str, kind: str) -> Path:
    urdf = tmp_path / "r.urdf"
    text = ROBOT.format(mesh=mesh, kind=kind)
    if kind == "collision":  # the mesh alone is the arm's collision geometry
        text = text.replace(
            '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>', ""
        )
    urdf.write_text(text)
    return urdf


def _balls_glb(nodes: int) -> bytes:
    """One 20-triangle ball drawn from ``nodes`` nodes, side by side."""
    scene = trimesh.Scene()
    ball = trimesh.creation.icosahedron().apply_scale(0.02)
    scene.add_geometry(ball, geom_name="ball", node_name="n0")
    for i in range(1, nodes):
        shift = trimesh.transformations.translation_matrix((0.05 * i, 0, 0))
        scene.graph.update(frame_to=f"n{i}", geometry="ball", matrix=shift)
    return bytes(scene.export(file_type="glb"))


@pytest.mark.parametrize("nodes, fitted", [(16, True), (17, False)])
def test_a_mesh_drawn_from_many_nodes_is_counted_before_it_is_copied(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, nodes: int, fitted: bool
) -> None:
    """The triangle limit (335 with a 0.001 MiB input limit; 5.4 million by default) counts
    each drawn copy, before ``scene.dump()`` makes them: 320 triangles are fitted, 340 are
    refused in one line naming the count."""
    monkeypatch.setenv("XRDF_TOOLS_MAX_INPUT_MB", "0.001")
    (tmp_path / "balls.glb").write_bytes(_balls_glb(nodes))
    if not fitted:
        monkeypatch.setattr(trimesh.Scene, "dump", lambda *a, **k: pytest.fail("copied"))
    out = tmp_path / "r.xrdf"
    urdf = _robot(tmp_path, "balls.glb", "collision")
    r = CliRunner().invoke(app, ["spheres", str(urdf), "--per-link", "2", "-o", str(out)])
    assert "Traceback" not in r.output
    if fitted:
        assert r.exit_code == 0, r.output
        return
    assert r.exit_code == 1 and not out.exists(), r.output
    (line,) = [t for t in r.output.splitlines() if "spheres-link-not-covered" in t]
    assert "balls.glb: 340 triangles, more than the 335 a mesh may have" in line


def _shared_children_glb(levels: int) -> bytes:
    """A node holding the next twice, ``levels`` deep, no mesh: 2^levels nodes."""
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"children": [i + 1, i + 1]} for i in range(levels)] + [{}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def test_a_visual_glb_of_2_to_the_60_nodes_is_left_unchecked_at_once(tmp_path: Path) -> None:
    """The visual check walked such a file for ever (xrdf spheres never ended); now its
    link is named unchecked, in the real executable within its bound."""
    (tmp_path / "dag.glb").write_bytes(_shared_children_glb(60))
    urdf = _robot(tmp_path, "dag.glb", "visual")
    out = tmp_path / "r.xrdf"
    args = ["spheres", str(urdf), "--per-link", "1", "--visual-check", "all", "-o", str(out)]
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    r = subprocess.run(
        [sys.executable, "-m", "xrdf_tools", *args],
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
    )
    assert r.returncode == 0 and out.exists(), r.stderr
    assert "Traceback" not in r.stderr
    assert "dag.glb: cannot read mesh (a scene of more than 100000 nodes" in r.stderr
