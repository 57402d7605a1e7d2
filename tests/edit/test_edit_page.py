"""The ``xrdf edit`` page object without a browser: it only drives the editing state.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf. Needs viser.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.browser import free_port
from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.edit import EditRobot, EditState, SetBuffer, SetDefaults, SetRadius
from xrdf_tools.edit.markup import code, text
from xrdf_tools.edit.view import CHECKED_RGB, SELECTED_RGB
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.util.numbers import REPORT_SAMPLES
from xrdf_tools.xrdf.io import load_xrdf

pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"


@pytest.mark.slow
def test_page_poses_configs_edits_and_saves_only_its_target(tmp_path: Path) -> None:
    from xrdf_tools.edit.page import EditorPage

    robot = load_robot(robot_urdf("panda"))
    x = load_xrdf(PANDA_XRDF)
    target = tmp_path / "panda.xrdf"
    target.write_bytes(PANDA_XRDF.read_bytes())
    configs = tmp_path / "q.csv"
    configs.write_text(
        "panda_joint1,panda_joint2,panda_joint3,panda_joint4,panda_joint5,panda_joint6,"
        "panda_joint7\n0,-1.3,0,-2.5,0,1.5,0.8\n0,1.0,0,-2.5,0,1.5,0.8\n"
    )
    page = EditorPage(robot, EditState.start(x), target=target, port=free_port(), configs=configs)
    try:
        assert page.url.startswith("http://127.0.0.1:")
        # the link the page shows is the one a buffer is typed for
        assert page.selected == (page.panels.spheres.link.value, None)
        first = page.panels.spheres.link.value
        page.panels.mask._set_buffer(0.01)
        sc = page.state.xrdf.self_collision
        assert sc is not None and sc.buffer_distance[first] == 0.01
        page.undo()
        assert page.configs is not None  # 7 arm joints and the finger, defaults filled in
        assert page.configs.shape == (2, len(page.robot.kin.actuated_joints))
        reference = EditRobot(robot, x)
        page.set_pose(page.configs[1])
        want = reference.collisions(x, page.configs[1])
        assert want.checked and page.collisions.pairs() == want.pairs()
        c = want.checked[0]
        assert CHECKED_RGB in page.view.colors[c.frame_a]
        assert np.isclose(page.panels.sliders[1].value, 1.0)
        page.pick("panda_link4", 1)
        assert page.view.colors["panda_link4"][1] == SELECTED_RGB
        assert not page.apply(SetRadius("panda_link4", 1, -1.0))
        assert "not done" in page.message and not page.state.dirty
        # a sphere larger than the slider's usual end is shown as it is, not clamped to it
        assert page.apply(SetRadius("panda_link4", 1, 0.45))
        assert page.panels.spheres.radius.value == 0.45 and page.panels.spheres.radius.max >= 0.45
        page.undo()
        assert not page.state.dirty
        # the buffered radii shown follow a buffer edit (and its undo)
        page.view.set_buffered(True, page.state.xrdf, page.state.group)
        assert x.self_collision is not None
        b0 = x.self_collision.buffer_distance.get("panda_link4", 0.0)
        r = page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"][1].radius
        assert page.apply(SetBuffer("panda_link4", b0 + 0.02))
        assert page.view.buffers["panda_link4"][1].radius == pytest.approx(r + b0 + 0.02)
        page.undo()
        assert page.view.buffers["panda_link4"][1].radius == pytest.approx(r + b0)
        page.view.set_buffered(False, page.state.xrdf, page.state.group)
        assert page.apply(SetRadius("panda_link4", 1, 0.05))
        assert target.read_bytes() == PANDA_XRDF.read_bytes()
        # the review goes from the file read to the file Confirm writes (-o: another file)
        page.panels.review()
        shown = page.panels.diff.content
        assert f"--- {PANDA_XRDF}" in shown and f"+++ {target}" in shown, shown
        warning = page.overwrite_warning()  # -o names another file, which exists
        assert warning == f"{target} exists; saving replaces it" and text(warning) in shown
        assert page.save() and not page.state.dirty
        page.apply(SetRadius("panda_link4", 1, 0.04))
        page.panels.review()
        assert f"--- {target}" in page.panels.diff.content  # now the saved file
        assert "Warning" not in page.panels.diff.content
        # another program rewrites the file: the review says Save would replace its change
        target.write_text("# tuned by hand\n" + target.read_text())
        page.panels.review()
        warning = page.overwrite_warning()
        assert warning == f"{target} changed on disk since the page read it; saving replaces it"
        assert text(warning) in page.panels.diff.content
        page.undo()
        # a change below the diff's tolerance: unsaved, and the review says why it shows none
        tiny = dict(page.state.xrdf.default_joint_positions or {}) | {"panda_joint1": 1e-320}
        assert page.apply(SetDefaults(tiny)) and page.state.dirty
        page.panels.review()
        assert "No semantic change" in page.panels.diff.content
        page.undo()
        saved = load_xrdf(target).resolved_spheres("panda_spheres")["panda_link4"][1]
        assert saved.radius == 0.05
        page.readonly = True
        page.apply(SetRadius("panda_link4", 1, 0.06))
        assert not page.save() and "read-only" in page.message
        assert load_xrdf(target).resolved_spheres("panda_spheres")["panda_link4"][1] == saved
        # connect the selected sphere to another with a chain; scale the link's spheres
        spheres = page.panels.spheres

        def link4() -> tuple[Any, ...]:
            return tuple(page.state.xrdf.resolved_spheres("panda_spheres")["panda_link4"])

        n = len(link4())
        page.pick("panda_link4", 0)
        spheres.other.box.value, spheres.between.box.value = "2", "3"
        spheres._connect()
        assert len(link4()) == n + 3 and "connect panda_link4[0]" in page.message
        assert page.selected == ("panda_link4", 0)
        radii = [s.radius for s in link4()]
        spheres.factor.box.value = "5e-1"
        spheres._scale()
        assert [s.radius for s in link4()] == pytest.approx([r * 0.5 for r in radii], abs=1e-6)
        page.pick("panda_link4", None)
        spheres._connect()
        assert "select a sphere first" in page.message
        # a typed centre past twice the robot's reach is refused (15, typing 15e-3)
        page.pick("panda_link4", 1)
        before = link4()[1].center
        spheres.set_center(0, 15.0)
        assert link4()[1].center == before and page.message.startswith("not moved: 15 m")
        spheres.set_center(0, 0.001)
        assert link4()[1].center == (0.001, *before[1:])
    finally:
        page.close()


@pytest.mark.slow
def test_page_report_and_its_recommended_mask(tmp_path: Path) -> None:
    from xrdf_tools.edit.page import EditorPage
    from xrdf_tools.report import recommended_xrdf

    robot = load_robot(robot_urdf("panda"))
    x = load_xrdf(PANDA_XRDF)
    page = EditorPage(robot, EditState.start(x), target=tmp_path / "out.xrdf", port=free_port())
    try:
        mask = page.panels.mask
        assert mask.samples.read() == REPORT_SAMPLES  # as `xrdf report` samples
        assert mask.samples.box.value == "100000"
        mask.samples.box.value = "3e2"
        mask.run_report()
        report = mask.report
        assert report is not None and report.samples == 300
        assert "| pair | rate | verdict | proof | mask |" in mask.summary.content
        top = max(report.pairs, key=lambda p: p.rate or 0.0)
        assert f"{code(top.frame_a)} ↔ {code(top.frame_b)}" in mask.summary.content
        mask._apply_mask()
        assert page.state.xrdf == recommended_xrdf(x, report)
        # 300 samples leave pairs "never seen" that collide rarely: said with the mask
        never = sum(p.classification == "never" for p in report.pairs)
        assert never > 0
        assert page.state.undo_label == (
            "apply the report's recommended mask (from 300 samples: "
            f"{never} pair(s) never seen colliding may collide rarely; xrdf report samples "
            f"{REPORT_SAMPLES:,})"
        )
        mask._apply_mask()  # again: the page says so rather than keep the last message
        assert page.message.startswith("no change: apply the report's recommended mask")
        page.undo()
        page.apply(SetRadius("panda_link4", 1, 0.05))  # the report is of an earlier version
        mask._apply_mask()
        assert page.message.startswith("done: apply the report's recommended mask")
        assert "earlier version" in page.message
    finally:
        page.close()


#: Links whose names only differ by the scene tree's separator, and names with spaces, a colon
#: and a non-ASCII letter (URDF allows any string).
ODD_URDF = """<?xml version="1.0"?>
<robot name="odd">
  <link name="base"/>
  <link name="a/b"/>
  <link name="a_b"/>
  <link name="ü link"/>
  <joint name="j 1" type="revolute"><parent link="base"/><child link="a/b"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j:2" type="revolute"><parent link="a/b"/><child link="a_b"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="fixed"><parent link="a_b"/><child link="ü link"/>
    <origin xyz="0 0 0.32"/></joint>
</robot>
"""
ODD_XRDF = """format: xrdf
format_version: 1.0
cspace:
  joint_names: ["j 1", "j:2"]
  acceleration_limits: [10.0, 10.0]
  jerk_limits: [1000.0, 1000.0]
tool_frames: ["ü link"]
collision:
  geometry: s
self_collision:
  geometry: s
  ignore: {base: [a/b]}
geometry:
  s:
    spheres:
      a/b: [{center: [0.0, 0.0, 0.1], radius: 0.04}]
      a_b: [{center: [0.0, 0.0, 0.1], radius: 0.04}, {center: [0.0, 0.0, 0.2], radius: 0.04}]
      "ü link": [{center: [0.0, 0.0, 0.0], radius: 0.05}]
"""


def test_frames_named_like_the_scene_tree_keep_their_own_spheres(tmp_path: Path) -> None:
    """``a/b`` and ``a_b`` are two links: each keeps its spheres, pose and gizmo on the page
    (one scene node for both lost a link's spheres and stopped the page at start)."""
    from xrdf_tools.edit.page import EditorPage

    (tmp_path / "odd.urdf").write_text(ODD_URDF, encoding="utf-8")
    (tmp_path / "odd.xrdf").write_text(ODD_XRDF, encoding="utf-8")
    robot = load_robot(tmp_path / "odd.urdf")
    x = load_xrdf(tmp_path / "odd.xrdf")
    page = EditorPage(robot, EditState.start(x), target=tmp_path / "odd.xrdf", port=free_port())
    try:
        drawn = {frame: len(handles) for frame, handles in page.view.spheres.items()}
        assert drawn == {"a/b": 1, "a_b": 2, "ü link": 1}
        names = {h.name for handles in page.view.spheres.values() for h in handles}
        assert len(names) == 4
        page.pick("a/b", 0)
        assert page.panels.spheres.gizmo is not None and page.panels.spheres.gizmo_for == ("a/b", 0)
        assert page.apply(SetRadius("a/b", 0, 0.03)) and page.save()
        saved = load_xrdf(tmp_path / "odd.xrdf").resolved_spheres("s")
        assert [s.radius for s in saved["a/b"]] == [0.03] and len(saved["a_b"]) == 2
    finally:
        page.close()


@pytest.mark.slow
def test_review_of_a_draft_says_what_it_writes(tmp_path: Path) -> None:
    """A draft (never saved: an empty saved document) has no old file to diff against: the
    review names the new file and its contents, not a change from an 'XRDF 2.0' that is not
    there."""
    from xrdf_tools.edit.page import EditorPage
    from xrdf_tools.xrdf.model import Xrdf

    robot = load_robot(robot_urdf("panda"))
    x = load_xrdf(PANDA_XRDF)
    target = tmp_path / "new.xrdf"
    page = EditorPage(robot, EditState.start(x, saved=Xrdf()), target=target, port=free_port())
    try:
        page.panels.review()
        shown = page.panels.diff.content
        n = sum(len(v) for v in x.resolved_spheres("panda_spheres").values())
        assert shown.startswith(f"**New file** {code(target)}: ")
        assert text(f"XRDF {x.format_version}, 7 c-space joint(s), {n} sphere(s)") in shown
        assert "---" not in shown and page.panels.confirm.visible
        target.write_text("x")  # another program creates the file meanwhile
        page.panels.review()
        assert page.panels.diff.content.startswith("**Warning**: ")
        page.panels._confirm()
        assert load_xrdf(target) == x and not page.state.dirty
    finally:
        page.close()
