"""A COLLADA scene that expands past the bounds is refused before any reader walks it: the
visual check's reader, trimesh's (pycollada expands every ``<instance_node>`` without a bound)
and so the sphere fitter; numbers that overflow once transformed print no numpy warning."""

from __future__ import annotations

import contextlib
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from tests.robot.test_collada_points import GEOMETRY, dae
from xrdf_tools.robot.collada_points import (
    MAX_NODES,
    ColladaNotRead,
    ColladaTooBig,
    check_collada_bounds,
    collada_vertices,
)
from xrdf_tools.robot.mesh_files import load_mesh_scene
from xrdf_tools.util.errors import XrdfToolsError

REPO = Path(__file__).resolve().parents[2]


def fan_out(levels: int, leaf: str = "") -> bytes:
    """A scene whose node instances a library node twice, which instances the next twice, ...
    ``levels`` deep: 2^levels nodes once expanded, in a file of a few kilobytes."""
    lib = "".join(
        f'<node id="n{i}"><instance_node url="#n{i + 1}"/><instance_node url="#n{i + 1}"/></node>'
        for i in range(levels)
    )
    lib += f'<node id="n{levels}">{leaf}</node>'
    return dae(f'<node id="a">{GEOMETRY}<instance_node url="#n0"/></node>', library_nodes=lib)


def test_a_node_fan_out_without_geometry_is_refused_not_walked() -> None:
    # 2^17 nodes: the walk took seconds and said nothing; at 2^60 it never ended
    assert MAX_NODES < 2**17
    with pytest.raises(ColladaTooBig, match=f"more than {MAX_NODES} nodes") as refused:
        collada_vertices(fan_out(17))
    assert refused.value.line is not None
    with pytest.raises(ColladaTooBig):
        collada_vertices(fan_out(60))


def test_a_small_fan_out_is_read() -> None:
    box = collada_vertices(fan_out(8, GEOMETRY))
    np.testing.assert_allclose([box.min(axis=0), box.max(axis=0)], [[0, 0, 0], [1, 1, 1]])


@pytest.mark.parametrize(
    ("library", "why"),
    [
        ('<node id="n0"><instance_node url="#n0"/></node>', "cycle"),
        (
            '<node id="n0"><instance_node url="#n1"/></node><node id="n1">'
            '<node><instance_node url="#n0"/></node></node>',
            "cycle",
        ),
        (
            "".join(f'<node id="n{i}"><instance_node url="#n{i + 1}"/></node>' for i in range(70))
            + '<node id="n70"/>',
            "deeper than 64",
        ),
    ],
    ids=["itself", "through-a-child", "a-chain-of-70"],
)
def test_cycles_and_deep_chains_are_refused(library: str, why: str) -> None:
    data = dae('<node id="a"><instance_node url="#n0"/></node>', library_nodes=library)
    with pytest.raises(ColladaTooBig, match=why):
        collada_vertices(data)
    with pytest.raises(ColladaTooBig, match=why):
        check_collada_bounds(data)


def test_what_the_bounds_check_does_not_read_is_left_to_the_reader() -> None:
    check_collada_bounds(b"not xml")
    check_collada_bounds(dae(f'<node id="a"><lookat>0 0 1 0 0 0 0 1 0</lookat>{GEOMETRY}</node>'))


def test_trimesh_is_not_handed_a_scene_past_the_bounds(tmp_path: Path) -> None:
    (tmp_path / "m.dae").write_bytes(fan_out(17))
    with pytest.raises(ColladaTooBig, match="nodes"):
        load_mesh_scene(tmp_path / "m.dae")


@pytest.mark.parametrize(
    "scene",
    [
        f'<node id="a"><rotate>1e20 1e20 1e20 90</rotate>{GEOMETRY}</node>',
        f'<node id="a"><scale>1e30 1e30 1e30</scale><scale>1e30 1e30 1e30</scale>{GEOMETRY}</node>',
        f'<node id="a"><scale>3e38 3e38 3e38</scale><translate>-3e38 0 0</translate>'
        f"{GEOMETRY}</node>",
    ],
    ids=["rotate-axis", "scales", "scale-translate"],
)
def test_transforms_that_overflow_print_no_warning(scene: str) -> None:
    # numpy's overflow warnings were printed on stderr in the middle of `xrdf spheres`' output
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with contextlib.suppress(ColladaNotRead):  # a give-up is fine, a warning is not
            collada_vertices(dae(scene))


def test_the_fitter_refuses_a_collision_mesh_past_the_bounds(tmp_path: Path) -> None:
    (tmp_path / "c.dae").write_bytes(fan_out(60, GEOMETRY))
    trimesh.creation.box((0.1, 0.1, 0.1)).export(tmp_path / "v.stl")
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="arm">'
        '<visual><geometry><mesh filename="v.stl"/></geometry></visual>'
        '<collision><geometry><mesh filename="c.dae"/></geometry></collision>'
        "</link></robot>"
    )
    out = tmp_path / "r.xrdf"
    args = ["spheres", str(tmp_path / "r.urdf"), "--per-link", "1", "-o", str(out)]
    # the old reader never returned: the timeout makes that a failure, not a hang
    done = subprocess.run(
        [sys.executable, "-m", "xrdf_tools", *args],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=REPO,
    )
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr
    assert "c.dae: cannot read mesh (" in done.stderr and "more than" in done.stderr
    assert not out.exists()


def test_trimesh_s_reading_of_an_overflowing_transform_prints_no_warning(tmp_path: Path) -> None:
    """A `<matrix>` holding -1e308 (the fuzzer's spheres-visual case 487 of seed 5): trimesh
    applies the scene's transforms when its scene is dumped, and numpy's `invalid value
    encountered in det` was printed on stderr, for the visual check under `--visual-check all`
    and for the fitter reading a collision mesh."""
    from xrdf_tools.spheres.count_policy import CountPolicy
    from xrdf_tools.spheres.robot_fit import fit_robot

    scene = f'<node id="a"><matrix>1 0 -1e308 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix>{GEOMETRY}</node>'
    (tmp_path / "v.dae").write_bytes(dae(scene))
    trimesh.creation.box((0.1, 0.1, 0.1)).export(tmp_path / "c.stl")
    for visual, collision in (("v.dae", "c.stl"), ("c.stl", "v.dae")):
        (tmp_path / "r.urdf").write_text(
            f'<robot name="r"><link name="arm">'
            f'<visual><geometry><mesh filename="{visual}"/></geometry></visual>'
            f'<collision><geometry><mesh filename="{collision}"/></geometry></collision>'
            "</link></robot>"
        )
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with contextlib.suppress(XrdfToolsError):  # the collision mesh: no spheres
                fit_robot(tmp_path / "r.urdf", counts=CountPolicy(per_link=1), visual_check="all")
        assert [str(w.message) for w in caught if w.category is RuntimeWarning] == []
