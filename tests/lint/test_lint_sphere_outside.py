"""``sphere-outside-geometry`` on real robots and when link geometry cannot be loaded."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.diagnostics import Diagnostic
from xrdf_tools.lint import lint_text
from xrdf_tools.lint.rules import sphere_outside_geometry as rule

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
UR10E = FIXTURES / "ur10e"
ARM_URDF = FIXTURES / "lint" / "sphere-outside-geometry" / "arm.urdf"
LINK3_SPHERE = "      panda_link3:\n        - center: [0.0, 0.0, -0.06]\n"


def _run(text: str, urdf: Path, path: str = "robot.xrdf") -> list[Diagnostic]:
    return lint_text(text, path, urdf=urdf, rules=(rule.RULE,))


def test_real_panda_spheres_pass_and_a_sphere_moved_half_a_metre_is_flagged() -> None:
    urdf = robot_urdf("panda")
    text = PANDA_XRDF.read_text()
    assert _run(text, urdf) == []
    assert LINK3_SPHERE in text
    moved = text.replace(LINK3_SPHERE, LINK3_SPHERE.replace("[0.0, 0.0,", "[0.5, 0.0,"))
    (d,) = _run(moved, urdf)
    line = text[: text.index(LINK3_SPHERE)].count("\n") + 2
    assert (d.rule, d.severity.value, d.line, d.col) == (rule.RULE_ID, "warning", line, 19)
    assert "sphere 0 of link 'panda_link3'" in d.message and " mm outside" in d.message
    assert d.key_path == "geometry.panda_spheres.spheres.panda_link3[0].center"


def test_ur10e_without_meshes_is_one_warning_or_with_allow_missing_meshes_one_info() -> None:
    text = (UR10E / "ur10e.xrdf").read_text()
    diags = _run(text, UR10E / "ur10e.urdf")
    assert [d.severity.value for d in diags] == ["warning"]
    assert "not checked" in diags[0].message and "mesh file not found" in diags[0].message
    assert "--package-path" in diags[0].message
    allowed = lint_text(
        text, "r.xrdf", urdf=UR10E / "ur10e.urdf", rules=(rule.RULE,), allow_missing_meshes=True
    )
    assert [d.severity.value for d in allowed] == ["info"]
    assert "mesh file not found" in allowed[0].message


def test_an_unreadable_mesh_is_a_warning_even_with_allow_missing_meshes(tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="a"><collision><geometry><mesh filename="bad.stl"/>'
        "</geometry></collision></link></robot>"
    )
    (tmp_path / "bad.stl").write_bytes(b"solid x\nfacet normal 0 0 1\n outer loop\n")  # cut
    text = (
        "format: xrdf\nformat_version: 2.0\nworld_collision:\n  geometry: g\ngeometry:\n"
        "  g:\n    spheres:\n      a:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n"
    )
    for allow in (False, True):
        (d,) = lint_text(text, "r.xrdf", urdf=urdf, rules=(rule.RULE,), allow_missing_meshes=allow)
        assert d.severity.value == "warning" and "cannot be read" in d.message
        assert "bad.stl" in d.message


def test_a_partly_loadable_link_is_skipped_not_checked_against_the_parts_that_loaded(
    tmp_path: Path,
) -> None:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="a">'
        '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>'
        '<collision><origin xyz="1 0 0"/><geometry><mesh filename="gone.stl"/></geometry>'
        "</collision></link></robot>"
    )
    text = (
        "format: xrdf\nformat_version: 2.0\nworld_collision:\n  geometry: g\ngeometry:\n"
        "  g:\n    spheres:\n      a:\n        - center: [1.0, 0.0, 0.0]\n          radius: 0.05\n"
    )
    (d,) = _run(text, urdf)
    assert (d.severity.value, d.line, d.col) == ("warning", 8, 7)
    assert "gone.stl" in d.message


def test_a_failing_geometry_loader_never_crashes_the_rule(monkeypatch: pytest.MonkeyPatch) -> None:
    import xrdf_tools.robot.link_geometry as geometry

    def boom(*args: object, **kwargs: object) -> object:
        raise RuntimeError("no trimesh today")

    monkeypatch.setattr(rule, "_CACHE", {})
    monkeypatch.setattr(geometry, "link_geometry", boom)
    (d,) = _run((FIXTURES / "lint" / "sphere-outside-geometry" / "fail.xrdf").read_text(), ARM_URDF)
    assert d.severity.value == "info" and "no trimesh today" in d.message


def test_box_distance_and_threshold() -> None:
    box = rule.Box((0.0, 0.0, 0.0), (0.4, 0.1, 0.1))
    assert box.distance((0.2, 0.05, 0.05)) == 0.0
    assert box.distance((0.7, 0.5, 0.1)) == pytest.approx(0.5)
    assert box.threshold == pytest.approx(0.1)
    assert rule.Box((0.0, 0.0, 0.0), (0.01, 0.01, 0.01)).threshold == rule.MIN_GAP


def test_the_rule_module_imports_no_mesh_library() -> None:
    code = (
        "import sys\nimport xrdf_tools.lint.rules.sphere_outside_geometry\n"
        "print([m for m in ('trimesh', 'yourdfpy', 'lxml') if m in sys.modules])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("name", ["kinova", "romeo", "pr2"])
def test_boxes_of_closed_parts_are_the_bounds_of_the_fitters_solids(name: str) -> None:
    """Links whose parts each enclose a volume take the parts' own bounds (no hulls, no
    union); the others the fitter's solid. Both give the boxes of the fitter's solids of
    every link (robots with closed and open meshes, several parts per link)."""
    from xrdf_tools.robot.xacro_source import load_robot

    fast = load_robot(robot_urdf(name))
    expected = dict(fast.collision_counts)
    boxes = rule._load_boxes(fast, expected)
    solids = load_robot(robot_urdf(name))
    solids.derived["link_solids"] = {}  # as after a fit: every box from the fitter's solids
    assert boxes == rule._load_boxes(solids, expected)
    from xrdf_tools.robot.link_geometry import link_geometry

    closed = rule._closed_part_boxes(link_geometry(fast, "auto"), expected)
    assert 0 < len(closed) <= len(expected) and all(
        isinstance(b, rule.Box) for b in closed.values()
    )


def test_without_the_fit_extra_in_a_pre_commit_hook_the_packages_to_add_are_named_in_full(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The hook installs the light default: the info said which packages to add to the hook's
    additional_dependencies, but cut at 160 characters it ended 'add its packages to the
    hook's additional_depende...)', the list gone."""
    import xrdf_tools.robot.link_geometry as geometry
    from xrdf_tools.util.extras import extra_requirements, require

    def no_fit_extra(*args: object, **kwargs: object) -> object:
        require(["no_such_module_for_xrdf"], "fit", "reading link geometry")
        raise AssertionError("require raises")

    monkeypatch.setenv("PRE_COMMIT", "1")
    monkeypatch.setattr(rule, "_CACHE", {})
    monkeypatch.setattr(geometry, "link_geometry", no_fit_extra)
    (d,) = _run((FIXTURES / "lint" / "sphere-outside-geometry" / "fail.xrdf").read_text(), ARM_URDF)
    packages = ", ".join(extra_requirements("fit"))
    assert d.severity.value == "info"
    assert d.message.endswith(f"additional_dependencies: [{packages}])"), d.message
