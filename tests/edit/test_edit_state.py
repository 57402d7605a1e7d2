"""The editing state of ``xrdf edit`` without a browser: edits, undo/redo, collisions at a pose,
refits, the report's mask, the diff and saving.

Real inputs: the example-robot-data Panda URDF with fixtures/panda/panda.xrdf.
"""

from __future__ import annotations

import itertools
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.diff import diff_files, diff_xrdf
from xrdf_tools.edit import (
    AddSphere,
    ConnectSpheres,
    DeleteSphere,
    DuplicateSphere,
    EditError,
    EditRobot,
    EditState,
    MoveSphere,
    ReplaceSpheres,
    ScaleSpheres,
    SetBuffer,
    SetCspace,
    SetDefaults,
    SetIgnored,
    SetMask,
    SetRadius,
    SetToolFrames,
    save,
)
from xrdf_tools.lint import lint_text
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.util.frozen import FrozenMap
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import GeometryGroup, SelfCollisionSection, Sphere, Xrdf

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"


@pytest.fixture(scope="module")
def panda() -> tuple[Any, Xrdf]:
    return load_robot(robot_urdf("panda")), load_xrdf(PANDA_XRDF)


@pytest.fixture(scope="module")
def edit_robot(panda: tuple[Any, Xrdf]) -> EditRobot:
    return EditRobot(panda[0], panda[1])


def spheres_of(x: Xrdf, frame: str) -> tuple[Sphere, ...]:
    return x.resolved_spheres("panda_spheres")[frame]


# --- edits and history -----------------------------------------------------------------------
def test_sphere_edits_change_only_their_sphere(panda: tuple[Any, Xrdf]) -> None:
    x = panda[1]
    st = EditState.start(x)
    before = spheres_of(x, "panda_link3")
    st = st.apply(MoveSphere("panda_link3", 1, (0.01, 0.02, 0.03)))
    st = st.apply(SetRadius("panda_link3", 1, 0.07))
    after = spheres_of(st.xrdf, "panda_link3")
    assert after[1] == Sphere((0.01, 0.02, 0.03), 0.07)
    assert after[:1] == before[:1] and after[2:] == before[2:]
    st = st.apply(AddSphere("panda_link3", Sphere((0.0, 0.0, 0.1), 0.02)))
    st = st.apply(DuplicateSphere("panda_link3", 0))
    assert len(spheres_of(st.xrdf, "panda_link3")) == len(before) + 2
    dup = spheres_of(st.xrdf, "panda_link3")[-1]
    assert dup.radius == before[0].radius
    assert dup.center[0] == pytest.approx(before[0].center[0] + before[0].radius / 2)
    st = st.apply(DeleteSphere("panda_link3", 0))
    assert spheres_of(st.xrdf, "panda_link3")[0] == after[1]
    # other frames untouched
    for frame in ("panda_link2", "panda_hand"):
        assert spheres_of(st.xrdf, frame) == spheres_of(x, frame)


def test_undo_redo_and_merged_drags(panda: tuple[Any, Xrdf]) -> None:
    x = panda[1]
    st = EditState.start(x)
    assert not st.can_undo and not st.dirty
    for k in range(5):  # one drag: five positions, one undo step
        st = st.apply(MoveSphere("panda_link5", 0, (0.0, 0.0, 0.01 * k)), merge_key="drag")
    st = st.apply(SetRadius("panda_link5", 0, 0.09))
    assert len(st.undo_stack) == 2 and st.dirty
    assert st.undo_label is not None and st.undo_label.startswith("radius of panda_link5[0]")
    once = st.undo()
    assert spheres_of(once.xrdf, "panda_link5")[0].center == (0.0, 0.0, 0.04)
    twice = once.undo()
    assert twice.xrdf == x and not twice.dirty and twice.undo() is twice
    again = twice.redo().redo()
    assert again.xrdf == st.xrdf and not again.can_redo
    # a new edit after an undo drops the redo stack
    branch = once.apply(SetBuffer("panda_link5", 0.03))
    assert not branch.can_redo


def test_edit_that_changes_nothing_is_not_a_step(panda: tuple[Any, Xrdf]) -> None:
    st = EditState.start(panda[1])
    same = st.apply(SetIgnored("panda_hand", "panda_leftfinger", True))
    assert same is st
    c = spheres_of(panda[1], "panda_link1")[0]
    assert st.apply(MoveSphere("panda_link1", 0, c.center)) is st


def test_mask_buffer_and_default_edits(panda: tuple[Any, Xrdf]) -> None:
    x = panda[1]
    st = EditState.start(x)
    sc = x.self_collision
    assert sc is not None and sc.is_ignored("panda_link2", "panda_link1")
    # removing a pair listed under the other frame's key
    st = st.apply(SetIgnored("panda_link2", "panda_link1", False))
    new = st.xrdf.self_collision
    assert new is not None and not new.is_ignored("panda_link1", "panda_link2")
    assert new.ignore_pairs() == sc.ignore_pairs() - {frozenset(("panda_link1", "panda_link2"))}
    st = st.apply(SetIgnored("panda_link0", "panda_hand", True))
    assert st.xrdf.self_collision is not None
    assert st.xrdf.self_collision.is_ignored("panda_hand", "panda_link0")
    st = st.apply(SetBuffer("panda_link3", 0.015))
    assert st.xrdf.self_collision.buffer_distance["panda_link3"] == 0.015
    st = st.apply(SetDefaults({"panda_joint4": -1.0}))
    d = st.xrdf.default_joint_positions
    assert d is not None and d["panda_joint4"] == -1.0 and d["panda_joint2"] == -1.3
    changes = {c.section for c in st.diff().changes}
    assert changes == {"self_collision", "default_joint_positions"}


def test_refused_edits(panda: tuple[Any, Xrdf]) -> None:
    st = EditState.start(panda[1])
    n = len(spheres_of(panda[1], "panda_link1"))
    with pytest.raises(EditError, match="no sphere"):
        st.apply(MoveSphere("panda_link1", n, (0.0, 0.0, 0.0)))
    with pytest.raises(EditError, match="radius"):
        st.apply(SetRadius("panda_link1", 0, -0.5))
    with pytest.raises(EditError, match="buffer"):
        st.apply(SetBuffer("panda_link1", -0.1))
    with pytest.raises(EditError, match="two different frames"):
        st.apply(SetIgnored("panda_link1", "panda_link1", True))


@pytest.mark.parametrize(
    "edit",
    [
        MoveSphere("panda_link1", 0, (float("nan"), 0.0, 0.0)),
        MoveSphere("panda_link1", 0, (0.0, float("inf"), 0.0)),
        MoveSphere("panda_link1", 0, (0.0, 0.0, 1e9)),
        SetRadius("panda_link1", 0, float("nan")),
        SetRadius("panda_link1", 0, float("inf")),
        SetRadius("panda_link1", 0, 1e9),
        SetRadius("panda_link1", 0, 0.0),
        AddSphere("panda_link1", Sphere((0.0, 0.0, 0.0), 0.0)),
        SetBuffer("panda_link1", float("nan")),
        SetBuffer("panda_link1", float("inf")),
        SetBuffer("panda_link1", 1e9),
        SetDefaults({"panda_joint1": float("nan")}),
    ],
    ids=lambda e: e.describe(),
)
def test_values_a_saved_file_cannot_hold_are_refused(panda: tuple[Any, Xrdf], edit: Any) -> None:
    """A value the reader would refuse on loading the saved file (NaN, infinite, past its
    bounds) or lint calls an error (radius 0) is refused before it reaches the document."""
    with pytest.raises(EditError, match=r"cannot be saved|more than 0"):
        EditState.start(panda[1]).apply(edit)


def test_the_smallest_radius_the_page_offers_saves_and_reads_back(
    panda: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    st = save(
        EditState.start(panda[1]).apply(SetRadius("panda_link1", 0, 0.0005)), tmp_path / "a.xrdf"
    )
    assert load_xrdf(tmp_path / "a.xrdf").resolved_spheres(st.group) == st.xrdf.resolved_spheres(
        st.group
    )


def test_an_attach_slot_keeps_its_negative_radius_when_moved(panda: tuple[Any, Xrdf]) -> None:
    """A 1.0 file's attach slots (radius -10, what cuRobo reads as attached-object slots) can
    be moved and duplicated; only a radius the edit sets must be more than 0."""
    st = EditState.start(panda[1])
    group = st.group
    geo = dict(panda[1].geometry or {})
    spheres = dict(geo[group].spheres)
    spheres["panda_hand"] = (*spheres["panda_hand"], Sphere((0.0, 0.0, 0.0), -10.0))
    geo[group] = replace(geo[group], spheres=FrozenMap(spheres))
    st = EditState.start(panda[1].replace(geometry=FrozenMap(geo)))
    k = len(spheres["panda_hand"]) - 1
    moved = st.apply(MoveSphere("panda_hand", k, (0.0, 0.0, 0.05)))
    assert spheres_of(moved.xrdf, "panda_hand")[k] == Sphere((0.0, 0.0, 0.05), -10.0)
    copied = moved.apply(DuplicateSphere("panda_hand", k))
    assert spheres_of(copied.xrdf, "panda_hand")[-1].radius == -10.0
    bare = panda[1].replace(self_collision=None)
    with pytest.raises(EditError, match="no self_collision"):
        EditState.start(bare).apply(SetIgnored("panda_link1", "panda_link5", True))


def test_sphere_edits_land_in_the_group_that_owns_the_sphere() -> None:
    base = GeometryGroup(spheres=FrozenMap({"a": (Sphere((0.0, 0.0, 0.0), 0.1),)}))
    top = GeometryGroup(
        spheres=FrozenMap({"a": (Sphere((1.0, 0.0, 0.0), 0.2),), "b": ()}), clone=("base",)
    )
    x = Xrdf(
        geometry=FrozenMap({"top": top, "base": base}),
        self_collision=SelfCollisionSection("top"),
    )
    st = EditState.start(x)
    assert st.group == "top"
    # resolved list of 'a': top's sphere first, then base's
    st = st.apply(SetRadius("a", 1, 0.3))
    geo = st.xrdf.geometry
    assert geo is not None
    assert geo["base"].spheres["a"][0].radius == 0.3
    assert geo["top"].spheres["a"][0].radius == 0.2
    st = st.apply(ReplaceSpheres("a", (Sphere((0.0, 0.0, 0.5), 0.05),)))
    geo = st.xrdf.geometry
    assert geo is not None and "a" not in geo["base"].spheres
    assert st.xrdf.resolved_spheres("top")["a"] == (Sphere((0.0, 0.0, 0.5), 0.05),)


def test_connect_puts_a_chain_between_two_spheres() -> None:
    """Closed form: the new centres split the segment between the two into equal parts and
    the radii change linearly; the two spheres stay where they were."""
    a, b = Sphere((0.0, 0.0, 0.0), 0.02), Sphere((0.0, 0.09, 0.03), 0.05)
    x = Xrdf(
        geometry=FrozenMap({"g": GeometryGroup(spheres=FrozenMap({"finger": (a, b)}))}),
        self_collision=SelfCollisionSection("g"),
    )
    st = EditState.start(x).apply(ConnectSpheres("finger", 1, 0, 2))
    got = st.xrdf.resolved_spheres("g")["finger"]
    assert got[:2] == (a, b) and len(got) == 4
    # from sphere 1 (b) towards sphere 0 (a): thirds of the way
    for k, s in enumerate(got[2:], start=1):
        t = k / 3
        want = [bc + t * (ac - bc) for ac, bc in zip(a.center, b.center, strict=True)]
        assert s.center == pytest.approx(want, abs=1e-6)
        assert s.radius == pytest.approx(b.radius + t * (a.radius - b.radius), abs=1e-6)
    assert st.undo_label == "connect finger[1] and finger[0] with 2 sphere(s)"


def test_scale_multiplies_every_radius_of_the_link_in_every_group_holding_them() -> None:
    base = GeometryGroup(spheres=FrozenMap({"a": (Sphere((0.0, 0.0, 0.0), 0.1),)}))
    top = GeometryGroup(
        spheres=FrozenMap({"a": (Sphere((1.0, 0.0, 0.0), 0.2),), "b": (Sphere((0, 0, 0), 0.3),)}),
        clone=("base",),
    )
    x = Xrdf(geometry=FrozenMap({"top": top, "base": base}))
    st = EditState.start(x, group="top").apply(ScaleSpheres("a", 1.5))
    got = st.xrdf.resolved_spheres("top")
    assert [s.radius for s in got["a"]] == pytest.approx([0.3, 0.15])
    assert [s.center for s in got["a"]] == [(1.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
    assert got["b"] == top.spheres["b"]  # other links keep theirs


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (ConnectSpheres("panda_link1", 0, 0, 2), "two different spheres"),
        (ConnectSpheres("panda_link1", 0, 99, 2), "no sphere 99"),
        (ConnectSpheres("panda_link1", 0, 1, 0), "1 to 32"),
        (ConnectSpheres("panda_link1", 0, 1, 33), "1 to 32"),
        (ScaleSpheres("panda_link1", 0.0), "more than 0"),
        (ScaleSpheres("panda_link1", float("nan")), "cannot be saved"),
        (ScaleSpheres("no_such_link", 2.0), "no spheres to scale"),
    ],
    ids=lambda e: e if isinstance(e, str) else e.describe(),
)
def test_connect_and_scale_refuse_what_does_not_fit(
    panda: tuple[Any, Xrdf], edit: Any, message: str
) -> None:
    with pytest.raises(EditError, match=message):
        EditState.start(panda[1]).apply(edit)


# --- saving ----------------------------------------------------------------------------------
def test_save_is_canonical_byte_stable_and_lints(panda: tuple[Any, Xrdf], tmp_path: Path) -> None:
    robot, x = panda
    target = tmp_path / "panda.xrdf"
    st = EditState.start(x).apply(SetRadius("panda_link4", 0, 0.061))
    st = st.apply(SetIgnored("panda_link1", "panda_link5", True))
    saved = save(st, target)
    assert not saved.dirty and saved.can_undo  # history kept
    text = target.read_text()
    assert text == dump_xrdf(st.xrdf)
    reloaded = load_xrdf(target)
    assert diff_xrdf(st.xrdf, reloaded).is_equal
    # a second save without edits writes the same bytes
    save(EditState.start(reloaded), target)
    assert target.read_text() == text
    d = diff_files(PANDA_XRDF, target)
    assert [c.section for c in d.changes] == ["self_collision", "geometry"]
    errors = [
        e for e in lint_text(text, str(target), urdf_model=robot) if e.severity.name == "ERROR"
    ]
    assert errors == []


def test_deleting_every_sphere_of_a_link_leaves_an_empty_list_that_lint_reports(
    panda: tuple[Any, Xrdf], tmp_path: Path
) -> None:
    """``panda_link7: []`` is what the file holds: cuRobo keeps the frame in its tree and loads
    no sphere for it, and lint says so at that key (it said nothing of an empty list)."""
    robot, x = panda
    st = EditState.start(x)
    for _ in spheres_of(x, "panda_link7"):
        st = st.apply(DeleteSphere("panda_link7", 0))
    target = tmp_path / "panda.xrdf"
    save(st, target)
    text = target.read_text()
    line = next(i for i, t in enumerate(text.splitlines(), 1) if t.strip() == "panda_link7: []")
    found = [
        d
        for d in lint_text(text, str(target), urdf_model=robot, target="cumotion")
        if d.rule == "mesh-without-spheres"
    ]
    assert [(d.line, d.severity.name) for d in found] == [(line, "ERROR")]
    assert "panda_link7" in found[0].message and "empty" in found[0].message


def test_draft_state_is_dirty_until_saved(panda: tuple[Any, Xrdf], tmp_path: Path) -> None:
    st = EditState.start(panda[1], saved=Xrdf())
    assert st.dirty and not st.diff().is_equal
    out = save(st, tmp_path / "new.xrdf")
    assert not out.dirty
    assert parse_xrdf((tmp_path / "new.xrdf").read_text()) == panda[1]


# --- poses and collisions --------------------------------------------------------------------
def reference_touching(
    robot: EditRobot, x: Xrdf, q: np.ndarray[Any, Any]
) -> dict[frozenset[str], bool]:
    """Touching frame pairs by a plain loop over sphere pairs: ``{pair: masked}``."""
    sc = x.self_collision
    assert sc is not None
    poses = robot.poses(q)
    index = {f: i for i, f in enumerate(robot.frame_names)}
    world: dict[str, list[tuple[np.ndarray[Any, Any], float]]] = {}
    for frame, spheres in x.self_collision_spheres().items():
        T = poses[index[frame]]
        b = sc.buffer_distance.get(frame, 0.0)
        world[frame] = [(T[:3, :3] @ np.array(s.center) + T[:3, 3], s.radius + b) for s in spheres]
    out: dict[frozenset[str], bool] = {}
    for fa, fb in itertools.combinations(world, 2):
        for (ca, ra), (cb, rb) in itertools.product(world[fa], world[fb]):
            if float(np.sum((ca - cb) ** 2)) < (ra + rb) ** 2:
                out[frozenset((fa, fb))] = sc.is_ignored(fa, fb)
                break
    return out


def test_collisions_match_a_plain_loop(edit_robot: EditRobot, panda: tuple[Any, Xrdf]) -> None:
    x = panda[1]
    poses = [edit_robot.default_pose(x)] + [edit_robot.random_pose(x, s) for s in range(12)]
    seen_checked = 0
    for q in poses:
        got = edit_robot.collisions(x, q)
        want = reference_touching(edit_robot, x, q)
        assert {frozenset((c.frame_a, c.frame_b)): c.masked for c in got.contacts} == want
        seen_checked += len(got.checked)
        for c in got.checked:  # the worst sphere pair is among the highlighted spheres
            assert c.sphere_a in got.spheres[c.frame_a]
            assert c.sphere_b in got.spheres[c.frame_b]
    assert seen_checked > 0  # some random pose really collides


def test_unmasking_a_touching_pair_turns_it_into_a_collision(
    edit_robot: EditRobot, panda: tuple[Any, Xrdf]
) -> None:
    x = panda[1]
    q = edit_robot.default_pose(x)
    before = edit_robot.collisions(x, q)
    assert before.checked == () and frozenset(("panda_link1", "panda_link2")) in before.pairs()
    x2 = EditState.start(x).apply(SetIgnored("panda_link1", "panda_link2", False)).xrdf
    after = edit_robot.collisions(x2, q)
    assert after.pairs(masked=False) == {frozenset(("panda_link1", "panda_link2"))}
    c = after.checked[0]
    assert c.sphere_a in after.spheres[c.frame_a] and c.sphere_b in after.spheres[c.frame_b]
    assert set(after.spheres) == {"panda_link1", "panda_link2"}


def test_poses(edit_robot: EditRobot, panda: tuple[Any, Xrdf]) -> None:
    x = panda[1]
    q = edit_robot.random_pose(x, 3)
    assert np.array_equal(q, edit_robot.random_pose(x, 3))
    qc = q[edit_robot.cspace_index]
    assert np.all(qc >= edit_robot.lower) and np.all(qc <= edit_robot.upper)
    q0 = edit_robot.default_pose(x)
    assert edit_robot.cspace_values(q0)["panda_joint4"] == -2.5
    moved = edit_robot.pose_from(q0, {"panda_joint2": 0.3})
    assert edit_robot.cspace_values(moved)["panda_joint2"] == 0.3
    with pytest.raises(Exception, match="cannot pose joint 'nope'"):
        edit_robot.pose_from(q0, {"nope": 1.0})


# --- refit and report ------------------------------------------------------------------------
@pytest.mark.slow
def test_refit_is_the_project_fitter_and_measures(panda: tuple[Any, Xrdf]) -> None:
    from xrdf_tools.edit.fit import propose_fit
    from xrdf_tools.spheres import fit_link_spheres

    robot, x = panda
    current = spheres_of(x, "panda_link3")
    p = propose_fit(robot, "panda_link3", current, count=3)
    fitted, _ = fit_link_spheres(robot, links=["panda_link3"], per_link=3, source="auto")
    assert p.spheres == fitted["panda_link3"]
    assert p.before.sphere_count == len(current) and p.after.sphere_count == 3
    assert 0.3 < p.after.coverage <= 1.0
    loose = propose_fit(robot, "panda_link3", current, coverage=0.6)
    tight = propose_fit(robot, "panda_link3", current, coverage=0.95)
    assert len(loose.spheres) < len(tight.spheres)
    assert tight.after.coverage > loose.after.coverage
    with pytest.raises(Exception, match="either a sphere count or a coverage"):
        propose_fit(robot, "panda_link3", current)


def test_report_mask_applies_as_the_report_writes_it(panda: tuple[Any, Xrdf]) -> None:
    from xrdf_tools.report import recommended_xrdf, self_collision_report

    robot, x = panda
    report = self_collision_report(robot, x, samples=300, seed=0)
    st = EditState.start(x).apply(SetMask(report.recommended_ignore))
    assert st.xrdf == recommended_xrdf(x, report)


def test_a_report_witness_poses_the_robot_where_its_pair_collides(
    panda: tuple[Any, Xrdf], edit_robot: EditRobot
) -> None:
    """The page's "Pose witness": the witness of a pair, as a pose, shows that pair touching."""
    from xrdf_tools.report import CertifyOptions, self_collision_report

    robot, x = panda
    # few samples leave pairs "never seen" that --certify then finds a colliding pose for
    report = self_collision_report(robot, x, samples=20, seed=0, certify=CertifyOptions())
    with_witness = [p for p in report.pairs if p.witness is not None]
    assert with_witness
    for p in with_witness[:5]:
        q = edit_robot.pose_from(edit_robot.default_pose(x), p.witness)
        touching = edit_robot.collisions(x, q).pairs()
        assert frozenset((p.frame_a, p.frame_b)) in touching, (p.frame_a, p.frame_b)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("urdf", "srdf", "groups", "hands"),
    [
        (
            FIXTURES / "demo_arm" / "demo_arm.urdf",
            FIXTURES / "demo_arm" / "demo_arm.srdf",
            (),
            ("base_link", "wrist_3_link"),
        ),
        (
            "pr2",
            "pr2.srdf",
            ("left_arm", "right_arm"),
            ("l_gripper_palm_link", "r_gripper_palm_link"),
        ),
    ],
    ids=["demo-arm", "pr2-two-arms"],
)
def test_edit_a_draft_of_the_demo_arm_and_a_two_arm_robot(
    urdf: Any, srdf: Any, groups: tuple[str, ...], hands: tuple[str, str], tmp_path: Path
) -> None:
    """From a draft: spheres added on two links, their collision seen at the default pose and
    gone when the pair is ignored, saved canonical, byte-stable, lint-clean with the URDF."""
    from xrdf_tools.convert.core import ConvertOptions, convert

    if isinstance(urdf, str):
        path = robot_urdf(urdf)
        urdf, srdf = path, path.parent.parent / "srdf" / srdf
    robot = load_robot(urdf)
    x, _ = convert(robot, ConvertOptions(srdf=srdf, groups=groups))
    big = Sphere((0.0, 0.0, 0.0), 2.0)  # reaches the other link whatever the pose
    st = EditState.start(x).apply(AddSphere(hands[0], big)).apply(AddSphere(hands[1], big))
    er = EditRobot(robot, st.xrdf)
    q0 = er.default_pose(st.xrdf)
    pair = {hands[0], hands[1]}
    hit = [c for c in er.collisions(st.xrdf, q0).contacts if {c.frame_a, c.frame_b} == pair]
    assert hit and not hit[0].masked
    st = st.apply(SetIgnored(hands[0], hands[1], True))
    masked = [c for c in er.collisions(st.xrdf, q0).contacts if {c.frame_a, c.frame_b} == pair]
    assert masked and masked[0].masked
    target = tmp_path / "robot.xrdf"
    save(st, target)
    text = target.read_text()
    save(EditState.start(load_xrdf(target)), target)
    assert target.read_text() == text
    errors = [
        e for e in lint_text(text, str(target), urdf_model=robot) if e.severity.name == "ERROR"
    ]
    assert errors == []


@pytest.mark.parametrize(
    "edit",
    [
        MoveSphere("panda_link1", -1, (0.0, 0.0, 0.0)),
        SetRadius("panda_link1", -1, 0.05),
        DuplicateSphere("panda_link1", -1),
        DeleteSphere("panda_link1", -2),
        SetRadius("no_such_link", -2, 0.05),
    ],
    ids=lambda e: e.describe(),
)
def test_a_negative_sphere_index_names_no_sphere(panda: tuple[Any, Xrdf], edit: Any) -> None:
    """Sphere -1 is refused, not the last sphere counted from the end (nor a KeyError for a
    frame without spheres)."""
    with pytest.raises(EditError, match="no sphere -"):
        EditState.start(panda[1]).apply(edit)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (AddSphere("no_such_link", Sphere((0.0, 0.0, 0.0), 0.05)), "not a frame of the robot"),
        (SetBuffer("no_such_link", 0.01), "not a frame of the robot"),
        (SetIgnored("panda_link1", "panda_lnk5", True), "did you mean 'panda_link5'"),
        (SetMask({"panda_link1": ("no_such_link",)}), "not a frame of the robot"),
        (SetToolFrames(("panda_hand", "no_such_link")), "not a frame of the robot"),
        (SetDefaults({"panda_joint4": 0.0}), r"outside its limits \[-3.0718, -0.0698\]"),
        (SetDefaults({"panda_finger_joint2": 0.01}), "is a mimic joint"),
        (SetDefaults({"panda_hand_joint": 0.0}), "is a fixed joint"),
        (SetDefaults({"no_such_joint": 0.0}), "not a joint of the robot"),
    ],
    ids=lambda v: v.describe() if hasattr(v, "describe") else "",
)
def test_with_its_robot_an_edit_may_not_bring_in_what_lint_calls_an_error(
    panda: tuple[Any, Xrdf], edit_robot: EditRobot, edit: Any, message: str
) -> None:
    """Names the robot does not have and defaults outside the joint's limits: the saved file
    would fail ``xrdf lint --urdf`` (unknown-frame, default-position). Without a robot the
    state takes them, as the pure edit does."""
    with pytest.raises(EditError, match=message):
        EditState.start(panda[1], robot=edit_robot).apply(edit)
    assert EditState.start(panda[1]).apply(edit).xrdf != panda[1]


def test_with_its_robot_a_cspace_joint_it_cannot_move_is_refused(
    panda: tuple[Any, Xrdf], edit_robot: EditRobot
) -> None:
    """Before, the fixed joint went in, and the robot following the c-space raised a
    UrdfError that the page does not show as a refusal."""
    x = panda[1]
    cs = edit_robot.cspace_with(x, "panda_hand_joint", included=True, acceleration=1, jerk=1)
    with pytest.raises(EditError, match="'panda_hand_joint' is a fixed joint"):
        EditState.start(x, robot=edit_robot).apply(SetCspace(cs))


def test_a_file_naming_what_the_robot_lacks_can_still_be_edited(
    panda: tuple[Any, Xrdf], edit_robot: EditRobot
) -> None:
    """Only what an edit brings in is checked: the file's own unknown tool frame stays (and
    lint still says so) while other edits are made."""
    x = panda[1].replace(tool_frames=("panda_hand", "ghost"))
    st = EditState.start(x, robot=edit_robot).apply(SetBuffer("panda_link1", 0.02))
    st = st.apply(SetDefaults({"panda_joint1": 0.5}))
    assert st.xrdf.tool_frames == ("panda_hand", "ghost")


def test_with_its_robot_the_last_joint_and_tool_frame_stay(
    panda: tuple[Any, Xrdf], edit_robot: EditRobot
) -> None:
    """The page refused leaving the last c-space joint out and removing the last tool frame,
    but the document took both from Python (a c-space of nothing to move; a file cuRobo and
    cuMotion refuse): the document refuses them now, the page through it."""
    from xrdf_tools.xrdf.model import CSpace

    x = panda[1]
    st = EditState.start(x, robot=edit_robot)
    with pytest.raises(EditError, match="is the last tool frame"):
        st.apply(SetToolFrames(()))
    with pytest.raises(EditError, match="panda_joint1 is the last c-space joint"):
        st.apply(SetCspace(CSpace((), (), ())))
    one = edit_robot.cspace_with(x, "panda_joint1", included=True, acceleration=1, jerk=1)
    assert st.apply(SetCspace(CSpace(one.joint_names[:1], (1.0,), (1.0,)))).xrdf.cspace
