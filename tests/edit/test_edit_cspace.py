"""The c-space and tool frames in ``xrdf edit``: which joints the planner moves, their limits,
and the frames a goal can be put on -- as edits, in the robot the page poses and in the page.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf (seven arm joints
in the c-space; ``panda_finger_joint1`` held at its default, ``panda_finger_joint2`` mimics it).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.diff import diff_xrdf
from xrdf_tools.edit import EditError, EditRobot, EditState, SetCspace, SetToolFrames, save
from xrdf_tools.edit.markup import code
from xrdf_tools.lint import lint_text
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import (
    CollisionSection,
    CSpace,
    FrozenMap,
    GeometryGroup,
    SelfCollisionSection,
    Sphere,
    Xrdf,
)

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
ARM = tuple(f"panda_joint{k}" for k in range(1, 8))


@pytest.fixture(scope="module")
def panda() -> tuple[Any, Xrdf]:
    return load_robot(robot_urdf("panda")), load_xrdf(PANDA_XRDF)


def errors(text: str, robot: Any) -> list[str]:
    return [
        d.message
        for d in lint_text(text, "panda.xrdf", urdf_model=robot)
        if d.severity.name == "ERROR"
    ]


@contextmanager
def served(robot: Any, x: Xrdf, target: Path) -> Iterator[Any]:
    """The editor page on ``x`` (Save would write ``target``), closed after; needs viser."""
    pytest.importorskip("viser", reason="xrdf edit needs viser (the edit extra)")
    from tests.browser import free_port
    from xrdf_tools.edit.page import EditorPage

    page = EditorPage(robot, EditState.start(x), target=target, port=free_port())
    try:
        yield page
    finally:
        page.close()


def test_choices_are_the_joints_a_cspace_can_hold_in_urdf_order(panda: tuple[Any, Xrdf]) -> None:
    robot, x = panda
    er = EditRobot(robot, x)
    choices = er.cspace_joint_choices()
    # the mimic finger is no coordinate; every other movable joint is, in the URDF's order
    urdf_order = [n for n, j in robot.joints.items() if j.is_actuated]
    assert choices == tuple(urdf_order) == (*ARM, "panda_finger_joint1")
    assert "panda_finger_joint2" not in choices


def test_a_joint_taken_in_goes_to_its_urdf_place_with_its_limits(panda: tuple[Any, Xrdf]) -> None:
    robot, x = panda
    er = EditRobot(robot, x)
    without3 = er.cspace_with(x, "panda_joint3", included=False, acceleration=1, jerk=1)
    assert without3.joint_names == tuple(n for n in ARM if n != "panda_joint3")
    st = EditState.start(x).apply(SetCspace(without3))
    back = er.cspace_with(st.xrdf, "panda_joint3", included=True, acceleration=7.5, jerk=250.0)
    assert back.joint_names == ARM  # between joint2 and joint4, not at the end
    k = ARM.index("panda_joint3")
    assert back.acceleration_limits[k] == 7.5 and back.jerk_limits[k] == 250.0
    others = [i for i in range(7) if i != k]
    assert x.cspace is not None
    assert [back.acceleration_limits[i] for i in others] == [
        x.cspace.acceleration_limits[i] for i in others
    ]
    finger = er.cspace_with(x, "panda_finger_joint1", included=True, acceleration=2, jerk=20)
    assert finger.joint_names == (*ARM, "panda_finger_joint1")
    # a joint already in keeps its place and takes the new limits
    again = er.cspace_with(x, "panda_joint5", included=True, acceleration=3, jerk=30)
    assert again.joint_names == ARM and again.acceleration_limits[4] == 3


def test_cspace_edit_saves_lints_and_undoes(panda: tuple[Any, Xrdf], tmp_path: Path) -> None:
    robot, x = panda
    er = EditRobot(robot, x)
    cs = er.cspace_with(x, "panda_finger_joint1", included=True, acceleration=2.0, jerk=20.0)
    st = EditState.start(x).apply(SetCspace(cs, "take the finger in"))
    st = st.apply(SetToolFrames(("panda_hand", "panda_link7")))
    assert st.undo_label == "tool frames to panda_hand, panda_link7"
    target = tmp_path / "panda.xrdf"
    save(st, target)
    back = load_xrdf(target)
    assert back.cspace == cs and back.tool_frames == ("panda_hand", "panda_link7")
    assert errors(target.read_text(), robot) == []
    sections = {c.section for c in diff_xrdf(x, back).changes}
    assert sections == {"cspace", "tool_frames"}
    assert st.undo().undo().xrdf == x


@pytest.mark.parametrize(
    ("cspace", "message"),
    [
        (CSpace(("panda_joint1", "panda_joint1"), (1.0, 1.0), (1.0, 1.0)), "named twice"),
        (CSpace(("panda_joint1",), (0.0,), (1.0,)), "more than 0"),
        (CSpace(("panda_joint1",), (1.0,), (-5.0,)), "more than 0"),
        (CSpace(("panda_joint1",), (float("nan"),), (1.0,)), "cannot be saved"),
        (CSpace(("panda_joint1",), (1.0,), (float("inf"),)), "cannot be saved"),
        (CSpace(("panda_joint1", "panda_joint2"), (1.0,), (1.0, 1.0)), "1 acceleration limit"),
    ],
)
def test_a_cspace_no_reader_can_take_is_refused(
    panda: tuple[Any, Xrdf], cspace: CSpace, message: str
) -> None:
    with pytest.raises(EditError, match=message):
        EditState.start(panda[1]).apply(SetCspace(cspace))


def test_an_empty_cspace_is_valid_xrdf_and_saves(panda: tuple[Any, Xrdf], tmp_path: Path) -> None:
    """The spec reads an empty c-space (joint_names null or []); the library does not refuse
    what lint accepts."""
    robot, x = panda
    st = EditState.start(x).apply(SetCspace(CSpace((), (), ())))
    save(st, tmp_path / "empty.xrdf")
    assert errors((tmp_path / "empty.xrdf").read_text(), robot) == []


def test_a_tool_frame_named_twice_is_refused(panda: tuple[Any, Xrdf]) -> None:
    with pytest.raises(EditError, match="named twice"):
        EditState.start(panda[1]).apply(SetToolFrames(("panda_hand", "panda_hand")))


def test_the_robot_follows_the_documents_cspace(panda: tuple[Any, Xrdf]) -> None:
    """After a c-space edit the poses move exactly the new c-space: as a robot built from the
    edited document would."""
    robot, x = panda
    er = EditRobot(robot, x)
    cs = er.cspace_with(x, "panda_joint7", included=False, acceleration=1, jerk=1)
    cs = er.cspace_with(
        x.replace(cspace=cs), "panda_finger_joint1", included=True, acceleration=1, jerk=1
    )
    edited = EditState.start(x).apply(SetCspace(cs)).xrdf
    assert er.follow(edited) and not er.follow(edited)
    fresh = EditRobot(robot, edited)
    assert er.cspace == fresh.cspace == (*ARM[:6], "panda_finger_joint1")
    assert np.array_equal(er.cspace_index, fresh.cspace_index)
    q = er.random_pose(edited, seed=3)
    assert np.array_equal(q, fresh.random_pose(edited, seed=3))
    j7 = er.kin.actuated_index("panda_joint7")
    assert q[j7] == er.default_pose(edited)[j7] == 0.8  # held at its default
    finger = er.kin.actuated_index("panda_finger_joint1")
    lo, hi = er.kin.lower[finger], er.kin.upper[finger]
    assert lo <= q[finger] <= hi and set(er.cspace_values(q)) == set(fresh.cspace)


@pytest.mark.slow
def test_page_cspace_panel_rebuilds_the_sliders_and_tool_frames(
    panda: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    robot, x = panda
    target = tmp_path / "panda.xrdf"
    target.write_bytes(PANDA_XRDF.read_bytes())
    with served(robot, x, target) as page:
        panel = page.panels.cspace
        assert [s.label for s in page.panels.sliders] == list(ARM)
        panel.joint.value = "panda_finger_joint1"
        panel.sync()
        assert panel.member.value is False and panel.acceleration.read() == 10.0
        panel.acceleration.box.value = "3"
        before = page.state
        panel._set_limits()  # not in the c-space: said, kept for when it is taken in
        assert page.state is before and "gets these limits when taken in" in page.message
        panel.member.value = True
        panel._set_member()
        cs = page.state.xrdf.cspace
        assert cs is not None and cs.joint_names == (*ARM, "panda_finger_joint1")
        assert cs.acceleration_limits[-1] == 3.0 and cs.jerk_limits[-1] == 1000.0
        assert [s.label for s in page.panels.sliders] == [*ARM, "panda_finger_joint1"]
        assert code("panda_finger_joint1") in panel.table.content
        # the new slider poses the finger
        finger = page.robot.kin.actuated_index("panda_finger_joint1")
        q = page.q.copy()
        q[finger] = 0.01
        page.set_pose(q)
        assert page.panels.sliders[-1].value == pytest.approx(0.01)
        # a limit typed for a joint in the c-space is one undo step per joint
        panel.jerk.box.value = "50"
        panel._set_limits()
        panel.jerk.box.value = "6e1"
        panel._set_limits()
        cs = page.state.xrdf.cspace
        assert cs is not None and cs.jerk_limits[-1] == 60.0
        page.undo()
        cs = page.state.xrdf.cspace
        assert cs is not None and cs.jerk_limits[-1] == 1000.0
        # undoing the membership: the slider goes and the finger is back at its default
        page.undo()
        assert [s.label for s in page.panels.sliders] == list(ARM)
        assert page.q[finger] == page.robot.default_pose(page.state.xrdf)[finger]
        assert panel.member.value is False
        # tool frames: added and removed with the view's axes following
        panel.frame.value = "panda_link7"
        panel._tool_frames(add=True)
        assert page.state.xrdf.tool_frames == ("panda_hand", "panda_link7")
        assert page.view.shown_tool_frames == ("panda_hand", "panda_link7")
        panel.frame.value = "panda_hand"
        panel._tool_frames(add=False)
        assert page.view.shown_tool_frames == ("panda_link7",)
        # the page keeps one joint: an empty c-space is valid XRDF, but moves nothing
        for joint in ARM[:-1]:
            panel.joint.value = joint
            panel.member.value = False
            panel._set_member()
        assert page.robot.cspace == ARM[-1:] and len(page.panels.sliders) == 1
        panel.joint.value = ARM[-1]
        panel.member.value = False
        panel._set_member()
        assert "last c-space joint" in page.message and page.robot.cspace == ARM[-1:]
        assert panel.member.value is True
        assert target.read_bytes() == PANDA_XRDF.read_bytes()  # nothing saved


#: PR2's arms as ``xrdf convert --group left_arm --group right_arm`` writes them: the left arm
#: first, where the URDF has the right arm first.
PR2_ARM = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "upper_arm_roll_joint",
    "forearm_roll_joint",
    "elbow_flex_joint",
    "wrist_flex_joint",
    "wrist_roll_joint",
)


@pytest.fixture(scope="module")
def pr2_two_arms() -> tuple[Any, Xrdf]:
    """The PR2 with both arms in the c-space, left before right, each joint with its own
    limits and default (so cuRobo's URDF-order filling would pair them wrongly)."""
    robot = load_robot(robot_urdf("pr2"))
    names = tuple(f"{side}_{j}" for side in "lr" for j in PR2_ARM)
    er = EditRobot(robot, Xrdf())
    defaults = {}
    for k, n in enumerate(names):
        i = er.kin.actuated_index(n)
        lo, hi = er.kin.lower[i], er.kin.upper[i]
        defaults[n] = round(float(lo + (hi - lo) * (k + 1) / 16), 4) if np.isfinite(lo) else k / 10
    cspace = CSpace(names, tuple(1.0 + k for k in range(14)), tuple(100.0 + k for k in range(14)))
    ball = (Sphere((0.0, 0.0, 0.0), 0.05),)
    spheres = {f"{side}_forearm_link": ball for side in "lr"}
    return robot, Xrdf(
        format_version="1.0",
        cspace=cspace,
        default_joint_positions=FrozenMap(defaults),
        tool_frames=("l_wrist_roll_link", "r_wrist_roll_link"),
        self_collision=SelfCollisionSection("arms"),
        geometry=FrozenMap({"arms": GeometryGroup(FrozenMap(spheres))}),
    )


def test_a_joint_taken_back_in_stays_with_its_arm_in_a_cspace_not_in_urdf_order(
    pr2_two_arms: tuple[Any, Xrdf],
) -> None:
    """Left out and taken in again, a joint goes back next to the joints before it in URDF
    order: in a two-arm c-space listed left arm first, the right wrist goes back to the end
    of the right arm, not into the left arm."""
    robot, x = pr2_two_arms
    assert x.cspace is not None
    er = EditRobot(robot, x)
    for joint in ("r_wrist_roll_joint", "r_shoulder_pan_joint", "l_elbow_flex_joint"):
        out = er.cspace_with(x, joint, included=False, acceleration=1, jerk=1)
        k = x.cspace.joint_names.index(joint)
        a, j = x.cspace.acceleration_limits[k], x.cspace.jerk_limits[k]
        back = er.cspace_with(x.replace(cspace=out), joint, included=True, acceleration=a, jerk=j)
        assert back == x.cspace, joint
    # a joint with no c-space joint before it in URDF order goes before the one after it
    torso = er.cspace_with(x, "torso_lift_joint", included=True, acceleration=1, jerk=1)
    at = torso.joint_names.index("torso_lift_joint")
    assert torso.joint_names[at + 1] == "r_shoulder_pan_joint"  # the URDF: torso, right arm
    ordered = er.urdf_ordered(x.replace(cspace=torso))
    assert ordered is not None and ordered.joint_names[:2] == (
        "torso_lift_joint",
        "r_shoulder_pan_joint",
    )


def test_a_cspace_put_in_urdf_order_keeps_its_limits_and_lints_clean(
    pr2_two_arms: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    robot, x = pr2_two_arms
    assert x.cspace is not None
    er = EditRobot(robot, x)
    st = EditState.start(x)
    save(st, tmp_path / "left_first.xrdf")
    found = lint_text((tmp_path / "left_first.xrdf").read_text(), "a.xrdf", urdf_model=robot)
    assert "curobo-default-order" in {d.rule for d in found}
    ordered = er.urdf_ordered(x)
    assert ordered is not None
    urdf = [n for n, j in robot.joints.items() if n in x.cspace.joint_names]
    assert list(ordered.joint_names) == urdf and urdf[0] == "r_shoulder_pan_joint"
    limits = dict(zip(x.cspace.joint_names, x.cspace.acceleration_limits, strict=True))
    jerks = dict(zip(x.cspace.joint_names, x.cspace.jerk_limits, strict=True))
    assert ordered.acceleration_limits == tuple(limits[n] for n in urdf)
    assert ordered.jerk_limits == tuple(jerks[n] for n in urdf)
    st = st.apply(SetCspace(ordered))
    assert er.urdf_ordered(st.xrdf) is None
    save(st, tmp_path / "ordered.xrdf")
    found = lint_text((tmp_path / "ordered.xrdf").read_text(), "b.xrdf", urdf_model=robot)
    assert "curobo-default-order" not in {d.rule for d in found}
    assert not [c for c in diff_xrdf(x, st.xrdf).changes if "default" in str(c).lower()]


@pytest.mark.slow
def test_page_says_a_cspace_is_not_in_urdf_order_and_orders_it(
    pr2_two_arms: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    robot, x = pr2_two_arms
    with served(robot, x, tmp_path / "pr2.xrdf") as page:
        panel = page.panels.cspace
        assert panel.order.visible and "Not in URDF order" in panel.table.content
        panel._urdf_order()
        cs = page.state.xrdf.cspace
        assert cs is not None and cs.joint_names[0] == "r_shoulder_pan_joint"
        assert not panel.order.visible and "Not in URDF order" not in panel.table.content
        assert [s.label for s in page.panels.sliders] == list(cs.joint_names)
        page.undo()
        assert panel.order.visible and page.state.xrdf == x
        # a joint cuRobo would not find in its robot is taken in, with a word why
        panel.joint.value = "head_pan_joint"
        panel.member.value = True
        panel._set_member()
        assert "head_pan_joint" in page.robot.cspace and "moves no tool frame" in page.message
        panel.joint.value = "torso_lift_joint"
        panel.member.value = True
        panel._set_member()
        assert page.message == "done: take torso_lift_joint into the c-space"
        page.undo()
        page.undo()
        assert [s.label for s in page.panels.sliders] == list(x.cspace.joint_names)  # type: ignore[union-attr]


@pytest.mark.slow
def test_page_tool_frames_keep_an_end_effector(panda: tuple[Any, Xrdf], tmp_path: Path) -> None:
    """The first tool frame is the end effector: the page says which, can make another one
    first, and does not remove the last one (cuRobo's loader raises without it)."""
    robot, x = panda
    with served(robot, x, tmp_path / "p.xrdf") as page:
        panel = page.panels.cspace
        assert x.tool_frames == ("panda_hand",)
        assert "(end effector)" in panel.tools.content
        panel.frame.value = "panda_link7"
        panel._tool_frames(add=True)
        panel._tool_frames(add=True, first=True)
        assert page.state.xrdf.tool_frames == ("panda_link7", "panda_hand")
        assert panel.tools.content.startswith(f"Tool frames: {code('panda_link7')} (end effector)")
        panel._tool_frames(add=False)
        panel.frame.value = "panda_hand"
        panel._tool_frames(add=False)
        assert page.state.xrdf.tool_frames == ("panda_hand",)
        assert "last tool frame" in page.message
        save(page.state, tmp_path / "p.xrdf")
        found = lint_text((tmp_path / "p.xrdf").read_text(), "p.xrdf", urdf_model=robot)
        assert "curobo-missing-key" not in {d.rule for d in found}
        page.undo()
        assert page.state.xrdf.tool_frames == ("panda_link7", "panda_hand")


def test_the_joints_cuRobo_would_refuse_are_the_ones_lint_names(
    pr2_two_arms: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    """A joint moving no tool frame, world-collision sphere frame or added frame: the page's
    answer for every joint the c-space can hold agrees with ``xrdf lint``
    (curobo-joint-outside-tree) on the saved file holding them all."""
    robot, x = pr2_two_arms
    world = CollisionSection("arms")
    x = x.replace(world_collision=world, tool_frames=("r_wrist_roll_link",))
    er = EditRobot(robot, x)
    every = er.cspace_joint_choices()
    cs = CSpace(every, (1.0,) * len(every), (100.0,) * len(every))
    save(EditState.start(x).apply(SetCspace(cs)), tmp_path / "all.xrdf")
    found = lint_text((tmp_path / "all.xrdf").read_text(), "all.xrdf", urdf_model=robot)
    named = {
        n
        for d in found
        if d.rule == "curobo-joint-outside-tree"
        for n in every
        if f"'{n}'" in d.message
    }
    refused = {n for n in every if not er.moves_curobo_frames(x, n)}
    assert refused == named
    # the head and the laser move nothing cuRobo builds; the left arm moves its forearm's
    # spheres only up to the elbow; the right arm moves the tool frame
    assert {"head_pan_joint", "laser_tilt_mount_joint", "l_wrist_roll_joint"} <= refused
    assert not {"torso_lift_joint", "r_wrist_roll_joint", "l_shoulder_pan_joint"} & refused


@pytest.mark.slow
def test_use_pose_as_default_warns_on_a_pose_in_self_collision(
    panda: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    """The default is written either way; a colliding pose (a checked pair touching, as the
    library finds it) is said, a free one is not."""
    robot, x = panda
    reference = EditRobot(robot, x)
    free = reference.default_pose(x)
    assert not reference.collisions(x, free).checked
    hit = free.copy()
    j2 = reference.kin.actuated_index("panda_joint2")
    for k in range(18):  # raise joint 2 until a checked pair touches
        hit[j2] = round(0.1 * k, 2)
        if reference.collisions(x, hit).checked:
            break
    first = reference.collisions(x, hit).checked[0]
    with served(robot, x, tmp_path / "p.xrdf") as page:
        page.set_pose(hit)
        page.panels.use_pose_as_default()
        defaults = page.state.xrdf.default_joint_positions
        assert defaults is not None and defaults["panda_joint2"] == hit[j2]
        assert "warning: this pose is in self-collision" in page.message
        assert f"{first.frame_a} ↔ {first.frame_b}" in page.message
        page.set_pose(free)
        page.panels.use_pose_as_default()
        assert "warning" not in page.message and page.message.startswith("done:")
