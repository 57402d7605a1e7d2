"""Adjacency (MoveIt's rule, bounded): frames without geometry collapse, and two geometry
frames joined through them are adjacent only while at most two joints between them move.

Drake's dual iiwa14 has collision geometry only on the two ``link_7`` frames: the unbounded
rule made them adjacent through 14 revolute joints, so the mask ignored the only pair the
robot has and convert stopped on an empty check. Small URDFs built here, no fetched files."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot
from xrdf_tools.export.srdf_held import held_pairs
from xrdf_tools.report import adjacent_frame_pairs
from xrdf_tools.robot.adjacency import MAX_ADJACENT_MOVING_JOINTS
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.spheres import ignore_adjacent
from xrdf_tools.xrdf.io import dump_xrdf, parse_xrdf

_BALL = '<collision><geometry><sphere radius="0.06"/></geometry></collision>'


def _joint(name: str, parent: str, child: str, xyz: str, axis: str, kind: str = "revolute") -> str:
    limit = '<limit lower="-2.9" upper="2.9" effort="1" velocity="1"/>' if kind != "fixed" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}"/><axis xyz="{axis}"/>{limit}</joint>'
    )


def two_arms(joints: int = 7) -> str:
    """Two ``joints``-joint arms on a base without geometry, a ball only at each tip."""
    links, js = ['<link name="base"/>'], []
    for side, y in (("l", 0.1), ("r", -0.1)):
        parent = "base"
        for i in range(1, joints + 1):
            name = f"{side}_link{i}"
            links.append(f'<link name="{name}">{_BALL if i == joints else ""}</link>')
            xyz = f"0 {y} 0.1" if i == 1 else "0 0 0.05"
            js.append(_joint(f"{side}_j{i}", parent, name, xyz, "0 0 1" if i % 2 else "0 1 0"))
            parent = name
    return '<robot name="two_arms">' + "".join(links + js) + "</robot>\n"


#: ``base`` → ``upper`` → bare ``elbow`` (visual only) → ``forearm`` → bare ``palm`` with two
#: fingers; ``forearm`` → bare ``a`` → bare ``b`` (fixed) → ``probe`` → bare ``tip`` (mimic)
#: → ``tip_ball``.
HAND = (
    '<robot name="hand">'
    f'<link name="base">{_BALL}</link><link name="upper">{_BALL}</link>'
    '<link name="elbow"><visual><geometry><box size="0.05 0.05 0.05"/></geometry></visual></link>'
    f'<link name="forearm">{_BALL}</link><link name="palm"/>'
    f'<link name="finger_l">{_BALL}</link><link name="finger_r">{_BALL}</link>'
    f'<link name="a"/><link name="b"/><link name="probe">{_BALL}</link>'
    + _joint("j1", "base", "upper", "0 0 0.1", "0 0 1")
    + _joint("j2", "upper", "elbow", "0 0 0.2", "0 1 0")
    + _joint("j3", "elbow", "forearm", "0 0 0.05", "0 0 1")
    + _joint("wrist", "forearm", "palm", "0 0 0.2", "0 1 0")
    + _joint("f1", "palm", "finger_l", "0 0.02 0.05", "0 1 0", "prismatic")
    + _joint("f2", "palm", "finger_r", "0 -0.02 0.05", "0 1 0", "prismatic")
    + _joint("p1", "forearm", "a", "0.1 0 0", "1 0 0")
    + _joint("p2", "a", "b", "0.1 0 0", "0 1 0", "fixed")
    + _joint("p3", "b", "probe", "0.1 0 0", "0 0 1")
    + '<joint name="p4" type="revolute"><parent link="probe"/><child link="tip"/>'
    '<origin xyz="0.1 0 0"/><axis xyz="0 0 1"/><mimic joint="p3"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    '<link name="tip"/>'
    + _joint("p5", "tip", "tip_ball", "0.1 0 0", "0 1 0")
    + f'<link name="tip_ball">{_BALL}</link>'
    "</robot>\n"
)


def _urdf(tmp_path: Path, text: str, name: str = "robot.urdf") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _adjacent(urdf: Path, frames: list[str]) -> frozenset[frozenset[str]]:
    kin, _ = build_kinematic_model(load_urdf(urdf))
    return adjacent_frame_pairs(kin, frames)


def test_tips_of_two_arms_on_a_bare_base_are_not_adjacent(tmp_path: Path) -> None:
    """14 revolute joints apart through frames without geometry: not adjacent; one joint
    more than the limit already is not, the limit itself still is."""
    urdf = _urdf(tmp_path, two_arms())
    assert _adjacent(urdf, ["l_link7", "r_link7"]) == frozenset()
    # each tip paired with its arm's first link: 6 moving joints apart
    assert _adjacent(urdf, ["l_link1", "l_link7"]) == frozenset()
    assert MAX_ADJACENT_MOVING_JOINTS == 2
    assert _adjacent(urdf, ["l_link1", "l_link3"]) == {frozenset(("l_link1", "l_link3"))}
    assert _adjacent(urdf, ["l_link1", "l_link4"]) == frozenset()


def test_elbow_and_fingers_stay_adjacent_four_moving_joints_do_not(tmp_path: Path) -> None:
    """A visual-only elbow (two joints) and fingers under a bare palm (siblings, two joints)
    stay adjacent as MoveIt's rule has them; ``forearm`` and ``tip_ball``, four moving joints
    apart through frames without geometry, are not."""
    frames = ["base", "upper", "forearm", "finger_l", "finger_r", "tip_ball"]
    adj = _adjacent(_urdf(tmp_path, HAND), frames)
    assert {tuple(sorted(p)) for p in adj} == {
        ("base", "upper"),
        ("forearm", "upper"),  # through the visual-only elbow: j2, j3
        ("finger_l", "finger_r"),  # siblings under the bare palm: f1, f2
        ("finger_l", "forearm"),  # wrist, f1
        ("finger_r", "forearm"),
    }


def test_a_fixed_joint_does_not_count_a_mimic_follower_does(tmp_path: Path) -> None:
    """``forearm`` →p1 ``a`` →p2 (fixed) ``b`` →p3 ``probe`` →p4 (mimic of p3) ``tip`` →p5
    ``tip_ball``."""
    urdf = _urdf(tmp_path, HAND)
    assert _adjacent(urdf, ["forearm", "probe"]) == {frozenset(("forearm", "probe"))}  # p1, p3
    assert _adjacent(urdf, ["probe", "tip_ball"]) == {frozenset(("probe", "tip_ball"))}
    assert _adjacent(urdf, ["a", "tip_ball"]) == frozenset()  # p3, p4 (mimic), p5
    assert _adjacent(urdf, ["b", "tip"]) == {frozenset(("b", "tip"))}  # p3, p4


def test_a_joint_held_by_equal_limits_does_not_count(tmp_path: Path) -> None:
    """``a`` →p2 becomes a revolute joint held still by equal limits (Toyota HSR's sensor
    frame): it counts as the fixed joint it acts as, in the report's, ``xrdf spheres``' and
    ``export srdf``'s adjacency alike. ``a`` and ``tip`` were three moving joints apart."""
    held = HAND.replace(
        _joint("p2", "a", "b", "0.1 0 0", "0 1 0", "fixed"),
        '<joint name="p2" type="revolute"><parent link="a"/><child link="b"/>'
        '<origin xyz="0.1 0 0"/><axis xyz="0 1 0"/>'
        '<limit lower="0.3" upper="0.3" effort="1" velocity="1"/></joint>',
    )
    assert held != HAND
    urdf = _urdf(tmp_path, held)
    assert _adjacent(urdf, ["a", "tip"]) == {frozenset(("a", "tip"))}  # p3, p4 (p2 held)
    assert _adjacent(urdf, ["a", "tip_ball"]) == frozenset()  # p3, p4, p5
    masked, _ = ignore_adjacent(parse_xrdf(_with_balls(urdf, ["a", "tip"])), urdf)
    assert masked.self_collision is not None
    assert masked.self_collision.ignore_pairs() == {frozenset(("a", "tip"))}


def test_a_mimic_follower_with_equal_limits_still_counts(tmp_path: Path) -> None:
    """``p4``, the mimic follower of ``p3``, exported with limits 0 0 (a CAD exporter's for
    limits never set): it still turns with ``p3``, so ``a`` and ``tip_ball`` stay three moving
    joints apart (p3, p4, p5). It counted as held, and the pair was ignored as adjacent."""
    zero = HAND.replace(
        '<mimic joint="p3"/><limit lower="-1" upper="1"',
        '<mimic joint="p3"/><limit lower="0" upper="0"',
    )
    assert zero != HAND
    urdf = _urdf(tmp_path, zero)
    assert _adjacent(urdf, ["a", "tip_ball"]) == frozenset()
    masked, _ = ignore_adjacent(parse_xrdf(_with_balls(urdf, ["a", "tip_ball"])), urdf)
    assert masked.self_collision is not None
    assert masked.self_collision.ignore_pairs() == frozenset()


def _with_balls(urdf: Path, frames: list[str]) -> str:
    """The XRDF ``xrdf convert`` drafts for ``urdf``, one sphere on each of ``frames``."""
    x, _ = convert(load_robot(urdf), ConvertOptions())
    block = "".join(
        f"      {f}:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n" for f in frames
    )
    text = dump_xrdf(x).replace("    spheres: {}\n", "    spheres:\n" + block)
    assert text != dump_xrdf(x)
    return text


def test_spheres_drafted_mask_follows_the_same_rule(tmp_path: Path) -> None:
    """``xrdf spheres``' drafted mask (:func:`ignore_adjacent`) ignores the pairs the report
    calls adjacent: fingers under a bare palm too (it took only a frame and its nearest
    ancestor with spheres), not four moving joints apart."""
    urdf = _urdf(tmp_path, HAND)
    frames = ["base", "upper", "forearm", "finger_l", "finger_r", "tip_ball"]
    masked, diags = ignore_adjacent(parse_xrdf(_with_balls(urdf, frames)), urdf)
    assert masked.self_collision is not None
    assert masked.self_collision.ignore_pairs() == _adjacent(urdf, frames)
    assert dict(masked.self_collision.ignore) == {
        "base": ("upper",),
        "upper": ("forearm",),
        "forearm": ("finger_l", "finger_r"),
        "finger_l": ("finger_r",),
    }
    assert "5 pair(s) of adjacent links" in diags[0].message


def test_export_srdf_holds_back_tips_many_joints_apart(tmp_path: Path) -> None:
    """The XRDF's mask made with the left arm only held the right arm's joints: the tip pair,
    joined only through frames without spheres but 14 moving joints apart, is not adjacent,
    so ``export srdf`` does not add it to the SRDF for every group."""
    urdf = _urdf(tmp_path, two_arms())
    x = parse_xrdf(_with_balls(urdf, ["l_link7", "r_link7"]))
    held = held_pairs(x, load_robot(urdf).tree, [("l_link7", "r_link7")])
    assert held.pairs == (("l_link7", "r_link7", tuple(f"r_j{i}" for i in range(7, 0, -1))),)


def test_convert_samples_the_tip_pair_and_succeeds(tmp_path: Path) -> None:
    """The dual-arm case end to end: the tip pair is sampled, collides sometimes, stays
    checked, and ``--target curobo`` writes the file (it stopped at ``curobo-no-pair``)."""
    urdf, out = _urdf(tmp_path, two_arms()), tmp_path / "two_arms.xrdf"
    args = ["convert", str(urdf), "--fit-spheres", "--samples", "400", "--target", "curobo"]
    r = CliRunner().invoke(app, [*args, "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "convert-mask-nothing-checked" not in r.output
    assert "1 pair(s) checked" in r.output
    x = parse_xrdf(out.read_text())
    assert x.self_collision is not None and not x.self_collision.ignore_pairs()


def _nothing_checked(urdf: Path, joints: tuple[str, ...]) -> str | None:
    result = convert_robot(
        urdf,
        ConvertOptions(joints=joints),
        fit=FitOptions(per_link=4),
        mask=MaskOptions(samples=400),
    )
    said = {d.rule: d.message for d in result.diagnostics}
    return said.get("convert-mask-nothing-checked")


def test_nothing_checked_says_which_cause(tmp_path: Path) -> None:
    """The warning said the c-space "moves no part against another" even when it moved every
    pair and the mask ignored each (adjacent ones included). It now tells the two causes
    apart and counts the pairs."""
    urdf = _urdf(tmp_path, HAND)
    # the wrist moves the fingers against the rest: 2 adjacent pairs, 8 that never collide
    moved = _nothing_checked(urdf, ("wrist",))
    assert moved is not None
    assert "the c-space (1: wrist) moves 10 of the 21 pair(s) relative to each other" in moved
    assert "ignores each of them (2 adjacent, 8 never colliding in the 400 samples)" in moved
    assert "moves no part" not in moved
    # without geometry on the base, j1 turns every part with geometry as one body
    bare = _urdf(
        tmp_path,
        HAND.replace(f'<link name="base">{_BALL}</link>', '<link name="base"/>'),
        "bare.urdf",
    )
    still = _nothing_checked(bare, ("j1",))
    assert still is not None and "moves none of them relative to another" in still
    assert "(1: j1)" in still and "all 15 pair(s) keep their relative pose" in still
