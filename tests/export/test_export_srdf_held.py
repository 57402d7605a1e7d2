"""``xrdf export srdf --merge``: pairs the XRDF ignores only because its mask held a joint
still are not written into MoveIt's SRDF.

The pattern of moveit_resources' dual-arm Panda: converted for one arm (the default group),
the other arm is held at its default, so every pair within it "never collides"; MoveIt plans
that arm too, and an added ``disable_collisions`` would switch its checks off.
"""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app


def _link(name: str) -> str:
    return (
        f'<link name="{name}"><collision><geometry><box size="0.1 0.1 0.1"/></geometry>'
        "</collision></link>"
    )


def _joint(name: str, parent: str, child: str, kind: str = "revolute", extra: str = "") -> str:
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if kind != "fixed" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>{limit}{extra}</joint>'
    )


URDF = (
    '<robot name="duo"><link name="world"/>'
    + "".join(_link(n) for n in ("l0", "l1", "l2", "r0", "r1", "r2", "fa", "fb"))
    + _joint("l_base", "world", "l0", "fixed")
    + _joint("l_j1", "l0", "l1")
    + _joint("l_j2", "l1", "l2")
    + _joint("r_base", "world", "r0", "fixed")
    + _joint("r_j1", "r0", "r1")
    + _joint("r_j2", "r1", "r2")
    + _joint("fa_j", "l2", "fa", "prismatic")
    + _joint("fb_j", "l2", "fb", "prismatic", '<mimic joint="fa_j"/>')
    + "</robot>"
)

SPHERES = "".join(
    f"      {n}: [{{center: [0, 0, 0], radius: 0.05}}]\n"
    for n in ("l0", "l1", "l2", "r0", "r1", "r2", "fa", "fb")
)
XRDF = f"""format: xrdf
format_version: 1.0
cspace:
  joint_names: [l_j1, l_j2]
  acceleration_limits: [10, 10]
  jerk_limits: [1000, 1000]
tool_frames: [l2]
collision:
  geometry: duo_spheres
self_collision:
  geometry: duo_spheres
  ignore:
    l0: [l1, r0, r1, r2]
    l1: [l2]
    r0: [r1, r2]
    r1: [r2]
    fa: [fb]
    l2: [fa]
geometry:
  duo_spheres:
    spheres:
{SPHERES}"""

SRDF = """<?xml version="1.0"?>
<robot name="duo">
  <group name="left"><chain base_link="l0" tip_link="l2"/></group>
  <group name="right"><chain base_link="r0" tip_link="r2"/></group>
  <disable_collisions link1="r0" link2="r1" reason="Adjacent"/>
  <disable_collisions link1="r1" link2="r2" reason="Adjacent"/>
  <enable_collisions link1="r0" link2="r2" reason="User"/>
</robot>
"""


def _run(tmp_path: Path, xrdf: str = XRDF) -> tuple[int, str, str]:
    for name, text in (("duo.urdf", URDF), ("duo.xrdf", xrdf), ("duo.srdf", SRDF)):
        (tmp_path / name).write_text(text)
    out = tmp_path / "out.srdf"
    files = [str(tmp_path / n) for n in ("duo.xrdf", "duo.urdf", "duo.srdf")]
    args = ["export", "srdf", files[0], "--urdf", files[1], "--merge", files[2], "-o", str(out)]
    r = CliRunner().invoke(app, args)
    return r.exit_code, out.read_text() if out.exists() else "", r.stderr


def _disabled(srdf: str) -> set[frozenset[str]]:
    from xrdf_tools.convert.sources.srdf import parse_srdf

    return {frozenset((a, b)) for a, b, _, _ in parse_srdf(srdf).disable_collisions}


def test_pairs_across_a_held_joint_are_not_added(tmp_path: Path) -> None:
    code, out, err = _run(tmp_path)
    assert code == 0, err
    disabled = _disabled(out)
    # the held right arm: r0/r2 stays enabled (its enable_collisions kept), adjacent pairs kept
    assert frozenset(("r0", "r2")) not in disabled
    assert '<enable_collisions link1="r0" link2="r2"' in out
    assert {frozenset(("r0", "r1")), frozenset(("r1", "r2"))} <= disabled
    # left arm vs the held right arm crosses r_j1 (l0/r0 are rigid: added); the fingers'
    # pair crosses the held fa_j and its mimic fb_j, and l2 has spheres between them
    assert frozenset(("l0", "r0")) in disabled
    assert frozenset(("l0", "r1")) not in disabled and frozenset(("l0", "r2")) not in disabled
    assert frozenset(("fa", "fb")) not in disabled
    # pairs the c-space moves, and adjacent pairs across a held joint, are added as before
    assert {frozenset(("l0", "l1")), frozenset(("l1", "l2")), frozenset(("l2", "fa"))} <= disabled
    line = next(x for x in err.splitlines() if "export-srdf-held-joint" in x)
    assert line.startswith(f"{tmp_path / 'duo.srdf'}: warning export-srdf-held-joint 4 ")
    assert "fa_j, r_j1, r_j2 at their default" in line and "fb_j" not in line
    assert "--group" in line


def test_with_every_joint_in_the_c_space_every_pair_is_added(tmp_path: Path) -> None:
    moved = XRDF.replace("[l_j1, l_j2]", "[l_j1, l_j2, r_j1, r_j2, fa_j]")
    moved = moved.replace("[10, 10]", "[10, 10, 10, 10, 10]").replace(
        "[1000, 1000]", "[1000, 1000, 1000, 1000, 1000]"
    )
    code, out, err = _run(tmp_path, moved)
    assert code == 0, err
    assert "export-srdf-held-joint" not in err
    assert {frozenset(("r0", "r2")), frozenset(("fa", "fb")), frozenset(("l0", "r2"))} <= (
        _disabled(out)
    )
    assert "enable_collisions" not in out
