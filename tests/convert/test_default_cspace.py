"""The c-space and tool frame picked without an SRDF group, on real robots and small trees.

Expectations are derived from each URDF's structure in the test (a plain walk over the tree),
not copied from the implementation's output.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest

from tests.robots import robots_dir
from xrdf_tools.convert.core import ConvertOptions, convert
from xrdf_tools.robot.chains import default_cspace, joint_roles, name_words
from xrdf_tools.robot.core import Robot, as_robot
from xrdf_tools.robot.tool_frame import guess_tool_frame
from xrdf_tools.robot.urdf_source import load_urdf

#: short name -> path below example-robot-data's robots/
REAL = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",
    "so101": "so_arm_description/urdf/so101.urdf",
    "tiago": "tiago_description/robots/tiago.urdf",
    "tiago_dual": "tiago_description/robots/tiago_dual.urdf",
    "talos": "talos_data/robots/talos_full_v2.urdf",
    "pr2": "pr2_description/urdf/pr2.urdf",
}

#: What the test itself calls a non-arm joint: a robotics engineer's reading of the names.
NOT_ARM = re.compile(r"wheel|caster|gripper|finger|hand|jaw|claw|thumb|head|neck|camera|laser")


def _robot(name: str) -> Robot:
    root = robots_dir()
    if root is None or not (root / REAL[name]).is_file():
        pytest.skip(f"example-robot-data has no {REAL[name]}")
    return as_robot(load_urdf(root / REAL[name]))


def _expected_length(robot: Robot) -> int:
    """Longest run of arm joints from the root to a leaf, stopping at the first non-arm joint."""
    tree = robot.tree
    leaders = {j.mimic_joint for j in tree.joints.values() if j.mimic_joint}
    best = 0
    for leaf in tree.links:
        if tree.child_joints.get(leaf):
            continue
        path = [
            tree.parent_joint[n] for n in [leaf, *tree.ancestors(leaf)] if n in tree.parent_joint
        ]
        count = 0
        for jn in reversed(path):
            j = tree.joints[jn]
            if not j.is_movable:
                continue
            if NOT_ARM.search(jn.lower()) or j.is_mimic or jn in leaders:
                break
            count += 1
        best = max(best, count)
    return best


def _fixed_path(robot: Robot, top: str, frame: str) -> bool:
    """Whether ``frame`` is ``top`` or hangs below it through fixed joints only."""
    tree = robot.tree
    cur = frame
    while cur != top:
        jn = tree.parent_joint.get(cur)
        if jn is None or tree.joints[jn].type != "fixed":
            return False
        cur = tree.joints[jn].parent
    return True


@pytest.mark.parametrize("name", sorted(REAL))
def test_default_is_the_longest_serial_arm_chain(name: str) -> None:
    robot = _robot(name)
    tree = robot.tree
    choice = default_cspace(tree, collision_links=set(robot.collision_counts))
    joints = list(choice.joints)
    assert len(joints) == _expected_length(robot)
    # a serial chain: each joint below the previous one, in tree order
    for upper, lower in itertools.pairwise(joints):
        assert tree.joints[upper].child in [
            tree.joints[lower].parent,
            *tree.ancestors(tree.joints[lower].parent),
        ]
    assert not [j for j in joints if NOT_ARM.search(j.lower())]
    assert all(tree.joints[j].is_actuated for j in joints)
    # the tool frame hangs below the last c-space joint through fixed joints only
    assert choice.tool is not None
    assert _fixed_path(robot, tree.joints[joints[-1]].child, choice.tool.frame)


@pytest.mark.parametrize("name", sorted(REAL))
def test_tool_frame_prefers_tool_names(name: str) -> None:
    """A frame named tool0 wins; otherwise a tool/tcp/ee-like name when one hangs there."""
    robot = _robot(name)
    tree = robot.tree
    choice = default_cspace(tree, collision_links=set(robot.collision_counts))
    assert choice.tool is not None
    top = tree.joints[choice.joints[-1]].child
    rigid = [lk for lk in tree.links if _fixed_path(robot, top, lk)]
    if "tool0" in rigid:
        assert choice.tool.frame == "tool0"
    elif any(re.search(r"tcp|tool|(^|_)ee(_|$)|eef|end_effector", lk) for lk in rigid):
        assert re.search(r"tcp|tool|(^|_)ee(_|$)|eef|end_effector", choice.tool.frame)
    assert choice.tool.frame in rigid


def test_named_robots() -> None:
    """The cases of the field: UR5 tool0, TIAGo's arm + torso, a two-arm robot's tie."""
    ur5 = default_cspace(_robot("ur5").tree)
    assert ur5.tool is not None and ur5.tool.frame == "tool0"
    tiago = _robot("tiago")
    t = default_cspace(tiago.tree, collision_links=set(tiago.collision_counts))
    movable = [j for j in tiago.tree.dfs_joints() if tiago.tree.joints[j].is_actuated]
    assert len(movable) > 40 and len(t.joints) < 10  # wheels, fingers, head all left out
    assert {"wheel", "gripper", "head"} <= set(t.left_out)
    assert t.tool is not None and "wheel" not in t.tool.frame and "tool" in t.tool.frame
    pr2 = default_cspace(_robot("pr2").tree)
    # two arms as long as each other: one is chosen, the other reported with its --chain
    assert len(pr2.ties) == 1
    other, tool = pr2.ties[0]
    assert {j[:2] for j in pr2.joints if j.startswith(("l_", "r_"))} != {
        j[:2] for j in other.cspace if j.startswith(("l_", "r_"))
    }
    assert f"--chain {other.base}:{tool.frame}" in pr2.describe()


def _tree_urdf(tmp_path: Path, joints: str, links: list[str]) -> Robot:
    body = "".join(f'<link name="{lk}"/>' for lk in links)
    p = tmp_path / "r.urdf"
    p.write_text(f'<robot name="r">{body}{joints}</robot>')
    return as_robot(load_urdf(p))


def _j(name: str, kind: str, parent: str, child: str, extra: str = "") -> str:
    limit = '<limit lower="-1" upper="1" velocity="1" effort="1"/>' if kind != "fixed" else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="0 0 1"/>{limit}{extra}</joint>'
    )


def test_roles_from_names_and_structure(tmp_path: Path) -> None:
    links = ["base", "w", "a1", "a2", "a3", "g1", "g2", "cam", "flange"]
    joints = "".join(
        [
            _j("drive", "continuous", "base", "w"),  # an unnamed wheel: continuous, on the base
            _j("shoulder_pan_joint", "revolute", "base", "a1"),  # 'pan' of an arm: an arm joint
            _j("behead", "revolute", "a1", "a2"),  # 'head' inside a word: an arm joint
            _j("j3", "revolute", "a2", "a3"),
            _j("grip_drive", "prismatic", "a3", "g1"),
            _j("follower", "prismatic", "a3", "g2", '<mimic joint="grip_drive"/>'),
            _j("pan_joint", "revolute", "base", "cam"),  # a pan joint alone: a head
            _j("tip_joint", "fixed", "a3", "flange"),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    roles = joint_roles(robot.tree)
    assert roles == {
        "drive": "wheel",
        "grip_drive": "gripper",
        "follower": "gripper",
        "pan_joint": "head",
    }
    choice = default_cspace(robot.tree)
    assert choice.joints == ("shoulder_pan_joint", "behead", "j3")
    assert choice.tool is not None and choice.tool.frame == "flange"  # a tool-like name
    assert name_words("rightHandJoint2") == ("right", "hand", "joint")


def test_a_mimic_of_a_torso_lift_is_no_gripper(tmp_path: Path) -> None:
    """A mobile manipulator's body panel follows its torso lift by a mimic joint (Kinova
    MOVO's mid_body_joint: half of linear_joint) and carries nothing: it is left out of the
    c-space as a mimic, but it is no gripper, as the lift that carries the arm is none."""
    links = ["base", "lift", "panel", "a1", "a2", "g1", "g2"]
    joints = "".join(
        [
            _j("linear_joint", "prismatic", "base", "lift"),
            _j("mid_body_joint", "prismatic", "base", "panel", '<mimic joint="linear_joint"/>'),
            _j("shoulder_joint", "revolute", "lift", "a1"),
            _j("elbow_joint", "revolute", "a1", "a2"),
            _j("j_a", "prismatic", "a2", "g1"),  # an unnamed gripper: a leader and its mimic
            _j("j_b", "prismatic", "a2", "g2", '<mimic joint="j_a"/>'),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    assert joint_roles(robot.tree) == {"j_a": "gripper", "j_b": "gripper"}
    choice = default_cspace(robot.tree)
    assert choice.joints == ("linear_joint", "shoulder_joint", "elbow_joint")


def test_a_wrist_into_a_link_named_hand_is_an_arm_joint_when_the_tool_is_below(
    tmp_path: Path,
) -> None:
    """The last wrist joint of some arms moves a link called 'hand' that carries the tool
    frame: the tool below says it is a wrist joint, not a finger; a hand link with fingers
    and no tool frame below still makes its joint a gripper's."""
    links = ["base", "arm", "hand", "tool0", "palm", "finger"]
    joints = "".join(
        [
            _j("j1", "revolute", "base", "arm"),
            _j("j2", "revolute", "arm", "hand"),
            _j("t", "fixed", "hand", "tool0"),
            _j("j3", "revolute", "hand", "palm"),  # no tool frame below: a gripper's
            _j("j4", "revolute", "palm", "finger"),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    assert joint_roles(robot.tree) == {"j3": "gripper", "j4": "gripper"}
    choice = default_cspace(robot.tree)
    assert choice.joints == ("j1", "j2")
    assert choice.tool is not None and choice.tool.frame == "tool0"


def test_a_joint_whose_limits_hold_it_still_is_no_cspace_joint(tmp_path: Path) -> None:
    """Toyota HSR's force-torque sensor frame hangs from the wrist by a revolute joint with
    limits [0, 0] (so do its bumpers): it cannot move, so the default c-space ends at the
    wrist and the tool frame is found through it as through a fixed joint."""
    held = '<limit lower="0" upper="0" velocity="1" effort="1"/>'
    links = ["base", "lift_link", "wrist_link", "ft_frame", "palm", "finger", "bumper"]
    joints = "".join(
        [
            _j("lift_joint", "prismatic", "base", "lift_link"),
            _j("wrist_joint", "revolute", "lift_link", "wrist_link"),
            _j("ft_frame_joint", "revolute", "wrist_link", "ft_frame").replace(
                '<limit lower="-1" upper="1" velocity="1" effort="1"/>', held
            ),
            _j("palm_joint", "fixed", "ft_frame", "palm"),
            _j("finger_joint", "revolute", "palm", "finger"),
            _j("bumper_joint", "revolute", "base", "bumper").replace(
                '<limit lower="-1" upper="1" velocity="1" effort="1"/>', held
            ),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    choice = default_cspace(robot.tree)
    assert choice.joints == ("lift_joint", "wrist_joint")
    assert choice.tool is not None and choice.tool.frame == "palm"
    for options in (ConvertOptions(), ConvertOptions(chains=(("base", "palm"),))):
        x, _ = convert(robot, options)  # the default, and the --chain it names
        assert x.cspace is not None and x.cspace.joint_names == ("lift_joint", "wrist_joint")
        assert x.tool_frames == ("palm",)
    # reversed limits are a mistake to report in the c-space, not a joint held still
    reversed_limits = joints.replace(held, '<limit lower="0.1" upper="-0.1" effort="1"/>', 1)
    (tmp_path / "reversed").mkdir()
    robot = _tree_urdf(tmp_path / "reversed", reversed_limits, links)
    assert default_cspace(robot.tree).joints == ("lift_joint", "wrist_joint", "ft_frame_joint")


def test_default_limits_name_the_unit_of_each_joint_kind(tmp_path: Path) -> None:
    """A mobile manipulator's lift is prismatic: its default acceleration is in m/s², not
    rad/s² (HSR's arm_lift_joint, PR2's torso_lift_joint)."""
    links = ["base", "lift_link", "wrist_link"]
    lift = _j("lift_joint", "prismatic", "base", "lift_link")
    wrist = _j("wrist_joint", "revolute", "lift_link", "wrist_link")
    robot = _tree_urdf(tmp_path, lift + wrist, links)
    cases = {
        ("lift_joint",): ("m/s²", "m/s³"),
        ("wrist_joint",): ("rad/s²", "rad/s³"),
        ("lift_joint", "wrist_joint"): (
            "rad/s² (m/s² for the prismatic ones)",
            "rad/s³ (m/s³ for the prismatic ones)",
        ),
    }
    for joints, (accel_unit, jerk_unit) in cases.items():
        _, diags = convert(robot, ConvertOptions(joints=joints))
        messages = {d.rule: d.message for d in diags}
        assert f"using the default 10 {accel_unit} (" in messages["convert-default-acceleration"]
        assert f"using the default 1000 {jerk_unit} (" in messages["convert-default-jerk"]


def test_a_hand_on_a_wrist_plans_for_the_wrist_and_leaves_its_fingers_out(
    tmp_path: Path,
) -> None:
    """The Shadow Hand's layout: two wrist joints with neutral names ('rh_WRJ2' into
    'rh_wrist', 'rh_WRJ1' into 'rh_palm'), then fingers whose names say nothing ('rh_FFJ4'
    into 'rh_ffknuckle', ...) on the palm. The joint into the palm moves the whole hand: a
    wrist joint, not a gripper's, and the default plans for both wrist joints; the fingers
    hanging from the palm are left out."""
    links = ["world", "rh_forearm", "rh_wrist", "rh_palm", "rh_manipulator"]
    joints = [
        _j("rh_world_joint", "fixed", "world", "rh_forearm"),
        _j("rh_WRJ2", "revolute", "rh_forearm", "rh_wrist"),
        _j("rh_WRJ1", "revolute", "rh_wrist", "rh_palm"),
        _j("rh_ee_fixed_joint", "fixed", "rh_palm", "rh_manipulator"),
    ]
    fingers = {"ff": 4, "mf": 4, "th": 5}
    for finger, count in fingers.items():
        parent = "rh_palm"
        segments = ["base", "knuckle", "proximal", "middle", "distal"][-count:]
        for k, segment in zip(range(count, 0, -1), segments, strict=True):
            link = f"rh_{finger}{segment}"
            links.append(link)
            joints.append(_j(f"rh_{finger.upper()}J{k}", "revolute", parent, link))
            parent = link
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    roles = joint_roles(robot.tree)
    first_joints = {f"rh_{f.upper()}J{n}" for f, n in fingers.items()}
    assert {j for j, role in roles.items() if role == "gripper"} == first_joints
    choice = default_cspace(robot.tree, collision_links=set(links) - {"world", "rh_manipulator"})
    assert choice.joints == ("rh_WRJ2", "rh_WRJ1")
    assert choice.tool is not None and choice.tool.frame == "rh_manipulator"
    assert set(choice.left_out["gripper"]) == first_joints

    # a joint into a hand with nothing moving below it is still a gripper's
    robot = _tree_urdf(
        tmp_path,
        _j("j1", "revolute", "base", "arm") + _j("j2", "revolute", "arm", "palm"),
        ["base", "arm", "palm"],
    )
    assert joint_roles(robot.tree) == {"j2": "gripper"}


def test_jaws_without_gripper_names_are_left_out(tmp_path: Path) -> None:
    """The AgileX Piper's jaws are independent prismatic joints 'joint7'/'joint8' into
    'link7'/'link8' on 'gripper_base': the link they hang from names the gripper. Two
    prismatic leaf joints on one link are a parallel gripper's jaws whatever the names; one
    prismatic joint at the end of an arm (a SCARA's quill) stays an arm joint."""
    links = ["base_link", "link1", "link2", "link6", "gripper_base", "link7", "link8"]
    joints = "".join(
        [
            _j("joint1", "revolute", "base_link", "link1"),
            _j("joint2", "revolute", "link1", "link2"),
            _j("joint6", "revolute", "link2", "link6"),
            _j("joint6_to_gripper_base", "fixed", "link6", "gripper_base"),
            _j("joint7", "prismatic", "gripper_base", "link7"),
            _j("joint8", "prismatic", "gripper_base", "link8"),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    assert joint_roles(robot.tree) == {"joint7": "gripper", "joint8": "gripper"}
    choice = default_cspace(robot.tree)
    assert choice.joints == ("joint1", "joint2", "joint6")
    assert choice.tool is not None and choice.tool.frame == "gripper_base"

    parallel = "".join(
        [
            _j("j1", "revolute", "base_link", "link1"),
            _j("j2", "revolute", "link1", "link6"),
            _j("a", "prismatic", "link6", "link7"),
            _j("b", "prismatic", "link6", "link8"),
        ]
    )
    robot = _tree_urdf(tmp_path, parallel, ["base_link", "link1", "link6", "link7", "link8"])
    assert joint_roles(robot.tree) == {"a": "gripper", "b": "gripper"}
    assert default_cspace(robot.tree).joints == ("j1", "j2")

    scara = "".join(
        [
            _j("j1", "revolute", "base_link", "link1"),
            _j("j2", "revolute", "link1", "link6"),
            _j("quill", "prismatic", "link6", "link7"),
        ]
    )
    robot = _tree_urdf(tmp_path, scara, ["base_link", "link1", "link6", "link7"])
    assert joint_roles(robot.tree) == {}
    assert default_cspace(robot.tree).joints == ("j1", "j2", "quill")


def test_convert_reports_each_guess_with_its_flag() -> None:
    robot = _robot("tiago")
    x, diags = convert(robot, ConvertOptions())
    assert x.cspace is not None
    choice = default_cspace(robot.tree, collision_links=set(robot.collision_counts))
    assert x.cspace.joint_names == choice.joints
    msgs = {d.rule: d.message for d in diags}
    assert "--chain" in msgs["convert-chosen-group"] and "wheel" in msgs["convert-chosen-group"]
    assert "--tool-frame" in msgs["convert-chosen-tool-frame"]
    assert x.tool_frames == (choice.tool.frame,) if choice.tool else ()
    # the flag the message names gives the same c-space, without guesses about it
    flag = msgs["convert-chosen-group"].split("--chain ")[1].split(",")[0]
    base, tip = flag.split(":")
    x2, diags2 = convert(robot, ConvertOptions(chains=((base, tip),)))
    assert x2.cspace is not None and x2.cspace.joint_names == x.cspace.joint_names
    assert "convert-chosen-group" not in {d.rule for d in diags2}


def test_joints_option_tool_frame_uses_the_same_guess() -> None:
    """--joints leaves the tool frame to the same guess as the default c-space, and it is
    reported like it: it was written without a word (the human hand model's --joints
    synergy_joint,thumb_abduction_joint got the tool frame 'dummy_synergy_link' silently)."""
    robot = _robot("ur5")
    joints = tuple(default_cspace(robot.tree).joints)
    x, diags = convert(robot, ConvertOptions(joints=joints))
    assert x.tool_frames == (guess_tool_frame(robot.tree, joints[-1]).frame,) == ("tool0",)
    (said,) = [d.message for d in diags if d.rule == "convert-chosen-tool-frame"]
    assert "using 'tool0'" in said and "--tool-frame" in said


PLANAR_URDF = """<robot name="mm">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="base_joint" type="planar"><parent link="world"/><child link="base"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
</robot>"""

PLANAR_SRDF = """<robot name="mm">
  <group name="whole"><joint name="base_joint"/><joint name="j1"/><joint name="j2"/></group>
  <group name="arm_on_odom"><joint name="odom"/><chain base_link="base" tip_link="l2"/></group>
  <virtual_joint name="odom" type="planar" parent_frame="map" child_link="world"/>
</robot>"""


@pytest.mark.parametrize(
    ("group", "joint", "line"), [("whole", "base_joint", 2), ("arm_on_odom", "odom", 3)]
)
def test_planar_joint_in_a_group_is_left_out_with_a_warning(
    tmp_path: Path, group: str, joint: str, line: int
) -> None:
    (tmp_path / "r.urdf").write_text(PLANAR_URDF)
    (tmp_path / "r.srdf").write_text(PLANAR_SRDF)
    robot = as_robot(load_urdf(tmp_path / "r.urdf"))
    x, diags = convert(robot, ConvertOptions(srdf=tmp_path / "r.srdf", group=group))
    assert x.cspace is not None and x.cspace.joint_names == ("j1", "j2")
    warned = [d for d in diags if d.rule == "convert-unplannable-joint"]
    assert len(warned) == 1 and f"'{joint}'" in warned[0].message and "planar" in warned[0].message
    assert warned[0].severity.value == "warning" and warned[0].line == line


#: xacro robots of rtb-data: a mobile manipulator and a two-arm robot
XACRO = {
    "frankie": "qut_frankie_description/robots/frankie_arm_hand.urdf.xacro",
    "dual_panda": "qut_frankie_description/robots/dual_panda_example.urdf.xacro",
}


@pytest.mark.parametrize("name", sorted(XACRO))
def test_xacro_mobile_and_two_arm_robots(name: str) -> None:
    import importlib.util

    from xrdf_tools.robot.xacro_source import load_robot

    spec = importlib.util.find_spec("rtbdata")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("rtb-data is not installed")
    root = Path(next(iter(spec.submodule_search_locations))) / "xacro"
    if not (root / XACRO[name]).is_file():
        pytest.skip(f"rtb-data has no {XACRO[name]}")
    pkg = {"qut_frankie_description": str(root / "qut_frankie_description")}
    robot = load_robot(root / XACRO[name], package_paths=pkg)
    choice = default_cspace(robot.tree, collision_links=set(robot.collision_counts))
    assert len(choice.joints) == _expected_length(robot)
    assert choice.tool is not None and "finger" not in choice.tool.frame
    assert not [j for j in choice.joints if NOT_ARM.search(j.lower())]
    assert _fixed_path(robot, robot.tree.joints[choice.joints[-1]].child, choice.tool.frame)
    if name == "dual_panda":  # the other arm is as long: named with its --chain
        assert len(choice.ties) == 1 and "--chain" in choice.describe()


def test_a_humanoids_arm_wins_over_its_equally_long_leg(tmp_path: Path) -> None:
    """A humanoid (Unitree H1's layout): each leg and each arm (with the torso) has five
    joints; the default plans for an arm and names the leg it passed over."""
    limbs = {
        "left_leg": ["left_hip_yaw", "left_hip_roll", "left_hip_pitch", "left_knee", "left_ankle"],
        "left_arm": [
            "torso",
            "left_shoulder_pitch",
            "left_shoulder_roll",
            "left_elbow",
            "left_wrist",
        ],
    }
    links, joints = ["pelvis"], []
    for chain in limbs.values():
        parent = "pelvis"
        for name in chain:
            if f"{name}_link" not in links:
                links.append(f"{name}_link")
                joints.append(_j(f"{name}_joint", "revolute", parent, f"{name}_link"))
            parent = f"{name}_link"
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    choice = default_cspace(robot.tree)
    arm = tuple(f"{n}_joint" for n in limbs["left_arm"])
    assert choice.joints == arm  # not the leg, which comes first in the tree
    assert choice.tool is not None and choice.tool.frame == "left_wrist_link"
    assert [c.cspace for c, _ in choice.legs] == [tuple(f"{n}_joint" for n in limbs["left_leg"])]
    assert not choice.ties


@pytest.mark.parametrize("name", sorted(REAL))
def test_what_lies_below_each_link_matches_a_walk_per_link(name: str) -> None:
    """The one-walk facts behind the joint roles against walking the tree from every link."""
    from xrdf_tools.robot.chains import _Subtrees
    from xrdf_tools.robot.names import TOOL_WORDS

    tree = _robot(name).tree
    leaders = {j.mimic_joint for j in tree.joints.values() if j.mimic_joint is not None}
    facts = _Subtrees(tree, leaders)
    for link in tree.links:
        below = tree.descendants(link)
        into = [tree.joints[tree.parent_joint[n]] for n in below]
        above = [
            tree.joints[tree.parent_joint[n]]
            for n in [link, *tree.ancestors(link)]
            if n in tree.parent_joint
        ]
        tool = any(set(name_words(n)) & TOOL_WORDS for n in (link, *below))
        assert facts.tool[link] == tool, link
        assert facts.free[link] == any(j.is_actuated and j.name not in leaders for j in into)
        assert facts.movable[link] == any(j.is_movable for j in into), link
        assert facts.movable_above[link] == any(j.is_movable for j in above), link


def test_a_chain_of_thousands_of_joints_gets_short_messages(tmp_path: Path) -> None:
    """A long serial chain (a generated snake robot) is picked whole, and each message names a
    few joints and counts the rest instead of listing thousands."""
    n = 2000
    parts = ['<robot name="snake">']
    parts += [f'<link name="l{i}"/>' for i in range(n + 1)]
    parts += [
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i in range(n)
    ]
    urdf = tmp_path / "snake.urdf"
    urdf.write_text("\n".join([*parts, "</robot>"]))
    x, diagnostics = convert(load_urdf(urdf), ConvertOptions())
    assert x.cspace is not None
    assert len(x.cspace.joint_names) == n
    messages = [d.message for d in diagnostics]
    assert any(f"and {n - 12} more" in m for m in messages)
    assert max(len(m) for m in messages) < 600


def test_a_humanoids_arm_wins_over_its_longer_leg(tmp_path: Path) -> None:
    """NAO's layout: six leg joints and five arm joints in camelCase names ('LHipYawPitch',
    'LShoulderPitch'), touch-sensor frames on the wrist. The default plans for the arm, not
    the longer leg (named in the message with its --chain), and the tool frame is no touch
    sensor; a robot made of legs only plans for its longest leg."""
    leg = ["LHipYawPitch", "LHipRoll", "LHipPitch", "LKneePitch", "LAnklePitch", "LAnkleRoll"]
    arm = ["LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll", "LWristYaw"]
    links, joints = ["base_link", "torso"], [_j("base_fixed", "fixed", "base_link", "torso")]
    for chain, tip in ((leg, "l_ankle"), (arm, "l_wrist")):
        parent = "torso"
        for k, name in enumerate(chain):
            child = tip if k == len(chain) - 1 else f"{name}_link"
            links.append(child)
            joints.append(_j(name, "revolute", parent, child))
            parent = child
    extra = {
        "l_sole": "l_ankle",
        "LFootBumperLeft_frame": "l_ankle",
        "LHandTouchBack_frame": "l_wrist",
        "LHandTouchLeft_frame": "l_wrist",
    }
    for child, parent in extra.items():
        links.append(child)
        joints.append(_j(f"{child}_joint", "fixed", parent, child))
    links.append("l_gripper")
    joints.append(_j("LHand", "revolute", "l_wrist", "l_gripper"))
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    geometry = {lk for lk in links if lk.endswith("_link")} | {"l_ankle", "l_wrist", "torso"}
    choice = default_cspace(robot.tree, collision_links=geometry)
    assert name_words("LHipYawPitch") == ("l", "hip", "yaw", "pitch")
    assert choice.joints == tuple(arm)
    assert choice.tool is not None and choice.tool.frame == "l_wrist"
    assert [(c.cspace, t.frame) for c, t in choice.legs] == [(tuple(leg), "l_sole")]
    assert "--chain base_link:l_sole" in choice.describe()

    # a robot of legs only (a quadruped, a biped whose arms are fixed): its longest leg, also
    # beside a sensor frame on the body (a chain without joints)
    legs_only = [j for j in joints if not any(f'"{a}"' in j for a in arm)]
    legs_only.append(_j("imu_joint", "fixed", "torso", "imu"))
    robot = _tree_urdf(tmp_path, "".join(legs_only), [*links, "imu"])
    choice = default_cspace(robot.tree, collision_links=geometry)
    assert choice.joints == tuple(leg) and not choice.legs


def test_a_jaw_named_like_an_arm_joint_is_left_out_by_its_finger_link(tmp_path: Path) -> None:
    """Boston Dynamics Spot with its arm: 'arm_f1x' opens the gripper, a revolute joint from
    the wrist 'arm_link_wr1' into 'arm_link_fngr' (the jaw) with nothing below. Its name says
    only 'arm', its link says finger ('fngr'): a gripper's joint, so the arm is the six
    joints up to 'arm_wr1' and the tool frame the wrist link the jaw hangs from. A joint
    into a finger link that carries further joints is no jaw."""
    arm = ["arm_sh0", "arm_sh1", "arm_el0", "arm_el1", "arm_wr0", "arm_wr1"]
    links, joints, parent = ["body"], [], "body"
    for name in arm:
        child = name.replace("arm_", "arm_link_")
        links.append(child)
        joints.append(_j(name, "revolute", parent, child))
        parent = child
    links.append("arm_link_fngr")
    joints.append(_j("arm_f1x", "revolute", "arm_link_wr1", "arm_link_fngr"))
    for leg in ("front_left", "front_right"):
        links += [f"{leg}_hip", f"{leg}_upper_leg", f"{leg}_lower_leg"]
        joints.append(_j(f"{leg}_hip_x", "revolute", "body", f"{leg}_hip"))
        joints.append(_j(f"{leg}_hip_y", "revolute", f"{leg}_hip", f"{leg}_upper_leg"))
        joints.append(_j(f"{leg}_knee", "revolute", f"{leg}_upper_leg", f"{leg}_lower_leg"))
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    assert joint_roles(robot.tree) == {"arm_f1x": "gripper"}
    choice = default_cspace(robot.tree)
    assert choice.joints == tuple(arm)
    assert choice.tool is not None and choice.tool.frame == "arm_link_wr1"

    finger_base = [
        _j("j1", "revolute", "base_link", "link1"),
        _j("arm_j2", "revolute", "link1", "finger_mount"),
        _j("j3", "revolute", "finger_mount", "link3"),
    ]
    robot = _tree_urdf(
        tmp_path, "".join(finger_base), ["base_link", "link1", "finger_mount", "link3"]
    )
    assert "arm_j2" not in joint_roles(robot.tree)


def test_a_joint_that_rolls_the_hand_is_the_last_arm_joint(tmp_path: Path) -> None:
    """Booster T1's seven-joint arm ends in 'Left_Hand_Roll' into 'left_hand_link': a joint
    named like a hand with a roll/pitch/yaw word turns the whole hand, a wrist joint; a hand
    joint with a finger word or no rotation word (NAO's 'LHand') stays a gripper's."""
    arm = ["Left_Shoulder_Pitch", "Left_Elbow_Pitch", "Left_Wrist_Yaw", "Left_Hand_Roll"]
    links, joints, parent = ["Trunk"], [], "Trunk"
    for k, name in enumerate(arm):
        child = "left_hand_link" if name == arm[-1] else f"AL{k + 1}"
        links.append(child)
        joints.append(_j(name, "revolute", parent, child))
        parent = child
    others = {
        "Left_Hand_Thumb_Roll": "thumb_link",
        "LHand": "l_gripper",
        "r2/left_arm/hand/index/yaw": "index_link",  # Robonaut 2's index finger
    }
    for name, child in others.items():
        links.append(child)
        joints.append(_j(name, "revolute", "left_hand_link", child))
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    assert joint_roles(robot.tree) == dict.fromkeys(others, "gripper")
    choice = default_cspace(robot.tree)
    assert choice.joints == tuple(arm)
    assert choice.tool is not None and choice.tool.frame == "left_hand_link"


def test_a_joint_named_hand_above_free_fingers_is_the_last_arm_joint(tmp_path: Path) -> None:
    """Unitree H1 with its hands: 'left_hand_joint' (elbow to 'left_hand_link') turns the
    hand whose fingers hang below it, each moving on its own with a mimic follower: a wrist
    joint, and the tool frame is the hand's base. A hand joint whose fingers all follow it
    as mimics (NAO's 'LHand') closes the hand: a gripper's."""
    arm = ["left_shoulder_pitch_joint", "left_elbow_joint", "left_hand_joint"]
    links = ["pelvis", "shoulder", "elbow", "left_hand_link", "L_hand_base_link"]
    joints = [
        _j(arm[0], "revolute", "pelvis", "shoulder"),
        _j(arm[1], "revolute", "shoulder", "elbow"),
        _j(arm[2], "revolute", "elbow", "left_hand_link"),
        _j("L_base_link_joint", "fixed", "left_hand_link", "L_hand_base_link"),
    ]
    for finger in ("index", "thumb"):
        prox, inter = f"L_{finger}_proximal", f"L_{finger}_intermediate"
        links += [prox, inter]
        joints += [
            _j(f"{prox}_joint", "revolute", "L_hand_base_link", prox),
            _j(f"{inter}_joint", "revolute", prox, inter, f'<mimic joint="{prox}_joint"/>'),
        ]
    links += ["r_hand", "r_finger_1", "r_finger_2"]
    joints += [  # a hand that closes: both fingers follow 'RHand'
        _j("RHand", "revolute", "pelvis", "r_hand"),
        _j("r_f1", "revolute", "r_hand", "r_finger_1", '<mimic joint="RHand"/>'),
        _j("r_f2", "revolute", "r_hand", "r_finger_2", '<mimic joint="RHand"/>'),
    ]
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    roles = joint_roles(robot.tree)
    assert "left_hand_joint" not in roles
    assert roles["RHand"] == "gripper"
    assert roles["L_index_proximal_joint"] == roles["L_thumb_intermediate_joint"] == "gripper"
    choice = default_cspace(robot.tree)
    assert choice.joints == tuple(arm)
    assert choice.tool is not None and choice.tool.frame == "L_hand_base_link"


def test_a_group_of_two_branches_gets_a_tool_frame_on_each(tmp_path: Path) -> None:
    """The Shadow Hand's SRDF group 'rh_little_finger_thumb' lists the joints of two fingers
    and names no end effector: each finger's tip is a tool frame (only the thumb's was). A
    serial chain keeps its one tool frame."""
    links = ["palm", "lf1", "lf2", "lftip", "th1", "th2", "thtip"]
    joints = "".join(
        [
            _j("LFJ2", "revolute", "palm", "lf1"),
            _j("LFJ1", "revolute", "lf1", "lf2"),
            _j("LFtip", "fixed", "lf2", "lftip"),
            _j("THJ2", "revolute", "palm", "th1"),
            _j("THJ1", "revolute", "th1", "th2"),
            _j("thtip", "fixed", "th2", "thtip"),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    srdf = tmp_path / "r.srdf"
    srdf.write_text(
        '<robot name="r"><group name="lf_th">'
        + "".join(f'<joint name="{j}"/>' for j in ("LFJ2", "LFJ1", "THJ2", "THJ1"))
        + "</group></robot>"
    )
    x, diags = convert(robot, ConvertOptions(srdf=srdf))
    assert x.tool_frames == ("lftip", "thtip")
    chosen = [d.message for d in diags if d.rule == "convert-chosen-tool-frame"]
    assert len(chosen) == 2 and "'lftip'" in chosen[0] and "'thtip'" in chosen[1]
    x, _ = convert(robot, ConvertOptions(joints=("THJ2", "THJ1")))
    assert x.tool_frames == ("thtip",)


def test_a_hand_alone_plans_for_its_longest_finger(tmp_path: Path) -> None:
    """The Allegro hand's root is its palm and every joint is a finger's: the default is
    the longest finger, said to be one; a gripper alone with one joint per jaw has no finger
    to plan and says what it left out."""
    links = ["palm_link", "f1a", "f1b", "f1c", "f2a", "f2b", "imu"]
    joints = "".join(
        [
            _j("joint_0", "revolute", "palm_link", "f1a"),
            _j("joint_1", "revolute", "f1a", "f1b"),
            _j("joint_2", "revolute", "f1b", "f1c"),
            _j("joint_4", "revolute", "palm_link", "f2a"),
            _j("joint_5", "revolute", "f2a", "f2b"),
            _j("imu_joint", "fixed", "palm_link", "imu"),
        ]
    )
    robot = _tree_urdf(tmp_path, joints, links)
    choice = default_cspace(robot.tree)
    assert choice.joints == ("joint_0", "joint_1", "joint_2") and choice.hand_alone
    assert choice.describe().startswith("the robot is a hand alone (only finger joints): ")
    assert choice.tool is not None and choice.tool.frame == "f1c"

    jaws = _j("left", "prismatic", "gripper_base", "l") + _j(
        "right", "prismatic", "gripper_base", "r"
    )
    robot = _tree_urdf(tmp_path, jaws, ["gripper_base", "l", "r"])
    choice = default_cspace(robot.tree)
    assert choice.joints == () and not choice.hand_alone
    assert "besides 2 gripper joint(s) (left, right)" in choice.describe()


def test_a_quadrupeds_other_legs_are_named_once_as_ties_not_as_passed_over(
    tmp_path: Path,
) -> None:
    """onshape-to-robot's quadruped: four three-joint legs. One is planned for; the other
    three are as long (each with its --chain), not 'passed over' legs as well."""
    links, joints = ["body"], []
    for k in range(1, 5):
        parent = "body"
        for part in "abc":
            child = f"leg{k}_{part}_link"
            links.append(child)
            joints.append(_j(f"leg{k}_{part}", "revolute", parent, child))
            parent = child
    robot = _tree_urdf(tmp_path, "".join(joints), links)
    choice = default_cspace(robot.tree)
    assert choice.joints == ("leg1_a", "leg1_b", "leg1_c")
    assert [c.cspace[0] for c, _ in choice.ties] == ["leg2_a", "leg3_a", "leg4_a"]
    assert choice.legs == ()
    text = choice.describe()
    assert "passed over" not in text
    assert text.count("--chain body:leg2_c_link") == 1


def test_a_grippers_frame_wins_over_a_wrist_cameras_frame(tmp_path: Path) -> None:
    """SO-101 with a wrist camera: two frames without geometry hang from the gripper,
    'gripper_frame_link' and 'd405_link' (a RealSense D405, its model in digits). The tool
    frame is the gripper's, whatever the names' order; a camera's frame is never chosen, and
    with no other frame the guess falls back to the link the chain ends at."""
    box = "<collision><geometry><box size='0.02 0.02 0.02'/></geometry></collision>"
    solid = ["base_link", "upper", "gripper_link", "jaw"]

    def urdf(frames: list[str]) -> Robot:
        links = "".join(f'<link name="{n}">{box}</link>' for n in solid)
        links += "".join(f'<link name="{n}"/>' for n in frames)
        joints = "".join(
            [
                _j("shoulder", "revolute", "base_link", "upper"),
                _j("wrist_roll", "revolute", "upper", "gripper_link"),
                _j("gripper", "revolute", "gripper_link", "jaw"),
                *(_j(f"to_{n}", "fixed", "gripper_link", n) for n in frames),
            ]
        )
        p = tmp_path / "so101.urdf"
        p.write_text(f'<robot name="so101">{links}{joints}</robot>')
        return as_robot(load_urdf(p))

    for frames in (["gripper_frame_link", "d405_link"], ["d405_link", "gripper_frame_link"]):
        x, _ = convert(urdf(frames), ConvertOptions())
        assert x.cspace is not None and x.cspace.joint_names == ("shoulder", "wrist_roll")
        assert x.tool_frames == ("gripper_frame_link",)
    for camera in ("d405_link", "camera_d435i_link", "wrist_L515", "realsense_link"):
        x, _ = convert(urdf([camera]), ConvertOptions())
        assert x.tool_frames == ("gripper_link",), camera


def test_joints_below_a_left_out_joint_are_counted_and_marked(tmp_path: Path) -> None:
    """KUKA iiwa + Allegro: the fingers' first joints are left out as a gripper's and the
    nine below them, named like nothing, were left out without a word ("left out: 7 gripper
    joint(s)" for 16). They are counted in the choice and marked in inspect's tree."""
    from typer.testing import CliRunner

    from xrdf_tools.cli import app

    joint = (
        '<joint name="{0}" type="revolute"><parent link="{1}"/><child link="{2}"/>'
        '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )
    chain = [("shoulder", "base", "l1"), ("elbow", "l1", "l2"), ("wrist", "l2", "palm")]
    chain += [("finger_base", "palm", "f1"), ("j_a", "f1", "f2"), ("j_b", "f2", "f3")]
    links = "".join(f'<link name="{n}"/>' for n in ("base", "l1", "l2", "palm", "f1", "f2", "f3"))
    urdf = tmp_path / "armhand.urdf"
    urdf.write_text(f'<robot name="a">{links}{"".join(joint.format(*j) for j in chain)}</robot>')
    chosen = default_cspace(as_robot(load_urdf(urdf)).tree)
    assert chosen.joints == ("shoulder", "elbow", "wrist")
    assert dict(chosen.left_out) == {"gripper": ("finger_base",), "below": ("j_a", "j_b")}
    assert "2 joint(s) below those (j_a, j_b)" in chosen.describe()
    r = CliRunner().invoke(app, ["inspect", str(urdf)])
    assert r.exit_code == 0, r.output
    assert "j_a (revolute [-1, 1], left out: below a left-out joint)" in r.stdout
