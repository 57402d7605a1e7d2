"""cuRobo configs → XRDF → cuRobo's loader gives back the same robot; lint --target curobo agrees
with what cuRobo's loader does.

The model of cuRobo's loader (tests/curobo_loader.py) is written from the reader facts in
docs/format.md, rule by rule, and checked against cuRobo itself on real robots by
benchmarks/check_curobo_loader.py; these tests never run cuRobo.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
import yaml
from typer.testing import CliRunner

from tests.curobo_loader import SLOT, CuroboRejects, from_config, from_xrdf, loads_as_written
from tests.paths import FIXTURES, SEED_XRDF, SHARED, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.lint import lint_text
from xrdf_tools.xrdf.io import dump_xrdf

CLASSIC = FIXTURES / "curobo_classic"
REFERENCE = SHARED / "reference" / "curobo-2.0"

#: (config, URDF): our classic-layout fixtures and cuRobo's own configs (when shared/ is there).
CONFIGS = [
    (CLASSIC / "ur10e_classic.yml", UR10E_URDF),
    (CLASSIC / "ur10e_inline.yml", UR10E_URDF),
    (CLASSIC / "ur10e_real_patterns.yml", UR10E_URDF),
    (REFERENCE / "ur10e.yml", REFERENCE / "ur10e.urdf"),
    (REFERENCE / "franka.yml", REFERENCE / "franka_panda.urdf"),
]


def _pair(config: Path, urdf: Path) -> tuple[Path, Path]:
    if not config.exists() or not urdf.exists():
        pytest.skip(f"{config} not available")
    return config, urdf


@pytest.mark.parametrize(("config", "urdf"), CONFIGS, ids=lambda p: p.name)
def test_curobo_loads_the_converted_config_as_the_same_robot(config: Path, urdf: Path) -> None:
    config, urdf = _pair(config, urdf)
    x, diags, _ = convert_files(urdf, ConvertOptions(curobo=config))  # default options
    text = dump_xrdf(x)
    assert x.format_version == "1.0"
    loaded = from_xrdf(text, urdf)
    try:
        expected = from_config(config, urdf)
    except CuroboRejects:  # cuRobo cannot load the config itself (a misspelt collision link)
        assert [d for d in diags if d.rule == "convert-unknown-link"]
        assert loads_as_written(text, urdf)  # the XRDF, without the unknown link, loads
        return
    kin = yaml.safe_load(config.read_text())["robot_cfg"]["kinematics"]
    # without collision_link_names cuRobo loads none of the config's spheres; the XRDF keeps
    # them (every XRDF sphere frame is checked) and the converter says so
    unlisted = kin.get("collision_link_names") is None and bool(kin.get("collision_spheres"))
    said = [d for d in diags if "no collision_link_names" in d.message]
    assert len(said) == unlisted and (not unlisted or expected.spheres == {})
    # field by field, so a failure names what cuRobo would get wrong; a value the config does
    # not give (None) is a reported fallback of the converter
    for field in expected.__dataclass_fields__:
        if unlisted and field in ("spheres", "world_buffer", "ignore"):
            continue
        if getattr(expected, field) is not None:
            assert getattr(loaded, field) == getattr(expected, field), field
    assert loads_as_written(text, urdf)
    errors = [
        d
        for d in lint_text(text, "out.xrdf", urdf=urdf, target="curobo")
        if d.severity.value == "error"
        # the configs written for the test-suite carry spheres on a few links only: for a
        # planner the others are invisible, which lint rightly calls an error
        and not (config.parent == CLASSIC and d.rule == "mesh-without-spheres")
    ]
    assert errors == []


def test_the_attached_object_slots_survive_for_curobo() -> None:
    config, urdf = _pair(REFERENCE / "franka.yml", REFERENCE / "franka_panda.urdf")
    x, _, _ = convert_files(urdf, ConvertOptions(curobo=config))
    text = dump_xrdf(x)
    doc = yaml.safe_load(text)
    written = doc["geometry"][doc["collision"]["geometry"]]["spheres"]
    assert [s["radius"] for s in written["attached_object"]] == [-10.0] * 4  # as cuMotion's
    loaded = from_xrdf(text, urdf)  # four slots, as cuRobo makes from the config
    assert loaded.spheres["attached_object"] == (((0.0, 0.0, 0.0), SLOT),) * 4
    assert from_config(config, urdf).spheres["attached_object"] == loaded.spheres["attached_object"]


def test_a_2_0_file_does_not_load_in_curobo_and_lint_says_so(
    runner: CliRunner, tmp_path: Path
) -> None:
    x, diags, _ = convert_files(
        UR10E_URDF, ConvertOptions(curobo=CLASSIC / "ur10e_classic.yml", format_version="2.0")
    )
    text = dump_xrdf(x)
    with pytest.raises(CuroboRejects, match="collision_spheres"):  # its robot loader stops
        from_xrdf(text, UR10E_URDF)
    (version_note,) = [d for d in diags if d.rule == "convert-version"]
    assert "cuRobo and Isaac ROS cuMotion" in version_note.message
    out = tmp_path / "ur10e.xrdf"
    out.write_text(text)
    plain = runner.invoke(app, ["lint", str(out)])
    assert plain.exit_code == 0 and plain.output.count("curobo-format-version") == 1
    assert "warning curobo-format-version" in plain.output
    curobo = runner.invoke(app, ["lint", "--target", "curobo", str(out)])
    assert curobo.exit_code == 1 and "error curobo-format-version" in curobo.output
    for reader in ("cumotion", "isaac-sim"):
        r = runner.invoke(app, ["lint", "--target", reader, str(out)])
        assert r.exit_code == 0 and "curobo-" not in r.output, reader


def test_convert_for_curobo_refuses_2_0(runner: CliRunner, tmp_path: Path) -> None:
    r = runner.invoke(
        app,
        [
            "convert",
            str(UR10E_URDF),
            "--curobo",
            str(CLASSIC / "ur10e_classic.yml"),
            "--target",
            "curobo",
            "--format-version",
            "2.0",
            "-o",
            str(tmp_path / "x.xrdf"),
        ],
    )
    assert r.exit_code == 2 and "reads 1.0" in r.output and not (tmp_path / "x.xrdf").exists()
    r = runner.invoke(app, ["convert", str(UR10E_URDF), "--target", "cuRobo2"])
    assert r.exit_code == 2 and "unknown target" in r.output


def test_isaac_ros_is_curobos_reader(runner: CliRunner, tmp_path: Path) -> None:
    """Isaac ROS cuMotion loads an XRDF through cuRobo's reader: ``--target isaac_ros`` (as a
    user writes it) is ``curobo``, never the Isaac Sim editor that a spelling match suggests."""
    args = ["convert", str(UR10E_URDF), "--curobo", str(CLASSIC / "ur10e_classic.yml")]
    for name in ("isaac_ros", "Isaac-ROS", "isaac-ros-cumotion"):
        r = runner.invoke(app, [*args, "--target", name, "--format-version", "2.0"])
        assert r.exit_code == 2 and "reads 1.0" in r.output, name  # curobo's rule
    r = runner.invoke(app, [*args, "--target", "isaac_sim", "--format-version", "2.0"])
    assert r.exit_code == 0, r.output  # the Isaac Sim editor loads 2.0
    two = tmp_path / "two.xrdf"
    two.write_text(r.stdout)
    lint = runner.invoke(app, ["lint", "--target", "isaac_ros", str(two)])
    assert lint.exit_code == 1 and "error curobo-format-version" in lint.output
    wrong = runner.invoke(app, [*args, "--target", "isaac-rso"])
    assert wrong.exit_code == 2 and "did you mean 'isaac-ros'?" in wrong.output


def _mutations(text: str) -> dict[str, str]:
    """Variants of a cuRobo-loadable 1.0 file, each something cuRobo raises on or silently
    changes (or, for the last ones, accepts)."""
    data = yaml.safe_load(text)
    out: dict[str, str] = {}

    def variant(name: str, change: object) -> None:
        d = yaml.safe_load(text)
        change(d)  # type: ignore[operator]
        out[name] = yaml.safe_dump(d, sort_keys=False)

    variant("no tool_frames", lambda d: d.pop("tool_frames"))
    variant("no ignore", lambda d: d["self_collision"].pop("ignore"))
    variant("no self_collision", lambda d: d.pop("self_collision"))
    variant("no defaults", lambda d: d.pop("default_joint_positions"))
    variant("2.0", lambda d: d.update(format_version=2.0, world_collision=d.pop("collision")))
    variant("integer scalar buffer", lambda d: d["collision"].update(buffer_distance=0))
    variant("reordered c-space", lambda d: _reorder(d))
    variant("other self group", lambda d: d["self_collision"].update(geometry="other"))
    variant("no collision", lambda d: d.pop("collision"))
    variant("ignore as a list", lambda d: d["self_collision"].update(ignore=[]))
    variant("scalar self buffer", lambda d: d["self_collision"].update(buffer_distance=0.01))
    variant("joints below every frame", _only_the_upper_arm)
    # accepted by cuRobo: integers in per-frame buffers and lists, a float scalar buffer
    variant(
        "integer per-frame buffer",
        lambda d: d["collision"].update(buffer_distance={"shoulder_link": 0}),
    )
    variant("float scalar buffer", lambda d: d["collision"].update(buffer_distance=0.01))
    variant(
        "integer limits",
        lambda d: d["cspace"].update(acceleration_limits=[12] * len(d["cspace"]["joint_names"])),
    )
    assert data  # the source itself loads
    return out


def _only_the_upper_arm(d: dict[str, Any]) -> None:
    """Tool frame and spheres on the upper arm only: the joints past it move none of them."""
    d["tool_frames"] = ["upper_arm_link"]
    spheres = d["geometry"][d["collision"]["geometry"]]["spheres"]
    for frame in [f for f in spheres if f not in ("shoulder_link", "upper_arm_link")]:
        del spheres[frame]


def _reorder(d: dict[str, object]) -> None:
    cs = d["cspace"]
    assert isinstance(cs, dict)
    cs["joint_names"] = [*cs["joint_names"][1:], cs["joint_names"][0]]


@pytest.mark.parametrize(
    "source", [SEED_XRDF, CLASSIC / "ur10e_classic.yml"], ids=["seed", "converted"]
)
def test_lint_target_curobo_errors_exactly_when_curobo_cannot_load_as_written(
    source: Path,
) -> None:
    if source.suffix == ".xrdf":
        text = source.read_text()
    else:
        text = dump_xrdf(convert_files(UR10E_URDF, ConvertOptions(curobo=source))[0])
    corpus = {"as is": text, **_mutations(text)}
    verdicts = {}
    for name, variant in corpus.items():
        diags = lint_text(variant, f"{name}.xrdf", urdf=UR10E_URDF, target="curobo")
        curobo_errors = [
            d for d in diags if d.severity.value == "error" and d.rule.startswith("curobo-")
        ]
        verdicts[name] = (loads_as_written(variant, UR10E_URDF), not curobo_errors)
    assert all(loads == clean for loads, clean in verdicts.values()), verdicts
    # the corpus has both kinds
    assert {v[0] for v in verdicts.values()} == {True, False}


def test_every_shipped_xrdf_lints_for_curobo_as_curobo_loads_it() -> None:
    files = [SEED_XRDF, UR10E_XRDF, FIXTURES / "panda" / "panda.xrdf"]
    files += sorted(REFERENCE.glob("*.xrdf")) if REFERENCE.exists() else []
    for f in files:
        text = f.read_text()
        urdf = f.with_name("ur10e.urdf") if f.parent == REFERENCE else UR10E_URDF
        if "panda" in f.name:
            urdf = None
        errors = [
            d.rule
            for d in lint_text(text, str(f), urdf=urdf, target="curobo")
            if d.severity.value == "error" and d.rule.startswith("curobo-")
        ]
        if urdf is not None:
            assert (errors == []) == loads_as_written(text, urdf), (f, errors)
        else:  # the Panda fixture is 2.0: cuRobo loads it without collision
            assert errors == ["curobo-format-version"], (f, errors)


def test_export_curobo_writes_a_urdf_path_curobo_finds_and_checks_the_urdf(
    runner: CliRunner,
    tmp_path: Path,
) -> None:
    out = tmp_path / "ur10e.yml"
    args = ["export", "curobo", str(SEED_XRDF), "--urdf", str(UR10E_URDF), "-o", str(out)]
    r = runner.invoke(app, [*args, "--absolute-paths"])
    assert r.exit_code == 0, r.output
    kin = yaml.safe_load(out.read_text())["robot_cfg"]["kinematics"]
    # cuRobo joins a relative urdf_path to its own asset directory: with --absolute-paths it
    # finds the URDF without setup (the default, relative paths: tests/export/test_export_paths.py)
    assert Path(kin["urdf_path"]).is_absolute() and Path(kin["urdf_path"]) == UR10E_URDF
    assert Path(kin["asset_root_path"]) == UR10E_URDF.parent
    # an XRDF of another robot is an error, not a config with no joints
    panda = FIXTURES / "panda" / "panda.xrdf"
    r = runner.invoke(app, ["export", "curobo", str(panda), "--urdf", str(UR10E_URDF)])
    assert r.exit_code == 2 and "different robots" in r.output and "Traceback" not in r.output


def test_convert_refuses_inputs_that_do_not_belong_together(runner: CliRunner) -> None:
    franka = REFERENCE / "franka.yml"
    if not franka.exists():
        pytest.skip("shared reference configs not available")
    r = runner.invoke(app, ["convert", str(UR10E_URDF), "--curobo", str(franka)])
    assert r.exit_code == 2 and "different robots" in r.output
    assert "joint_names: []" not in r.output


def test_export_xrdf_rewrites_a_2_0_file_for_curobo(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "for_curobo.xrdf"
    r = runner.invoke(
        app, ["export", "xrdf", str(UR10E_XRDF), "--target", "curobo", "-o", str(out)]
    )
    assert r.exit_code == 0, r.output
    text = out.read_text()
    assert loads_as_written(text, UR10E_URDF)
    assert from_xrdf(text, UR10E_URDF).spheres  # collision is back
    r = runner.invoke(app, ["export", "xrdf", str(out), "-o", str(out)])
    assert r.exit_code == 2  # never overwrites its input


def test_disconnected_urdf_converts_from_the_chosen_base(runner: CliRunner, tmp_path: Path) -> None:
    # like cuRobo's tri_ur10e.urdf: parts that the chosen base_link does not reach
    text = UR10E_URDF.read_text()
    extra = (
        '<link name="second_base"/><link name="second_arm"/>'
        '<joint name="second_joint" type="revolute"><parent link="second_base"/>'
        '<child link="second_arm"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    urdf = tmp_path / "ur10e_parts.urdf"
    urdf.write_text(text[: text.rindex("</robot>")] + extra)
    x, diags, _ = convert_files(urdf, ConvertOptions(curobo=CLASSIC / "ur10e_classic.yml"))
    (note,) = [d for d in diags if d.rule == "convert-unreachable-links"]
    assert "second_base" in note.message and "second_arm" in note.message
    assert x.cspace is not None and "second_joint" not in x.cspace.joint_names
    # without a base to choose the part, the URDF is refused with a clear message
    srdf = tmp_path / "empty.srdf"
    srdf.write_text('<robot name="ur10e"/>')
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf)])
    assert r.exit_code == 2 and "not one tree" in r.output
    # placed at the root of the smaller part, which it names (it had no line)
    line = text[: text.rindex("</robot>")].count("\n") + 1
    assert f"{urdf}:{line}: the URDF is not one tree" in r.stderr, r.stderr
    assert "the smallest part starts at 'second_base'" in r.stderr


@pytest.mark.parametrize("drop", [None, "tool_frames", "self_collision"])
def test_export_xrdf_for_curobo_writes_only_what_curobo_loads(
    runner: CliRunner, tmp_path: Path, drop: str | None
) -> None:
    """``export xrdf --target curobo`` writes the file exactly when cuRobo loads the rewrite as
    written; otherwise it lists the errors, writes nothing and exits 1. Without --target the
    rewrite is written as asked."""
    doc = yaml.safe_load(UR10E_XRDF.read_text())
    if drop is not None:
        del doc[drop]
    source = tmp_path / "source.xrdf"
    source.write_text(yaml.safe_dump(doc, sort_keys=False))
    plain = tmp_path / "plain.xrdf"
    r = runner.invoke(
        app, ["export", "xrdf", str(source), "--format-version", "1.0", "-o", str(plain)]
    )
    assert r.exit_code == 0, r.output
    loads = loads_as_written(plain.read_text(), UR10E_URDF)
    assert loads == (drop is None)
    out = tmp_path / "for_curobo.xrdf"
    r = runner.invoke(app, ["export", "xrdf", str(source), "--target", "curobo", "-o", str(out)])
    assert (r.exit_code == 0) == loads, r.output
    assert out.exists() == loads
    if not loads:
        assert r.exit_code == 1 and "not written" in r.output and "curobo-" in r.output


@pytest.mark.parametrize(
    "rule",
    ["curobo-joint-axis", "curobo-joint-outside-tree", "curobo-no-pair", "curobo-self-buffer"],
)
def test_the_rules_learnt_from_curobos_loader_agree_with_the_model(rule: str) -> None:
    """Each failing fixture of these rules is a file cuRobo's loader raises on (checked with
    cuRobo itself, benchmarks/check_curobo_loader.py), each passing one a file it loads."""
    for f in sorted((FIXTURES / "lint" / rule).glob("*.xrdf")):
        text = f.read_text()
        given = re.search(r"^# urdf: (.+)$", text, re.M)
        urdf = (f.parent / given.group(1)).resolve() if given else UR10E_URDF
        found = [
            d.rule
            for d in lint_text(text, str(f), urdf=urdf, target="curobo")
            if d.rule == rule and d.severity.value == "error"
        ]
        try:
            from_xrdf(text, urdf)
        except CuroboRejects:
            assert f.name.startswith("fail") and found, f
        else:
            assert f.name.startswith("pass") and not found, f


def _three_link(tools: str, cspace: list[str]) -> str:
    """The curobo-joint-outside-tree passing fixture (three_link_mimic.urdf) with these tool
    frames and c-space joints."""
    text = (FIXTURES / "lint" / "curobo-joint-outside-tree" / "pass.xrdf").read_text()
    x = yaml.safe_load(text.replace("tool_frames: [tool]", f"tool_frames: {tools}"))
    n = len(cspace)
    x["cspace"] = {
        "joint_names": cspace,
        "acceleration_limits": [10.0] * n,
        "jerk_limits": [1e3] * n,
    }
    return yaml.safe_dump(x, sort_keys=False)


def test_curobo_puts_a_tool_frame_on_the_chain_to_the_first_first_unless_a_joint_is_locked() -> (
    None
):
    """Checked with cuRobo main: with every joint on its chains in the c-space it reorders the
    tool frames from the base outwards; a locked joint there keeps the order written."""
    urdf = FIXTURES / "urdf" / "three_link_mimic.urdf"
    free = from_xrdf(_three_link("[tool, link1]", ["joint1", "joint2", "joint3"]), urdf)
    assert free.ee_link == "link1" and free.link_names == {"tool", "link1"}
    locked = from_xrdf(_three_link("[tool, link1]", ["joint1", "joint2"]), urdf)
    assert locked.ee_link == "tool" and locked.locked == {"joint3": 0.1}
    assert from_xrdf(
        _three_link("[tool, base_link]", ["joint1", "joint2", "joint3"]), urdf
    ).ee_link == ("base_link")


def test_a_joint_curobo_plans_for_needs_an_effort_range(tmp_path: Path) -> None:
    """Checked with cuRobo main: a URDF ``effort="0"`` on a planned joint makes its loader
    raise as velocity 0 does; lint names the attribute."""
    text = (FIXTURES / "urdf" / "zero_velocity_arm.urdf").read_text()
    urdf = tmp_path / "effort.urdf"
    urdf.write_text(text.replace('effort="0" velocity="0"', 'effort="0" velocity="2.0"'))
    xrdf = _three_link("[link3]", ["joint1", "joint2", "joint3"])
    with pytest.raises(CuroboRejects, match="joint1"):
        from_xrdf(xrdf, urdf)
    (found,) = [
        d
        for d in lint_text(xrdf, "x.xrdf", urdf=urdf, target="curobo")
        if d.rule == "curobo-zero-velocity"
    ]
    assert 'effort="0"' in found.message and "velocity=" not in found.message


def test_a_joint_curobo_plans_for_needs_a_velocity_range() -> None:
    """Checked with cuRobo main: a planned joint with URDF velocity 0 makes its loader raise;
    held outside the c-space (locked) it loads, and lint says so."""
    urdf = FIXTURES / "urdf" / "zero_velocity_arm.urdf"
    text = _three_link("[link3]", ["joint1", "joint2", "joint3"])
    with pytest.raises(CuroboRejects, match="joint1"):
        from_xrdf(text, urdf)
    rules = {d.rule for d in lint_text(text, "x.xrdf", urdf=urdf, target="curobo")}
    assert "curobo-zero-velocity" in rules
    assert from_xrdf(_three_link("[link3]", ["joint2", "joint3"]), urdf).locked == {"joint1": 0.0}
