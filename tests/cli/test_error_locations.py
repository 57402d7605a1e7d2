"""Input errors point at the file and position that is wrong (issue 13): a name the XRDF takes
from the URDF is the XRDF's mistake, so the error is located in the XRDF and names the URDF."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.util.errors import XrdfToolsError


def _error(runner: CliRunner, *args: str) -> str:
    """The one error line of ``xrdf ARGS`` (exit 2, no traceback)."""
    r = runner.invoke(app, list(args))
    out = r.output
    if isinstance(r.exception, XrdfToolsError):  # cli.main prints these as one line
        out += f"error: {r.exception}\n"
    elif r.exception is not None and not isinstance(r.exception, SystemExit):
        raise AssertionError(f"traceback: {r.exception!r}")
    lines = [x for x in out.splitlines() if x.startswith("error:")]
    assert len(lines) == 1, out
    return lines[0]


def _line_of(path: Path, text: str) -> int:
    return next(i for i, x in enumerate(path.read_text().splitlines(), 1) if text in x)


def _renamed_cspace_joint(tmp_path: Path) -> Path:
    x = tmp_path / "robot.xrdf"
    x.write_text(UR10E_XRDF.read_text().replace("- elbow_joint", "- elbow", 1))
    return x


def test_report_blames_the_xrdf_for_a_cspace_joint_the_urdf_lacks(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = _renamed_cspace_joint(tmp_path)
    line = _line_of(x, "- elbow")
    err = _error(runner, "report", str(x), "--urdf", str(UR10E_URDF), "-n", "10")
    assert re.match(rf"^error: {re.escape(str(x))}:{line}:\d+: ur10e.urdf does not match", err)
    assert "c-space joint 'elbow' is not a joint of the robot; did you mean 'elbow_joint'?" in err


def test_viz_and_export_blame_the_xrdf_too(runner: CliRunner, tmp_path: Path) -> None:
    x = _renamed_cspace_joint(tmp_path)
    line = _line_of(x, "- elbow")
    viz = _error(runner, "viz", str(x), "--urdf", str(UR10E_URDF), "--png", str(tmp_path / "v.png"))
    export = _error(
        runner, "export", "curobo", str(x), "--urdf", str(UR10E_URDF), "-o", str(tmp_path / "c.yml")
    )
    for err in (viz, export):
        assert err.startswith(f"error: {x}:{line}:"), err
        assert "ur10e.urdf does not match this XRDF" in err and "'elbow'" in err
    assert not (tmp_path / "v.png").exists() and not (tmp_path / "c.yml").exists()


def test_a_mimic_joint_in_the_cspace_says_why(runner: CliRunner, tmp_path: Path) -> None:
    from tests.selfcollision.test_collision import THREE_LINK

    x = tmp_path / "mimic.xrdf"
    x.write_text(
        "format: xrdf\nformat_version: 2.0\ncspace:\n  joint_names: [joint1, finger_joint]\n"
        "  acceleration_limits: [1, 1]\n  jerk_limits: [1, 1]\n"
        "world_collision:\n  geometry: g\n"
        "geometry:\n  g:\n    spheres:\n      link1: [{center: [0, 0, 0], radius: 0.1}]\n"
    )
    r = runner.invoke(app, ["viz", str(x), "--urdf", str(THREE_LINK), "--png", str(tmp_path / "p")])
    assert r.exit_code == 2
    assert f"{x}:4:" in r.output and "'finger_joint' is a mimic joint" in r.output


def test_an_undefined_geometry_group_is_located_when_the_xrdf_is_read(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = tmp_path / "robot.xrdf"
    text = UR10E_XRDF.read_text()
    x.write_text(text.replace("geometry: ur10e_collision_spheres", "geometry: ur10e_spheres", 1))
    line = _line_of(x, "geometry: ur10e_spheres")
    for args in (
        ("diff", str(x), str(UR10E_XRDF)),
        ("report", str(x), "--urdf", str(UR10E_URDF), "-n", "10"),
    ):
        err = _error(runner, *args)
        where = f"error: {x}:{line}:13: world_collision.geometry: "
        assert err.startswith(where + "geometry group"), err
        assert "'ur10e_spheres' is not defined (defined: ur10e_collision_spheres)" in err


def test_a_clone_of_a_missing_group_is_located(runner: CliRunner, tmp_path: Path) -> None:
    x = tmp_path / "robot.xrdf"
    text = UR10E_XRDF.read_text().replace(
        "  ur10e_collision_spheres:\n", "  ur10e_collision_spheres:\n    clone: [gone]\n", 1
    )
    x.write_text(text)
    err = _error(runner, "diff", str(x), str(UR10E_XRDF))
    assert re.match(rf"^error: {re.escape(str(x))}:\d+:\d+: world_collision.geometry: ", err), err
    assert "clones 'gone', which is not defined" in err


def test_lint_still_reports_an_undefined_group_as_a_finding(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = tmp_path / "robot.xrdf"
    text = UR10E_XRDF.read_text()
    x.write_text(text.replace("geometry: ur10e_collision_spheres", "geometry: ur10e_spheres", 1))
    r = runner.invoke(app, ["lint", str(x), "--urdf", str(UR10E_URDF)])
    assert r.exit_code == 1 and "ur10e_spheres" in r.output and "error:" not in r.output


def test_lint_config_errors_point_at_the_key(runner: CliRunner, tmp_path: Path) -> None:
    cfg = tmp_path / ".xrdf-lint.yaml"
    cases = {
        "rules:\n  curobo-: off\noptions:\n  x: 1\n": ":3:1: unknown configuration key 'options'",
        "rules:\n  sphere-radiu: off\n": ":2:3: unknown rule 'sphere-radiu'",
        "rules:\n  curobo-: {level: bad}\n": ":2:20: rule 'curobo-': level must be one of",
        "rules:\n  curobo-: in\n": ":2:12: rule 'curobo-': level must be one of",
    }
    for text, where in cases.items():
        cfg.write_text(text)
        err = _error(runner, "lint", str(UR10E_XRDF), "--config", str(cfg))
        assert err.startswith(f"error: {cfg}{where.split(' ', 1)[0]} "), err
        assert where.split(" ", 1)[1] in err


def test_configuration_file_errors_point_at_the_row(runner: CliRunner, tmp_path: Path) -> None:
    configs = tmp_path / "configs.yaml"
    configs.write_text("configurations:\n  - [0, 0, 0, 0, 0, 0]\n  - [0, 0, x, 0, 0, 0]\n")
    err = _error(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(configs)
    )
    assert err.startswith(f"error: {configs}:3:") and "configuration 1" in err, err
    configs.write_text("configurations:\n  a: 1\n")
    err = _error(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(configs)
    )
    assert err.startswith(f"error: {configs}:2:") and "expected a list" in err, err
    configs.write_text("")
    err = _error(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(configs)
    )
    assert err.startswith(f"error: {configs}:1: expected a list") and "file is empty" in err, err
    as_json = tmp_path / "configs.json"
    as_json.write_text('\n\n{"a": 1}\n')
    err = _error(
        runner, "report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--configs", str(as_json)
    )
    assert err.startswith(f"error: {as_json}:3: expected a list"), err


def test_an_unknown_xacro_substitution_is_located_and_said_once(
    runner: CliRunner, tmp_path: Path
) -> None:
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="length" default="0.3"/>\n'
        '  <link name="a"><visual><geometry><box size="$(tool0 length) 1 1"/></geometry>'
        "</visual></link>\n</robot>\n"
    )
    col = top.read_text().splitlines()[3].index("$(tool0") + 1
    err = _error(runner, "expand", str(top))
    assert err.startswith(f"error: {top}:4:{col}: xacro failed: Unknown substitution command"), err
    assert err.count("Unknown substitution command") == 1 and "<class" not in err, err


def test_xacro_syntax_errors_point_into_the_file_that_has_them(
    runner: CliRunner, tmp_path: Path
) -> None:
    top = tmp_path / "top.urdf.xacro"
    inc = tmp_path / "inc.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="inc.xacro"/>\n  <link name="a"/>\n</robot>\n'
    )
    inc.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="b"><\n</robot>\n'
    )
    err = _error(runner, "expand", str(top))
    assert err.startswith(f"error: {inc}:3:19: xacro failed: not valid XML: not well-formed"), err
    top.write_text(top.read_text().replace('<link name="a"/>', '<link name="a">'))
    err = _error(runner, "expand", str(top))
    assert err.startswith(f"error: {top}:5:3: xacro failed: not valid XML: mismatched tag"), err


def test_a_macro_body_error_points_into_the_include_and_names_an_unprefixed_property(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A macro defined in an include fails where it is called, but the expression it quotes
    is written in the include: the error points there. ROS 1 descriptions define properties
    by ``<property>`` without the ``xacro:`` prefix, which xacro 2 ignores: the error says
    where and what to write."""
    top = tmp_path / "top.urdf.xacro"
    inc = tmp_path / "arm.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="arm.xacro"/>\n  <link name="base"/>\n'
        '  <xacro:arm parent="base"/>\n</robot>\n'
    )
    inc.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <property name="pan_rpy" value="0 3.14 0"/>\n'
        '  <xacro:macro name="arm" params="parent">\n'
        '    <link name="arm"/>\n'
        '    <joint name="pan" type="fixed"><parent link="${parent}"/><child link="arm"/>\n'
        '      <origin rpy="${pan_rpy}"/></joint>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    err = _error(runner, "expand", str(top))
    assert err.startswith(f"error: {inc}:7:20: xacro failed: name 'pan_rpy' is not defined"), err
    assert err.endswith(
        f"({inc}:3 defines it by <property> without the xacro: prefix, which xacro 2 no "
        "longer reads: write <xacro:property> there)"
    ), err
    inc.write_text(inc.read_text().replace("<property", "<xacro:property"))
    assert runner.invoke(app, ["expand", str(top)]).exit_code == 0


def test_an_unprefixed_macro_is_named_where_its_parameter_is_undefined(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A ROS 1 ``<macro>`` without the ``xacro:`` prefix is plain XML to xacro 2: its body's
    ``${joint}`` names a parameter nothing defines (Toyota HSR's description). The error says
    which macro takes it and what to write."""
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base"/>\n'
        '  <macro name="wheel" params="joint parent">\n'
        '    <link name="${joint}_link"/>\n'
        "  </macro>\n</robot>\n"
    )
    err = _error(runner, "expand", str(robot))
    assert "name 'joint' is not defined" in err, err
    assert err.endswith(
        f"({robot}:4 takes it as a <macro> parameter without the xacro: prefix, which xacro 2 "
        "no longer reads: write <xacro:macro> there)"
    ), err


def test_a_macro_of_an_unprefixed_include_is_unknown_and_the_include_is_named(
    runner: CliRunner, tmp_path: Path
) -> None:
    """The Fuerte-era youBot description includes its parts by ``<include>`` (no ``xacro:``
    prefix), which xacro 2 leaves as plain XML: the macros those files define are unknown
    where they are called, with no word on why. The error names the include; a macro defined
    by an unprefixed ``<macro>`` is named likewise."""
    robot = tmp_path / "r.urdf.xacro"
    (tmp_path / "base.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="base"><link name="base"/></xacro:macro>\n</robot>\n'
    )
    robot.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <include filename="base.xacro"/>\n'
        "  <xacro:base/>\n</robot>\n"
    )
    err = _error(runner, "expand", str(robot))
    assert "unknown macro name: xacro:base" in err, err
    assert err.endswith(
        f"({robot}:3 includes a file by <include> without the xacro: prefix, which xacro 2 "
        "no longer reads: write <xacro:include> there)"
    ), err
    robot.write_text(robot.read_text().replace("<include", "<xacro:include"))
    assert runner.invoke(app, ["expand", str(robot)]).exit_code == 0
    robot.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <macro name="base"><link name="base"/></macro>\n'
        "  <xacro:base/>\n</robot>\n"
    )
    err = _error(runner, "expand", str(robot))
    assert err.endswith(
        f"({robot}:3 defines it by <macro> without the xacro: prefix, which xacro 2 no longer "
        "reads: write <xacro:macro> there)"
    ), err


def _urdf_with(tmp_path: Path, old: str, new: str) -> Path:
    text = UR10E_URDF.read_text()
    assert old in text
    out = tmp_path / "robot.urdf"
    out.write_text(text.replace(old, new, 1))
    return out


def test_urdf_numbers_yourdfpy_parses_are_checked_with_their_line(
    runner: CliRunner, tmp_path: Path
) -> None:
    text = UR10E_URDF.read_text()
    mass = next(x for x in text.splitlines() if "<mass value=" in x).strip()
    u = _urdf_with(tmp_path, mass, '<mass value="heavy"/>')
    line = _line_of(u, 'mass value="heavy"')
    err = _error(runner, "convert", str(u), "-o", str(tmp_path / "out.xrdf"))
    assert err == (
        f"error: {u}:{line}: link 'base_link_inertia' <inertial> <mass> value='heavy' is not a "
        "number"
    ), err


def test_an_unknown_geometry_is_located_and_invisible_characters_are_escaped(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    text = UR10E_URDF.read_text()
    geometry = next(x for x in text.splitlines() if "<mesh filename=" in x).strip()
    u = _urdf_with(tmp_path, geometry, '<spher\ufeffe radius="0.1"/>')
    line = _line_of(u, "<spher")
    err = _error(runner, "convert", str(u), "-o", str(tmp_path / "out.xrdf"))
    assert err.startswith(f"error: {u}:{line}: link 'base_link_inertia' <visual> <geometry> ")
    assert "holds <spher\\ufeffe>; a URDF geometry is one of <box>" in err and "\ufeff" not in err


def test_a_second_root_link_is_located(runner: CliRunner, tmp_path: Path) -> None:
    u = _urdf_with(tmp_path, '<parent link="base_link"/>', '<parent link="floating"/>')
    u.write_text(u.read_text().replace("</robot>", '  <link name="floating"/>\n</robot>'))
    x = tmp_path / "robot.xrdf"
    x.write_text(re.sub(r"modifiers:\n(  - .*\n)+", "", UR10E_XRDF.read_text()))
    err = _error(runner, "report", str(x), "--urdf", str(u), "-n", "10")
    assert re.match(rf"^error: {re.escape(str(u))}:\d+: 2 links have no parent joint", err), err


def test_a_bad_byte_in_a_xacro_file_is_located(runner: CliRunner, tmp_path: Path) -> None:
    x = tmp_path / "bad.urdf.xacro"
    x.write_bytes(b'<robot name="r">\n <link name="\xff"/>\n</robot>\n')
    assert _error(runner, "expand", str(x)) == (
        f"error: {x}:2:14: xacro file is not UTF-8 text (byte 0xff: invalid start byte)"
    )


def test_a_bad_byte_in_an_included_xacro_file_is_located(runner: CliRunner, tmp_path: Path) -> None:
    """A Fusion 360 export (fusion2urdf's Assem1) writes its joint names in GBK in the top
    file and in the included Assem1.trans: the top file's byte was located, the include's was
    Python's "'utf-8' codec can't decode byte 0xd0 in position 114" without a line."""
    top = tmp_path / "arm.xacro"
    top.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        ' <xacro:include filename="arm.trans"/>\n <link name="a"/>\n</robot>\n'
    )
    (tmp_path / "arm.trans").write_bytes(
        b'<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        b' <transmission name="\xd0\xfd1_tran"/>\n</robot>\n'
    )
    inc = tmp_path / "arm.trans"
    assert _error(runner, "expand", str(top)) == (
        f"error: {inc}:2:22: xacro file is not UTF-8 text (byte 0xd0: invalid continuation byte)"
    )


def test_write_mask_without_a_self_collision_section_names_the_xrdf(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = tmp_path / "robot.xrdf"
    text = UR10E_XRDF.read_text()
    x.write_text(text[: text.index("self_collision:")] + text[text.index("geometry:\n") :])
    err = _error(
        runner,
        "report",
        str(x),
        "--urdf",
        str(UR10E_URDF),
        "-n",
        "10",
        "--write-mask",
        str(tmp_path / "m"),
    )
    assert err.startswith(f"error: {x}:1: the XRDF has no self_collision section"), err


def test_xacro_evaluation_errors_point_at_what_they_quote(
    runner: CliRunner, tmp_path: Path
) -> None:
    """xacro keeps no positions; the name or expression its message quotes is found in the
    file it was processing."""
    x = tmp_path / "arm.urdf.xacro"
    head = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
    cases = {
        '  <xacro:property name="l" value="a"/>\n  <link name="${l / 2}"/>\n': (
            "3:15: xacro failed: unsupported operand type(s) for /: 'str' and 'int' when "
            "evaluating expression 'l / 2'"
        ),
        '  <link name="a"/>\n  <xacro:nope/>\n': (
            "3:3: xacro failed: unknown macro name: xacro:nope"
        ),
        '  <xacro:property name="1 2" value="3"/>\n': (
            "2:19: xacro failed: Property names must be valid python identifiers: 1 2"
        ),
        '  <link name="$(arg kind)"/>\n': (
            "2:15: xacro failed: Undefined substitution argument kind "
            "(pass --xacro-arg kind:=VALUE)"
        ),
    }
    for body, where in cases.items():
        x.write_text(head + body + "</robot>\n")
        assert _error(runner, "expand", str(x)) == f"error: {x}:{where}"


def test_fuzz_seed3_case583_a_collision_without_geometry(runner: CliRunner, tmp_path: Path) -> None:
    u = _urdf_with(tmp_path, "</collision>", "</collision>\n    <collision/>")
    line = _line_of(u, "<collision/>")
    err = _error(runner, "convert", str(u), "-o", str(tmp_path / "out.xrdf"))
    assert err == f"error: {u}:{line}: link 'base_link_inertia' <collision> has no <geometry>"


def test_fuzz_seed3_case860_an_escaped_expression_is_found(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = tmp_path / "arm.urdf.xacro"
    x.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="a"><visual><geometry><sphere radius="${&amp; / 2}"/></geometry>'
        "</visual></link>\n</robot>\n"
    )
    err = _error(runner, "expand", str(x))
    assert err.startswith(f"error: {x}:2:52: xacro failed: ") and "'& / 2'" in err, err


def test_fuzz_seed11_case917_an_unterminated_expression_is_found(
    runner: CliRunner, tmp_path: Path
) -> None:
    x = tmp_path / "arm.urdf.xacro"
    x.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="${pare"/>\n</robot>\n'
    )
    assert (
        _error(runner, "expand", str(x))
        == f"error: {x}:2:15: xacro failed: invalid expression: ${{pare"
    )


def test_an_unreadable_urdf_named_by_the_lint_config_points_at_the_entry(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "robot.xrdf").write_bytes(UR10E_XRDF.read_bytes())
    cfg = tmp_path / ".xrdf-lint.yaml"
    cfg.write_text('rules:\n  curobo-: off\nurdf:\n  "*.xrdf": missing.urdf\n')
    monkeypatch.chdir(tmp_path)
    err = _error(runner, "lint", "robot.xrdf")
    assert err.startswith(f"error: {cfg}:4:13: the URDF this entry names cannot be read: "), err
    assert "missing.urdf" in err


def _xacro(tmp_path: Path, body: str) -> Path:
    x = tmp_path / "arm.urdf.xacro"
    x.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n' + body + "</robot>\n"
    )
    return x


def test_fuzz_seed0_cases_2198_5167_8858_more_xacro_errors_are_located(
    runner: CliRunner, tmp_path: Path
) -> None:
    cases = {
        '  <xacro:property name="" value="1"/>\n': (
            "2:19: xacro failed: Property names must be valid python identifiers:"
        ),
        '  <link name="a"><visual><geometry><sphere radius="${}"/></geometry></visual></link>\n': (
            "2:52: xacro failed: invalid syntax (<expression>, line 0) when evaluating "
            "expression ''"
        ),
        '  <xacro:macro name="m"><link name="a"/></xacro:macro>\n  <xacro:macro params="x"/>\n': (
            "3:3: xacro failed: xacro:macro: missing attribute 'name'"
        ),
    }
    for body, where in cases.items():
        x = _xacro(tmp_path, body)
        assert _error(runner, "expand", str(x)) == f"error: {x}:{where}"


def test_fuzz_seed0_cases_4464_7935_8887_joint_limits_without_their_mapping(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    from tests.paths import FIXTURES

    limits = tmp_path / "joint_limits.yaml"
    demo = FIXTURES / "demo_arm"
    for text, where in (
        ("joint_limits: 5\n", ":1:15:"),
        ("# nothing\n", ":1:"),
        ("a: 1\n", ":1:1:"),
    ):
        limits.write_text(text)
        err = _error(runner,
            "convert", str(demo / "demo_arm.urdf"), "--joint-limits", str(limits), "-o",
            str(tmp_path / "o.xrdf"),
        )  # fmt: skip
        assert err.startswith(f"error: {limits}{where} a MoveIt joint limits file needs"), err


def test_fuzz_seed0_case7652_viz_without_a_collision_section_names_the_xrdf(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    x = tmp_path / "robot.xrdf"
    text = UR10E_XRDF.read_text()
    x.write_text(text[: text.index("world_collision:")])
    err = _error(runner, "viz", str(x), "--urdf", str(UR10E_URDF), "--png", str(tmp_path / "v.png"))
    assert err.startswith(f"error: {x}:1: no collision section names a geometry group"), err
    assert "no spheres to draw; fit them with `xrdf spheres" in err and "--group" not in err


@pytest.mark.parametrize(
    ("mimic", "message"),
    [
        ('<mimic joint="j8"/>', "joint 'j1' mimics 'j8', which is not a joint"),
        ('<mimic joint="j1"/>', "mimic joints form a loop: j1 -> j1"),
    ],
)
def test_convert_blames_a_urdf_no_reader_loads_at_its_line(
    runner: CliRunner, tmp_path: Path, mimic: str, message: str
) -> None:
    """Not a lint finding located in an XRDF that is never written: the URDF's own line,
    exit 2, before any work."""
    from tests.xrdf.test_real_xrdf_patterns import _chain_urdf

    urdf = _chain_urdf(tmp_path, 2, mimic=mimic)
    out = tmp_path / "robot.xrdf"
    err = _error(runner, "convert", str(urdf), "--joints", "j0", "-o", str(out))
    line = _line_of(urdf, 'name="j1"')
    assert err.startswith(f"error: {urdf}:{line}: ") and message in err, err
    assert not out.exists()


def test_a_yaml_file_given_as_the_robot_says_which_file_goes_where(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A cuRobo config or an XRDF passed where the URDF goes is named for what it is (the
    config with its urdf_path and the --curobo spelling), not 'malformed XML'."""
    cfg = tmp_path / "arm.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    urdf_path: robot/arm/arm.urdf\n"
        "    cspace:\n      joint_names: [j1]\n"
    )
    err = _error(runner, "convert", str(cfg))
    assert err.startswith(f"error: {cfg}:1:1: a cuRobo robot config, not a URDF"), err
    assert "'robot/arm/arm.urdf'" in err and "--curobo arm.yml" in err
    err = _error(runner, "export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_XRDF))
    assert err.startswith(f"error: {UR10E_XRDF}:1:1: an XRDF file, not a URDF"), err
    other = tmp_path / "other.yml"
    other.write_text("a: 1\n")  # YAML, but neither: the XML parser's own message
    assert "malformed XML" in _error(runner, "convert", str(other))


@pytest.mark.parametrize(
    "name, data",
    [
        ("robot.usda", b'#usda 1.0\n(\n    defaultPrim = "robot"\n)\n'),
        ("robot.usd", b"PXR-USDC" + bytes(88)),
        ("robot.usdz", b"PK\x03\x04" + bytes(60)),
    ],
)
def test_a_usd_stage_given_as_the_robot_is_named_for_what_it_is(
    runner: CliRunner, tmp_path: Path, name: str, data: bytes
) -> None:
    """Isaac Sim's robots come as USD stages: given where the URDF goes, the error was the XML
    parser's 'malformed XML: Start tag expected'."""
    usd = tmp_path / name
    usd.write_bytes(data)
    err = _error(runner, "inspect", str(usd))
    assert err.startswith(f"error: {usd}:1:1: a USD stage (Isaac Sim), not a URDF"), err
    assert "USD to URDF Exporter" in err and len(err.splitlines()) == 1, err


def test_an_include_that_cannot_be_read_is_located_at_its_include_tag(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A package path pointing at the wrong directory makes an include unreadable: the error
    names the file and points at the ``<xacro:include>`` in the file that includes it (here
    an include itself), not at the top file without a line."""
    top = tmp_path / "top.urdf.xacro"
    (tmp_path / "inc").mkdir()
    inc = tmp_path / "inc" / "arm.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="a"/>\n  <xacro:include filename="inc/arm.xacro"/>\n</robot>\n'
    )
    inc.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        "  <!-- includes the arm_macro.xacro below -->\n"
        '  <xacro:include filename="../other.xacro"/>\n'
        '  <xacro:include filename="$(find arm_pkg)/urdf/arm_macro.xacro"/>\n</robot>\n'
    )
    (tmp_path / "other.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"/>')
    wrong = tmp_path / "wrong"
    wrong.mkdir()
    err = _error(runner, "expand", str(top), "--package-path", f"arm_pkg={wrong}")
    missing = wrong / "urdf" / "arm_macro.xacro"
    assert err == f"error: {inc}:5:28: xacro failed: the included file {missing} does not exist", (
        err
    )


def test_an_arg_used_before_its_default_is_declared_says_so(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Flexiv's rizon.urdf.xacro names its robot ``$(arg name)`` and declares the default
    inside ``<robot>``: xacro evaluates the root's attributes first, so the default is not
    known yet (its launch file passes the name). The error says why the default did not
    count; an arg without a default gets no such note."""
    x = tmp_path / "rizon.urdf.xacro"
    x.write_text(
        '<?xml version="1.0"?>\n'
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="$(arg name)">\n'
        '  <xacro:arg name="name" default="rizon"/>\n  <link name="base"/>\n</robot>\n'
    )
    assert _error(runner, "expand", str(x)) == (
        f"error: {x}:2:58: xacro failed: Undefined substitution argument name (pass "
        "--xacro-arg name:=VALUE); line 3 declares a default for it, but xacro evaluates it "
        "here before reading that declaration"
    )
    assert runner.invoke(app, ["expand", str(x), "--xacro-arg", "name:=r"]).exit_code == 0
    x.write_text(x.read_text().replace('<xacro:arg name="name" default="rizon"/>', ""))
    assert _error(runner, "expand", str(x)).endswith("(pass --xacro-arg name:=VALUE)")


def test_a_macro_call_with_a_parameter_the_macro_lacks_points_at_that_call(
    runner: CliRunner, tmp_path: Path
) -> None:
    """ros2_kortex's kortex_robot.xacro passes gripper= to the Gen3 lite's load_arm, which
    has no such parameter; the top file passes gripper= too, legitimately, to load_robot.
    The error points at the load_arm call in the include and names the macro."""
    top = tmp_path / "robot.xacro"
    inc = tmp_path / "kortex_robot.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://ros.org/wiki/xacro">\n'
        '  <xacro:include filename="kortex_robot.xacro"/>\n  <link name="world"/>\n'
        '  <xacro:load_robot parent="world"\n      gripper="2f"/>\n</robot>\n'
    )
    inc.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://ros.org/wiki/xacro">\n'
        '  <xacro:macro name="load_arm" params="parent">\n'
        '    <link name="arm"/>\n'
        '    <joint name="j" type="fixed"><parent link="${parent}"/><child link="arm"/></joint>\n'
        "  </xacro:macro>\n"
        '  <xacro:macro name="load_robot" params="parent gripper">\n'
        '    <xacro:load_arm parent="${parent}"\n      gripper="${gripper}"/>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    assert _error(runner, "expand", str(top)) == (
        f'error: {inc}:8:5: xacro failed: Invalid parameter "gripper" in a call of macro '
        "'load_arm', which has no parameter 'gripper'"
    )


def _macro_robot(tmp_path: Path) -> tuple[Path, Path]:
    """A xacro robot whose links a macro of an included file makes, one with a missing mesh."""
    top = tmp_path / "robot.urdf.xacro"
    inc = tmp_path / "arm_macro.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="arm_macro.xacro"/>\n  <link name="world"/>\n'
        '  <xacro:arm prefix="left_" parent="world"/>\n</robot>\n'
    )
    inc.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:macro name="arm" params="prefix parent">\n'
        '  <link name="${prefix}base"><collision><geometry><box size="0.1 0.1 0.1"/>'
        "</geometry></collision></link>\n"
        '  <joint name="${prefix}j1" type="revolute"><parent link="${parent}"/>'
        '<child link="${prefix}base"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        "</joint>\n"
        '  <link\n    name="${prefix}base_link">\n'
        '    <collision><geometry><mesh filename="meshes/gone.stl"/></geometry></collision>\n'
        "  </link>\n"
        '  <joint name="${prefix}j2" type="revolute"><parent link="${prefix}base"/>'
        '<child link="${prefix}base_link"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        "</joint>\n"
        "</xacro:macro>\n</robot>\n"
    )
    return top, inc


def test_links_a_macro_makes_are_located_in_the_file_that_writes_them(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Errors and warnings about a link made by a macro of an included file point at the
    macro's ``<link name="${prefix}…">`` (the closest template: ``${prefix}base_link`` for
    left_base_link, not ``${prefix}base``), not at the top file without a line."""
    from xrdf_tools.robot.xacro_source import load_robot

    top, inc = _macro_robot(tmp_path)
    robot = load_robot(top)
    assert robot.place("link", "world") == (str(top), 4)
    assert robot.place("link", "left_base") == (str(inc), 4)
    assert robot.place("link", "left_base_link") == (str(inc), 6)
    assert robot.place("joint", "left_j2") == (str(inc), 10)
    out = tmp_path / "out.xrdf"
    err = _error(runner, "convert", str(top), "--fit-spheres", "-o", str(out))
    assert err.startswith(f"error: {inc}:6: 1 mesh file(s) cannot be found: link 'left_base_link'")
    assert not out.exists()
    result = runner.invoke(
        app, ["convert", str(top), "--fit-spheres", "--allow-missing-meshes", "-o", str(out)]
    )
    assert result.exit_code == 0, result.output
    warned = [line for line in result.output.splitlines() if "spheres-mesh-unreadable" in line]
    assert warned and all(line.startswith(f"{inc}:6: ") for line in warned), result.output
