"""`xrdf convert ... --fit-spheres`: one command from meshes to a planning-ready XRDF.

The real-robot tests run the command as a user would and then check the result with
`xrdf report` and `xrdf lint`: neither may find an error. The small synthetic robot checks
the library call (:func:`xrdf_tools.convert.pipeline.convert_robot`) quickly.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robot_urdf, robots_dir
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot
from xrdf_tools.diagnostics import Severity
from xrdf_tools.lint import lint_text
from xrdf_tools.report import self_collision_report
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.spheres.geometry import load_link_geometry
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import Xrdf

# A base, two links with collision boxes and one link with a visual box only.
BOXES = """<robot name="boxes">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="upper">
    <collision><origin xyz="0 0 0.15"/><geometry><box size="0.06 0.06 0.3"/></geometry></collision>
  </link>
  <link name="lower">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.2"/></geometry></collision>
  </link>
  <link name="camera"><visual><geometry><box size="0.05 0.05 0.05"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="cam" type="fixed"><parent link="base"/><child link="camera"/>
    <origin xyz="0.1 0 0.1"/></joint>
</robot>
"""


def _check_with_report_and_lint(
    runner: CliRunner, xrdf: Path, urdf: Path, samples: int = 3000, extra: tuple[str, ...] = ()
) -> None:
    """`xrdf report` and `xrdf lint` on the written XRDF: exit 0 and no error."""
    rep = runner.invoke(
        app, ["report", str(xrdf), "--urdf", str(urdf), "-n", str(samples), "-f", "json", *extra]
    )
    assert rep.exit_code == 0, rep.output
    data = json.loads(rep.stdout)
    assert [d for d in data["diagnostics"] if d["severity"] == "error"] == []
    assert data["default_ok"]
    lint = runner.invoke(app, ["lint", str(xrdf), "--urdf", str(urdf), "-f", "json", *extra])
    assert lint.exit_code == 0, lint.output
    found = json.loads(lint.stdout)["diagnostics"]
    assert [d for d in found if d["severity"] == "error"] == []


# --------------------------------------------------------------------------------------------
# The library call on a small robot
# --------------------------------------------------------------------------------------------
@pytest.fixture
def boxes(tmp_path: Path) -> Path:
    p = tmp_path / "boxes.urdf"
    p.write_text(BOXES)
    return p


def test_convert_robot_fits_masks_and_lints_clean(boxes: Path) -> None:
    result = convert_robot(
        boxes,
        ConvertOptions(),
        fit=FitOptions(per_link=2),
        mask=MaskOptions(samples=500),
    )
    x = result.xrdf
    spheres = x.world_collision_spheres()
    # collision geometry only: the visual-only camera gets no spheres
    assert set(spheres) == {"base", "upper", "lower"} == set(result.fitted)
    rules = {d.rule: d for d in result.diagnostics}
    assert "convert-no-spheres" not in rules
    fitted = rules["convert-fitted-spheres"].message
    assert "6 sphere(s) to 3 link(s)" in fitted and "camera" in fitted and "--from visual" in fitted
    mask = rules["convert-computed-mask"].message
    assert "500 uniform samples" in mask and "adjacent" in mask
    # adjacent pairs (joined by a joint) are masked, as `report --write-mask` does
    assert x.self_collision is not None
    assert x.self_collision.is_ignored("base", "upper")
    assert x.self_collision.is_ignored("upper", "lower")
    assert result.report is not None and result.report.samples == 500
    assert result.lint_errors == []
    # the mask is a fixed point: the same report on the result recommends no change
    again = self_collision_report(result.robot, x, samples=500, seed=0)
    assert again.mask_change.empty


def test_from_visual_fits_visual_only_links(boxes: Path) -> None:
    result = convert_robot(
        boxes, ConvertOptions(), fit=FitOptions(source="visual", per_link=1), mask=MaskOptions(200)
    )
    assert set(result.fitted) == {"camera"}  # the only link with visual geometry
    auto = convert_robot(
        boxes, ConvertOptions(), fit=FitOptions(source="auto", per_link=1), mask=MaskOptions(200)
    )
    assert set(auto.fitted) == {"base", "upper", "lower", "camera"}


def test_geometry_source_choice(boxes: Path) -> None:
    col, _ = load_link_geometry(boxes, source="collision")
    vis, _ = load_link_geometry(boxes, source="visual")
    auto, diags = load_link_geometry(boxes)
    assert set(col) == {"base", "upper", "lower"}
    assert set(vis) == {"camera"}
    assert set(auto) == {"base", "upper", "lower", "camera"}
    assert [d.rule for d in diags] == ["spheres-visual-fallback"]


def test_fit_uses_the_expanded_xacro_with_its_arguments(runner: CliRunner, tmp_path: Path) -> None:
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(XACRO)  # the small two-link xacro defined below
    result = convert_robot(
        robot,
        ConvertOptions(),
        xacro_args={"prefix": "z_"},
        fit=FitOptions(per_link=1),
        mask=MaskOptions(200),
    )
    assert set(result.fitted) == {"z_base", "z_tip"}
    assert result.lint_errors == []
    cli = runner.invoke(
        app,
        ["convert", str(robot), "--xacro-arg", "prefix:=q_", "--fit-spheres", "-n", "200"],
    )
    assert cli.exit_code == 0, cli.output
    assert "q_tip:" in cli.stdout and "a_tip" not in cli.stdout


def test_lint_reads_the_given_urdf_object(boxes: Path) -> None:
    result = convert_robot(
        boxes, ConvertOptions(), fit=FitOptions(per_link=1), mask=MaskOptions(200)
    )
    model = load_urdf(boxes)
    assert lint_text(result.text, "<x>", urdf_model=model) == lint_text(
        result.text, "<x>", urdf=boxes
    )


def test_cli_summary_and_options(runner: CliRunner, boxes: Path, tmp_path: Path) -> None:
    out = tmp_path / "boxes.xrdf"
    r = runner.invoke(
        app,
        [
            *("convert", str(boxes), "--joints", "j1,j2", "--fit-spheres", "-n", "300"),
            *("-o", str(out), "-v"),
        ],
    )
    assert r.exit_code == 0, r.output
    assert "convert-fitted-spheres" in r.output and "convert-computed-mask" in r.output
    # -v without a terminal (a CI log): a line per step of the fit, naming its link
    steps = [ln for ln in r.stderr.splitlines() if ln.startswith("fitting spheres (2 steps")]
    assert steps and steps[-1].endswith(f": {len(steps)}/{len(steps)} lower")
    x = load_xrdf(out)
    assert x.cspace is not None and list(x.cspace.joint_names) == ["j1", "j2"]
    assert x.tool_frames == ("lower",)
    _check_with_report_and_lint(runner, out, boxes, samples=300)


def test_verbose_off_a_terminal_prints_a_line_per_tenth_of_the_mask_sampling(
    runner: CliRunner, boxes: Path, tmp_path: Path
) -> None:
    """A CI log of `convert --fit-spheres -v` follows the sampling as `report -v` does (it
    printed only the last step: the sample comes in chunks, never one configuration apart)."""
    r = runner.invoke(
        app,
        [
            *("convert", str(boxes), "--joints", "j1,j2", "--fit-spheres", "--per-link", "1"),
            *("-n", "50000", "-o", str(tmp_path / "boxes.xrdf"), "-v"),
        ],
    )
    assert r.exit_code == 0, r.output
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("sampling the mask: ")]
    assert [ln.split()[3] for ln in lines] == [str(p) for p in range(10, 101, 10)], r.stderr
    assert "(50,000/50,000)" in lines[-1]


# --------------------------------------------------------------------------------------------
# Real robots with meshes
# --------------------------------------------------------------------------------------------
def _srdf(name: str) -> Path:
    root = robots_dir()
    assert root is not None
    return root / name


#: The one command, small enough for CI: three spheres a link, 3,000 samples for the mask.
FAST_FIT = ("--fit-spheres", "--per-link", "3", "-n", "3000")


def _one_command(runner: CliRunner, out: Path, *args: str) -> tuple[Xrdf, str]:
    """Run ``xrdf convert ARGS --fit-spheres … -o OUT``; the XRDF written and the output."""
    r = runner.invoke(app, ["convert", *args, *FAST_FIT, "-o", str(out)])
    assert r.exit_code == 0, r.output
    return load_xrdf(out), r.output


@pytest.mark.slow
def test_panda_from_srdf(runner: CliRunner, tmp_path: Path) -> None:
    urdf = robot_urdf("panda")
    srdf = _srdf("panda_description/srdf/panda.srdf")
    out = tmp_path / "panda.xrdf"
    x, output = _one_command(runner, out, str(urdf), "--srdf", str(srdf))
    assert "planning group 'arm' chosen" in output
    assert len(x.world_collision_spheres()) == 11  # every link with collision geometry
    _check_with_report_and_lint(runner, out, urdf)


def _rtb_xacro() -> Path:
    spec = importlib.util.find_spec("rtbdata")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("rtb-data is not installed")
    root = Path(next(iter(spec.submodule_search_locations))) / "xacro" / "trossen_descriptions"
    if not root.is_dir():
        pytest.skip("rtb-data has no trossen_descriptions")
    return root


@pytest.mark.slow
def test_xacro_only_robot_with_xacro_arg(runner: CliRunner, tmp_path: Path) -> None:
    pkg = _rtb_xacro()
    robot = pkg / "urdf" / "px150.urdf.xacro"
    out = tmp_path / "px150.xrdf"
    x, _ = _one_command(
        runner,
        out,
        str(robot),
        "--package-path",
        f"trossen_descriptions={pkg}",
        "--xacro-arg",
        "robot_name:=px150",
        "--chain",
        "px150/base_link:px150/ee_arm_link",
    )
    assert x.cspace is not None
    assert list(x.cspace.joint_names) == [
        "waist",
        "shoulder",
        "elbow",
        "wrist_angle",
        "wrist_rotate",
    ]
    assert x.tool_frames == ("px150/ee_arm_link",)
    # the spheres were fitted to the expansion with robot_name:=px150
    assert x.world_collision_spheres() and all(
        f.startswith("px150/") for f in x.world_collision_spheres()
    )
    # report and lint read the xacro with the same arguments (no expanded copy needed)
    extra = ("--xacro-arg", "robot_name:=px150", "--package-path", f"trossen_descriptions={pkg}")
    _check_with_report_and_lint(runner, out, robot, extra=extra)


@pytest.mark.slow
def test_pr2_mobile_manipulator_two_arms(runner: CliRunner, tmp_path: Path) -> None:
    """PR2: a mobile base with visual-only links, both arms in one c-space from two groups."""
    urdf = robot_urdf("pr2")
    srdf = _srdf("pr2_description/srdf/pr2.srdf")
    out = tmp_path / "pr2.xrdf"
    x, output = _one_command(
        runner, out, str(urdf), "--srdf", str(srdf), "--group", "left_arm", "--group", "right_arm"
    )
    assert x.cspace is not None
    names = list(x.cspace.joint_names)
    assert len(names) == 14 and names[0].startswith("l_") and names[-1].startswith("r_")
    assert x.tool_frames == ("l_wrist_roll_link", "r_wrist_roll_link")
    spheres = x.world_collision_spheres()
    model = load_urdf(urdf)
    visual_only = [n for n, link in model.link_map.items() if link.visuals and not link.collisions]
    assert visual_only and not set(visual_only) & set(spheres)
    assert "with visual geometry only get none" in output
    _check_with_report_and_lint(runner, out, urdf)


def test_cli_usage_errors_are_one_line_exit_2(runner: CliRunner, boxes: Path) -> None:
    for args, match in (
        (["--chain", "base"], "--chain expects BASE_LINK:TIP_LINK, got 'base'"),
        (["--joints", "j1", "--chain", "base:lower"], "not both"),
        (["--joints", "nope"], "--joints: 'nope' is not a joint"),
    ):
        r = runner.invoke(app, ["convert", str(boxes), *args])
        assert r.exit_code == 2, r.output
        assert match in r.output and "Traceback" not in r.output


XACRO = """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default="a_"/>
  <link name="$(arg prefix)base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry>
  </collision></link>
  <link name="$(arg prefix)tip"><collision><origin xyz="0 0 0.1"/><geometry>
  <box size="0.04 0.04 0.2"/></geometry></collision></link>
  <joint name="$(arg prefix)j" type="revolute"><parent link="$(arg prefix)base"/>
    <child link="$(arg prefix)tip"/><origin xyz="0 0 0.05"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"""


def test_every_command_reads_a_xacro_with_its_arguments(runner: CliRunner, tmp_path: Path) -> None:
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(XACRO)
    out = tmp_path / "r.xrdf"
    args = ["--xacro-arg", "prefix:=z_"]
    r = runner.invoke(
        app, ["convert", str(robot), *args, "--fit-spheres", "-n", "200", "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    _check_with_report_and_lint(runner, out, robot, samples=200, extra=tuple(args))
    # without the argument the frames do not exist: lint says so (the xacro default is a_)
    plain = runner.invoke(app, ["lint", str(out), "--urdf", str(robot)])
    assert plain.exit_code == 1 and "z_tip" in plain.output
    d = runner.invoke(app, ["diff", str(out), str(out), "--urdf", str(robot), *args])
    assert d.exit_code == 0, d.output
    png = tmp_path / "r.png"
    v = runner.invoke(app, ["viz", str(out), "--urdf", str(robot), *args, "--png", str(png)])
    assert v.exit_code == 0, v.output
    assert png.stat().st_size > 0
    expanded = tmp_path / "r.urdf"
    e = runner.invoke(app, ["expand", str(robot), *args, "-o", str(expanded)])
    assert e.exit_code == 0, e.output
    assert 'link name="z_tip"' in expanded.read_text()
    assert load_urdf(expanded).link_map.keys() == {"z_base", "z_tip"}
    again = runner.invoke(app, ["lint", str(out), "--urdf", str(expanded)])
    assert again.exit_code == 0, again.output
    sph = runner.invoke(app, ["spheres", str(robot), *args, "--per-link", "1"])
    assert sph.exit_code == 0, sph.output
    assert "z_tip:" in sph.stdout
    not_xacro = runner.invoke(app, ["expand", str(expanded)])
    assert not_xacro.exit_code == 2 and "not a xacro file" in not_xacro.output


def test_fit_spheres_on_a_robot_with_visual_geometry_only_is_an_input_error(
    tmp_path: Path,
) -> None:
    """A vendor URDF with <visual> meshes and no <collision> (Doosan's m1013.white.urdf):
    --fit-spheres would write an XRDF that checks no collision. It stops with exit 2, names
    the links and --from visual, and writes nothing; --from visual fits them."""
    visual_only = BOXES.replace("<collision>", "<visual>").replace("</collision>", "</visual>")
    urdf = tmp_path / "visual_only.urdf"
    urdf.write_text(visual_only)
    out = tmp_path / "out.xrdf"
    runner = CliRunner()
    res = runner.invoke(app, ["convert", str(urdf), "--fit-spheres", "-o", str(out)])
    assert res.exit_code == 2, res.output
    assert f"{urdf}: " in res.output and "4 link(s) have visual geometry only" in res.output
    assert "--from visual" in res.output and "Traceback" not in res.output
    assert not out.exists()
    ok = runner.invoke(
        app, ["convert", str(urdf), "--fit-spheres", "--from", "visual", "--per-link", "1",
              "--samples", "200", "-o", str(out)]
    )  # fmt: skip
    assert ok.exit_code == 0, ok.output
    assert set(load_xrdf(out).world_collision_spheres()) == {"base", "upper", "lower", "camera"}


TWO_PARTS = """<robot name="two_parts">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm">
    <collision><origin xyz="0 0 0.15"/><geometry><box size="0.06 0.06 0.3"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="spare"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="spare_arm">
    <collision><geometry><box size="0.05 0.05 0.2"/></geometry></collision>
  </link>
  <joint name="k1" type="revolute"><parent link="spare"/><child link="spare_arm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def test_fitting_leaves_out_the_urdf_parts_the_base_does_not_reach(tmp_path: Path) -> None:
    """A URDF with a second, disconnected part (as cuRobo's tri_ur10e.urdf): a cuRobo config's
    base_link chooses the robot, and --fit-spheres fits its links only; spheres on the other
    part would name frames the base removes, and lint would refuse the file."""
    urdf = tmp_path / "two_parts.urdf"
    urdf.write_text(TWO_PARTS)
    cfg = tmp_path / "two_parts.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base\n    ee_link: arm\n"
        "    cspace:\n      joint_names: [j1]\n      retract_config: [0.0]\n"
        "      max_acceleration: 10.0\n      max_jerk: 500.0\n"
    )
    result = convert_robot(
        urdf,
        ConvertOptions(curobo=cfg, target="curobo"),
        fit=FitOptions(per_link=2),
        mask=MaskOptions(samples=200),
    )
    assert sorted(result.xrdf.world_collision_spheres()) == ["arm", "base"]
    # no frame the base removes is named; the one pair of sphere frames is masked (adjacent),
    # which leaves cuRobo's self-collision check nothing to check: it raises, and lint says so
    errors = [d.rule for d in result.lint if d.severity is Severity.ERROR]
    assert errors == ["curobo-no-pair"]
    assert "convert-unreachable-links" in {d.rule for d in result.diagnostics}


def test_more_links_with_geometry_than_the_mask_checks_stop_before_the_fit(
    tmp_path: Path,
) -> None:
    """A URDF whose base carries hundreds of small marker links with collision boxes: the
    mask refuses more than MAX_SPHERE_FRAMES frames, so the command says so before fitting
    (exit 2, nothing written) instead of after fitting every marker."""
    from xrdf_tools.selfcollision.collision import MAX_SPHERE_FRAMES

    n = MAX_SPHERE_FRAMES
    markers = "".join(
        f'<link name="m{i}"><collision><geometry><box size=".01 .01 .01"/></geometry>'
        f'</collision></link><joint name="m{i}_fixed" type="fixed"><parent link="base"/>'
        f'<child link="m{i}"/><origin xyz="{0.3 + 0.01 * i} 0 0"/></joint>'
        for i in range(n)
    )
    urdf = tmp_path / "markers.urdf"
    urdf.write_text(BOXES.replace("</robot>", markers + "</robot>"))
    out = tmp_path / "out.xrdf"
    res = CliRunner().invoke(app, ["convert", str(urdf), "--fit-spheres", "-o", str(out)])
    assert res.exit_code == 2, res.output
    line = res.output.strip().splitlines()[-1]
    assert f"{n + 3:,} links would carry spheres" in line and f"at most {n:,}" in line
    assert "fitted" not in res.output and not out.exists()


# The second link folds back over the base: at the SRDF's 'folded' home it passes through it.
FOLDING = """<robot name="folding">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="upper">
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.04 0.04 0.1"/></geometry></collision>
  </link>
  <link name="lower">
    <collision><origin xyz="0 0 0.15"/><geometry><box size="0.04 0.04 0.3"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""
FOLDED_HOME = """<robot name="folding">
  <group name="arm"><joint name="j1"/><joint name="j2"/></group>
  <group_state name="home" group="arm"><joint name="j1" value="0"/><joint name="j2" value="3"/>
  </group_state>
</robot>
"""


def test_a_pair_masked_for_colliding_at_a_colliding_home_is_a_warning(tmp_path: Path) -> None:
    """A default pose in self-collision (a folded home, spheres reaching past a mesh) makes
    the Setup Assistant's rule ignore a pair that collides only there and near it: the
    planner no longer sees it. Convert says so, naming the pair; a home free of collision
    gives no such warning."""
    urdf, srdf = tmp_path / "folding.urdf", tmp_path / "folding.srdf"
    urdf.write_text(FOLDING)
    srdf.write_text(FOLDED_HOME)

    def run(home: str) -> tuple[Xrdf, dict[str, str]]:
        srdf.write_text(FOLDED_HOME.replace('value="3"', f'value="{home}"'))
        result = convert_robot(
            urdf,
            ConvertOptions(srdf=str(srdf)),
            fit=FitOptions(per_link=4),
            mask=MaskOptions(samples=400),
        )
        return result.xrdf, {d.rule: d.message for d in result.diagnostics}

    folded, rules = run("3")
    assert folded.self_collision is not None and folded.self_collision.is_ignored("base", "lower")
    warning = rules["convert-mask-default-pose"]
    assert "base/lower (apart in" in warning and "--state" in warning
    # a robot without an SRDF (the Stretch) has no --state: the XRDF's default and
    # `xrdf report --write-mask` are the way that works for it too
    assert "default_joint_positions, then `xrdf report" in warning and "--write-mask" in warning
    upright, rules = run("0")
    assert upright.self_collision is not None
    assert not upright.self_collision.is_ignored("base", "lower")
    assert "convert-mask-default-pose" not in rules


def test_a_cspace_that_moves_no_part_against_another_is_said(tmp_path: Path) -> None:
    """The Shadow Hand's default c-space is its two wrist joints: they turn the whole hand,
    no finger moves, so every pair is masked (adjacent or never colliding) and cuRobo's
    loader raises on the file. Convert only counted "0 pair(s) checked"; it now warns, counts
    the pairs the c-space moves and why each is ignored, and names the flags that change it.
    A c-space that folds the arm onto its base gives no such warning."""
    urdf = tmp_path / "folding.urdf"
    urdf.write_text(FOLDING)

    def rules(joints: tuple[str, ...]) -> dict[str, str]:
        result = convert_robot(
            urdf,
            ConvertOptions(joints=joints),
            fit=FitOptions(per_link=4),
            mask=MaskOptions(samples=400),
        )
        return {d.rule: d.message for d in result.diagnostics}

    turning = rules(("j1",))["convert-mask-nothing-checked"]
    assert "the c-space (1: j1) moves 2 of the 3 pair(s) relative to each other" in turning
    assert "ignores each of them (1 adjacent, 1 never colliding in the 400 samples)" in turning
    assert "(--joints, --chain or --group)" in turning
    assert "convert-mask-nothing-checked" not in rules(("j1", "j2"))


def test_without_fit_spheres_the_empty_group_says_what_fit_spheres_would_take(
    tmp_path: Path,
) -> None:
    """Drake's Jaco writes its collision geometry as 88 <sphere> elements: convert without
    --fit-spheres said "NO COLLISION SPHERES in the inputs" and listed --fit-spheres among
    other ways, as if there were nothing to start from. The warning now says --fit-spheres
    fits the collision geometry of the links that have it and takes <sphere> elements as
    they are."""
    urdf = tmp_path / "balls.urdf"
    urdf.write_text(
        """<robot name="balls">
  <link name="base"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="arm"><collision><geometry><sphere radius="0.04"/></geometry></collision></link>
</robot>"""
    )
    result = CliRunner().invoke(app, ["convert", str(urdf), "-o", str(tmp_path / "b.xrdf")])
    (line,) = [t for t in result.output.splitlines() if "convert-no-spheres" in t]
    assert "--fit-spheres: it fits them to the collision geometry of the URDF's 2 link(s)" in line
    assert "takes <sphere> elements as they are" in line
