"""`xrdf viz --mcap` / `--rrd` recordings made in blocks of samples and written as they are
made: the content does not depend on the block size, the MCAP messages are the JSON that
``json.dumps`` writes (odd frame names included), the .rrd reaches the disk while it is being
recorded, and the batched poses and quaternions have the bits of one at a time.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from tests.viz.test_viz import _read_mcap, _rrd_columns
from xrdf_tools.cli import app
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.util.fixed_order import matmul, rigid_inverse
from xrdf_tools.util.rotations import quat_xyzw_from_matrix, quats_xyzw_from_matrices
from xrdf_tools.viz import Scene, build_scene, render, sample_configurations
from xrdf_tools.xrdf.io import load_xrdf


@pytest.fixture(scope="module")
def scene() -> Scene:
    urdf_path = robot_urdf("panda")
    urdf, xrdf = load_urdf(urdf_path), load_xrdf(FIXTURES / "panda" / "panda.xrdf")
    kin, _ = build_kinematic_model(urdf, xrdf)
    q = sample_configurations(kin, xrdf, 40, seed=0)
    return build_scene(urdf, xrdf, q, kinematic_model=kin, meshes="collision", urdf_path=urdf_path)


def test_recordings_do_not_depend_on_the_block_size(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("mcap")
    pytest.importorskip("rerun")
    from xrdf_tools.viz import mcap_backend, rerun_backend

    assert any(s.contacts for s in scene.samples)  # colours change between blocks
    render(scene, "mcap", tmp_path / "one.mcap", buffered=True)
    render(scene, "rrd", tmp_path / "one.rrd", buffered=True)
    monkeypatch.setattr(mcap_backend, "BLOCK", 7)
    monkeypatch.setattr(rerun_backend, "BLOCK", 7)
    render(scene, "mcap", tmp_path / "blocks.mcap", buffered=True)
    render(scene, "rrd", tmp_path / "blocks.rrd", buffered=True)
    assert (tmp_path / "one.mcap").read_bytes() == (tmp_path / "blocks.mcap").read_bytes()

    def content(path: Path) -> dict[Any, Any]:
        cols = _rrd_columns(path)
        cols.pop(("/__properties", True), None)  # the recording's start time
        return {key: dict(c) for key, c in cols.items()}

    one, blocks = content(tmp_path / "one.rrd"), content(tmp_path / "blocks.rrd")
    assert one == blocks
    assert len(one[("/samples", False)]["sample"]) == len(scene.samples)


@pytest.mark.skipif(not Path("/dev/fd").is_dir(), reason="the .rrd is streamed through /dev/fd")
def test_rrd_reaches_the_disk_while_it_is_recorded(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Before the last sample is logged the temporary file already holds the recording so
    far: the recording is not kept in memory until the end."""
    pytest.importorskip("rerun")
    monkeypatch.setenv("RERUN_FLUSH_NUM_BYTES", "1")  # rerun hands on every row at once
    out = tmp_path / "panda.rrd"
    written: list[int] = []

    def progress(done: int, total: int) -> None:
        if done < total:
            return
        (tmp,) = [p for p in tmp_path.iterdir() if p.name.startswith(".panda.rrd.")]
        deadline = time.monotonic() + 10.0
        while tmp.stat().st_size == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        written.append(tmp.stat().st_size)

    render(scene, "rrd", out, progress=progress)
    assert written and 0 < written[0] <= out.stat().st_size
    assert [p.name for p in tmp_path.iterdir()] == ["panda.rrd"]


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="counts open descriptors")
def test_rrd_whose_copy_thread_cannot_start_closes_its_pipe(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A process out of threads: the recording fails with the thread's error, and neither end
    of the pipe nor a temporary file is left behind (the read end leaked, one per attempt)."""
    pytest.importorskip("rerun")
    from xrdf_tools.viz import rerun_backend

    render(scene, "rrd", tmp_path / "first.rrd")  # rerun's own descriptors are open from here
    open_before = len(list(Path("/proc/self/fd").iterdir()))

    def no_thread(self: object) -> None:
        raise RuntimeError("can't start new thread")

    monkeypatch.setattr(rerun_backend._PipeToFile, "start", no_thread)
    for _ in range(3):
        with pytest.raises(RuntimeError, match="can't start new thread"):
            render(scene, "rrd", tmp_path / "panda.rrd")
    assert len(list(Path("/proc/self/fd").iterdir())) == open_before
    assert [p.name for p in tmp_path.iterdir()] == ["first.rrd"]


def test_rrd_without_dev_fd_is_encoded_in_memory_with_the_same_content(
    scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Where the system has no ``/dev/fd`` (Windows) the recording is made in memory and
    written at the end: the same content, nothing left beside it."""
    pytest.importorskip("rerun")
    from xrdf_tools.viz import rerun_backend

    render(scene, "rrd", tmp_path / "piped.rrd")
    monkeypatch.setattr(rerun_backend, "_FD_DIR", tmp_path / "no-such-dir")
    render(scene, "rrd", tmp_path / "memory.rrd")
    piped, memory = _rrd_columns(tmp_path / "piped.rrd"), _rrd_columns(tmp_path / "memory.rrd")
    for cols in (piped, memory):
        cols.pop(("/__properties", True), None)
    assert {k: dict(v) for k, v in piped.items()} == {k: dict(v) for k, v in memory.items()}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["memory.rrd", "piped.rrd"]


def test_mcap_messages_are_the_json_that_json_dumps_writes(tmp_path: Path) -> None:
    """Frame names with a quote, a backslash, a ``%`` and accents: every message is compact
    JSON exactly as ``json.dumps`` writes it (the /tf and sphere messages are formatted from
    templates), and the names read back as written."""
    pytest.importorskip("mcap")
    names = ['base "b"', "arm\\%s%d", "coude é"]
    xml = {n: n.replace('"', "&quot;") for n in names}
    links = "".join(
        f'<link name="{xml[n]}"><collision><origin xyz="0 0 {0.2 * k}"/><geometry>'
        '<box size=".06 .06 .15"/></geometry></collision></link>'
        for k, n in enumerate(names)
    )
    joints = "".join(
        f'<joint name="j{k}" type="revolute"><parent link="{xml[names[k - 1]]}"/>'
        f'<child link="{xml[names[k]]}"/><origin xyz="0 0 .2"/><axis xyz="0 1 0"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for k in range(1, len(names))
    )
    urdf = tmp_path / "odd.urdf"
    urdf.write_text(f'<robot name="odd%s">{links}{joints}</robot>', encoding="utf-8")
    xrdf, out = tmp_path / "odd.xrdf", tmp_path / "odd.mcap"
    runner = CliRunner()
    args = ["convert", str(urdf), "--fit-spheres", "--per-link", "1", "-n", "50", "-o", str(xrdf)]
    assert runner.invoke(app, args).exit_code == 0
    r = runner.invoke(app, ["viz", str(xrdf), "--urdf", str(urdf), "-n", "3", "--mcap", str(out)])
    assert r.exit_code == 0, r.output
    from mcap.reader import make_reader

    with open(out, "rb") as f:
        raw = [(c.topic, m.data) for _, c, m in make_reader(f).iter_messages()]
    for _, data in raw:
        assert data == json.dumps(json.loads(data), separators=(",", ":")).encode("utf-8")
    _, messages = _read_mcap(out)
    tf = [m for topic, _, m in messages if topic == "/tf"]
    assert {m["child_frame_id"] for m in tf} == set(names[1:])
    assert {m["parent_frame_id"] for m in tf} == set(names[:2])
    spheres = [m for topic, _, m in messages if topic == "/xrdf/spheres"]
    assert len(spheres) == 4 and {e["frame_id"] for e in spheres[0]["entities"]} == set(names)


def test_batched_poses_and_quaternions_have_the_bits_of_one_at_a_time(scene: Scene) -> None:
    relative = scene.relative_poses(0, len(scene.samples))
    for step in (0, 7, len(scene.samples) - 1):
        for f, p in enumerate(scene.parent):
            T = scene.poses[step, f]
            one = T if p < 0 else matmul(rigid_inverse(scene.poses[step, p]), T)
            assert np.array_equal(relative[step, f], one)
    rotations = relative[..., :3, :3].reshape(-1, 3, 3)
    batch = quats_xyzw_from_matrices(rotations)
    assert all(
        tuple(batch[k].tolist()) == quat_xyzw_from_matrix(r) for k, r in enumerate(rotations)
    )
    # the quaternions rotate as the matrices do (w >= 0)
    x, y, z, w = batch.T
    rebuilt = np.stack(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    ).transpose(2, 0, 1)
    np.testing.assert_allclose(rebuilt, rotations, atol=1e-12)
    assert (w >= 0).all()
