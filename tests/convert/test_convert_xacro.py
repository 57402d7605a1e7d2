"""xacro robots from rtb-data converted on the command line without ROS (package paths given)."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from xrdf_tools.cli import app
from xrdf_tools.robot.xacro_source import expand_xacro
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.io import parse_xrdf


def _rtb() -> Path:
    spec = importlib.util.find_spec("rtbdata")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("rtb-data is not installed")
    root = Path(next(iter(spec.submodule_search_locations))) / "xacro"
    if not root.is_dir():
        pytest.skip("rtb-data has no xacro directory")
    return root


#: name -> (xacro below rtbdata/xacro, {package: dir below rtbdata/xacro}, default c-space)
XACRO_ROBOTS = {
    "kuka_iiwa": (
        "kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.xacro",
        {
            "kuka_lbr_iiwa_support": "kuka_description/kuka_lbr_iiwa",
            "kuka_resources": "kuka_description/kuka_resources",
        },
        [f"joint_a{i}" for i in range(1, 8)],
    ),
    "panda": (
        "qut_frankie_description/robots/panda_arm_hand.urdf.xacro",
        {"qut_frankie_description": "qut_frankie_description"},
        [f"panda_joint{i}" for i in range(1, 8)],  # the fingers are left out by default
    ),
    "interbotix_px150": (
        "trossen_descriptions/urdf/px150.urdf.xacro",
        {"trossen_descriptions": "trossen_descriptions"},
        ["waist", "shoulder", "elbow", "wrist_angle", "wrist_rotate"],  # no gripper/fingers
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(XACRO_ROBOTS))
def test_rtb_xacro_converts_with_package_paths(
    runner: CliRunner, name: str, tmp_path: Path
) -> None:
    root = _rtb()
    rel, packages, cspace = XACRO_ROBOTS[name]
    args = ["convert", str(root / rel), "-o", str(tmp_path / "out.xrdf")]
    for pkg, d in packages.items():
        args += ["--package-path", f"{pkg}={root / d}"]
    result = runner.invoke(app, args)
    # linted against the expanded URDF: no errors, exit 0
    assert result.exit_code == 0, result.output
    x = parse_xrdf((tmp_path / "out.xrdf").read_text())
    assert x.cspace is not None and list(x.cspace.joint_names) == cspace
    assert "convert-no-spheres" in result.output  # reported loudly on stderr
    # ... once, instead of a mesh-without-spheres line for every link
    assert "mesh-without-spheres" not in result.output


def test_unresolved_package_names_it_and_the_search(runner: CliRunner, tmp_path: Path) -> None:
    root = _rtb()
    rel, _, _ = XACRO_ROBOTS["kuka_iiwa"]
    result = runner.invoke(app, ["convert", str(root / rel)])
    assert result.exit_code == 2
    assert "cannot find ROS package 'kuka_lbr_iiwa_support'" in result.output
    assert "searched" in result.output and "--package-path kuka_lbr_iiwa_support=DIR" in (
        result.output
    )
    assert "Traceback" not in result.output


def _unfound_at(top: Path, text: str, package: str) -> tuple[str | None, int | None, int | None]:
    """Where expanding ``top`` (written as ``text``) says ``package`` cannot be found."""
    top.write_text(text)
    with pytest.raises(SourceError, match=f"cannot find ROS package '{package}'") as e:
        expand_xacro(top)
    return e.value.path, e.value.line, e.value.col


def test_an_unfound_package_is_located_at_its_find(tmp_path: Path) -> None:
    """The error names the file and the line and column of the $(find NAME) that asks for
    the package: in the top file (an include's path) and inside an included macro (a mesh
    path evaluated where the macro is expanded)."""
    top = tmp_path / "r.urdf.xacro"
    head = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n  <link name="base"/>\n'
    include = '  <xacro:include filename="$(find missing_pkg)/urdf/arm.xacro"/>\n</robot>\n'
    assert _unfound_at(top, head + include, "missing_pkg") == (str(top), 3, 28)
    arm = tmp_path / "arm.xacro"
    arm.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="arm" params="parent">\n'
        '    <link name="l1"><visual><geometry>\n'
        '      <mesh filename="file://$(find vendor_meshes)/l1.stl"/></geometry></visual></link>\n'
        '    <joint name="j1" type="fixed"><parent link="${parent}"/><child link="l1"/></joint>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    body = '  <xacro:include filename="arm.xacro"/>\n  <xacro:arm parent="base"/>\n</robot>\n'
    assert _unfound_at(top, head + body, "vendor_meshes") == (str(arm), 4, 30)


def test_a_missing_include_is_located_at_its_include_and_names_the_unset_arg(
    tmp_path: Path,
) -> None:
    """A robot family's xacro picks its arm file by an argument whose default is empty
    (Interbotix LoCoBot: arms/$(arg arm_model).urdf.xacro): the error is located at the
    include that names the file, not at another include whose name is all substitutions,
    and says which argument was not given; a given argument gets no such hint."""
    (tmp_path / "arms").mkdir()
    (tmp_path / "arms" / "mobile_arm.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="mobile_arm">\n'
        '    <xacro:include filename="$(find my_bot)/arms/$(arg arm_model).urdf.xacro"/>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    (tmp_path / "package.xml").write_text("<package><name>my_bot</name></package>")
    top = tmp_path / "bot.urdf.xacro"
    top.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="arm_model" default=""/>\n'
        '  <xacro:arg name="extra" default=""/>\n'
        "  <xacro:if value=\"${'$(arg extra)' != ''}\">\n"
        '    <xacro:include filename="$(arg extra)"/>\n'
        "  </xacro:if>\n"
        '  <xacro:include filename="arms/mobile_arm.xacro"/>\n'
        '  <link name="base"/>\n'
        "  <xacro:mobile_arm/>\n"
        "</robot>\n"
    )
    arm = str(tmp_path / "arms" / "mobile_arm.xacro")
    with pytest.raises(SourceError) as e:
        expand_xacro(top)
    assert (e.value.path, e.value.line, e.value.col) == (arm, 3, 30)
    assert f"the included file {tmp_path / 'arms' / '.urdf.xacro'} does not exist" in str(e.value)
    assert "$(arg arm_model), not given, so '': pass --xacro-arg arm_model:=VALUE" in str(e.value)
    assert "Errno" not in str(e.value)
    with pytest.raises(SourceError) as e:
        expand_xacro(top, {"arm_model": "wx999"})
    assert (e.value.path, e.value.line) == (arm, 3)
    assert "wx999.urdf.xacro does not exist" in str(e.value)
    assert "--xacro-arg" not in str(e.value)
    top.write_text(top.read_text().replace("arms/mobile_arm.xacro", "arms/mobile_arms.xacro"))
    with pytest.raises(SourceError) as e:
        expand_xacro(top)
    assert (e.value.path, e.value.line, e.value.col) == (str(top), 7, 28)


def test_xacro_warnings_are_diagnostics_not_raw_stderr(runner: CliRunner, tmp_path: Path) -> None:
    """Sawyer's xacro passes <xacro:arg> children to an include, which xacro ignores with a
    warning it prints itself: that went to stderr past -q and --format json. It is now an
    xacro-warning diagnostic of the file xacro was reading (robot and SRDF xacro alike), placed
    at the include with a body (it had no line)."""
    (tmp_path / "arm.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="arm"/>\n'
        '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>\n'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>\n'
    )
    (tmp_path / "none.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>\n')
    include = '<xacro:include filename="arm.xacro"><xacro:arg name="x" value="1"/></xacro:include>'
    robot = tmp_path / "bot.urdf.xacro"
    robot.write_text(
        f'<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n<link name="base"/>\n'
        '<xacro:include filename="none.xacro"/> <xacro:include filename="none.xacro">\n'
        "<!-- <link/> --></xacro:include>\n"
        f"  {include}\n</robot>\n"
    )
    (tmp_path / "groups.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<group name="arm"><joint name="j"/></group></robot>\n'
    )
    srdf = tmp_path / "bot.srdf.xacro"
    srdf.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:include filename="groups.xacro"><xacro:arg name="y" value="2"/></xacro:include>\n'
        "</robot>\n"
    )
    out = tmp_path / "bot.xrdf"
    args = ["convert", str(robot), "--srdf", str(srdf), "-o", str(out)]
    quiet = runner.invoke(app, [*args, "-q"])
    assert quiet.exit_code == 0, quiet.output
    assert quiet.stderr == ""
    loud = runner.invoke(app, [*args, "--format", "json"])
    assert loud.exit_code == 0, loud.output
    import json

    found = [d for d in json.loads(loud.stderr)["diagnostics"] if d["rule"] == "xacro-warning"]
    assert sorted(d["path"] for d in found) == sorted([str(robot), str(srdf)])
    # placed at the include with a body (not at one closed or holding only a comment)
    assert sorted((d["path"], d["line"], d["col"]) for d in found) == sorted(
        [(str(robot), 5, 3), (str(srdf), 2, 1)]
    )
    assert {d["message"] for d in found} == {
        "xacro: Child elements of a <xacro:include> tag are ignored"
    }
    expand = runner.invoke(app, ["expand", str(robot), "-o", str(tmp_path / "bot.urdf")])
    assert expand.exit_code == 0
    assert f"{robot}:5:3: warning xacro-warning xacro: Child elements" in expand.stderr
    assert "when processing file" not in expand.stderr


def test_a_package_named_only_in_gazebo_or_ros2_control_is_a_warning(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Reachy's xacro names $(find reachy_gazebo) in a <gazebo> plugin's parameters: with only
    the description at hand every command stopped. No command reads <gazebo>,
    <ros2_control> or <transmission>: a located warning, and the expansion keeps the
    $(find) as written. The same package in a mesh, an include or a load_yaml stays an
    error at its $(find)."""
    head = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n<link name="base"/>\n'
    gazebo = (
        '<gazebo><plugin name="c" filename="libc.so">\n'
        "<parameters>$(find sim_pkg)/config/c.yaml</parameters></plugin></gazebo>\n"
        '<ros2_control name="s" type="system"><hardware>\n'
        '<param name="f">$(find ctl_pkg)/p.yaml</param></hardware></ros2_control>\n'
    )
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(head + gazebo + "</robot>\n")
    result = runner.invoke(app, ["expand", str(robot)])
    assert result.exit_code == 0, result.output
    assert "<parameters>$(find sim_pkg)/config/c.yaml</parameters>" in result.stdout
    assert '<param name="f">$(find ctl_pkg)/p.yaml</param>' in result.stdout
    warned = [line for line in result.stderr.splitlines() if "xacro-package-unused" in line]
    assert len(warned) == 2
    assert warned[0].startswith(f"{robot}:4:13: warning xacro-package-unused cannot find ROS ")
    assert "named only in <gazebo>, which no command reads: left as $(find sim_pkg)" in warned[0]
    assert warned[1].startswith(f"{robot}:6:17:") and "<ros2_control>" in warned[1]
    used = {
        "mesh": '<link name="l"><visual><geometry><mesh filename="file://$(find sim_pkg)/m.stl"/>'
        "</geometry></visual></link>\n",
        "include": '<xacro:include filename="$(find sim_pkg)/urdf/arm.xacro"/>\n',
        "yaml": '<xacro:property name="y" value="${xacro.load_yaml(\'$(find sim_pkg)/y.yaml\')}"/>'
        '<link name="${y}"/>\n',
    }
    for what, text in used.items():
        robot.write_text(head + gazebo + text + "</robot>\n")
        with pytest.raises(SourceError, match="cannot find ROS package 'sim_pkg'") as e:
            expand_xacro(robot)
        assert (e.value.path, e.value.line) == (str(robot), 4), what


@pytest.mark.parametrize(
    "old, new, line",
    [
        ('parent="base_link"', 'parent="' + "0" * 40 + '"', 22),  # the macro call naming it
        ('length="$(arg length)"', 'length="$(arg 1 2)"', 22),  # a malformed substitution
        ('upper="${pi / 2}"', 'upper=""', 18),  # an attribute the message names with its value
        # numbers xacro writes another way: the joint '0_joint', the parent link '1e+308'
        ('name="upper" parent="base_link"', 'name="000" parent="1e308"', 22),
        ('<link name="${name}">', '<link name="${1e308}">', 7),  # link '1e+308' twice
        ('<link name="${name}">', '<link name="&amp;">', 7),  # link '&' twice
        ('parent="base_link"', 'parent="{x}"', 22),  # braces in a quoted value
        ('<link name="base_link"/>', '<link base_link="base_link"/>', 21),  # a nameless link
        ('name="upper"', 'name=""', 22),  # an empty name: xacro drops the attribute
        ('<robot name="arm"', '<robot label="arm"', 3),  # a nameless robot
        ('<link name="${name}">', '<link label="${name}">', 7),  # a macro's nameless link
    ],
)
def test_errors_about_macro_made_parts_are_located_in_the_xacro(
    runner: CliRunner, tmp_path: Path, old: str, new: str, line: int
) -> None:
    """The fuzz arm's segments are made by a macro: an error about one points at the line of
    the xacro that writes what it quotes (the call's name="upper" for 'upper_joint', the
    attribute upper="" the message names, the $(arg ...) xacro rejects)."""
    robot = tmp_path / "arm.urdf.xacro"
    text = (FIXTURES / "fuzz" / "arm.urdf.xacro").read_text()
    assert old in text
    robot.write_text(text.replace(old, new, 1))
    result = runner.invoke(app, ["convert", str(robot)])
    assert result.exit_code == 2, result.output
    assert f"error: {robot}:{line}" in result.output, result.output


def test_xacro_args_and_find(runner: CliRunner, tmp_path: Path) -> None:
    pkg = tmp_path / "my_pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>my_pkg</name></package>")
    (pkg / "urdf" / "link.xacro").write_text(
        """<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
        <xacro:macro name="lnk" params="n"><link name="${n}"/></xacro:macro></robot>"""
    )
    robot = pkg / "urdf" / "r.urdf.xacro"
    robot.write_text(
        """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
        <xacro:arg name="prefix" default="a_"/>
        <xacro:include filename="$(find my_pkg)/urdf/link.xacro"/>
        <xacro:lnk n="$(arg prefix)base"/><xacro:lnk n="$(arg prefix)tip"/>
        <joint name="$(arg prefix)j" type="revolute"><parent link="$(arg prefix)base"/>
          <child link="$(arg prefix)tip"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
        </joint></robot>"""
    )
    assert 'name="a_base"' in expand_xacro(robot)  # $(find) via package.xml near the input
    assert 'name="b_base"' in expand_xacro(robot, {"prefix": "b_"})
    result = runner.invoke(app, ["convert", str(robot), "--xacro-arg", "prefix:=z_"])
    assert result.exit_code == 0, result.output
    assert "z_j" in result.output
    broken = tmp_path / "broken.xacro"
    broken.write_text(
        '<robot name="b" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find nowhere_pkg)/x.xacro"/></robot>'
    )
    with pytest.raises(SourceError, match="cannot find ROS package 'nowhere_pkg'"):
        expand_xacro(broken)
    bad_arg = runner.invoke(app, ["convert", str(robot), "--xacro-arg", "prefix"])
    assert bad_arg.exit_code == 2 and "NAME:=VALUE" in bad_arg.output


def _prefixed_arm(tmp_path: Path) -> tuple[Path, Path]:
    """A three-link xacro arm named by a ``prefix`` argument, and its MoveIt SRDF as a xacro
    that names the same links through the same argument (as MoveIt configurations ship)."""
    pkg = tmp_path / "arm_pkg"
    (pkg / "config").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>arm_pkg</name></package>")
    joints = "".join(
        f"""<joint name="$(arg prefix)j{i}" type="revolute"><parent link="$(arg prefix)l{i}"/>
          <child link="$(arg prefix)l{i + 1}"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
          <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"""
        for i in range(2)
    )
    robot = pkg / "arm.urdf.xacro"
    robot.write_text(
        f"""<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
        <xacro:arg name="prefix" default="a_"/>
        <link name="$(arg prefix)l0"/><link name="$(arg prefix)l1"/><link name="$(arg prefix)l2"/>
        {joints}</robot>"""
    )
    srdf = pkg / "config" / "arm.srdf.xacro"
    srdf.write_text(
        """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default="a_"/>
  <xacro:property name="p" value="$(arg prefix)"/>
  <group name="arm"><chain base_link="${p}l0" tip_link="${p}l2"/></group>
  <group_state name="home" group="arm">
    <joint name="${p}j0" value="0.25"/><joint name="${p}j1" value="-0.5"/>
  </group_state>
  <disable_collisions link1="${p}l0" link2="${p}l2" reason="Never"/>
</robot>"""
    )
    return robot, srdf


def test_srdf_xacro_is_expanded_with_the_robots_arguments(
    runner: CliRunner, tmp_path: Path
) -> None:
    robot, srdf = _prefixed_arm(tmp_path)
    out = tmp_path / "arm.xrdf"
    args = ["convert", str(robot), "--srdf", str(srdf), "--xacro-arg", "prefix:=z_"]
    result = runner.invoke(app, [*args, "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "$(arg" not in result.output and "unknown-link" not in result.output
    x = parse_xrdf(out.read_text())
    assert x.cspace is not None and list(x.cspace.joint_names) == ["z_j0", "z_j1"]
    assert list(x.default_joint_positions.values()) == [0.25, -0.5]  # the SRDF's home state
    assert x.self_collision is not None
    assert tuple(x.self_collision.ignore.get("z_l0", ())) == ("z_l2",)  # kept
    # the expansion's lines are not the file's: an element is located where the xacro file
    # writes it
    assert f"{srdf}:5: info convert-chosen-group" in result.output  # its only group
    assert f"{srdf}:6: warning convert-chosen-state" in result.output
    shown = runner.invoke(app, ["inspect", str(robot), "--srdf", str(srdf)])
    assert shown.exit_code == 0, shown.output
    assert "arm: 2 c-space joint(s): a_j0, a_j1" in shown.output


def test_expand_writes_an_srdf_xacro_as_the_srdf_convert_reads(
    runner: CliRunner, tmp_path: Path
) -> None:
    """`xrdf expand robot.srdf.xacro` writes the SRDF (its arguments applied, checked as an
    SRDF) instead of refusing it as a URDF without links; a robot's xacro is still a URDF."""
    robot, srdf = _prefixed_arm(tmp_path)
    out = tmp_path / "arm.srdf"
    res = runner.invoke(app, ["expand", str(srdf), "--xacro-arg", "prefix:=z_", "-o", str(out)])
    assert res.exit_code == 0, res.output
    text = out.read_text()
    assert 'link1="z_l0" link2="z_l2"' in text and "$(arg" not in text and "${" not in text
    urdf = runner.invoke(app, ["expand", str(robot), "--xacro-arg", "prefix:=z_"])
    assert urdf.exit_code == 0 and '<link name="z_l0"' in urdf.stdout, urdf.output
    # a file that expands to neither keeps the URDF's reason
    empty = tmp_path / "empty.xacro"
    empty.write_text('<robot name="e" xmlns:xacro="http://www.ros.org/wiki/xacro"/>')
    bad = runner.invoke(app, ["expand", str(empty)])
    assert bad.exit_code == 2 and "has no <link>" in bad.output, bad.output


def test_a_xacro_robots_messages_name_no_line_of_its_expansion(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Lines of the expanded URDF are not lines of the xacro file: a message about a xacro
    robot names the line of the xacro file where the element is written literally, or the
    macro call that makes it (a name all expressions: ``name="${n}"``), else no line (not a
    line of the expansion, which the file may not even have)."""
    macro = """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
    <xacro:macro name="part" params="n parent">
      <link name="${n}"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>
        <material name="m_${n}"><color rgba="1 0 0 1 1"/></material></visual>
        <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
      <joint name="j_${n}" type="revolute"><parent link="${parent}"/><child link="${n}"/>
        <origin xyz="0 0 0.2"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </xacro:macro>
    <link name="base"/>
    <xacro:part n="a" parent="base"/><xacro:part n="b" parent="%s"/></robot>"""
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(macro % "a")
    located = re.compile(re.escape(str(robot)) + r":(\d+)")
    ok = runner.invoke(app, ["convert", str(robot), "--fit-spheres", "-n", "200"])
    assert ok.exit_code == 0, ok.output
    assert f"{robot}: warning urdf-color-ignored link 'b'" in ok.output
    # the spheres' notes on links: at the calls (line 10), never at a line of the expansion
    assert {m.group(1) for m in located.finditer(ok.output)} <= {"10"}, ok.output
    robot.write_text(macro % "nowhere")
    bad = runner.invoke(app, ["convert", str(robot)])
    # a joint a macro made: at the line that writes the value the message quotes
    at = (
        (macro % "nowhere")
        .splitlines()
        .index('    <xacro:part n="a" parent="base"/><xacro:part n="b" parent="nowhere"/></robot>')
    )
    assert bad.exit_code == 2 and f"{robot}:{at + 1}: " in bad.output, bad.output
    literal = (macro % "a").replace(
        "</robot>",
        '\n<link name="c"/>\n<joint name="j_c" type="fixed">'
        '<parent link="elsewhere"/><child link="c"/></joint></robot>',
    )
    robot.write_text(literal)
    line = (
        literal.splitlines().index(
            '<joint name="j_c" type="fixed">'
            '<parent link="elsewhere"/><child link="c"/></joint></robot>'
        )
        + 1
    )
    bad = runner.invoke(app, ["convert", str(robot)])
    assert bad.exit_code == 2 and f"{robot}:{line}: " in bad.output, bad.output


def test_what_xacro_prints_becomes_warnings_in_the_chosen_format(
    runner: CliRunner, tmp_path: Path
) -> None:
    """xacro prints its own warnings (xArm's description calls the deprecated load_yaml()) to
    the terminal: they broke `--format json` on stderr and ignored -q. They are diagnostics
    now, one per distinct message."""
    import json

    (tmp_path / "len.yaml").write_text("length: 0.3\n")
    arm = tmp_path / "arm.urdf.xacro"
    arm.write_text(
        '<?xml version="1.0"?>\n<robot name="arm" xmlns:xacro="http://ros.org/wiki/xacro">\n'
        f'  <xacro:property name="p" value="${{load_yaml(\'{tmp_path / "len.yaml"}\')}}"/>\n'
        f'  <xacro:property name="q" value="${{load_yaml(\'{tmp_path / "len.yaml"}\')}}"/>\n'
        '  <link name="base"/><link name="l1"/>\n'
        '  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>\n'
        '    <origin xyz="0 0 ${p[\'length\']}"/><axis xyz="0 0 1"/>\n'
        '    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n</robot>\n'
    )
    out = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(arm), "--format", "json", "-o", str(out)])
    assert r.exit_code == 0, r.output
    diags = json.loads(r.stderr)["diagnostics"]
    printed = [d for d in diags if d["rule"] == "xacro-warning"]
    assert [(d["path"], d["severity"]) for d in printed] == [(str(arm), "warning")]
    assert "load_yaml() directly is deprecated" in printed[0]["message"]
    r = runner.invoke(app, ["convert", str(arm), "-q", "-o", str(out)])
    assert r.exit_code == 0 and r.stderr == ""
    r = runner.invoke(app, ["expand", str(arm)])
    assert r.exit_code == 0 and r.stdout.lstrip().startswith("<?xml")
    assert r.stderr.startswith(f"{arm}:3:35: warning xacro-warning xacro: Using load_yaml()")


def test_a_xacro_warning_names_the_line_of_the_included_file_that_causes_it(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Every MoveIt 2 configuration's ros2_control.xacro reads its initial positions with the
    deprecated ``${load_yaml(...)}`` inside a macro the top file calls: xacro warns while it
    expands the top file, and the warning named that file without a line. It names the
    included file and the line that calls load_yaml()."""
    (tmp_path / "initial_positions.yaml").write_text("initial_positions: {j1: 0.25}\n")
    control = tmp_path / "arm.ros2_control.xacro"
    control.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://ros.org/wiki/xacro">\n'
        '  <xacro:macro name="arm_control" params="file">\n'
        '    <xacro:property name="init" value="${load_yaml(file)[\'initial_positions\']}"/>\n'
        '    <ros2_control name="fake" type="system"><joint name="j1">\n'
        '      <state_interface name="position"><param name="initial_value">${init[\'j1\']}'
        "</param></state_interface></joint></ros2_control>\n"
        "  </xacro:macro>\n</robot>\n"
    )
    arm = tmp_path / "arm.urdf.xacro"
    arm.write_text(
        '<?xml version="1.0"?>\n<robot name="arm" xmlns:xacro="http://ros.org/wiki/xacro">\n'
        '  <xacro:include filename="arm.ros2_control.xacro"/>\n'
        '  <link name="base"/><link name="l1"/>\n'
        '  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>\n'
        '    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        f'  <xacro:arm_control file="{tmp_path / "initial_positions.yaml"}"/>\n</robot>\n'
    )
    r = runner.invoke(app, ["expand", str(arm)])
    assert r.exit_code == 0 and "<ros2_control" in r.stdout
    assert r.stderr.startswith(f"{control}:4:"), r.stderr
    assert "warning xacro-warning xacro: Using load_yaml() directly is deprecated" in r.stderr


def test_a_xacro_arg_the_expansion_never_reads_is_a_warning(
    runner: CliRunner, tmp_path: Path
) -> None:
    """xacro ignores a mapping nothing declares or reads: the KMR iiwa's
    `--xacro-arg ee_typ:=dd` silently expanded the default gripper. Each given argument that
    no <xacro:arg> or $(arg) of the expansion reads is a located warning with the closest
    name; the arguments it does read (declared, or read in a taken branch) are not, and an SRDF
    xacro given the robot's arguments does not warn about the ones only the robot reads."""
    robot = tmp_path / "bot.urdf.xacro"
    robot.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:arg name="ee_type" default="bb"/>\n'
        '<link name="base"/><link name="$(arg ee_type)"/>\n'
        '<joint name="j" type="revolute"><parent link="base"/><child link="$(arg ee_type)"/>\n'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "<xacro:if value=\"${xacro.arg('prefix') == 'x'}\"><link name=\"x\"/>\n"
        '<joint name="jx" type="fixed"><parent link="base"/><child link="x"/></joint>\n'
        "</xacro:if>\n"
        "</robot>\n"
    )
    srdf = tmp_path / "bot.srdf.xacro"
    srdf.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<group name="arm"><joint name="j"/></group></robot>\n'
    )
    out = tmp_path / "bot.urdf"
    args = ["--xacro-arg", "ee_typ:=dd", "--xacro-arg", "prefix:=y"]
    r = runner.invoke(app, ["expand", str(robot), *args, "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert r.stderr.splitlines() == [
        f"{robot}: warning xacro-arg-unread --xacro-arg ee_typ:=dd: no <xacro:arg> or $(arg) "
        "of the expansion reads 'ee_typ', so it changes nothing (arguments read: ee_type, "
        "prefix); did you mean 'ee_type'?"
    ]
    assert '<link name="bb"/>' in out.read_text()
    fine = ["--xacro-arg", "ee_type:=dd", "--xacro-arg", "prefix:=x"]
    r = runner.invoke(app, ["convert", str(robot), "--srdf", str(srdf), *fine, "-q"])
    assert r.exit_code == 0, r.output
    assert r.stderr == ""
    r = runner.invoke(app, ["convert", str(robot), "--srdf", str(srdf), *fine, *args[:2]])
    unread = [ln for ln in r.stderr.splitlines() if "xacro-arg-unread" in ln]
    assert len(unread) == 1 and unread[0].startswith(f"{robot}: warning"), r.stderr


def test_an_argument_only_the_srdf_xacro_reads_is_not_unread(
    runner: CliRunner, tmp_path: Path
) -> None:
    """The Annin AR4's MoveIt SRDF xacro names its robot `$(arg name)`, which its URDF xacro
    never reads: `--xacro-arg name:=mk3`, needed by the SRDF, was warned about as changing
    nothing. convert and inspect expand both with the same arguments: only an argument
    neither file reads is warned about."""
    robot = tmp_path / "bot.urdf.xacro"
    robot.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:arg name="model" default="bot"/>\n'
        '<link name="base"/><link name="arm"/>\n'
        '<joint name="j" type="revolute"><parent link="base"/><child link="arm"/>\n'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "</robot>\n"
    )
    srdf = tmp_path / "bot.srdf.xacro"
    srdf.write_text(
        '<robot name="$(arg name)" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<group name="arm"><joint name="j"/></group></robot>\n'
    )
    args = ["--xacro-arg", "name:=bot", "--xacro-arg", "nmae:=x", "--srdf", str(srdf)]
    for command in ("convert", "inspect"):
        r = runner.invoke(app, [command, str(robot), *args])
        assert r.exit_code == 0, r.output
        unread = [ln for ln in r.stderr.splitlines() if "xacro-arg-unread" in ln]
        assert len(unread) == 1 and "'nmae'" in unread[0], r.stderr
        assert "did you mean 'name'?" in unread[0], r.stderr


def test_an_unset_argument_names_the_others_the_files_use_without_a_default(
    tmp_path: Path,
) -> None:
    """PAL's Talos needs six arguments its launch file passes: the error about the first
    names the others its files use without a default (in the top file, an include found by
    $(find), not in a comment), so one run finds them all."""
    pkg = tmp_path / "robo_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>robo_description</name></package>")
    (pkg / "urdf" / "parts.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="with_default" default="1"/>\n'
        '  <link name="$(arg head_type)_$(arg with_default)"/>\n'
        "  <!-- $(arg commented_out) -->\n</robot>\n"
    )
    top = pkg / "robot.urdf.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:if value="$(arg enable_crane)"><link name="crane"/></xacro:if>\n'
        '  <xacro:include filename="$(find robo_description)/urdf/parts.xacro"/>\n'
        '  <link name="base_$(arg test)"/>\n</robot>\n'
    )
    with pytest.raises(SourceError) as e:
        expand_xacro(top)
    assert e.value.line == 2 and "Undefined substitution argument enable_crane" in e.value.message
    assert e.value.message.endswith(
        "; used without a default too: --xacro-arg test:=VALUE --xacro-arg head_type:=VALUE"
    )
    with pytest.raises(SourceError) as e:
        expand_xacro(top, {"enable_crane": "false", "head_type": "a"})
    assert e.value.message.endswith("(pass --xacro-arg test:=VALUE)")


def test_an_unknown_package_names_the_others_the_files_name(tmp_path: Path) -> None:
    """Reachy 2's reachy.urdf.xacro names four packages beside its own (orbita2d/3d,
    dynamixel, zuuu); the error about the first was all a run said, so finding them took four
    runs. It names the others its files name (the top file and the includes found by
    $(find), not a comment), with the flag for each; a found package is not named."""
    pkg = tmp_path / "robo_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>robo_description</name></package>")
    (pkg / "urdf" / "arm.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find wrist_description)/urdf/wrist.xacro"/>\n'
        "  <!-- $(find commented_description) -->\n</robot>\n"
    )
    top = pkg / "robot.urdf.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find head_description)/urdf/head.xacro"/>\n'
        '  <xacro:include filename="$(find robo_description)/urdf/arm.xacro"/>\n'
        '  <link name="base"/>\n</robot>\n'
    )
    with pytest.raises(SourceError) as e:
        expand_xacro(top)
    msg = e.value.message
    assert e.value.line == 2 and "cannot find ROS package 'head_description'" in msg
    assert msg.endswith(": --package-path wrist_description=DIR"), msg
    assert "robo_description=DIR" not in msg and "commented" not in msg
    head = tmp_path / "head_description"
    (head / "urdf").mkdir(parents=True)
    (head / "urdf" / "head.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="head"/></robot>'
    )
    with pytest.raises(SourceError) as e:
        expand_xacro(top, package_paths={"head_description": str(head)})
    assert "cannot find ROS package 'wrist_description'" in e.value.message
    assert "either" not in e.value.message  # the only one left


def test_a_yaml_file_named_by_an_arg_default_is_located_with_the_arg_to_pass(
    tmp_path: Path,
) -> None:
    """Mitsubishi's MELFA xacros read `xacro.load_yaml(initial_positions_file)` inside
    `<ros2_control>`, the argument defaulting to a bare file name that the launch file
    replaces by a full path: without it every command failed with "[Errno 2] No such file or
    directory" and no word of the argument. Now: located at the expression, the file named,
    the --xacro-arg to pass and the file of that name in the robot's package."""
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "initial_positions.yaml").write_text("initial_positions: {j1: 0.5}\n")
    (tmp_path / "hardware.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="hardware" params="initial_positions_file">\n'
        '    <xacro:property name="initial" value="${xacro.load_yaml(initial_positions_file)}"/>\n'
        '    <ros2_control name="arm" type="system">\n'
        '      <joint name="j1"><param name="initial_value">'
        "${initial['initial_positions']['j1']}</param></joint>\n"
        "    </ros2_control>\n"
        "  </xacro:macro>\n</robot>\n"
    )
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="initial_positions_file" default="initial_positions.yaml"/>\n'
        '  <xacro:include filename="hardware.xacro"/>\n'
        '  <link name="base"/>\n'
        '  <xacro:hardware initial_positions_file="$(arg initial_positions_file)"/>\n'
        "</robot>\n"
    )
    with pytest.raises(SourceError) as e:
        expand_xacro(top)
    assert (e.value.path, e.value.line) == (str(tmp_path / "hardware.xacro"), 3), str(e.value)
    message = str(e.value)
    assert f"the file {tmp_path / 'initial_positions.yaml'} does not exist" in message
    assert "Errno" not in message
    assert "$(arg initial_positions_file), not given, so 'initial_positions.yaml'" in message
    found = tmp_path / "config" / "initial_positions.yaml"  # where the launch file points
    assert message.endswith(
        f"pass --xacro-arg initial_positions_file:=PATH; a file of that name: {found})"
    )
    given = {"initial_positions_file": str(tmp_path / "config" / "initial_positions.yaml")}
    assert '<param name="initial_value">0.5</param>' in expand_xacro(top, given)


def test_an_error_in_an_element_an_included_macro_wrote_is_located_there(
    tmp_path: Path,
) -> None:
    """HEBI's rosie.urdf.xacro calls the omnibase macro of urdf/components/omnibase.xacro,
    whose wheel joints name child links no macro makes: the error named the top file without
    a line. It is located at the included file's line that writes the child link; the "did you
    mean" suggestion, a name written elsewhere in that file, is not taken for it."""
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    (tmp_path / "components").mkdir()
    base = tmp_path / "components" / "base.xacro"
    base.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="omnibase" params="child">\n'
        '    <link name="omni_base"/>\n'
        '    <joint name="base_child_joint" type="fixed">\n'
        '      <parent link="omni_base"/><child link="${child}"/>\n'
        "    </joint>\n"
        '    <joint name="wheel_1_joint" type="fixed">\n'
        '      <parent link="omni_base"/>\n'
        '      <child link="wheel_1"/>\n'
        "    </joint>\n"
        '    <link name="wheel_1_end"/>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    top = tmp_path / "rosie.urdf.xacro"
    top.write_text(
        '<robot name="rosie" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="components/base.xacro"/>\n'
        '  <link name="arm_base"/>\n'
        '  <xacro:omnibase child="arm_base"/>\n'
        "</robot>\n"
    )
    with pytest.raises(UrdfError) as e:
        load_robot(top)
    assert (e.value.path, e.value.line) == (str(base), 9), str(e.value)
    assert "unknown child link 'wheel_1'; did you mean 'wheel_1_end'?" in str(e.value)


def test_a_link_two_includes_define_is_located_at_a_definition(tmp_path: Path) -> None:
    """HEBI's rosie.urdf.xacro includes an arm kit that defines '$(arg prefix)base_link' and
    calls an omnibase macro that defines 'base_link': with no prefix the link is defined twice,
    and the error pointed at the top file's `<child link="base_link"/>`, the first place that
    quotes the name, which defines nothing. It is located where a file defines it."""
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    (tmp_path / "kit.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="prefix" default=""/>\n'
        '  <link name="$(arg prefix)base_link"/>\n'
        "</robot>\n"
    )
    base = tmp_path / "base.xacro"
    base.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="omnibase">\n'
        '    <link name="base_link"/>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    top = tmp_path / "rosie.urdf.xacro"
    top.write_text(
        '<robot name="rosie" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="kit.xacro"/>\n'
        '  <xacro:include filename="base.xacro"/>\n'
        '  <link name="footprint"/>\n'
        '  <joint name="base_joint" type="fixed">\n'
        '    <parent link="footprint"/><child link="base_link"/>\n'
        "  </joint>\n"
        "  <xacro:omnibase/>\n"
        "</robot>\n"
    )
    with pytest.raises(UrdfError) as e:
        load_robot(top)
    assert (e.value.path, e.value.line) == (str(base), 3), str(e.value)
    assert "link 'base_link' is defined twice" in str(e.value)


def test_a_link_the_file_and_a_macro_both_define_says_so(tmp_path: Path) -> None:
    """A robot on a lift defines 'base_link' and calls UR's macro with an empty prefix, which
    defines 'base_link' again: the macro's copy took the line of the file's literal tag, and
    the error read ':4: link 'base_link' is defined twice (first on line 4)'."""
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    top = tmp_path / "lift.urdf.xacro"
    top.write_text(
        '<robot name="lift" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="arm" params="prefix">\n'
        '    <link name="${prefix}base_link"/>\n'
        "  </xacro:macro>\n"
        '  <link name="base_link"/>\n'
        '  <xacro:arm prefix=""/>\n'
        "</robot>\n"
    )
    with pytest.raises(UrdfError) as e:
        load_robot(top)
    assert (e.value.path, e.value.line) == (str(top), 5), str(e.value)
    assert str(e.value).endswith(
        "link 'base_link' is defined twice (on line 5, and again by a xacro macro or include)"
    )


@pytest.mark.parametrize(
    ("name", "defined"), [("lower", "link 'lower'"), ("-1", "joint '-1_joint'")]
)
def test_a_macro_call_pasted_twice_is_located_at_the_second_call(
    tmp_path: Path, name: str, defined: str
) -> None:
    """A macro call line pasted twice defines its link (or a joint whose name the macro
    composes from the one passed) twice; no line of the file writes the tag, and the error had
    no location. It points at the second call."""
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    link = '    <link name="${name}"/>\n' if name == "lower" else ""
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="segment" params="name parent">\n'
        f"{link}"
        '    <joint name="${name}_joint" type="fixed">\n'
        '      <parent link="${parent}"/><child link="tip_${name}"/>\n'
        "    </joint>\n"
        "  </xacro:macro>\n"
        '  <link name="base"/>\n'
        f'  <xacro:segment name="{name}" parent="base"/>\n'
        f'  <xacro:segment name="{name}" parent="base"/>\n'
        "</robot>\n"
    )
    second = top.read_text().splitlines().index(f'  <xacro:segment name="{name}" parent="base"/>')
    with pytest.raises(UrdfError) as e:
        load_robot(top)
    assert f"{defined} is defined twice" in str(e.value)
    assert (e.value.path, e.value.line) == (str(top), second + 2), str(e.value)


def test_a_link_written_one_attribute_a_line_is_located_in_a_xacro(
    runner: CliRunner, tmp_path: Path
) -> None:
    # a SolidWorks export renamed to .urdf.xacro: '<link\n    name="arm">' was not found in
    # the xacro text, so what was said about the link had no line
    x = tmp_path / "arm.urdf.xacro"
    x.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="s" value="0.1"/>\n'
        '  <link\n    name="base"/>\n'
        "  <link\n"
        '    name="arm">\n'
        '    <collision><geometry><mesh filename="meshes/arm.STL"/></geometry></collision>\n'
        "  </link>\n"
        '  <joint\n    name="j"\n    type="revolute">\n'
        '    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>\n'
        '    <limit lower="-1" upper="1" effort="1" velocity="${s}"/></joint>\n'
        "</robot>\n"
    )
    r = runner.invoke(
        app, ["convert", str(x), "--fit-spheres", "-n", "10", "-o", str(tmp_path / "o")]
    )
    assert r.exit_code == 2, r.output
    assert f"error: {x}:5: 1 mesh file(s) cannot be found: link 'arm' collision:" in r.output


@pytest.mark.parametrize(
    ("tag", "defined"),
    [
        ('<joint name="${1e308}_joint" type="fixed"><parent link="base"/>', "joint '1e+308_joint'"),
        ('<link name="${nan}"/><joint name="j${seg}" type="fixed"><parent link="base"/>', "'nan'"),
    ],
)
def test_a_name_an_expression_makes_twice_is_located_at_the_expression(
    tmp_path: Path, tag: str, defined: str
) -> None:
    """A macro whose element name is an expression (``${1e308}_joint``, ``${nan}``) defines it
    on every call: no text writes ``1e+308_joint`` or ``nan`` as it is, and the error had no
    line. It points at the attribute whose expression can make the name."""
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    top = tmp_path / "r.urdf.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base"/>\n'
        '  <xacro:macro name="seg" params="seg">\n'
        '    <link name="l${seg}"/>\n'
        f'    {tag}<child link="l${{seg}}"/></joint>\n'
        "  </xacro:macro>\n"
        '  <xacro:seg seg="1"/>\n'
        '  <xacro:seg seg="2"/>\n'
        "</robot>\n"
    )
    with pytest.raises(UrdfError) as e:
        load_robot(top)
    assert defined in str(e.value) and "defined twice" in str(e.value), str(e.value)
    assert (e.value.path, e.value.line) == (str(top), 5), str(e.value)


def test_a_kinematic_error_of_a_macro_made_joint_is_placed_at_the_macro(tmp_path: Path) -> None:
    """A joint a macro of the file itself makes (``${name}_joint``) with a zero axis: the
    error named the joint but had no line; it points where the macro writes the joint."""
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.util.errors import UrdfError

    top = tmp_path / "r.urdf.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base"/>\n'
        '  <xacro:macro name="seg" params="name parent">\n'
        '    <link name="${name}"/>\n'
        '    <joint name="${name}_joint" type="revolute"><parent link="${parent}"/>\n'
        '      <child link="${name}"/><axis xyz="0 0 0"/>\n'
        '      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "  </xacro:macro>\n"
        '  <xacro:seg name="upper" parent="base"/>\n'
        "</robot>\n"
    )
    with pytest.raises(UrdfError) as e:
        build_kinematic_model(load_robot(top))
    assert "joint 'upper_joint' has a zero or invalid axis" in str(e.value)
    assert (e.value.path, e.value.line) == (str(top), 5), str(e.value)


def test_a_link_a_macro_makes_in_another_macro_is_placed_at_the_inner_call(
    tmp_path: Path,
) -> None:
    """A link made by a macro (``<link name="${name}">``) that another macro calls with a
    name that is a template itself (the Omnid delta robot's
    ``<xacro:cylinder_link name="robot_${prefix}/base_link"/>`` in its ``base_link`` macro):
    placed at that inner call, where the name is written; it had no line."""
    from xrdf_tools.robot.xacro_source import load_robot

    top = tmp_path / "r.urdf.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="cylinder_link" params="name">\n'
        '    <link name="${name}"/>\n'
        "  </xacro:macro>\n"
        '  <xacro:macro name="base" params="prefix">\n'
        '    <xacro:cylinder_link name="robot_${prefix}/base_link"/>\n'
        "  </xacro:macro>\n"
        '  <link name="world"/>\n'
        '  <xacro:base prefix="1"/>\n'
        '  <joint name="j" type="fixed"><parent link="world"/>\n'
        '    <child link="robot_1/base_link"/></joint>\n'
        "</robot>\n"
    )
    robot = load_robot(top)
    assert robot.place("link", "robot_1/base_link") == (str(top), 6)
