"""``xrdf inspect``: the tree, chains, SRDF groups and the default choice, as text and JSON."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import UR10E_URDF
from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.convert.inspect import inspect_robot
from xrdf_tools.robot.core import as_robot
from xrdf_tools.robot.urdf_source import load_urdf


def _path(rel: str) -> Path:
    root = robots_dir()
    if root is None or not (root / rel).is_file():
        pytest.skip(f"example-robot-data has no {rel}")
    return root / rel


TIAGO = "tiago_description/robots/tiago.urdf"
PR2 = ("pr2_description/urdf/pr2.urdf", "pr2_description/srdf/pr2.srdf")


def test_json_describes_every_link_and_joint_of_the_urdf(runner: CliRunner) -> None:
    urdf = _path(TIAGO)
    result = runner.invoke(app, ["inspect", str(urdf), "--format", "json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert list(data) == [
        "version", "robot", "path", "srdf", "root", "roots", "links", "joints", "chains", "groups",
        "left_out", "frames", "default",
    ]  # fmt: skip
    robot = as_robot(load_urdf(urdf))
    assert data["roots"] == [data["root"]] == [robot.root_link()]
    assert [lk["name"] for lk in data["links"]] == list(robot.links)
    assert {lk["name"] for lk in data["links"] if lk["collision"]} == set(robot.collision_counts)
    by_name = {j["name"]: j for j in data["joints"]}
    assert list(by_name) == list(robot.joints)
    for name, j in robot.joints.items():
        got = by_name[name]
        assert (got["type"], got["parent"], got["child"]) == (j.type, j.parent, j.child)
        assert (got["lower"], got["upper"], got["actuated"]) == (j.lower, j.upper, j.is_actuated)
        assert (got["mimic"] or {}).get("joint") == j.mimic_joint
    # one chain per leaf link, each ending at its leaf
    leaves = [lk for lk in robot.links if not robot.tree.child_joints.get(lk)]
    assert sorted(c["leaf"] for c in data["chains"]) == sorted(leaves)
    for c in data["chains"]:
        assert robot.joints[c["joints"][-1]].child == c["leaf"]
    # the default is what convert writes
    x, _ = convert(robot, ConvertOptions())
    assert x.cspace is not None
    assert data["default"]["cspace"] == list(x.cspace.joint_names)
    assert data["default"]["tool_frames"] == list(x.tool_frames or ())
    assert data["default"]["source"] == "chain"
    assert data["default"]["chain_flag"] == f"--chain {robot.tree.root}:{x.tool_frames[0]}"
    assert set(data["left_out"]) == {"wheel", "gripper", "head"}


def test_text_is_a_tree_with_the_default_marked(runner: CliRunner) -> None:
    urdf = _path(TIAGO)
    result = runner.invoke(app, ["inspect", str(urdf)])
    assert result.exit_code == 0, result.output
    out = result.stdout
    robot = as_robot(load_urdf(urdf))
    lines = out.splitlines()
    # every joint on one tree line, 'joint (type …) → child'
    for name, j in robot.joints.items():
        assert sum(1 for ln in lines if f"─ {name} (" in ln and f"→ {j.child}" in ln) == 1
    choice = inspect_robot(robot).default
    for i, name in enumerate(choice.cspace, 1):
        assert any(f"{name} (" in ln and f"c-space #{i})" in ln for ln in lines)
    assert any("left out: wheel" in ln for ln in lines)
    assert f"--chain {robot.tree.root}:{choice.tool_frames[0]}" in out
    assert len(lines) < 2 * (len(robot.joints) + 10)  # readable: about a line per joint


def test_srdf_groups_resolved_and_default_from_the_srdf(runner: CliRunner) -> None:
    urdf, srdf = _path(PR2[0]), _path(PR2[1])
    result = runner.invoke(app, ["inspect", str(urdf), "--srdf", str(srdf), "--format", "json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    groups = {g["name"]: g for g in data["groups"]}
    assert set(groups["arms"]["cspace"]) == set(groups["left_arm"]["cspace"]) | set(
        groups["right_arm"]["cspace"]
    )
    assert groups["base"]["unplannable"] == ["world_joint"]  # the SRDF's planar virtual joint
    robot = as_robot(load_urdf(urdf))
    x, _ = convert(robot, ConvertOptions(srdf=srdf))
    assert x.cspace is not None
    assert data["default"] == {**data["default"], "source": "srdf", "chain_flag": None}
    assert data["default"]["cspace"] == list(x.cspace.joint_names)
    text = runner.invoke(app, ["inspect", str(urdf), "--srdf", str(srdf)]).stdout
    assert "SRDF groups" in text and "world_joint" in text


def test_bad_input_is_one_line_exit_2(runner: CliRunner, tmp_path: Path) -> None:
    result = runner.invoke(app, ["inspect", str(tmp_path / "missing.urdf")])
    assert result.exit_code == 2
    assert "missing.urdf" in result.output and "Traceback" not in result.output
    bad = tmp_path / "bad.srdf"
    bad.write_text("<robot name='x'><group name='g'>")
    urdf = _path(PR2[0])
    result = runner.invoke(app, ["inspect", str(urdf), "--srdf", str(bad)])
    assert result.exit_code == 2 and "bad.srdf" in result.output


def test_disconnected_parts_are_shown_not_hidden(runner: CliRunner, tmp_path: Path) -> None:
    urdf = tmp_path / "two.urdf"
    urdf.write_text(
        '<robot name="two"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<limit lower="-1" upper="1" velocity="1" effort="1"/></joint></robot>'
    )
    result = runner.invoke(app, ["inspect", str(urdf), "--format", "json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["roots"] == ["a", "c"]
    assert data["default"]["source"] == "error" and "not one tree" in data["default"]["error"]
    text = runner.invoke(app, ["inspect", str(urdf)]).stdout
    assert "c ·  (not connected to 'a')" in text and "nothing, it fails" in text


@pytest.mark.parametrize(
    ("joint_extra", "axis", "error"),
    [
        ('<mimic joint="k"/>', "0 0 1", "mimic joints form a loop: j -> k -> j"),
        ('<mimic joint="nope"/>', "0 0 1", "mimics 'nope', which is not a joint"),
        ("", "0 0 0", "zero or invalid axis"),
    ],
)
def test_a_robot_convert_refuses_has_no_default_choice(
    runner: CliRunner, tmp_path: Path, joint_extra: str, axis: str, error: str
) -> None:
    """What `xrdf convert` would pick is an error when convert fails on the robot's
    kinematics, not a c-space it would never write."""
    limit = '<limit lower="-1" upper="1" velocity="1" effort="1"/>'
    urdf = tmp_path / "bad.urdf"
    urdf.write_text(
        '<robot name="bad"><link name="a"/><link name="b"/><link name="c"/>'
        f'<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        f'<axis xyz="{axis}"/>{limit}{joint_extra}</joint>'
        '<joint name="k" type="revolute"><parent link="b"/><child link="c"/>'
        f'{limit}<mimic joint="j"/></joint></robot>'
    )
    result = runner.invoke(app, ["inspect", str(urdf), "--format", "json"])
    assert result.exit_code == 0, result.output
    default = json.loads(result.stdout)["default"]
    assert default["source"] == "error" and error in default["error"], default
    assert default["cspace"] == []
    convert = runner.invoke(app, ["convert", str(urdf)])
    assert convert.exit_code == 2 and error in convert.output


def test_reads_no_geometry_library() -> None:
    """A light install (no [fit] extra) inspects: neither yourdfpy nor trimesh is imported."""
    import subprocess
    import sys

    urdf = _path(TIAGO)
    code = (
        "import sys\n"
        "from xrdf_tools.cli import main\n"
        f"sys.argv = ['xrdf', 'inspect', {str(urdf)!r}]\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "print(sorted(m for m in ('yourdfpy', 'trimesh') if m in sys.modules), file=sys.stderr)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stderr.strip().splitlines()[-1] == "[]"
    assert "arm_tool_link" in done.stdout


def _parents_from_tree(text: str) -> dict[str, str]:
    """Read the tree back: each joint's parent joint ('' at the root), from columns alone."""
    lines = text.split("\n\n")[1].splitlines()[2:]
    parents: dict[str, str] = {}
    above: list[tuple[int, str]] = []  # (label column, joint) of the lines read so far
    for line in lines:
        label = len(line) - len(line.lstrip(" │├└─"))
        name = line[label:].split(" ", 1)[0]
        if line[label - 3 : label] in ("└─ ", "├─ "):
            column = label - 3
            parents[name] = next((j for c, j in reversed(above) if c == column), "")
        else:  # a chain carried on at the same depth: the line above is its parent
            parents[name] = above[-1][1]
        above.append((label, name))
    return parents


def test_deep_chain_tree_stays_narrow_and_readable(runner: CliRunner, tmp_path: Path) -> None:
    """A 300-joint chain that forks halfway: the text grows with the joints, not their square,
    and every joint's parent can still be read from the columns."""
    from xrdf_tools.convert.inspect_text import MAX_TREE_INDENT

    links = ['<link name="l0"/>']
    joints: dict[str, str] = {}  # joint -> parent joint
    parent_of_link = {"l0": ""}

    def add(name: str, parent: str, child: str) -> None:
        links.append(f'<link name="{child}"/>')
        links.append(
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
        )
        joints[name] = parent_of_link[parent]
        parent_of_link[child] = name

    for i in range(1, 151):
        add(f"j{i}", f"l{i - 1}", f"l{i}")
    for side in ("a", "b"):
        add(f"{side}1", "l150", f"{side}l1")
        for i in range(2, 76):
            add(f"{side}{i}", f"{side}l{i - 1}", f"{side}l{i}")
    urdf = tmp_path / "snake.urdf"
    urdf.write_text('<robot name="snake">' + "".join(links) + "</robot>")
    result = runner.invoke(app, ["inspect", str(urdf)])
    assert result.exit_code == 0, result.output
    tree = result.stdout.split("\n\n")[1].splitlines()[2:]
    assert len(tree) == len(joints)
    widest = max(len(line) - len(line.lstrip(" │├└─")) for line in tree)
    assert widest <= 3 * (MAX_TREE_INDENT + 2)
    assert _parents_from_tree(result.stdout) == joints


def test_convert_choice_flags_show_what_convert_picks_with_them(runner: CliRunner) -> None:
    """A user copies convert's --group/--chain/--state/--tool-frame onto inspect: the last
    section and the tree's c-space numbers are then what convert writes with those flags."""
    urdf, srdf = _path(PR2[0]), _path(PR2[1])
    flags = ["--group", "left_arm", "--group", "right_arm", "--tool-frame", "r_gripper_tool_frame"]
    result = runner.invoke(
        app, ["inspect", str(urdf), "--srdf", str(srdf), *flags, "--format", "json"]
    )
    assert result.exit_code == 0, result.output
    default = json.loads(result.stdout)["default"]
    robot = as_robot(load_urdf(urdf))
    x, _ = convert(
        robot,
        ConvertOptions(
            srdf=srdf, groups=("left_arm", "right_arm"), tool_frames=("r_gripper_tool_frame",)
        ),
    )
    assert x.cspace is not None
    assert default["cspace"] == list(x.cspace.joint_names)
    assert default["tool_frames"] == list(x.tool_frames) == ["r_gripper_tool_frame"]
    assert default["source"] == "flags" and default["chain_flag"] is None
    assert default["flags"] == [
        "--group left_arm",
        "--group right_arm",
        "--tool-frame r_gripper_tool_frame",
    ]
    text = runner.invoke(app, ["inspect", str(urdf), "--srdf", str(srdf), *flags]).stdout
    head = "what `xrdf convert --group left_arm --group right_arm --tool-frame"
    assert head in text
    numbered = [line for line in text.splitlines() if "c-space #" in line]
    assert len(numbered) == len(x.cspace.joint_names) == 14
    # --chain without an SRDF, comma lists for --joints, as convert reads them
    tiago = _path(TIAGO)
    chain = runner.invoke(
        app, ["inspect", str(tiago), "--chain", "base_footprint:arm_tool_link", "-f", "json"]
    )
    picked = json.loads(chain.stdout)["default"]
    joints = runner.invoke(
        app, ["inspect", str(tiago), "--joints", ",".join(picked["cspace"]), "-f", "json"]
    )
    assert json.loads(joints.stdout)["default"]["cspace"] == picked["cspace"]
    assert picked["cspace"][0] == "torso_lift_joint" and picked["tool_frames"] == ["arm_tool_link"]


def test_a_choice_flag_convert_refuses_is_one_line_exit_2(runner: CliRunner) -> None:
    urdf, srdf = _path(PR2[0]), _path(PR2[1])
    result = runner.invoke(app, ["inspect", str(urdf), "--srdf", str(srdf), "--group", "left_ram"])
    assert result.exit_code == 2
    assert "no group 'left_ram'" in result.output and "did you mean 'left_arm'" in result.output
    assert "Traceback" not in result.output


def test_a_fixed_joint_shows_no_limits_even_with_a_limit_element(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Kinova's URDFs give fixed joints a <limit>: it limits nothing and is not shown."""
    urdf = tmp_path / "r.urdf"
    limit = '<limit lower="0" upper="0" effort="1" velocity="1"/>'
    urdf.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        f'<joint name="mount" type="fixed"><parent link="a"/><child link="b"/>{limit}</joint>'
        '<joint name="j" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    out = runner.invoke(app, ["inspect", str(urdf)]).stdout
    assert "mount (fixed) → b" in out and "j (revolute [-1, 1], c-space #1) → c" in out, out


@pytest.mark.parametrize("flag", ["--joints", "--chain"])
@pytest.mark.parametrize("command", ["inspect", "convert"])
def test_a_joints_or_chain_flag_naming_nothing_is_refused(
    runner: CliRunner, command: str, flag: str
) -> None:
    """``--joints ,,`` (an empty shell variable, a stray comma) was read as no flag: convert
    wrote the SRDF's or the whole tree's c-space, exit 0, without a word."""
    result = runner.invoke(app, [command, str(UR10E_URDF), flag, " , ,"])
    assert result.exit_code == 2, result.output
    assert f"{flag} ' , ,' names nothing; give {flag} " in result.output
    assert "Traceback" not in result.output


def test_a_tool_frame_given_twice_is_one_tool_frame(runner: CliRunner, tmp_path: Path) -> None:
    """convert wrote `tool_frames: [tool0, tool0]` (lint's repeated-tool-frame warns on it)."""
    urdf = _path(TIAGO)
    out = tmp_path / "t.xrdf"
    flags = ["--chain", "base_footprint:arm_tool_link"]
    flags += ["--tool-frame", "arm_tool_link", "--tool-frame", "arm_tool_link"]
    result = runner.invoke(app, ["convert", str(urdf), *flags, "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "tool_frames: [arm_tool_link]" in out.read_text()
    lint = runner.invoke(app, ["lint", str(out), "--urdf", str(urdf)])
    assert "repeated-tool-frame" not in lint.output


def test_a_group_that_does_not_resolve_shows_every_unknown_name(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Toyota HSR's `base` group names odom_x, odom_y and odom_t, none a URDF joint: inspect
    named only the first; it names all three, as convert does."""
    srdf = tmp_path / "ur.srdf"
    srdf.write_text(
        '<robot name="ur"><group name="base"><joint name="odom_x"/><joint name="odom_y"/>'
        '<joint name="odom_t"/></group><group name="arm"><chain base_link="base_link" '
        'tip_link="tool0"/></group></robot>'
    )
    r = runner.invoke(app, ["inspect", str(UR10E_URDF), "--srdf", str(srdf), "--format", "json"])
    assert r.exit_code == 0, r.output
    (base,) = [g for g in json.loads(r.stdout)["groups"] if g["name"] == "base"]
    assert "unknown joints 'odom_x', 'odom_y', 'odom_t'" in base["problem"]
