"""Bad input never crashes, hangs or loses a file (issue 13): one regression test per failure.

Readers (size, non-regular files, control characters, YAML bombs and depth), cycle-safe walks
(URDF, SRDF groups, mimic chains), the tracebacks of the issue, and the one output writer
(symlinks, devices, temporary files, clashing outputs). Crashes found by the fuzz suite
(``tests/test_fuzz_cli.py``) are kept here as well.
"""

from __future__ import annotations

import io
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.convert.sources import RobotTree
from xrdf_tools.diagnostics import Diagnostic, Severity
from xrdf_tools.robot.core import as_robot
from xrdf_tools.util.errors import (
    InputError,
    OutputError,
    SchemaError,
    SourceError,
    UrdfError,
    XrdfToolsError,
    YamlError,
)
from xrdf_tools.util.fileio import (
    ENV_MAX_INPUT,
    atomic_output,
    read_input_bytes,
    read_input_text,
    write_atomic,
)
from xrdf_tools.util.graph import find_cycle, reachable
from xrdf_tools.yaml.io import load_yaml, parse_yaml, to_python

posix = pytest.mark.skipif(os.name != "posix", reason="FIFOs and /dev/zero are POSIX")
MIMIC_URDF = FIXTURES / "urdf" / "three_link_mimic.urdf"
MIMIC_XRDF = FIXTURES / "fuzz" / "three_link_mimic.xrdf"
CUROBO_CLASSIC = FIXTURES / "curobo_classic" / "ur10e_classic.yml"


def _cli(runner: CliRunner, *args: str) -> tuple[int, str]:
    """Exit code and output of ``xrdf ARGS``; fails on a traceback."""
    res = runner.invoke(app, list(args))
    exc = res.exception
    if exc is not None and not isinstance(exc, SystemExit):
        if isinstance(exc, XrdfToolsError):  # cli.main prints these, exit 2
            return 2, res.output + f"error: {exc}\n"
        raise AssertionError(f"traceback: {exc!r}\n{res.output}") from exc
    assert "Traceback" not in res.output
    return res.exit_code, res.output


def _replace(src: Path, dest: Path, old: str, new: str) -> Path:
    text = src.read_text(encoding="utf-8")
    assert old in text, old
    dest.write_text(text.replace(old, new, 1), encoding="utf-8")
    return dest


# --------------------------------------------------------------------------------------------
# One guarded reader
# --------------------------------------------------------------------------------------------
@posix
@pytest.mark.parametrize("command", ["lint", "diff"])
def test_a_fifo_input_is_refused_without_reading(
    runner: CliRunner, tmp_path: Path, command: str
) -> None:
    fifo = tmp_path / "robot.xrdf"
    os.mkfifo(fifo)
    args = [command, str(fifo)] + ([str(UR10E_XRDF)] if command == "diff" else [])
    start = time.monotonic()
    code, out = _cli(runner, *args)
    assert code == 2 and "FIFO" in out and f"{fifo}:" in out
    assert time.monotonic() - start < 10


@posix
def test_dev_zero_and_directories_are_refused_as_inputs(runner: CliRunner, tmp_path: Path) -> None:
    with pytest.raises(UrdfError, match="character device, not a regular file"):
        read_input_bytes("/dev/zero", what="URDF file", error=UrdfError)
    with pytest.raises(InputError, match=r"is a directory \(file expected\)"):
        read_input_bytes(tmp_path)
    code, out = _cli(runner, "convert", str(UR10E_URDF), "--srdf", "/dev/zero")
    assert code == 2 and "/dev/zero: is a character device" in out


@posix
def test_a_link_to_dev_zero_is_refused(runner: CliRunner, tmp_path: Path) -> None:
    link = tmp_path / "robot.urdf"
    link.symlink_to("/dev/zero")
    code, out = _cli(runner, "lint", str(UR10E_XRDF), "--urdf", str(link))
    assert code == 2 and "not a regular file" in out


def test_size_limit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    big = tmp_path / "big.xrdf"
    big.write_text("- 1\n" * 1000)
    monkeypatch.setenv(ENV_MAX_INPUT, "0.001")
    with pytest.raises(YamlError, match=f"input limit; set {ENV_MAX_INPUT}") as e:
        load_yaml(big)
    assert e.value.path == str(big)
    monkeypatch.setenv(ENV_MAX_INPUT, "nonsense")
    with pytest.raises(InputError, match="positive number"):
        read_input_bytes(big)
    monkeypatch.delenv(ENV_MAX_INPUT)
    assert load_yaml(big).root is not None


def test_stdin_only_when_allowed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"a: 1\n")))
    assert read_input_text("-", allow_stdin=True) == "a: 1\n"
    with pytest.raises(InputError, match="not found"):
        read_input_bytes("-")


def test_non_utf8_is_reported_at_its_position(tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_bytes(b"format: xrdf\nname: caf\xe9\n")
    with pytest.raises(YamlError, match="not UTF-8") as e:
        load_yaml(p)
    assert (e.value.line, e.value.col) == (2, 10)


@pytest.mark.parametrize(("char", "col"), [("\x01", 5), ("\uffff", 5), ("\x1b", 5), ("\ufffe", 5)])
def test_control_characters_are_errors_with_a_position(char: str, col: int) -> None:
    with pytest.raises(YamlError, match=f"U\\+{ord(char):04X} is not allowed") as e:
        parse_yaml(f"a: 1\nb: a{char}b\n", "x.yaml")
    assert str(e.value).startswith(f"x.yaml:2:{col}: ")


def test_control_character_in_cli_input_is_one_line(runner: CliRunner, tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_text('format: xrdf\nformat_version: 2.0\nx: "a\x01b"\n')
    for args in (["lint", str(p)], ["diff", str(p), str(UR10E_XRDF)]):
        code, out = _cli(runner, *args)
        assert f"{p}:3:" in out and "U+0001" in out and code in (1, 2)


def _laughs(levels: int = 9) -> str:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, levels)]
    return "\n".join(lines) + "\n"


def test_billion_laughs_fails_fast() -> None:
    text = _laughs()
    assert len(text) < 1024
    start = time.monotonic()
    with pytest.raises(YamlError, match="aliases expand this document beyond"):
        parse_yaml(text, "bomb.yaml")
    assert time.monotonic() - start < 2


@pytest.mark.parametrize("command", ["lint", "diff", "convert"])
def test_billion_laughs_through_the_cli(runner: CliRunner, tmp_path: Path, command: str) -> None:
    bomb = tmp_path / "bomb.yml"
    bomb.write_text(_laughs())
    args = {
        "lint": ["lint", str(bomb)],
        "diff": ["diff", str(bomb), str(UR10E_XRDF)],
        "convert": ["convert", str(UR10E_URDF), "--curobo", str(bomb)],
    }[command]
    start = time.monotonic()
    code, out = _cli(runner, *args)
    assert code in (1, 2) and "aliases expand" in out
    assert time.monotonic() - start < 10


def test_a_few_aliases_still_work() -> None:
    doc = parse_yaml("base: &b {radius: 0.1}\nothers: [*b, *b, *b]\n")
    assert to_python(doc.root)["others"][2] == {"radius": 0.1}


def test_too_many_aliases() -> None:
    text = "a: &a 1\nb: [" + ", ".join(["*a"] * 10_001) + "]\n"
    with pytest.raises(YamlError, match="more than 10000 aliases"):
        parse_yaml(text)


def test_recursive_alias_is_an_error() -> None:
    with pytest.raises(YamlError, match="refers to a node that contains it"):
        parse_yaml("a: &a [1, *a]\n")


@pytest.mark.parametrize(
    "text",
    [
        "x: " + "[" * 1000 + "]" * 1000 + "\n",
        "x: " + "{a: " * 1000 + "1" + "}" * 1000 + "\n",
        "".join("  " * i + f"k{i}:\n" for i in range(1000)),
        "a: &a " + "[" * 60 + "]" * 60 + "\nb: " + "[" * 60 + "*a" + "]" * 60 + "\n",
    ],
)
def test_deep_nesting_is_an_error_not_a_recursion_error(text: str) -> None:
    with pytest.raises(YamlError, match="nesting deeper than 100 levels"):
        parse_yaml(text, "deep.yaml")


def test_deep_nesting_through_lint_is_a_finding(runner: CliRunner, tmp_path: Path) -> None:
    p = tmp_path / "deep.xrdf"
    p.write_text("x: " + "[" * 1000 + "]" * 1000 + "\n")
    code, out = _cli(runner, "lint", str(p))
    assert code == 1 and "yaml-syntax" in out and "nesting deeper" in out


@pytest.mark.parametrize(
    ("text", "kind"), [("? {a: 1}\n: 2\n", "mapping"), ("? [1]\n: 2\n", "list")]
)
def test_a_collection_as_a_mapping_key_is_an_error(text: str, kind: str) -> None:
    with pytest.raises(YamlError, match=f"a {kind} is used as a mapping key") as e:
        parse_yaml(text, "k.yaml")
    assert e.value.line == 1


def test_values_with_newlines_are_not_echoed_raw(tmp_path: Path) -> None:
    p = tmp_path / "robot.xrdf"
    p.write_text(UR10E_XRDF.read_text().replace("tool_frames: [tool0]", 'tool_frames: "a\\nb"'))
    from xrdf_tools.xrdf.io import load_xrdf

    with pytest.raises(SchemaError) as e:
        load_xrdf(p)
    assert "\n" not in str(e.value) and "a\\nb" in str(e.value)


# --------------------------------------------------------------------------------------------
# Cycle-safe walks
# --------------------------------------------------------------------------------------------
CYCLE_URDF = """<robot name="r">
  <link name="base"/><link name="a"/><link name="b"/>
  <joint name="j0" type="fixed"><parent link="base"/><child link="a"/></joint>
  <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>
"""
CHAIN_SRDF = (
    '<robot name="r"><group name="arm"><chain base_link="base" tip_link="b"/></group></robot>'
)


def test_joint_whose_parent_is_its_own_child_with_srdf_chain_does_not_hang(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    urdf = tmp_path / "cyc.urdf"
    urdf.write_text(CYCLE_URDF)
    srdf = tmp_path / "cyc.srdf"
    srdf.write_text(CHAIN_SRDF)
    start = time.monotonic()
    code, out = _cli(runner, "convert", str(urdf), "--srdf", str(srdf))
    assert code == 2 and "is the child of two joints" in out and f"{urdf}:5" in out
    assert time.monotonic() - start < 10


def test_a_loop_of_joints_is_refused_with_its_path(tmp_path: Path) -> None:
    from xrdf_tools.robot.urdf_source import parse_urdf_string

    text = CYCLE_URDF.replace(
        '<child link="a"/></joint>\n  <joint name="j1"',
        '<child link="c"/></joint>\n  <joint name="j1"',
    ).replace('<link name="b"/>', '<link name="b"/><link name="c"/>')
    with pytest.raises(
        UrdfError, match=r"the joints form a cycle \(b -> a -> b, through joints j2 -> j1\)"
    ):
        parse_urdf_string(text, "loop.urdf")
    self_loop = CYCLE_URDF.replace(
        '<parent link="b"/><child link="a"/>', '<parent link="b"/><child link="b"/>'
    )
    with pytest.raises(UrdfError, match="as both parent and child"):
        parse_urdf_string(self_loop, "self.urdf")


def test_robot_tree_walks_terminate_on_a_hand_made_cycle() -> None:
    from xrdf_tools.robot.urdf_source import JointInfo

    eye = [[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]]
    joints = {
        "j0": JointInfo("j0", "fixed", "base", "a", eye),
        "j1": JointInfo("j1", "fixed", "a", "b", eye),
        "j2": JointInfo("j2", "fixed", "b", "a", eye),
    }
    tree = RobotTree(
        "r",
        "r.urdf",
        ("base", "a", "b"),
        joints,
        "base",
        {"a": "j2", "b": "j1"},
        {"base": ("j0",), "a": ("j1",), "b": ("j2",)},
    )
    with pytest.raises(UrdfError, match="cycle"):
        tree.ancestors("a")
    assert tree.dfs_joints() == ["j0", "j1", "j2"]
    assert sorted(tree.descendants("base")) == ["a", "b"]


def _nested_groups(n: int, close_cycle: bool = False) -> str:
    groups = [f'<group name="g{i}"><group name="g{i + 1}"/></group>' for i in range(n)]
    last = '<group name="g0"/>' if close_cycle else '<joint name="shoulder_pan_joint"/>'
    groups.append(f'<group name="g{n}">{last}</group>')
    return f'<robot name="ur10e">{"".join(groups)}</robot>'


def _tree() -> RobotTree:
    from xrdf_tools.robot.urdf_source import load_urdf

    return as_robot(load_urdf(UR10E_URDF)).tree


def test_1200_nested_srdf_subgroups() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    srdf = parse_srdf(_nested_groups(1200), "deep.srdf")
    assert group_joints(srdf, "g0", _tree()) == ["shoulder_pan_joint"]


def test_srdf_subgroup_cycle_is_an_error() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    srdf = parse_srdf(_nested_groups(5, close_cycle=True), "loop.srdf")
    with pytest.raises(SourceError, match=r"groups include each other: g0 -> g1 .* -> g0"):
        group_joints(srdf, "g0", _tree())


def test_srdf_diamond_of_subgroups_is_linear() -> None:
    from xrdf_tools.convert.sources.srdf import group_joints, parse_srdf

    n = 40  # each group includes the next two: 2**40 paths, 40 groups
    groups = [
        f'<group name="g{i}"><group name="g{i + 1}"/><group name="g{i + 2}"/></group>'
        for i in range(n)
    ]
    groups += [
        f'<group name="g{n}"><joint name="elbow_joint"/></group>',
        f'<group name="g{n + 1}"/>',
    ]
    srdf = parse_srdf(f'<robot name="r">{"".join(groups)}</robot>', "diamond.srdf")
    start = time.monotonic()
    assert group_joints(srdf, "g0", _tree()) == ["elbow_joint"]
    assert time.monotonic() - start < 2


def _mimic_chain_urdf(n: int, loop: bool = False) -> str:
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = []
    for i in range(n):
        mimic = f'<mimic joint="j{i + 1}"/>' if i < n - 1 else ""
        if loop and i == n - 1:
            mimic = '<mimic joint="j0"/>'
        joints.append(
            f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{mimic}</joint>'
        )
    return f'<robot name="chain">{links}{"".join(joints)}</robot>'


def test_a_long_mimic_chain_resolves_in_linear_time() -> None:
    from xrdf_tools.robot.kinematics import _resolve_mimic
    from xrdf_tools.robot.urdf_source import joints_of, parse_urdf_string

    joints = joints_of(parse_urdf_string(_mimic_chain_urdf(3000), "chain.urdf"))
    memo: dict[str, tuple[str | None, float, float, str]] = {}
    start = time.monotonic()
    for j in joints.values():
        if j.is_mimic:
            master, m, o, _ = _resolve_mimic(j, joints, joints, {}, UrdfError, memo)
            assert (master, m, o) == ("j2999", 1.0, 0.0)
    assert time.monotonic() - start < 2


def test_mimic_loop_is_an_error() -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.robot.urdf_source import parse_urdf_string
    from xrdf_tools.xrdf.io import parse_xrdf

    urdf = parse_urdf_string(_mimic_chain_urdf(4, loop=True), "loop.urdf")
    x = parse_xrdf("format: xrdf\nformat_version: 2.0\n", "x.xrdf")
    with pytest.raises(UrdfError, match="mimic joints form a loop"):
        build_kinematic_model(urdf, x)


def test_graph_helpers() -> None:
    edges = {"a": ["b", "c"], "b": ["d"], "c": ["d"], "d": []}
    assert reachable("a", edges.__getitem__) == (["a", "b", "d", "c"], None)
    edges["d"] = ["b"]
    assert reachable("a", edges.__getitem__)[1] == ["b", "d", "b"]
    assert find_cycle(["c"], edges.__getitem__) == ["d", "b", "d"]
    chain = {i: [i + 1] for i in range(100_000)}
    assert find_cycle(chain, lambda i: chain.get(i, [])) is None


# --------------------------------------------------------------------------------------------
# Tracebacks of the issue
# --------------------------------------------------------------------------------------------
def test_non_utf8_pyproject_found_by_discovery(tmp_path: Path) -> None:
    from xrdf_tools.lint.config import ConfigError, discover_config

    (tmp_path / "pyproject.toml").write_bytes(b"[tool.xrdf.lint]\n# \xff\xfe\n")
    with pytest.raises(ConfigError, match="not UTF-8") as e:
        discover_config(tmp_path)
    assert e.value.line == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1: a\nfoo: b\n", "unknown configuration key '1'"),
        ("rules: [1]\n", "rules must be a mapping, not a list"),
        ("urdf: {'*.xrdf': [1]}\n", r"urdf.\*.xrdf must be a name, not a list"),
        ("options: {x: 1}\n", "1:1: unknown configuration key 'options'"),
        ("target: [curobo]\n", "target must be a name, not a list"),
        ("rules: {curobo-: {level: [1]}}\n", "rules.curobo-.level must be a level"),
    ],
)
def test_lint_config_shape_errors(
    runner: CliRunner, tmp_path: Path, text: str, message: str
) -> None:
    from xrdf_tools.lint.config import ConfigError, load_config

    p = tmp_path / ".xrdf-lint.yaml"
    p.write_text(text)
    with pytest.raises(ConfigError, match=message):
        load_config(p)
    code, out = _cli(runner, "lint", "--config", str(p), str(UR10E_XRDF))
    assert code == 2 and f"{p}" in out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'lower="-6.283185307179586" upper="6.283185307179586"',
            'lower="1" upper="-1"',
            "lower=1 is above upper=-1",
        ),
        ('lower="-6.283185307179586"', 'lower="-inf"', "lower='-inf': numbers must be finite"),
        ('lower="-6.283185307179586"', 'lower="nan"', "lower='nan': numbers must be finite"),
        (
            '<origin rpy="0 0 0" xyz="0 0 0.1807"/>',
            '<origin rpy="0 0 0" xyz="0 0 inf"/>',
            "must be finite",
        ),
    ],
)
def test_bad_urdf_limits_are_input_errors(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    urdf = _replace(UR10E_URDF, tmp_path / "bad.urdf", old, new)
    for args in (
        ["report", str(UR10E_XRDF), "--urdf", str(urdf), "-n", "10"],
        ["viz", str(UR10E_XRDF), "--urdf", str(urdf), "--png", str(tmp_path / "o.png")],
    ):
        code, out = _cli(runner, *args)
        assert code == 2 and message in out and f"{urdf}:" in out, (args, out)
    # lint checks the XRDF against the URDF: no reader loads it with this one, a finding
    code, out = _cli(runner, "lint", str(UR10E_XRDF), "--urdf", str(urdf))
    assert code == 1 and "urdf-invalid" in out and message in out and f"{urdf}:" in out, out


def test_mimic_offset_inf(runner: CliRunner, tmp_path: Path) -> None:
    urdf = _replace(MIMIC_URDF, tmp_path / "m.urdf", 'offset="0.1"', 'offset="inf"')
    code, out = _cli(runner, "convert", str(urdf))
    assert code == 2 and "<mimic> offset='inf': numbers must be finite" in out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('<box size="0.25 0.06 0.06"/>', '<box size="1 2"/>', "<box> size='1 2' must be 3 numbers"),
        ('<sphere radius="0.02"/>', '<sphere radius="-1"/>', "must not be negative"),
        ('<cylinder radius="0.08" length="0.1"/>', '<cylinder radius="0.08"/>', "no 'length'"),
    ],
)
def test_bad_geometry_is_an_input_error(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    urdf = _replace(MIMIC_URDF, tmp_path / "g.urdf", old, new)
    code, out = _cli(runner, "report", str(MIMIC_XRDF), "--urdf", str(urdf), "-n", "10")
    assert code == 2 and message in out


def test_planar_joint_in_viz_sorts_its_diagnostics(runner: CliRunner, tmp_path: Path) -> None:
    urdf = _replace(
        UR10E_URDF,
        tmp_path / "planar.urdf",
        '<joint name="camera_mount_joint" type="fixed">',
        '<joint name="camera_mount_joint" type="planar">',
    )
    pytest.importorskip("mcap")
    out_file = str(tmp_path / "o.mcap")
    # the fixture's meshes are not bundled: their warnings sort with the joint's
    code, out = _cli(
        runner,
        "viz",
        str(UR10E_XRDF),
        "--urdf",
        str(urdf),
        "--mcap",
        out_file,
        "--allow-missing-meshes",
    )
    assert code == 0 and "joint-held-fixed" in out and "mesh-not-loaded" in out


def test_diagnostics_with_and_without_a_line_sort() -> None:
    a = Diagnostic("f", None, None, "r", Severity.WARNING, "m")
    b = Diagnostic("f", 3, None, "r", Severity.WARNING, "m")
    assert sorted([b, a]) == [a, b]


@pytest.mark.parametrize("command", ["report", "viz"])
def test_negative_seed_is_a_usage_error(runner: CliRunner, tmp_path: Path, command: str) -> None:
    extra = ["--png", str(tmp_path / "o.png"), "-n", "2"] if command == "viz" else ["-n", "2"]
    code, out = _cli(
        runner, command, str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--seed", "-1", *extra
    )
    assert code == 2 and "--seed" in out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("center: [0.0, 0.0, 0.0]", "center: [1e308, 1e308, 0.0]", "center[0] is 1e+308"),
        ("center: [0.0, 0.0, 0.0]", "center: [.inf, 0.0, 0.0]", "center[0] is inf; lengths"),
        ("radius: 0.05", "radius: 1e308", "radius is 1e+308"),
    ],
)
def test_huge_sphere_values_are_errors_not_overflows(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    x = _replace(UR10E_XRDF, tmp_path / "big.xrdf", old, new)
    for args in (
        ["viz", str(x), "--urdf", str(UR10E_URDF), "--png", str(tmp_path / "o.png")],
        ["report", str(x), "--urdf", str(UR10E_URDF), "-n", "10"],
    ):
        code, out = _cli(runner, *args)
        assert code == 2 and message in out and out.count("\n") == 1, out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("link_names: [tool0, flange]", "link_names: 5", "link_names must be a list of names"),
        (
            "    collision_link_names:\n",
            "    collision_link_names: 5\n    x:\n",
            "collision_link_names must be",
        ),
        (
            "upper_arm_link: [forearm_link, shoulder_link]",
            "upper_arm_link: 7",
            "self_collision_ignore.upper_arm_link must be",
        ),
        ("      joint_names:\n", "      joint_names: 3\n      x:\n", "cspace.joint_names must be"),
        ("  kinematics:\n", "  kinematics: 4\n  x:\n", "robot_cfg.kinematics must be a mapping"),
        (
            "link_names: [tool0, flange]",
            "link_names: [tool0, {a: b}]",
            "link_names[1] must be a name",
        ),
        ("link_names: [tool0, flange]", "? {a: 1}\n    : 1", "a mapping is used as a mapping key"),
    ],
)
def test_curobo_shape_errors(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    cfg = _replace(CUROBO_CLASSIC, tmp_path / "cfg.yml", old, new)
    (tmp_path / "spheres").mkdir()
    (tmp_path / "spheres" / "ur10e.yml").write_bytes(
        (CUROBO_CLASSIC.parent / "spheres" / "ur10e.yml").read_bytes()
    )
    code, out = _cli(runner, "convert", str(UR10E_URDF), "--curobo", str(cfg))
    assert code == 2 and message in out and f"{cfg}:" in out, out


def test_configs_json_nested_too_deeply(runner: CliRunner, tmp_path: Path) -> None:
    q = tmp_path / "q.json"
    q.write_text("[" * 100_000 + "]" * 100_000)
    code, out = _cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "nested too deeply" in out


def test_configs_yaml_bomb(runner: CliRunner, tmp_path: Path) -> None:
    q = tmp_path / "q.yaml"
    q.write_text(_laughs())
    code, out = _cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "aliases expand" in out


def test_npy_of_the_wrong_shape(runner: CliRunner, tmp_path: Path) -> None:
    import numpy as np

    q = tmp_path / "q.npy"
    np.save(q, np.zeros((2, 2, 2)))
    code, out = _cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "[B, k]" in out
    q.write_bytes(b"\x93NUMPY garbage")
    code, out = _cli(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(q)
    )
    assert code == 2 and "not a numeric .npy array" in out


# --------------------------------------------------------------------------------------------
# One output writer
# --------------------------------------------------------------------------------------------
@posix
def test_writing_through_a_symlink_keeps_the_link(tmp_path: Path) -> None:
    target = tmp_path / "real.xrdf"
    target.write_text("old")
    target.chmod(0o640)
    link = tmp_path / "link.xrdf"
    link.symlink_to(target.name)
    write_atomic(link, "new")
    assert link.is_symlink() and target.read_text() == "new"
    assert (target.stat().st_mode & 0o777) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.xrdf", "real.xrdf"]


@posix
def test_devices_and_fifos_are_refused_as_outputs(runner: CliRunner, tmp_path: Path) -> None:
    fifo = tmp_path / "out.xrdf"
    os.mkfifo(fifo)
    for path in (fifo, Path("/dev/null")):
        with pytest.raises(OutputError, match="not a regular file; refusing to replace it") as e:
            write_atomic(path, "x")
        assert e.value.path == str(path)
        code, out = _cli(runner, "convert", str(UR10E_URDF), "-o", str(path))
        assert code == 2 and f"{path}: is a" in out
    assert fifo.exists() and not fifo.is_file()
    with pytest.raises(OutputError, match="is a directory"):
        write_atomic(tmp_path, "x")


def test_temporary_file_is_removed_on_interrupt(tmp_path: Path) -> None:
    out = tmp_path / "out.txt"
    with pytest.raises(KeyboardInterrupt), atomic_output(out) as tmp:
        tmp.write_text("partial")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_write_errors_name_the_requested_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / ".out.x.tmp"))

    monkeypatch.setattr(os, "replace", full)
    out = tmp_path / "out.xrdf"
    with pytest.raises(OutputError) as e:
        write_atomic(out, "data")
    assert str(e.value) == f"{out}: cannot write: No space left on device"
    assert isinstance(e.value, OSError) and e.value.filename == str(out)
    assert list(tmp_path.iterdir()) == []


@posix
def test_sigterm_removes_the_temporary_file(tmp_path: Path) -> None:
    script = (
        "import os, signal, sys\n"
        "from xrdf_tools.cli import _on_signal\n"
        "from xrdf_tools.util.fileio import atomic_output\n"
        "signal.signal(signal.SIGTERM, _on_signal)\n"
        f"with atomic_output({str(tmp_path / 'out.txt')!r}) as tmp:\n"
        "    tmp.write_text('partial')\n"
        "    os.kill(os.getpid(), signal.SIGTERM)\n"
        "    signal.pause()\n"
    )
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parent.parent)}
    res = subprocess.run([sys.executable, "-c", script], env=env, timeout=60, check=False)
    assert res.returncode == 128 + 15
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("first", "second"), [("-o", "--write-mask"), ("-o", "--plot"), ("--plot", "--write-mask")]
)
def test_report_refuses_one_path_for_two_outputs(
    runner: CliRunner, tmp_path: Path, first: str, second: str
) -> None:
    r = tmp_path / "R"
    code, out = _cli(
        runner,
        "report",
        str(UR10E_XRDF),
        "--urdf",
        str(UR10E_URDF),
        "-n",
        "10",
        first,
        str(r),
        second,
        str(r),
    )
    assert code == 2 and "given for both" in out
    assert not r.exists()


def test_report_errors_name_the_output_not_the_temporary(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import errno

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device", "/somewhere/.mask.tmp")

    monkeypatch.setattr(os, "replace", full)
    mask = tmp_path / "mask.xrdf"
    code, out = _cli(
        runner,
        "report",
        str(UR10E_XRDF),
        "--urdf",
        str(UR10E_URDF),
        "-n",
        "10",
        "--write-mask",
        str(mask),
    )
    assert code == 2 and f"{mask}: " in out and ".tmp" not in out and "No space left" in out


def test_math_is_still_finite_for_in_range_values(tmp_path: Path) -> None:
    """The length bound leaves real robots alone: the bundled XRDF loads and lints clean."""
    from xrdf_tools.xrdf.io import load_xrdf

    x = load_xrdf(UR10E_XRDF)
    assert all(math.isfinite(s.radius) for ss in x.world_collision_spheres().values() for s in ss)


def _clone_chain(n: int, cycle: bool) -> str:
    lines = ["format: xrdf", "format_version: 2.0", "geometry:"]
    for i in range(n):
        last = i == n - 1
        clone = "[g0]" if last and cycle else f"[g{i + 1}]"
        spheres = "    spheres: {a: [{center: [0, 0, 0], radius: 0.1}]}"
        lines += [f"  g{i}:", spheres if last and not cycle else f"    clone: {clone}"]
    lines += ["world_collision:", "  geometry: g0"]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("cycle", [False, True])
def test_long_clone_chains_lint_in_linear_time(cycle: bool) -> None:
    from xrdf_tools.lint import lint_text

    start = time.monotonic()
    diags = lint_text(_clone_chain(3000, cycle), "clones.xrdf")
    assert time.monotonic() - start < 15
    assert (sum(d.rule == "clone-cycle" for d in diags) == 3000) is cycle


def test_clone_cycle_message_is_one_short_line() -> None:
    from xrdf_tools.xrdf.io import parse_xrdf

    with pytest.raises(
        SchemaError,
        match=r"^clones.xrdf:\d+:\d+: world_collision.geometry: geometry groups clone each other: "
        r"g0 -> .* \(2993 more\) -> g2997 -> g2998 -> g2999 -> g0$",
    ):
        parse_xrdf(_clone_chain(3000, True), "clones.xrdf")


def test_nodes_on_cycles() -> None:
    from xrdf_tools.util.graph import nodes_on_cycles, show_path

    edges = {"a": ["b"], "b": ["c", "a"], "c": ["c"], "d": ["a"], "e": []}
    assert nodes_on_cycles(edges, edges.__getitem__) == {"a", "b", "c"}
    chain = {i: [i + 1] for i in range(100_000)}
    chain[100_000] = [0]
    assert len(nodes_on_cycles(chain, chain.__getitem__)) == 100_001
    assert show_path(range(20)) == "0 -> 1 -> 2 -> 3 -> ... (12 more) -> 16 -> 17 -> 18 -> 19"


def test_choosing_among_thousands_of_nested_groups_is_linear() -> None:
    from xrdf_tools.convert.sources.srdf import choose_group, parse_srdf

    srdf = parse_srdf(_nested_groups(5000), "deep.srdf")
    start = time.monotonic()
    group, _ = choose_group(srdf, _tree())
    assert group is not None and time.monotonic() - start < 5
    looped = parse_srdf(_nested_groups(50, close_cycle=True), "loop.srdf")
    assert choose_group(looped, _tree()) == (None, "the SRDF has no group with movable joints")


def test_postorder_puts_children_first() -> None:
    from xrdf_tools.util.graph import postorder

    edges = {"a": ["b", "c"], "b": [], "c": ["b"], "d": ["d"]}
    order = postorder(edges, edges.__getitem__)
    assert order.index("b") < order.index("c") < order.index("a") and "d" in order


# Crashes found by benchmarks/fuzz_cli.py (seed 0), kept as regression tests.
def test_fuzz_case_5907_repeated_cspace_joint_in_viz(runner: CliRunner, tmp_path: Path) -> None:
    x = _replace(MIMIC_XRDF, tmp_path / "m.xrdf", "    - joint2\n", "    - joint2\n    - joint2\n")
    code, out = _cli(
        runner,
        "viz",
        str(x),
        "--urdf",
        str(MIMIC_URDF),
        "--png",
        str(tmp_path / "o.png"),
        "-n",
        "2",
    )
    assert code == 2 and "joint 'joint2' is listed twice" in out and f"{x}:" in out


def test_fuzz_case_9969_nan_default_position_in_viz_mcap(runner: CliRunner, tmp_path: Path) -> None:
    pytest.importorskip("mcap")
    x = _replace(UR10E_XRDF, tmp_path / "n.xrdf", "elbow_joint: 1.9", "elbow_joint: .nan")
    code, out = _cli(
        runner,
        "viz",
        str(x),
        "--urdf",
        str(UR10E_URDF),
        "--mcap",
        str(tmp_path / "o.mcap"),
        "-n",
        "2",
    )
    assert code == 2 and "is nan; numbers must be finite" in out
    assert not (tmp_path / "o.mcap").exists()


def test_convert_refuses_to_overwrite_the_spheres_file_its_config_reads(
    runner: CliRunner, tmp_path: Path
) -> None:
    import shutil

    from tests.paths import FIXTURES

    cfg_dir = tmp_path / "cfg"
    shutil.copytree(FIXTURES / "curobo_classic", cfg_dir)
    spheres = cfg_dir / "spheres" / "ur10e.yml"
    before = spheres.read_bytes()
    code, out = _cli(
        runner,
        "convert",
        str(UR10E_URDF),
        "--curobo",
        str(cfg_dir / "ur10e_classic.yml"),
        "-o",
        str(spheres),
    )
    assert code == 2 and "refusing to overwrite an input file" in out
    assert spheres.read_bytes() == before


@pytest.mark.parametrize(
    ("old", "key"),
    [
        ("radius: 0.05", "radius"),
        ("shoulder_lift_joint: -2.2", "default_joint_positions.shoulder_lift_joint"),
    ],
)
def test_an_integer_beyond_float_range_is_an_input_error(
    runner: CliRunner, tmp_path: Path, old: str, key: str
) -> None:
    """YAML integers have no size limit; a 400-digit one is not finite as a float."""
    text = UR10E_XRDF.read_text()
    assert old in text
    x = tmp_path / "big.xrdf"
    x.write_text(text.replace(old, old.split(":")[0] + ": " + "9" * 400, 1))
    code, out = _cli(runner, "diff", str(x), str(UR10E_XRDF))
    assert code == 2 and "is about 1e400; " in out, out
    code, out = _cli(runner, "lint", str(x))
    assert code == 1 and "internal-error" not in out and "is about 1e400; " in out, out


def test_a_curobo_sphere_beyond_float_range_is_reported(runner: CliRunner, tmp_path: Path) -> None:
    from tests.paths import FIXTURES

    cfg = tmp_path / "ur10e.yml"
    text = (FIXTURES / "curobo_classic" / "ur10e_inline.yml").read_text()
    assert '"radius": 0.05' in text or "radius: 0.05" in text
    cfg.write_text(text.replace("0.05", "9" * 400, 1))
    code, out = _cli(
        runner, "convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(tmp_path / "o")
    )
    assert code in (0, 2) and "Traceback" not in out, out
