"""cuRobo robot YAML → XRDF: cuRobo's real 2.0-layout configs and our classic-layout fixtures."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tests.paths import FIXTURES, UR10E_URDF, shared_file
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.diagnostics import Diagnostic
from xrdf_tools.diff import diff_xrdf
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import AddFrame, Sphere

CLASSIC = FIXTURES / "curobo_classic"


def _rules(diags: list[Diagnostic]) -> dict[str, list[Diagnostic]]:
    out: dict[str, list[Diagnostic]] = {}
    for d in diags:
        out.setdefault(d.rule, []).append(d)
    return out


def test_curobo_ur10e_matches_curobos_own_xrdf_except_explained_differences() -> None:
    yml = shared_file("reference", "curobo-2.0", "ur10e.yml")
    urdf = shared_file("reference", "curobo-2.0", "ur10e.urdf")
    reference = load_xrdf(shared_file("reference", "curobo-2.0", "ur10e.xrdf"))
    x, diags, _ = convert_files(urdf, ConvertOptions(curobo=yml, format_version="1.0"))
    rules = _rules(diags)

    # the real typo in cuRobo's ur10e.yml: reported with a suggestion and its position
    (typo,) = rules["convert-unknown-link"]
    assert "'forarm_link'" in typo.message and "did you mean 'forearm_link'" in typo.message
    assert typo.path == str(yml) and typo.line == 129
    # the tool0 sphere of radius -0.01 is part of the robot (a real sphere once buffered)
    assert [s.radius for s in x.world_collision_spheres()["tool0"]] == [-0.01]
    # camera_mount has spheres but is not a collision link: cuRobo never used them
    assert any("camera_mount" in d.message for d in rules["convert-unused-spheres"])
    dropped = " ".join(d.message for d in rules["convert-dropped-key"])
    for key in ("dynamics", "cspace_distance_weight", "null_space_weight", "position_limit_clip"):
        assert key in dropped

    result = diff_xrdf(reference, x)
    found = {(c.section, c.kind, c.subject) for c in result.changes}
    frames = ("shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link")
    frames += ("wrist_2_link", "wrist_3_link", "tool0")
    explained = {
        # ur10e.xrdf has world buffers of 0.01; ur10e.yml says collision_sphere_buffer: 0.0
        *(("world_collision", "buffer-removed", f) for f in frames),
        # ur10e.xrdf has a tool0 self buffer of 0.05; ur10e.yml has `tool0: 0.0 # 0.05`
        ("self_collision", "buffer-removed", "tool0"),
        # the xrdf fixed the typo by hand; from the yml the misspelt pair is reported and dropped
        ("self_collision", "ignore-pair-removed", "forearm_link <-> wrist_1_link"),
        # the yml masks camera_mount (a URDF link) against tool0 and wrist_3_link; the xrdf not
        ("self_collision", "ignore-pair-added", "camera_mount <-> tool0"),
        ("self_collision", "ignore-pair-added", "camera_mount <-> wrist_3_link"),
    }
    assert found == explained, sorted(found ^ explained)
    # every other section is equal: c-space, limits, defaults, tool frames, effective spheres
    assert {c.section for c in result.changes} == {"world_collision", "self_collision"}
    # 1.0 is the default; 2.0 carries the same content except the sphere 2.0 cannot express,
    # which is reported
    assert convert_files(urdf, ConvertOptions(curobo=yml))[0] == x
    x2, diags2, _ = convert_files(urdf, ConvertOptions(curobo=yml, format_version="2.0"))
    assert x2.format_version == "2.0"
    assert "tool0" not in x2.world_collision_spheres()
    (dropped,) = _rules(diags2)["dropped-nonpositive-sphere"]
    assert "'tool0'" in dropped.message and "-0.01" in dropped.message
    assert {c.section for c in diff_xrdf(x, x2).changes} == {"format", "geometry"}


def test_curobo_franka_attached_object_slots_kept_in_1_0_reported_in_2_0() -> None:
    yml = shared_file("reference", "curobo-2.0", "franka.yml")
    urdf = shared_file("reference", "curobo-2.0", "franka_panda.urdf")
    for version in ("2.0", "1.0"):
        x, diags, _ = convert_files(urdf, ConvertOptions(curobo=yml, format_version=version))
        rules = _rules(diags)
        spheres = x.world_collision_spheres()
        if version == "1.0":
            # extra_collision_spheres: {attached_object: 4} -> four radius -10 slots at the
            # link origin, as cuMotion's own franka_curobo.xrdf carries them
            assert spheres["attached_object"] == (Sphere((0.0, 0.0, 0.0), -10.0),) * 4
            assert "dropped-nonpositive-sphere" not in rules
        else:
            assert "attached_object" not in spheres
            slots = rules["dropped-nonpositive-sphere"]
            assert len(slots) == 4 and all("attached-object slot" in d.message for d in slots)
        # the attached_object frame is added (extra_links), but gets no spheres at all
        added = [m for m in x.modifiers if isinstance(m, AddFrame)]
        assert [(m.frame_name, m.parent_frame_name, m.joint_name) for m in added] == [
            ("attached_object", "panda_hand", "attach_joint")
        ]
        assert all(s.radius > 0 for f, ss in spheres.items() if f != "attached_object" for s in ss)
        assert len(spheres["panda_hand"]) == 18
        # lock_joints: fingers leave the c-space, their values become default positions
        assert x.cspace is not None
        assert x.cspace.joint_names == tuple(f"panda_joint{i}" for i in range(1, 8))
        assert x.cspace.acceleration_limits == (15.0,) * 7
        assert x.cspace.jerk_limits == (500.0,) * 7
        defaults = dict(x.default_joint_positions or {})
        assert defaults["panda_finger_joint1"] == 0.04
        assert defaults["panda_joint4"] == -2.5
        assert x.tool_frames == ("panda_hand",)
        assert x.self_collision is not None
        assert frozenset(("panda_link7", "attached_object")) in x.self_collision.ignore_pairs()
        assert x.self_collision.buffer_distance["panda_link0"] == 0.1
        assert "panda_link2" not in x.self_collision.buffer_distance  # zero buffers not written
        assert parse_xrdf(dump_xrdf(x)) == x


def test_classic_layout_separate_spheres_file() -> None:
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=CLASSIC / "ur10e_classic.yml"))
    rules = _rules(diags)
    assert x.format_version == "1.0"  # the version every reader loads
    assert x.tool_frames == ("tool0", "flange")  # ee_link first, then link_names, deduplicated
    assert x.cspace is not None
    assert x.cspace.acceleration_limits == (12.0,) * 6  # scalar broadcast
    assert x.cspace.jerk_limits == (500.0, 500.0, 500.0, 400.0, 400.0, 400.0)  # per joint
    assert dict(x.default_joint_positions or {}) == {  # retract_config mapped by name
        "shoulder_pan_joint": 0.0,
        "shoulder_lift_joint": -2.2,
        "elbow_joint": 1.9,
        "wrist_1_joint": -1.383,
        "wrist_2_joint": -1.57,
        "wrist_3_joint": 0.0,
    }
    (frame,) = x.added_frames()
    assert frame.frame_name == "gripper_center" and frame.parent_frame_name == "tool0"
    assert frame.position == (0.0, 0.0, 0.15)
    assert frame.orientation.as_wxyz() == pytest.approx((0.7071068, 0, 0, 0.7071068), abs=1e-6)
    spheres = x.world_collision_spheres()
    # spheres come from spheres/ur10e.yml; base_link is not a collision link → dropped, reported
    assert "base_link" not in spheres and len(spheres["upper_arm_link"]) == 3
    assert "camera_mount" in spheres
    (unused,) = rules["convert-unused-spheres"]
    assert unused.path.endswith("spheres/ur10e.yml") and unused.line == 33
    assert x.world_collision is not None
    assert dict(x.world_collision.buffer_distance) == {
        "shoulder_link": 0.01,
        "upper_arm_link": 0.01,
        "forearm_link": 0.01,
        "wrist_1_link": 0.005,
        "wrist_2_link": 0.005,
    }
    assert x.self_collision is not None
    assert dict(x.self_collision.buffer_distance) == {"shoulder_link": 0.07}
    # gripper_center is an added frame: valid in the ignore list
    assert frozenset(("wrist_3_link", "gripper_center")) in x.self_collision.ignore_pairs()
    dropped = " ".join(d.message for d in rules["convert-dropped-key"])
    assert "null_space_weight" in dropped and "position_limit_clip" in dropped
    assert "usd" not in dropped and "mesh_link_names" not in dropped  # ignored silently
    assert "convert-default-acceleration" not in rules


def test_classic_layout_inline_locks_and_typos() -> None:
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=CLASSIC / "ur10e_inline.yml"))
    rules = _rules(diags)
    assert x.cspace is not None
    # wrist_3_joint is locked: out of the c-space, its lock value is its default position
    assert "wrist_3_joint" not in x.cspace.joint_names
    assert x.cspace.acceleration_limits == (10.0, 11.0, 12.0, 13.0, 14.0)
    assert dict(x.default_joint_positions or {})["wrist_3_joint"] == 0.5
    assert dict(x.default_joint_positions or {})["shoulder_pan_joint"] == 0.1
    # no max_jerk: the default, reported
    assert x.cspace.jerk_limits == (1000.0,) * 5
    assert "convert-default-jerk" in rules
    # scalar buffer → per sphere frame; the small negative radius is kept as written (cuRobo
    # makes it a real sphere once buffered); typo reported with a suggestion
    assert x.world_collision is not None
    assert dict(x.world_collision.buffer_distance) == dict.fromkeys(
        ("upper_arm_link", "forearm_link", "wrist_3_link", "tool0"), 0.005
    )
    assert [s.radius for s in x.world_collision_spheres()["tool0"]] == [-0.01]
    (typo,) = rules["convert-unknown-link"]
    assert "did you mean 'forearm_link'" in typo.message and typo.line == 24
    # velocity_scale: [1.0, ...] is what cuRobo takes without it: dropping it loses nothing
    assert "convert-dropped-key" not in rules


def test_lula_robot_description() -> None:
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=CLASSIC / "ur10e_lula.yaml"))
    assert x.cspace is not None and len(x.cspace.joint_names) == 6
    assert x.cspace.jerk_limits == (10000.0,) * 6
    assert dict(x.default_joint_positions or {})["shoulder_lift_joint"] == -1.57
    assert len(x.world_collision_spheres()["forearm_link"]) == 2
    assert "convert-chosen-tool-frame" in _rules(diags)


def test_not_a_curobo_config(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yml"
    bad.write_text("robot_cfg: {dynamics: {}}\n")
    with pytest.raises(SourceError, match="not a cuRobo robot configuration"):
        convert_files(UR10E_URDF, ConvertOptions(curobo=bad))
    bad.write_text(
        "robot_cfg:\n  kinematics:\n    cspace:\n      joint_names: [elbow_joint]\n"
        "      max_acceleration: [1.0, 2.0]\n"
    )
    with pytest.raises(SourceError, match=r"bad.yml:5:.*2 values for 1 joints"):
        convert_files(UR10E_URDF, ConvertOptions(curobo=bad))


def test_a_locked_cspace_joint_keeps_its_lock_value_and_says_its_default_is_unused(
    tmp_path: Path,
) -> None:
    """A joint in both cspace.joint_names and lock_joints is held at its lock value (as cuRobo
    holds it); a different retract_config value for it is reported at its list item, an equal
    one is not."""
    joints = "shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint"
    cfg = tmp_path / "ur.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base_link\n    ee_link: tool0\n"
        "    lock_joints: {wrist_1_joint: 0.5, elbow_joint: 1.0}\n"
        f"    cspace:\n      joint_names: [{joints}]\n"
        "      retract_config: [0.0, -1.0, 1.0, 0.25]\n"
    )
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    assert x.cspace is not None
    assert x.cspace.joint_names == ("shoulder_pan_joint", "shoulder_lift_joint")
    defaults = dict(x.default_joint_positions or {})
    assert defaults["wrist_1_joint"] == 0.5 and defaults["elbow_joint"] == 1.0
    (note,) = _rules(diags)["convert-dropped-joint-value"]
    assert "'wrist_1_joint' is also in lock_joints" in note.message
    assert "lock value 0.5" in note.message and "retract_config value 0.25" in note.message
    line = cfg.read_text().splitlines()[7]
    assert (note.path, note.line, note.col) == (str(cfg), 8, line.index("0.25") + 1)


def test_a_default_or_lock_outside_the_urdf_limits_is_clamped_and_said_at_its_value(
    tmp_path: Path,
) -> None:
    """A retract_config value and a lock value outside the joint's URDF limits are brought inside
    them, each said at the line that gives it (it was said with no position)."""
    cfg = tmp_path / "ur.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base_link\n    ee_link: tool0\n"
        "    lock_joints: {wrist_1_joint: 9.0}\n"
        "    cspace:\n      joint_names: [shoulder_pan_joint, elbow_joint]\n"
        "      retract_config:\n        - 0.0\n        - 5.0\n"
    )
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    defaults = dict(x.default_joint_positions or {})
    assert defaults["elbow_joint"] == pytest.approx(5.0 - 2 * math.pi)  # the same pose
    said = {d.message.split("'")[1]: d for d in _rules(diags)["convert-clamped-default"]}
    assert set(said) == {"elbow_joint", "wrist_1_joint"}
    assert (said["elbow_joint"].path, said["elbow_joint"].line) == (str(cfg), 10)
    assert (said["wrist_1_joint"].path, said["wrist_1_joint"].line) == (str(cfg), 5)


def test_a_target_refusing_links_without_spheres_names_fit_spheres(tmp_path: Path) -> None:
    """A cuRobo config that gives spheres to some moving links only (cuRobo's kinova_gen3 and
    iiwa configs leave out links on purpose) fails --target curobo; the closing line says how
    many of the errors are such links and that --fit-spheres fits the rest."""
    from typer.testing import CliRunner

    from xrdf_tools.cli import app

    cfg = tmp_path / "ur.yml"
    cfg.write_text(
        "robot_cfg:\n  kinematics:\n    base_link: base_link\n    ee_link: tool0\n"
        "    collision_link_names: [forearm_link]\n"
        "    collision_spheres:\n      forearm_link:\n"
        "        - {center: [0.0, 0.0, 0.1], radius: 0.05}\n"
        "    cspace:\n      joint_names: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint,"
        " wrist_1_joint, wrist_2_joint, wrist_3_joint]\n"
    )
    args = ["convert", str(UR10E_URDF), "--curobo", str(cfg), "--target", "curobo"]
    res = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "ur.xrdf")])
    assert res.exit_code == 1, res.output
    last = res.output.strip().splitlines()[-1]
    assert "are moving links with collision geometry and no spheres" in last
    assert "--fit-spheres" in last and not (tmp_path / "ur.xrdf").exists()
