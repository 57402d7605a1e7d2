"""cuRobo extra links an XRDF cannot hold: a moving virtual base, a re-parented URDF link.

cuRobo's Unitree G1 config hangs a six-joint floating base (``X_PRISM`` … ``Z_ROT`` extra links,
their joints in the c-space, ``base_j_z`` defaulting to 0.8 m) between ``base_link`` and the
URDF's ``pelvis`` (``child_link_name``). The config below has the same shape on the UR10e.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.diagnostics import Diagnostic, Severity
from xrdf_tools.util.errors import SourceError
from xrdf_tools.xrdf.io import parse_xrdf
from xrdf_tools.xrdf.model import AddFrame

#: The UR arm's six joints, as the fixture's own c-space lists them.
ARM = list(parse_xrdf(UR10E_XRDF.read_text(), str(UR10E_XRDF)).cspace.joint_names)  # type: ignore[union-attr]


def _config(tmp_path: Path, *, lift: str = "[0, 0, 0, 1, 0, 0, 0]", locks: str = "{}") -> Path:
    names = ["base_j_x", "base_j_yaw", *ARM]
    text = f"""kinematics:
  base_link: base_link
  tool_frames: [tool0]
  lock_joints: {locks}
  load_meshes: false
  use_external_assets: false
  debug: null
  extra_links:
    base_x:
      parent_link_name: base_link
      link_name: base_x
      joint_name: base_j_x
      joint_type: X_PRISM
      fixed_transform: {lift}
      joint_limits: [-10.0, 10.0]
      joint_velocity_limits: [-1.0, 1.0]
    base_yaw:
      parent_link_name: base_x
      child_link_name: base_link_inertia
      link_name: base_yaw
      joint_name: base_j_yaw
      joint_type: Z_ROT
      fixed_transform: [0, 0, 0, 1, 0, 0, 0]
      link_mass: 0.01
  cspace:
    joint_names: [{", ".join(names)}]
    default_joint_position: [0.0, 0.3, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0]
    max_acceleration: 10.0
    max_jerk: 500.0
"""
    path = tmp_path / "floating_ur10e.yml"
    path.write_text(text, encoding="utf-8")
    return path


def _line(path: Path, text: str) -> int:
    return next(i for i, s in enumerate(path.read_text().splitlines(), 1) if text in s)


def _by_rule(diags: list[Diagnostic]) -> dict[str, list[Diagnostic]]:
    out: dict[str, list[Diagnostic]] = {}
    for d in diags:
        out.setdefault(d.rule, []).append(d)
    return out


def test_a_moving_virtual_base_is_written_fixed_and_said_once_per_link(tmp_path: Path) -> None:
    cfg = _config(tmp_path)
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    rules = _by_rule(diags)
    # the arm is the c-space; the base's joints are not "unknown joints" with a did-you-mean
    assert x.cspace is not None and list(x.cspace.joint_names) == ARM
    assert "convert-unknown-joint" not in rules
    moving = {
        d.line: d.message for d in rules["convert-dropped-key"] if "moves in cuRobo" in d.message
    }
    assert set(moving) == {_line(cfg, "X_PRISM"), _line(cfg, "Z_ROT")}
    assert "joint 'base_j_x', X_PRISM, limits [-10.0, 10.0]" in moving[_line(cfg, "X_PRISM")]
    assert "'base_j_yaw' is left out of the c-space" in moving[_line(cfg, "Z_ROT")]
    # both frames are added, fixed, in order, so the tool frames and spheres may use them
    frames = [m for m in x.modifiers if isinstance(m, AddFrame)]
    assert [(f.frame_name, f.parent_frame_name, f.joint_type) for f in frames] == [
        ("base_x", "base_link", "FIXED"),
        ("base_yaw", "base_x", "FIXED"),
    ]
    # a default the XRDF cannot apply is said where it is written
    (held,) = rules["convert-dropped-joint-value"]
    assert held.line == _line(cfg, "default_joint_position")
    assert "'base_j_yaw'" in held.message and "0.3 is not applied" in held.message
    # the child link stays where the URDF puts it, which is where cuRobo puts it: an info
    (child,) = [d for d in rules["convert-dropped-key"] if "child_link_name" in d.message]
    assert child.severity is Severity.INFO and child.line == _line(cfg, "child_link_name")
    assert "stays on 'base_link' (joint 'base_link-base_link_inertia')" in child.message
    # a key no XRDF holds is said dropped; the motion keys go with the moving link's warning
    dropped = [d.message for d in rules["convert-dropped-key"]]
    assert any("extra_links.base_yaw.link_mass has no XRDF equivalent" in m for m in dropped)
    assert not any("joint_limits" in m or "joint_velocity_limits" in m for m in dropped)
    # G1's loader settings (meshes for display, where assets are, debug) are not robot facts
    assert not any(k in m for k in ("load_meshes", "use_external_assets", "debug") for m in dropped)


def test_a_child_the_extra_links_move_is_refused_where_it_is_written(tmp_path: Path) -> None:
    cfg = _config(tmp_path, lift="[0, 0, 0.1, 0.7071068, 0, 0, 0.7071068]")
    with pytest.raises(SourceError) as err:
        convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    assert err.value.path == str(cfg) and err.value.line == _line(cfg, "child_link_name")
    assert "100 mm and 90° away" in err.value.message
    assert "joint 'base_link-base_link_inertia'" in err.value.message


def test_a_lock_on_a_moving_joint_is_said_unless_it_is_zero(tmp_path: Path) -> None:
    for value, said in (("0.2", True), ("0.0", False)):
        cfg = _config(tmp_path, locks=f"{{base_j_x: {value}}}")
        _, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
        locks = [d for d in diags if "locked joint 'base_j_x'" in d.message]
        assert bool(locks) is said, diags
        assert not [d for d in diags if d.rule == "convert-unknown-joint"]
        if said:
            assert locks[0].line == _line(cfg, "lock_joints")
            assert "its lock value 0.2 is not applied" in locks[0].message


def test_the_written_xrdf_lints_clean_and_the_refusal_exits_2(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "floating.xrdf"
    cfg = _config(tmp_path)
    code, text = run_cli(runner, "convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(out))
    assert code == 0, text
    code, text = run_cli(runner, "lint", str(out), "--urdf", str(UR10E_URDF))
    assert code == 0, text
    moved = _config(tmp_path, lift="[0, 0, 0.1, 1, 0, 0, 0]")
    code, text = run_cli(runner, "convert", str(UR10E_URDF), "--curobo", str(moved))
    assert code == 2 and f"{moved}:{_line(moved, 'child_link_name')}" in text, text
    assert "100 mm and 0° away" in text


def test_a_child_of_an_extra_link_that_is_not_added_is_not_called_unknown(tmp_path: Path) -> None:
    cfg = _config(tmp_path)
    text = cfg.read_text().replace("parent_link_name: base_x", "parent_link_name: base_q")
    cfg.write_text(text)
    _, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    said = [d.message for d in diags if "base_q" in d.message or "base_link_inertia" in d.message]
    assert len(said) == 1 and "'base_q' (extra link parent) is not a link" in said[0], said
    # a child that is no URDF link, or the URDF's root, is said dropped
    for child, why in (
        ("base_link_inertai", "did you mean 'base_link_inertia'"),
        ("base_link", "root"),
    ):
        cfg.write_text(
            _config(tmp_path)
            .read_text()
            .replace("child_link_name: base_link_inertia", f"child_link_name: {child}")
        )
        _, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
        (d,) = [d for d in diags if "child_link_name" in d.message]
        assert why in d.message and d.line == _line(cfg, "child_link_name"), d


def _extra(tmp_path: Path, links: str) -> Path:
    """A fixed-arm UR10e config with these ``extra_links`` (indented under the key)."""
    path = tmp_path / "extra.yml"
    path.write_text(
        f"""kinematics:
  base_link: base_link
  tool_frames: [tool0]
  extra_links:
{links}  cspace:
    joint_names: [{", ".join(ARM)}]
    default_joint_position: [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    max_acceleration: 10.0
    max_jerk: 500.0
""",
        encoding="utf-8",
    )
    return path


@pytest.mark.parametrize(
    ("second", "said"),
    [
        ("joint_name: elbow_joint", "joint 'elbow_joint' is already a joint of the URDF"),
        ("joint_name: tcp_joint", "joint 'tcp_joint' is already a joint of extra link 'tcp'"),
    ],
)
def test_a_joint_name_already_taken_is_refused_in_the_config(
    tmp_path: Path, second: str, said: str
) -> None:
    """Before: the URDF's line-less 'add_frame 'tip': joint name … already exists', naming a
    modifier the user never wrote and not the config."""
    cfg = _extra(
        tmp_path,
        f"""    tcp:
      parent_link_name: tool0
    tip:
      parent_link_name: tcp
      {second}
""",
    )
    with pytest.raises(SourceError) as err:
        convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    assert err.value.path == str(cfg) and err.value.line == _line(cfg, second)
    assert said in err.value.message and "give this extra link a joint_name" in err.value.message


def test_a_link_name_an_earlier_extra_link_has_is_said_so_and_not_called_moving(
    tmp_path: Path,
) -> None:
    cfg = _extra(
        tmp_path,
        """    tcp:
      parent_link_name: tool0
    tcp_again:
      parent_link_name: tool0
      link_name: tcp
      joint_name: tcp_again_joint
      joint_type: Z_ROT
""",
    )
    _, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    rules = _by_rule(diags)
    (dup,) = rules["convert-duplicate-frame"]
    assert "'tcp' already exists as an earlier extra link; not added" in dup.message
    assert not any("moves in cuRobo" in d.message for d in rules.get("convert-dropped-key", []))


def test_a_quaternion_of_zeros_is_refused_where_it_is_written(tmp_path: Path) -> None:
    """Before: exit 1 on a lint error located in the XRDF convert did not write."""
    cfg = _extra(
        tmp_path,
        """    tcp:
      parent_link_name: tool0
      fixed_transform: [0, 0, 0.1, 0, 0, 0, 0]
""",
    )
    with pytest.raises(SourceError) as err:
        convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    assert err.value.line == _line(cfg, "fixed_transform") and "all zeros" in err.value.message


def test_extra_links_in_any_order_are_added_parents_first(tmp_path: Path) -> None:
    """cuRobo builds its tree from extra_links in any order; a child written before its parent
    was called "not a link of the URDF" and dropped."""
    cfg = _config(tmp_path)
    text = cfg.read_text()
    x_block = text[text.index("    base_x:\n") : text.index("    base_yaw:\n")]
    yaw_end = text.index("  cspace:\n")
    yaw_block = text[text.index("    base_yaw:\n") : yaw_end]
    cfg.write_text(text.replace(x_block + yaw_block, yaw_block + x_block))
    assert cfg.read_text().index("base_yaw:") < cfg.read_text().index("base_x:")
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=cfg))
    assert not [d for d in diags if d.rule == "convert-unknown-link"], diags
    frames = [(m.frame_name, m.parent_frame_name) for m in x.modifiers if isinstance(m, AddFrame)]
    assert frames == [("base_x", "base_link"), ("base_yaw", "base_x")]
