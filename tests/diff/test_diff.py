"""`xrdf diff` and the semantic diff library (xrdf_tools.diff, xrdf_tools.diff.render)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import SEED_XRDF, UR10E_XRDF, shared_file
from xrdf_tools.cli import app
from xrdf_tools.diff import Level, XrdfDiff, compare_spheres, diff_files, diff_xrdf
from xrdf_tools.diff.render import render_json, render_text
from xrdf_tools.util.errors import XrdfToolsError
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Sphere
from xrdf_tools.xrdf.versions import to_version

# A small 2.0 document; tests derive variants from it by text edits.
BASE = """\
format: xrdf
format_version: 2.0
modifiers:
  - set_base_frame: base
  - add_frame:
      frame_name: tcp
      parent_frame_name: link2
      joint_name: tcp_joint
      joint_type: FIXED
      fixed_transform:
        position: [0.0, 0.0, 0.1]
        orientation: {w: 0.7071067811865476, xyz: [0.0, 0.0, 0.7071067811865476]}
default_joint_positions:
  j1: 0.5
  j2: -1.0
cspace:
  joint_names: [j1, j2, j3]
  acceleration_limits: [10.0, 20.0, 30.0]
  jerk_limits: [100.0, 200.0, 300.0]
tool_frames: [tcp, link2]
world_collision:
  geometry: arm
  buffer_distance:
    link1: 0.01
    link2: 0.02
self_collision:
  geometry: arm
  buffer_distance:
    link1: 0.03
  ignore:
    link1: [link2]
    link2: [tcp]
geometry:
  arm:
    spheres:
      link1:
        - {center: [0.0, 0.0, 0.0], radius: 0.1}
        - {center: [0.0, 0.0, 0.2], radius: 0.1}
        - {center: [0.0, 0.0, 0.4], radius: 0.08}
      link2:
        - {center: [0.1, 0.0, 0.0], radius: 0.05}
"""


def diff_text(a: str, b: str, tolerance: float = 1e-9) -> XrdfDiff:
    return diff_xrdf(parse_xrdf(a, "a.xrdf"), parse_xrdf(b, "b.xrdf"), tolerance)


def kinds(d: XrdfDiff) -> list[str]:
    return [c.kind for c in d.changes]


def write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


# --- acceptance: a 1.0 file against itself converted to 2.0 ---------------------------------


@pytest.mark.parametrize("source", ["seed", "shared"])
def test_ur10e_against_its_2_0_conversion_reports_the_version_and_the_lost_sphere(
    runner: CliRunner, tmp_path: Path, source: str
) -> None:
    path = SEED_XRDF if source == "seed" else shared_file("reference", "curobo-2.0", "ur10e.xrdf")
    original = load_xrdf(path)
    converted, _ = to_version(original, "2.0")
    out = write(tmp_path, "ur10e_2_0.xrdf", dump_xrdf(converted))

    result = runner.invoke(app, ["diff", str(path), str(out), "--format", "json"])
    assert result.exit_code == 1, result.output
    doc = json.loads(result.output)
    assert doc["summary"]["changes"] == 2
    sections = {s["section"]: s["changes"] for s in doc["sections"]}
    (change,) = sections["format"]
    assert (change["kind"], change["before"], change["after"]) == ("version-changed", "1.0", "2.0")
    # 2.0 cannot express tool0's radius -0.01 sphere, which 1.0 readers make real once
    # buffered: losing it is a real difference, in both collision scopes
    assert {(c["kind"], c["subject"]) for c in sections["geometry"]} == {
        ("spheres-changed", "tool0")
    }
    assert doc["notes"] == []


def test_identical_files_exit_0(runner: CliRunner, tmp_path: Path) -> None:
    for path in (SEED_XRDF, UR10E_XRDF):
        result = runner.invoke(app, ["diff", str(path), str(path)])
        assert result.exit_code == 0, result.output
        assert "identical" in result.output
    # A canonical re-dump of the same model is also identical.
    again = write(tmp_path, "again.xrdf", dump_xrdf(load_xrdf(UR10E_XRDF)))
    assert diff_files(UR10E_XRDF, again).is_equal


# --- order and symmetry -------------------------------------------------------------------------


def test_mapping_and_sphere_order_are_ignored() -> None:
    reordered = """\
format: xrdf
format_version: 2.0
geometry:
  arm:
    spheres:
      link2:
        - {center: [0.1, 0.0, 0.0], radius: 0.05}
      link1:
        - {center: [0.0, 0.0, 0.4], radius: 0.08}
        - {center: [0.0, 0.0, 0.0], radius: 0.1}
        - {center: [0.0, 0.0, 0.2], radius: 0.1}
self_collision:
  ignore:
    tcp: [link2]
    link2: [link1]
  buffer_distance:
    link1: 0.03
  geometry: arm
world_collision:
  buffer_distance:
    link2: 0.02
    link1: 0.01
  geometry: arm
tool_frames: [tcp, link2]
cspace:
  jerk_limits: [100.0, 200.0, 300.0]
  acceleration_limits: [10.0, 20.0, 30.0]
  joint_names: [j1, j2, j3]
default_joint_positions:
  j2: -1.0
  j1: 0.5
modifiers:
  - set_base_frame: base
  - add_frame:
      fixed_transform:
        orientation: {xyz: [0.0, 0.0, 0.7071067811865476], w: 0.7071067811865476}
        position: [0.0, 0.0, 0.1]
      joint_type: FIXED
      joint_name: tcp_joint
      parent_frame_name: link2
      frame_name: tcp
"""
    d = diff_text(BASE, reordered)
    assert d.is_equal, render_text(d)
    assert d.notes == ()


def test_ignore_pairs_are_a_symmetric_set() -> None:
    both_ways = BASE.replace(
        "    link1: [link2]\n    link2: [tcp]\n",
        "    link2: [link1, tcp]\n    tcp: [link2]\n    link1: [link2]\n",
    )
    assert diff_text(BASE, both_ways).is_equal

    more = BASE.replace("    link2: [tcp]\n", "    link2: [tcp]\n    tcp: [link1]\n")
    fewer = BASE.replace("    link2: [tcp]\n", "")
    d = diff_text(BASE, more)
    assert kinds(d) == ["ignore-pair-added"]
    assert d.changes[0].after == ["link1", "tcp"] and d.changes[0].section == "self_collision"
    d = diff_text(BASE, fewer)
    assert kinds(d) == ["ignore-pair-removed"]
    assert d.changes[0].subject == "link2 <-> tcp"


# --- spheres --------------------------------------------------------------------------------------


def test_spheres_are_multisets_within_tolerance() -> None:
    nudged = BASE.replace(
        "[0.0, 0.0, 0.2], radius: 0.1}", "[0.0, 0.0, 0.2000000000001], radius: 0.1}"
    )
    assert diff_text(BASE, nudged).is_equal

    moved = BASE.replace("[0.0, 0.0, 0.2], radius: 0.1}", "[0.0, 0.0, 0.2000001], radius: 0.1}")
    d = diff_text(BASE, moved)
    assert kinds(d) == ["spheres-changed"]
    assert dict(d.changes[0].counts) == {"moved": 1}
    assert diff_text(BASE, moved, tolerance=1e-6).is_equal

    # A repeated sphere counts twice: multisets, not sets.
    doubled = BASE.replace(
        "      link2:\n        - {center: [0.1, 0.0, 0.0], radius: 0.05}\n",
        "      link2:\n        - {center: [0.1, 0.0, 0.0], radius: 0.05}\n"
        "        - {center: [0.1, 0.0, 0.0], radius: 0.05}\n",
    )
    d = diff_text(BASE, doubled)
    assert [(c.subject, dict(c.counts)) for c in d.changes] == [("link2", {"added": 1})]


def test_added_spheres_and_radius_changes_are_counted_per_frame() -> None:
    changed = BASE.replace(
        "        - {center: [0.0, 0.0, 0.0], radius: 0.1}\n"
        "        - {center: [0.0, 0.0, 0.2], radius: 0.1}\n",
        "        - {center: [0.0, 0.0, 0.0], radius: 0.12}\n"
        "        - {center: [0.0, 0.0, 0.2], radius: 0.09}\n"
        "        - {center: [1.0, 0.0, 0.0], radius: 0.01}\n"
        "        - {center: [2.0, 0.0, 0.0], radius: 0.01}\n"
        "        - {center: [3.0, 0.0, 0.0], radius: 0.01}\n",
    )
    d = diff_text(BASE, changed)
    (c,) = d.changes
    assert (c.section, c.subject, c.scope, c.level) == (
        "geometry",
        "link1",
        "world+self",
        Level.MAJOR,
    )
    assert dict(c.counts) == {"added": 3, "radius_changed": 2}
    assert c.message == "link1 (world and self): +3 spheres, radius changed on 2"
    radius = [(x.before, x.after) for x in c.details if x.kind == "radius-changed"]
    assert radius == [
        (Sphere((0.0, 0.0, 0.0), 0.1), Sphere((0.0, 0.0, 0.0), 0.12)),
        (Sphere((0.0, 0.0, 0.2), 0.1), Sphere((0.0, 0.0, 0.2), 0.09)),
    ]
    text = render_text(d)
    assert "geometry: 1 change\n" in text
    assert "~ center [0.0, 0.0, 0.0] radius 0.1 -> 0.12" in text


def test_matching_is_maximal_not_greedy() -> None:
    # a[0] is within 0.1 of both b's; a[1] only of b[0]. Greedy a[0]->b[0] would leave a[1] out.
    a = [Sphere((0.0, 0.0, 0.0), 1.0), Sphere((0.0, 0.0, 0.0), 1.08)]
    b = [Sphere((0.0, 0.0, 0.0), 1.05), Sphere((0.0, 0.0, 0.0), 0.93)]
    assert not compare_spheres(a, b, 0.1)
    assert compare_spheres(a, b, 0.01).radius_changed


def test_a_far_jump_is_removed_and_added_not_moved() -> None:
    near = [Sphere((0.0, 0.0, 0.05), 0.1)]
    far = [Sphere((0.0, 0.0, 0.5), 0.1)]
    start = [Sphere((0.0, 0.0, 0.0), 0.1)]
    assert len(compare_spheres(start, near, 1e-9).moved) == 1
    result = compare_spheres(start, far, 1e-9)
    assert (result.moved, result.removed, result.added) == ((), tuple(start), tuple(far))


def test_attached_object_slots_are_notes_small_negative_radii_are_spheres() -> None:
    def with_sphere(radius: float) -> str:
        return BASE.replace(
            "      link2:\n",
            f"      tcp:\n        - {{center: [0.0, 0.0, 0.0], radius: {radius}}}\n      link2:\n",
        )

    d = diff_text(BASE, with_sphere(-10.0))
    assert d.is_equal
    assert [(n.kind, n.subject, n.before, n.after) for n in d.notes] == [
        ("placeholder-spheres", "tcp", 0, 1)
    ]
    d = diff_text(BASE, with_sphere(-0.01))
    assert not d.is_equal and d.notes == ()
    assert {(c.kind, c.subject) for c in d.changes} == {("spheres-changed", "tcp")}


def test_world_and_self_differences_are_scoped() -> None:
    split = BASE.replace("self_collision:\n  geometry: arm", "self_collision:\n  geometry: coarse")
    split += "  coarse:\n    clone: [arm]\n    spheres:\n      link2:\n" + (
        "        - {center: [0.0, 0.0, 0.0], radius: 0.2}\n"
    )
    d = diff_text(BASE, split)
    assert kinds(d) == ["group-renamed", "spheres-changed"]
    rename, spheres = d.changes
    assert (rename.section, rename.level, rename.before, rename.after) == (
        "self_collision",
        Level.MINOR,
        "arm",
        "coarse",
    )
    assert (spheres.scope, spheres.subject, dict(spheres.counts)) == ("self", "link2", {"added": 1})


# --- geometry groups and clones -------------------------------------------------------------------

CLONED = """\
format: xrdf
format_version: 2.0
cspace: {joint_names: [j1], acceleration_limits: [1.0], jerk_limits: [2.0]}
world_collision: {geometry: robot}
self_collision: {geometry: robot}
geometry:
  robot:
    clone: [arm, hand]
    spheres:
      hand: [{center: [0, 0, 0.05], radius: 0.03}]
  arm:
    spheres:
      link1: [{center: [0, 0, 0], radius: 0.1}]
      hand: [{center: [0, 0, 0], radius: 0.04}]
  hand:
    clone: [fingers]
    spheres:
      hand: [{center: [0, 0.02, 0], radius: 0.02}]
  fingers:
    spheres:
      finger: [{center: [0, 0, 0.01], radius: 0.01}]
"""

FLAT_1_0 = """\
format: xrdf
format_version: 1.0
cspace: {joint_names: [j1], acceleration_limits: [1.0], jerk_limits: [2.0]}
collision: {geometry: robot}
self_collision: {geometry: robot}
geometry:
  robot:
    spheres:
      finger: [{center: [0, 0, 0.01], radius: 0.01}]
      hand:
        - {center: [0, 0.02, 0], radius: 0.02}
        - {center: [0, 0, 0], radius: 0.04}
        - {center: [0, 0, 0.05], radius: 0.03}
      link1: [{center: [0, 0, 0], radius: 0.1}]
  arm:
    spheres:
      link1: [{center: [0, 0, 0], radius: 0.1}]
      hand: [{center: [0, 0, 0], radius: 0.04}]
  hand:
    spheres:
      hand: [{center: [0, 0.02, 0], radius: 0.02}]
      finger: [{center: [0, 0, 0.01], radius: 0.01}]
  fingers:
    spheres:
      finger: [{center: [0, 0, 0.01], radius: 0.01}]
"""


def test_clones_are_resolved_before_comparing() -> None:
    d = diff_text(CLONED, FLAT_1_0)
    assert kinds(d) == ["version-changed"], render_text(d)
    flattened, _ = to_version(parse_xrdf(CLONED), "1.0")
    assert kinds(diff_xrdf(parse_xrdf(CLONED), flattened)) == ["version-changed"]

    # Without 'fingers' in the clone chain the finger sphere is gone from the effective set.
    d = diff_text(CLONED, CLONED.replace("    clone: [fingers]\n", ""))
    assert [(c.kind, c.subject, dict(c.counts)) for c in d.changes] == [
        ("spheres-changed", "finger", {"removed": 1})
    ]


def test_group_rename_alone_is_a_minor_naming_change() -> None:
    renamed = BASE.replace("geometry: arm", "geometry: links").replace("  arm:\n", "  links:\n")
    d = diff_text(BASE, renamed)
    assert kinds(d) == ["group-renamed", "group-renamed"]
    assert {c.section for c in d.changes} == {"world_collision", "self_collision"}
    assert all(c.level is Level.MINOR for c in d.changes)
    assert d.major_changes == ()


def test_unused_groups_are_minor() -> None:
    extra = BASE + "  spare:\n    spheres:\n      link1: [{center: [0, 0, 0], radius: 0.3}]\n"
    d = diff_text(BASE, extra)
    assert [(c.kind, c.level) for c in d.changes] == [("group-added", Level.MINOR)]
    changed = extra.replace("radius: 0.3}", "radius: 0.4}")
    d = diff_text(extra, changed)
    assert [(c.kind, c.scope, c.level) for c in d.changes] == [
        ("spheres-changed", "group:spare", Level.MINOR)
    ]


# --- cspace, defaults, tool frames, buffers, modifiers ------------------------------------------


def test_cspace_reorder_is_reported_apart_from_add_and_remove() -> None:
    reordered = BASE.replace(
        "  joint_names: [j1, j2, j3]\n"
        "  acceleration_limits: [10.0, 20.0, 30.0]\n"
        "  jerk_limits: [100.0, 200.0, 300.0]\n",
        "  joint_names: [j2, j1, j3]\n"
        "  acceleration_limits: [20.0, 10.0, 30.0]\n"
        "  jerk_limits: [200.0, 100.0, 300.0]\n",
    )
    d = diff_text(BASE, reordered)
    assert kinds(d) == ["joints-reordered"]
    assert (d.changes[0].before, d.changes[0].after) == (["j1", "j2", "j3"], ["j2", "j1", "j3"])

    grown = (
        BASE.replace("[j1, j2, j3]", "[j1, j2, j3, j4]")
        .replace("[10.0, 20.0, 30.0]", "[10.0, 20.0, 30.000000000001, 5.0]")
        .replace("[100.0, 200.0, 300.0]", "[100.0, 250.0, 300.0, 50.0]")
    )
    d = diff_text(BASE, grown)
    assert [(c.kind, c.subject) for c in d.changes] == [
        ("joint-added", "j4"),
        ("jerk-limit-changed", "j2"),
    ]
    shrunk = (
        BASE.replace("[j1, j2, j3]", "[j1, j3]")
        .replace("[10.0, 20.0, 30.0]", "[10.0, 30.0]")
        .replace("[100.0, 200.0, 300.0]", "[100.0, 300.0]")
    )
    assert kinds(diff_text(BASE, shrunk)) == ["joint-removed"]


def test_default_positions_are_a_map() -> None:
    changed = BASE.replace("  j2: -1.0\n", "  j2: -1.1\n  j3: 0.2\n")
    d = diff_text(BASE, changed)
    assert [(c.kind, c.subject, c.before, c.after) for c in d.changes] == [
        ("default-changed", "j2", -1.0, -1.1),
        ("default-added", "j3", None, 0.2),
    ]


def test_tool_frame_order_matters() -> None:
    swapped = BASE.replace("tool_frames: [tcp, link2]", "tool_frames: [link2, tcp]")
    assert kinds(diff_text(BASE, swapped)) == ["end-effector-changed", "tool-frames-reordered"]
    appended = BASE.replace("tool_frames: [tcp, link2]", "tool_frames: [tcp, link2, link1]")
    assert kinds(diff_text(BASE, appended)) == ["tool-frame-added"]


def test_missing_buffer_is_zero() -> None:
    explicit_zero = BASE.replace("    link1: 0.03\n", "    link1: 0.03\n    link2: 0.0\n")
    assert diff_text(BASE, explicit_zero).is_equal
    dropped = BASE.replace("    link1: 0.01\n", "")
    d = diff_text(BASE, dropped)
    (c,) = d.changes
    assert (c.section, c.kind, c.subject, c.before, c.after) == (
        "world_collision",
        "buffer-removed",
        "link1",
        0.01,
        0.0,
    )
    assert "a missing buffer is 0.0" in c.message


def test_orientations_compare_as_rotations() -> None:
    half = "0.7071067811865476"
    forms = {
        "negated": f"{{w: -{half}, xyz: [0.0, 0.0, -{half}]}}",
        "quaternion": f"{{quaternion: [{half}, 0.0, 0.0, {half}]}}",
        "euler": "{euler_rpy: [0.0, 0.0, 1.5707963267948966]}",
    }
    original = f"{{w: {half}, xyz: [0.0, 0.0, {half}]}}"
    for name, form in forms.items():
        d = diff_text(BASE, BASE.replace(original, form))
        assert d.is_equal, (name, render_text(d))
    assert [n.kind for n in diff_text(BASE, BASE.replace(original, forms["euler"])).notes] == [
        "orientation-form"
    ]
    turned = BASE.replace(original, "{euler_rpy: [0.0, 0.0, 1.0]}")
    assert kinds(diff_text(BASE, turned)) == ["frame-orientation-changed"]
    moved = BASE.replace("position: [0.0, 0.0, 0.1]", "position: [0.0, 0.0, 0.11]")
    assert kinds(diff_text(BASE, moved)) == ["frame-position-changed"]
    lower = BASE.replace("joint_type: FIXED", "joint_type: fixed")
    assert diff_text(BASE, lower).is_equal


def test_base_frame_and_added_frames() -> None:
    rebased = BASE.replace("set_base_frame: base", "set_base_frame: link1")
    d = diff_text(BASE, rebased)
    assert [(c.kind, c.before, c.after) for c in d.changes] == [
        ("base-frame-changed", "base", "link1")
    ]
    no_frame = BASE.replace(BASE[BASE.index("  - add_frame:") : BASE.index("default_joint")], "")
    assert kinds(diff_text(BASE, no_frame)) == ["frame-removed"]


def test_removing_a_section_is_one_change() -> None:
    no_world = BASE.replace(
        "world_collision:\n  geometry: arm\n  buffer_distance:\n    link1: 0.01\n    link2: 0.02\n",
        "",
    )
    d = diff_text(BASE, no_world)
    assert [(c.section, c.kind) for c in d.changes] == [("world_collision", "section-removed")]
    assert "4 spheres" in d.changes[0].message


# --- output and CLI -----------------------------------------------------------------------------


def test_json_shape(runner: CliRunner, tmp_path: Path) -> None:
    a = write(tmp_path, "a.xrdf", BASE)
    b = write(tmp_path, "b.xrdf", BASE.replace("radius: 0.05}", "radius: 0.06}"))
    result = runner.invoke(app, ["diff", str(a), str(b), "--format", "json"])
    assert result.exit_code == 1
    doc = json.loads(result.output)
    assert set(doc) == {
        "schema",
        "version",
        "a",
        "b",
        "tolerance",
        "equal",
        "summary",
        "sections",
        "notes",
    }
    assert (doc["schema"], doc["version"], doc["equal"]) == ("xrdf-diff", 1, False)
    assert doc["a"] == {"path": str(a), "format_version": "2.0"}
    assert doc["summary"] == {
        "changes": 1,
        "major": 1,
        "minor": 0,
        "notes": 0,
        "sections": {"geometry": 1},
    }
    (change,) = doc["sections"][0]["changes"]
    assert set(change) == {
        "section",
        "kind",
        "level",
        "subject",
        "key_path",
        "scope",
        "message",
        "before",
        "after",
        "counts",
        "details",
    }
    assert change["counts"] == {"radius_changed": 1}
    assert change["details"] == [
        {
            "kind": "radius-changed",
            "before": {"center": [0.1, 0.0, 0.0], "radius": 0.05},
            "after": {"center": [0.1, 0.0, 0.0], "radius": 0.06},
        }
    ]
    assert change["key_path"] == "geometry.arm.spheres.link2"
    assert json.loads(render_json(diff_files(a, a)))["equal"] is True


def test_cli_exit_codes_and_tolerance(runner: CliRunner, tmp_path: Path) -> None:
    a = write(tmp_path, "a.xrdf", BASE)
    b = write(tmp_path, "b.xrdf", BASE.replace("j1: 0.5", "j1: 0.5000001"))
    assert runner.invoke(app, ["diff", str(a), str(a)]).exit_code == 0
    result = runner.invoke(app, ["diff", str(a), str(b)])
    assert result.exit_code == 1
    assert "default_joint_positions: 1 change" in result.output
    assert "j1 = 0.5 -> 0.5000001" in result.output
    assert runner.invoke(app, ["diff", str(a), str(b), "--tolerance", "1e-6"]).exit_code == 0
    bad_tol = runner.invoke(app, ["diff", str(a), str(b), "--tolerance", "-1"])
    assert bad_tol.exit_code == 2 and "tolerance" in bad_tol.output


@pytest.mark.parametrize(
    "content",
    [
        "format: xrdf\nformat_version: 2.0\ncspace: [\n",  # YAML syntax error
        "format: xrdf\nformat_version: 3.0\n",  # unsupported version
        "format: xrdf\nformat_version: 2.0\nworld_collision: {geometry: nope}\n",  # no group
        None,  # missing file
    ],
)
def test_bad_input_is_exit_2_with_one_line_error(
    runner: CliRunner, tmp_path: Path, content: str | None
) -> None:
    good = write(tmp_path, "good.xrdf", BASE)
    bad = tmp_path / "bad.xrdf"
    if content is not None:
        bad.write_text(content, encoding="utf-8")
    for args in ([str(good), str(bad)], [str(bad), str(good)]):
        result = runner.invoke(app, ["diff", *args])
        assert result.exit_code == 2, result.output
        assert result.output.startswith(f"error: {bad}")
        assert result.output.count("\n") == 1
        assert "Traceback" not in result.output
    with pytest.raises(XrdfToolsError):
        diff_files(good, bad)


def test_help(runner: CliRunner) -> None:
    result = runner.invoke(app, ["diff", "--help"])
    assert result.exit_code == 0
    assert "--tolerance" in result.output and "--format" in result.output


def test_negative_tolerance_is_rejected_by_the_library() -> None:
    x = parse_xrdf(BASE)
    with pytest.raises(ValueError, match="tolerance"):
        diff_xrdf(x, x, -1.0)


def test_set_base_frame_on_the_urdf_root_is_no_change() -> None:
    from tests.paths import UR10E_URDF
    from xrdf_tools.robot.urdf_source import load_urdf, root_link

    root = root_link(load_urdf(UR10E_URDF))
    assert root == "base_link"
    with_base = parse_xrdf(
        "format: xrdf\nformat_version: 2.0\nmodifiers:\n  - set_base_frame: base_link\n"
    )
    without = parse_xrdf("format: xrdf\nformat_version: 2.0\n")
    unaware = diff_xrdf(with_base, without)
    assert [c.kind for c in unaware.changes] == ["base-frame-changed"]
    aware = diff_xrdf(with_base, without, root_frame=root)
    assert aware.is_equal
    assert [n.kind for n in aware.notes] == ["base-frame-is-root"]
    moved = parse_xrdf(
        "format: xrdf\nformat_version: 2.0\nmodifiers:\n  - set_base_frame: shoulder_link\n"
    )
    assert [c.kind for c in diff_xrdf(without, moved, root_frame=root).changes] == [
        "base-frame-changed"
    ]


def test_a_default_written_at_its_unset_value_is_no_change_with_the_urdf(
    runner: CliRunner, tmp_path: Path
) -> None:
    """An unset default is 0 clamped to the joint's limits. A round trip through export curobo
    and convert --curobo writes 0.0 for a gripper finger cuRobo locks (ARX R5a's joint7,
    limits [0, 0.044]): with --urdf that is no change; 0.0 on a joint whose limits exclude 0,
    or another value, still is."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(
        '<robot name="arm"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="finger" type="prismatic"><parent link="a"/><child link="b"/>'
        '<limit lower="0" upper="0.044" effort="1" velocity="1"/></joint>'
        '<joint name="lifted" type="prismatic"><parent link="a"/><child link="c"/>'
        '<limit lower="0.2" upper="0.5" effort="1" velocity="1"/></joint></robot>'
    )
    head = "format: xrdf\nformat_version: 1.0\n"
    unset = tmp_path / "unset.xrdf"
    unset.write_text(head)
    zero = tmp_path / "zero.xrdf"
    zero.write_text(head + "default_joint_positions: {finger: 0.0}\n")
    r = runner.invoke(app, ["diff", str(unset), str(zero), "--urdf", str(urdf)])
    assert r.exit_code == 0, r.output
    assert "finger = 0.0 added: the value it has unset" in r.output
    r = runner.invoke(app, ["diff", str(zero), str(unset), "--format", "json", "--urdf", str(urdf)])
    assert r.exit_code == 0, r.output
    notes = json.loads(r.output[r.output.index("{") :])["notes"]
    assert [n["kind"] for n in notes] == ["default-as-unset"]
    assert runner.invoke(app, ["diff", str(unset), str(zero)]).exit_code == 1  # no URDF
    for text in ("{finger: 0.01}", "{lifted: 0.0}"):
        other = tmp_path / "other.xrdf"
        other.write_text(head + f"default_joint_positions: {text}\n")
        r = runner.invoke(app, ["diff", str(unset), str(other), "--urdf", str(urdf)])
        assert r.exit_code == 1 and "default-added" not in r.output, r.output
        assert "added (was unset: 0 clamped to the limits)" in r.output


def test_many_defaults_written_at_their_unset_value_are_one_note_line(
    runner: CliRunner, tmp_path: Path
) -> None:
    """The PR2's round trip through export curobo wrote a default for each of the 32 joints
    cuRobo locks (wheels, head, the other arm, grippers): 32 note lines, each saying it changes
    nothing, before `identical`. Past three they are one line naming the joints; JSON keeps
    one note per joint."""
    joints = [f"j{i}" for i in range(8)]
    links = "".join(f'<link name="l{i}"/>' for i in range(9))
    urdf = tmp_path / "many.urdf"
    urdf.write_text(
        f'<robot name="many">{links}'
        + "".join(
            f'<joint name="{j}" type="continuous"><parent link="l{i}"/><child link="l{i + 1}"/>'
            "</joint>"
            for i, j in enumerate(joints)
        )
        + "</robot>"
    )
    head = "format: xrdf\nformat_version: 1.0\n"
    unset = tmp_path / "unset.xrdf"
    unset.write_text(head)
    zeros = tmp_path / "zeros.xrdf"
    zeros.write_text(
        head + "default_joint_positions: {" + ", ".join(f"{j}: 0.0" for j in joints) + "}\n"
    )
    r = runner.invoke(app, ["diff", str(unset), str(zeros), "--urdf", str(urdf)])
    assert r.exit_code == 0, r.output
    (line,) = [ln for ln in r.output.splitlines() if "default positions added" in ln]
    assert line.startswith("  i 8 default positions added at the value each joint has unset")
    assert "j0, j1, j2, j3, j4, j5 and 2 more" in line
    assert "the value it has unset (0 clamped" not in r.output  # no line per joint
    r = runner.invoke(app, ["diff", str(zeros), str(unset), "--urdf", str(urdf)])
    assert "8 default positions removed at the value" in r.output, r.output
    r = runner.invoke(
        app, ["diff", str(unset), str(zeros), "--urdf", str(urdf), "--format", "json"]
    )
    notes = json.loads(r.output[r.output.index("{") :])["notes"]
    assert [n["subject"] for n in notes] == joints


def test_every_diff_format_is_one_entry_of_the_renderer_table() -> None:
    from xrdf_tools.cli.commands.diff import DiffFormat
    from xrdf_tools.diff.render import RENDERERS

    assert list(RENDERERS) == [f.value for f in DiffFormat]
