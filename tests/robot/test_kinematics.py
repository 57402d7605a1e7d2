"""Kinematic model and batched FK, checked against yourdfpy's per-configuration FK."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from xrdf_tools.diagnostics import Severity
from xrdf_tools.robot.kinematics import (
    JointType,
    KinematicModel,
    build_kinematic_model,
    default_configuration,
    fk,
    fk_batch_last,
    fk_rt,
    full_configuration,
)
from xrdf_tools.robot.urdf_source import joints_of, links_of, load_urdf, parse_urdf_string
from xrdf_tools.util.errors import UrdfError
from xrdf_tools.xrdf.io import parse_xrdf

THREE_LINK = FIXTURES / "urdf" / "three_link_mimic.urdf"
TOL = 1e-9


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------
def random_q(model: KinematicModel, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(model.lower, model.upper, size=(n, model.n_actuated))


def reference_fk(urdf, model: KinematicModel, q: np.ndarray, frames=None) -> np.ndarray:
    """yourdfpy, one configuration at a time: [B, F, 4, 4] relative to the model's base."""
    names = list(model.frame_names if frames is None else frames)
    out = np.empty((q.shape[0], len(names), 4, 4))
    for b in range(q.shape[0]):
        urdf.update_cfg({n: float(q[b, k]) for k, n in enumerate(model.actuated_joints)})
        for i, f in enumerate(names):
            out[b, i] = urdf.get_transform(f, model.base_frame)
    return out


def xrdf_with(modifiers: str) -> str:
    return (
        "format: xrdf\nformat_version: 2.0\nmodifiers:\n"
        + modifiers
        + "cspace:\n  joint_names: []\n  acceleration_limits: []\n  jerk_limits: []\n"
    )


def tiny_urdf(joints: str, links: tuple[str, ...] = ("a", "b", "c", "d")) -> str:
    body = "".join(f'<link name="{n}"/>' for n in links)
    return f'<robot name="tiny">{body}\n{joints}</robot>'


def rev(name: str, parent: str, child: str, extra: str = "") -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0.1 0.2 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0 0 1"/>'
        f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>\n'
    )


@pytest.fixture(scope="module")
def three_link():
    urdf = load_urdf(THREE_LINK, build_scene_graph=True)
    model, diags = build_kinematic_model(urdf)
    assert diags == []
    return urdf, model


@pytest.fixture(scope="module")
def panda():
    urdf = load_urdf(robot_urdf("panda"), build_scene_graph=True)
    model, diags = build_kinematic_model(urdf)
    assert diags == []
    return urdf, model


# --------------------------------------------------------------------------------------------
# FK against yourdfpy on real robots
# --------------------------------------------------------------------------------------------
FAST_ROBOTS = ["panda", "ur5", "kinova", "xarm7", "z1"]
LARGE_ROBOTS = ["pr2", "baxter", "romeo", "talos"]  # 50-90 links each, still < 0.1 s


def check_against_yourdfpy(name: str, seeds=(0, 1, 2), batch: int = 4) -> KinematicModel:
    urdf = load_urdf(robot_urdf(name), build_scene_graph=True)
    model, diags = build_kinematic_model(urdf)
    assert diags == []
    assert set(model.frame_names) == set(links_of(urdf))
    for seed in seeds:
        q = random_q(model, batch, seed)
        got = fk(model, q)
        want = reference_fk(urdf, model, q)
        np.testing.assert_allclose(got, want, rtol=0, atol=TOL, err_msg=f"{name} seed {seed}")
    return model


@pytest.mark.parametrize("name", FAST_ROBOTS)
def test_fk_matches_yourdfpy(name: str) -> None:
    check_against_yourdfpy(name)


@pytest.mark.parametrize("name", LARGE_ROBOTS)
def test_fk_matches_yourdfpy_large_robots(name: str) -> None:
    model = check_against_yourdfpy(name, seeds=(0, 1), batch=3)
    assert model.mimic_joints  # all four have mimic joints
    assert model.n_frames >= 50 or name == "baxter"


def test_robot_joint_kinds_are_covered() -> None:
    kinds = set()
    for name in ("panda", "kinova"):
        model, _ = build_kinematic_model(load_urdf(robot_urdf(name)))
        kinds |= {JointType(int(c)).name for c in model.joint_type}
    assert {"REVOLUTE", "CONTINUOUS", "PRISMATIC", "FIXED"} <= kinds


def test_panda_mimic_finger(panda) -> None:
    _, model = panda
    assert "panda_finger_joint2" not in model.actuated_joints
    assert model.mimic_joints == ("panda_finger_joint2",)
    i = model.frame_index("panda_rightfinger")
    assert model.q_index[i] == model.actuated_index("panda_finger_joint1")
    q = random_q(model, 2, 7)
    q[:, model.actuated_index("panda_finger_joint1")] = [0.0, 0.04]
    T = fk(model, q, ["panda_leftfinger", "panda_rightfinger"])
    gap = np.linalg.norm(T[:, 0, :3, 3] - T[:, 1, :3, 3], axis=-1)
    np.testing.assert_allclose(gap, [0.0, 0.08], atol=1e-12)


# --------------------------------------------------------------------------------------------
# the small fixture: revolute, continuous, prismatic, mimic with multiplier/offset, fixed
# --------------------------------------------------------------------------------------------
def test_three_link_structure(three_link) -> None:
    _, m = three_link
    assert m.frame_names == ("base_link", "link1", "link2", "link3", "finger", "tool")
    assert m.actuated_joints == ("joint1", "joint2", "joint3")
    assert m.base_frame == "base_link"
    assert list(m.parent) == [-1, 0, 1, 2, 3, 3]
    assert m.joint_of_frame == (None, "joint1", "joint2", "joint3", "finger_joint", "tool_joint")
    assert [JointType(int(c)) for c in m.joint_type] == [
        JointType.FIXED,
        JointType.REVOLUTE,
        JointType.CONTINUOUS,
        JointType.PRISMATIC,
        JointType.REVOLUTE,
        JointType.FIXED,
    ]
    np.testing.assert_allclose(m.lower, [-2.0, -math.pi, 0.05])
    np.testing.assert_allclose(m.upper, [2.0, math.pi, 0.4])
    assert list(m.continuous) == [False, True, False]
    f = m.frame_index("finger")
    assert (m.q_index[f], m.mimic_multiplier[f], m.mimic_offset[f]) == (0, -0.5, 0.1)
    assert list(m.q_index) == [-1, 0, 1, 2, 0, -1]
    assert m.mimic_joints == ("finger_joint",)
    assert list(m.joints) == ["joint1", "joint2", "joint3", "finger_joint", "tool_joint"]
    assert m.pruned_frames == () and m.pruned_joints == ()
    with pytest.raises(ValueError):
        m.parent[0] = 3  # read-only


def test_three_link_matches_yourdfpy(three_link) -> None:
    urdf, m = three_link
    for seed in range(5):
        q = random_q(m, 6, seed)
        q[0, 1] = 5.0  # continuous joints are not limited
        np.testing.assert_allclose(fk(m, q), reference_fk(urdf, m, q), rtol=0, atol=TOL)


def test_three_link_hand_computed(three_link) -> None:
    _, m = three_link
    T = fk(m, [0.0, 0.0, 0.2], ["link3"])

    # link3 = trans(0,0,0.1) · [trans(.3,0,.05) rpy(.1,-.2,.3)] · trans(.25,0,0) ry(.5) · tx(.2)
    want = (
        _tf([0, 0, 0.1])
        @ _tf([0.3, 0, 0.05], _rpy(0.1, -0.2, 0.3))
        @ _tf([0.25, 0, 0], _rpy(0, 0.5, 0))
        @ _tf([0.2, 0, 0])
    )
    np.testing.assert_allclose(T[0], want, atol=1e-12)


def test_joints_of_and_links_of(three_link) -> None:
    urdf, _ = three_link
    assert links_of(urdf) == ["base_link", "link1", "link2", "link3", "finger", "tool"]
    joints = joints_of(urdf)
    assert list(joints) == ["joint1", "joint2", "joint3", "finger_joint", "tool_joint"]
    j = joints["finger_joint"]
    assert (j.type, j.parent, j.child) == ("revolute", "link3", "finger")
    assert (j.mimic_joint, j.mimic_multiplier, j.mimic_offset) == ("joint1", -0.5, 0.1)
    assert j.is_mimic and j.is_movable and not j.is_actuated
    assert (j.lower, j.upper, j.velocity) == (-1.5, 1.5, 1.0)
    assert j.axis == (0.6, 0.0, 0.8)
    assert joints["joint2"].lower is None and joints["joint2"].velocity == 2.0
    assert joints["tool_joint"].origin.shape == (4, 4)
    text = THREE_LINK.read_text().splitlines()
    assert 'name="finger_joint"' in text[joints["finger_joint"].line - 1]
    assert joints["joint1"] == joints_of(urdf)["joint1"]
    assert joints["joint1"] != joints["joint2"]


# --------------------------------------------------------------------------------------------
# batch FK properties and API
# --------------------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(
    st.integers(min_value=1, max_value=12),
    st.integers(min_value=0, max_value=2**32 - 1),
    st.sampled_from(["three_link", "panda"]),
)
def test_batch_equals_loop_of_single(batch: int, seed: int, which: str) -> None:
    m = _MODELS[which]()
    q = random_q(m, batch, seed)
    T = fk(m, q)
    R, t = fk_rt(m, q)
    for b in range(batch):
        single = fk(m, q[b])
        assert single.shape == (m.n_frames, 4, 4)
        np.testing.assert_allclose(T[b], single, rtol=0, atol=1e-12)
        np.testing.assert_allclose(R[b], single[:, :3, :3], rtol=0, atol=1e-12)
        np.testing.assert_allclose(t[b], single[:, :3, 3], rtol=0, atol=1e-12)


def _load_model(path: Path) -> KinematicModel:
    return build_kinematic_model(load_urdf(path))[0]


_CACHE: dict[str, KinematicModel] = {}
_MODELS = {
    "three_link": lambda: _CACHE.setdefault("t", _load_model(THREE_LINK)),
    "panda": lambda: _CACHE.setdefault("p", _load_model(robot_urdf("panda"))),
}


def test_fk_results_are_rigid_transforms(panda) -> None:
    _, m = panda
    T = fk(m, random_q(m, 64, 3))
    R = T[..., :3, :3]
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-12)  # fmt: skip
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    np.testing.assert_array_equal(T[..., 3, :], np.broadcast_to([0, 0, 0, 1], T[..., 3, :].shape))


def test_frame_selection(panda) -> None:
    _, m = panda
    q = random_q(m, 5, 11)
    full = fk(m, q)
    names = ["panda_hand_tcp", "panda_link3", "panda_link0", "panda_hand_tcp"]
    idx = [m.frame_index(n) for n in names]
    np.testing.assert_array_equal(fk(m, q, names), full[:, idx])
    np.testing.assert_array_equal(fk(m, q, idx), full[:, idx])
    np.testing.assert_array_equal(fk(m, q, np.array(idx)), full[:, idx])
    R, t = fk_rt(m, q, names)
    assert R.shape == (5, 4, 3, 3) and t.shape == (5, 4, 3)
    np.testing.assert_array_equal(t, full[:, idx][..., :3, 3])
    Rb, tb = fk_batch_last(m, q, names)
    assert Rb.shape == (4, 3, 3, 5) and tb.shape == (4, 3, 5)
    np.testing.assert_array_equal(np.moveaxis(Rb, -1, 0), full[:, idx, :3, :3])
    out = (np.empty((4, 3, 3, 5)), np.empty((4, 3, 5)))
    res = fk_batch_last(m, q, names, out=out)
    assert res[0] is out[0] and res[1] is out[1]
    np.testing.assert_array_equal(out[1], tb)
    out_all = (np.empty((m.n_frames, 3, 3, 5)), np.empty((m.n_frames, 3, 5)))
    fk_batch_last(m, q, out=out_all)
    np.testing.assert_array_equal(np.moveaxis(out_all[1], -1, 0), full[..., :3, 3])


def test_fk_input_checks(three_link) -> None:
    _, m = three_link
    with pytest.raises(ValueError, match=r"shape \[3\] or \[B, 3\].*joint1, joint2, joint3"):
        fk(m, np.zeros(4))
    with pytest.raises(ValueError, match=r"got \[2, 2\]"):
        fk(m, np.zeros((2, 2)))
    with pytest.raises(ValueError, match="got"):
        fk(m, np.zeros((1, 2, 3)))
    with pytest.raises(ValueError, match="out of range"):
        fk(m, np.zeros(3), [6])
    with pytest.raises(UrdfError, match="did you mean 'link2'"):
        fk(m, np.zeros(3), ["lnk2"])
    with pytest.raises(ValueError, match="out must be"):
        fk_batch_last(m, np.zeros((2, 3)), out=(np.empty((6, 3, 3, 3)), np.empty((6, 3, 2))))
    assert fk(m, np.zeros((0, 3))).shape == (0, 6, 4, 4)
    assert fk(m, [0.0, 0.0, 0.1], "tool").shape == (1, 4, 4)


def test_configurations(three_link) -> None:
    _, m = three_link
    np.testing.assert_array_equal(default_configuration(m), [0.0, 0.0, 0.05])  # zero clamped
    np.testing.assert_array_equal(default_configuration(m, {"joint2": 1.0}), [0.0, 1.0, 0.05])
    q = full_configuration(m, ["joint3", "joint1"], [[0.3, -1.0], [0.1, 1.0]], {"joint2": 0.5})
    np.testing.assert_array_equal(q, [[-1.0, 0.5, 0.3], [1.0, 0.5, 0.1]])
    np.testing.assert_array_equal(full_configuration(m, ["joint1"], [0.7]), [0.7, 0.0, 0.05])
    np.testing.assert_array_equal(full_configuration(m, [], np.zeros((2, 0))), [[0, 0, 0.05]] * 2)
    with pytest.raises(UrdfError, match=r"mimic joint.*follows 'joint1'"):
        full_configuration(m, ["finger_joint"], [0.0])
    with pytest.raises(UrdfError, match="fixed joint"):
        full_configuration(m, ["tool_joint"], [0.0])
    with pytest.raises(UrdfError, match="did you mean 'joint3'"):
        full_configuration(m, ["joint33"], [0.0])
    with pytest.raises(ValueError, match="repeat"):
        full_configuration(m, ["joint1", "joint1"], [0.0, 0.0])
    with pytest.raises(ValueError, match="q_cspace must have shape"):
        full_configuration(m, ["joint1"], [[0.0, 1.0]])


# --------------------------------------------------------------------------------------------
# XRDF modifiers
# --------------------------------------------------------------------------------------------
PANDA_MODIFIERS = """\
  - add_frame:
      frame_name: marker
      parent_frame_name: panda_link0
      joint_name: marker_joint
      joint_type: FIXED
      fixed_transform: {position: [0.5, 0.0, 0.0], orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}}
  - add_frame:
      frame_name: tcp
      parent_frame_name: panda_hand
      joint_name: tcp_joint
      joint_type: fixed
      fixed_transform:
        position: [0.0, 0.01, 0.1034]
        orientation: {w: 0.9238795325112867, xyz: [0.0, 0.0, -0.3826834323650898]}
  - set_base_frame: panda_link2
  - add_frame:
      frame_name: tcp_tip
      parent_frame_name: tcp
      joint_name: tcp_tip_joint
      joint_type: FIXED
      fixed_transform: {position: [0.01, 0.02, 0.03], orientation: {euler_rpy: [0.3, -0.2, 0.1]}}
"""


def test_set_base_frame_and_add_frame(panda) -> None:
    urdf, _ = panda
    x = parse_xrdf(xrdf_with(PANDA_MODIFIERS), "panda_test.xrdf")
    m, diags = build_kinematic_model(urdf, x)
    assert diags == []
    assert m.base_frame == "panda_link2"
    assert set(m.pruned_frames) == {"panda_link0", "panda_link1", "marker"}
    assert set(m.pruned_joints) == {"panda_joint1", "panda_joint2", "marker_joint"}
    assert m.actuated_joints[:2] == ("panda_joint3", "panda_joint4")
    assert "panda_joint1" not in m.actuated_joints and "panda_joint2" not in m.joints
    assert m.added_frames == ("tcp", "tcp_tip")
    assert m.frame_names.index("tcp_tip") > m.frame_names.index("tcp")
    assert m.joints["tcp_joint"].type == "fixed"
    for name in ("panda_link0", "marker"):
        with pytest.raises(UrdfError, match="removed by set_base_frame 'panda_link2'"):
            m.frame_index(name)
    with pytest.raises(UrdfError, match="removed by set_base_frame"):
        m.actuated_index("panda_joint1")

    pose_tcp = _tf([0.0, 0.01, 0.1034], _rot_z(-math.pi / 4))
    pose_tip = _tf([0.01, 0.02, 0.03], _rpy(0.3, -0.2, 0.1))
    urdf_frames = [f for f in m.frame_names if f not in ("tcp", "tcp_tip")]
    for seed in (0, 1, 2):
        q = random_q(m, 4, seed)
        T = fk(m, q)
        assert np.allclose(T[:, 0], np.eye(4), atol=0)  # the new base is the identity
        want = reference_fk(urdf, m, q, urdf_frames)
        np.testing.assert_allclose(T[:, [m.frame_index(f) for f in urdf_frames]], want, atol=TOL)
        hand = want[:, urdf_frames.index("panda_hand")]
        np.testing.assert_allclose(T[:, m.frame_index("tcp")], hand @ pose_tcp, atol=TOL)
        np.testing.assert_allclose(
            T[:, m.frame_index("tcp_tip")], hand @ pose_tcp @ pose_tip, atol=TOL
        )


def _tf(xyz, R=None) -> np.ndarray:
    M = np.eye(4)
    M[:3, :3] = np.eye(3) if R is None else R
    M[:3, 3] = xyz
    return M


def _rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rpy(r: float, p: float, y: float) -> np.ndarray:
    cr, sr, cp, sp = math.cos(r), math.sin(r), math.cos(p), math.sin(p)
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return _rot_z(y) @ Ry @ Rx


def test_set_base_frame_to_added_frame(three_link) -> None:
    urdf, _ = three_link
    mods = """\
  - add_frame:
      frame_name: mount
      parent_frame_name: link2
      joint_name: mount_joint
      fixed_transform: {position: [0.0, 0.0, 0.2], orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}}
  - set_base_frame: mount
"""
    m, _ = build_kinematic_model(urdf, parse_xrdf(xrdf_with(mods)))
    assert m.frame_names == ("mount",)
    assert m.actuated_joints == ()
    assert fk(m, np.zeros((3, 0))).shape == (3, 1, 4, 4)


def test_remove_mimic_attributes(three_link) -> None:
    urdf, _ = three_link
    mods = """\
  - remove_mimic_attributes:
      joint_name: finger_joint
      position_limits: [-1.0, 0.5]
      velocity_limits: 3.0
"""
    m, _ = build_kinematic_model(urdf, parse_xrdf(xrdf_with(mods)))
    assert m.actuated_joints == ("joint1", "joint2", "joint3", "finger_joint")
    assert m.mimic_joints == ()
    np.testing.assert_allclose(m.lower, [-2.0, -math.pi, 0.05, -1.0])
    np.testing.assert_allclose(m.upper, [2.0, math.pi, 0.4, 0.5])
    j = m.joints["finger_joint"]
    assert j.mimic_joint is None and j.velocity == 3.0 and j.is_actuated
    # the same as the URDF without <mimic>
    text = re.sub(r"<mimic [^>]*/>", "", THREE_LINK.read_text())
    free = parse_urdf_string(text, str(THREE_LINK), build_scene_graph=True)
    q = random_q(m, 5, 4)
    np.testing.assert_allclose(fk(m, q), reference_fk(free, m, q), atol=TOL)


def test_mimic_chain_resolved() -> None:
    chain = tiny_urdf(
        rev("j1", "a", "b")
        + rev("j2", "b", "c", '<mimic joint="j1" multiplier="2" offset="0.1"/>')
        + rev("j3", "c", "d", '<mimic joint="j2" multiplier="-1" offset="0.3"/>')
    )
    direct = tiny_urdf(
        rev("j1", "a", "b")
        + rev("j2", "b", "c", '<mimic joint="j1" multiplier="2" offset="0.1"/>')
        + rev("j3", "c", "d", '<mimic joint="j1" multiplier="-2" offset="0.2"/>')
    )
    m, _ = build_kinematic_model(parse_urdf_string(chain, "chain.urdf"))
    d = m.frame_index("d")
    assert m.actuated_joints == ("j1",)
    assert (m.q_index[d], m.mimic_multiplier[d]) == (0, -2.0)
    assert m.mimic_offset[d] == pytest.approx(0.2, abs=1e-15)
    ref = parse_urdf_string(direct, "direct.urdf", build_scene_graph=True)
    q = np.linspace(-1, 1, 7)[:, None]
    np.testing.assert_allclose(fk(m, q), reference_fk(ref, m, q), atol=TOL)


def test_floating_and_planar_joints_are_held_fixed() -> None:
    text = tiny_urdf(
        '<joint name="free" type="floating"><parent link="a"/><child link="b"/>'
        '<origin xyz="1 2 3"/></joint>\n'
        '<joint name="slide" type="planar"><parent link="b"/><child link="c"/>'
        '<axis xyz="0 0 1"/></joint>\n' + rev("j", "c", "d")
    )
    m, diags = build_kinematic_model(parse_urdf_string(text, "robot.urdf"))
    assert m.actuated_joints == ("j",)
    assert [(d.rule, d.severity, d.path, d.line) for d in diags] == [
        ("joint-held-fixed", Severity.WARNING, "robot.urdf", 2),
        ("joint-held-fixed", Severity.WARNING, "robot.urdf", 3),
    ]
    assert "floating joint 'free'" in diags[0].message
    T = fk(m, [0.5], ["c"])
    np.testing.assert_allclose(T[0, :3, 3], [1, 2, 3])
    with pytest.raises(UrdfError, match="floating joint"):
        m.actuated_index("free")


def test_missing_limits_warn() -> None:
    text = tiny_urdf(
        '<joint name="j" type="prismatic"><parent link="a"/><child link="b"/></joint>',
        ("a", "b"),
    )
    m, diags = build_kinematic_model(parse_urdf_string(text, "r.urdf"))
    assert [d.rule for d in diags] == ["joint-limits-missing"]
    assert (m.lower[0], m.upper[0]) == (0.0, 0.0)


# --------------------------------------------------------------------------------------------
# errors
# --------------------------------------------------------------------------------------------
def test_set_base_frame_missing_frame(panda) -> None:
    urdf, _ = panda
    x = parse_xrdf(xrdf_with("  - set_base_frame: panda_lnk2\n"), "bad.xrdf")
    with pytest.raises(UrdfError) as e:
        build_kinematic_model(urdf, x)
    msg = str(e.value)
    assert msg.startswith("bad.xrdf:4:21: set_base_frame: frame 'panda_lnk2'")
    assert "did you mean 'panda_link2'?" in msg
    assert "\n" not in msg


@pytest.mark.parametrize(
    ("mods", "pattern"),
    [
        (
            "  - add_frame: {frame_name: x, parent_frame_name: panda_hnd, joint_name: xj,"
            " fixed_transform: {position: [0, 0, 0]}}\n",
            r"parent frame 'panda_hnd' is not a frame of panda.urdf; did you mean 'panda_hand'",
        ),
        (
            "  - add_frame: {frame_name: panda_hand, parent_frame_name: panda_link8,"
            " joint_name: xj, fixed_transform: {position: [0, 0, 0]}}\n",
            r"frame 'panda_hand' already exists \(a link of panda.urdf\)",
        ),
        (
            "  - add_frame: {frame_name: x, parent_frame_name: panda_link8, joint_name: j,"
            " fixed_transform: {position: [0, 0, 0]}}\n"
            "  - add_frame: {frame_name: x, parent_frame_name: panda_link8, joint_name: k,"
            " fixed_transform: {position: [0, 0, 0]}}\n",
            r"frame 'x' already exists \(an earlier add_frame\)",
        ),
        (
            "  - add_frame: {frame_name: x, parent_frame_name: panda_link8,"
            " joint_name: panda_joint3, fixed_transform: {position: [0, 0, 0]}}\n",
            r"joint name 'panda_joint3' already exists",
        ),
        (
            "  - add_frame: {frame_name: x, parent_frame_name: panda_link8, joint_name: xj,"
            " joint_type: REVOLUTE, fixed_transform: {position: [0, 0, 0]}}\n",
            r"joint_type must be FIXED",
        ),
        (
            "  - set_base_frame: panda_link3\n"
            "  - add_frame: {frame_name: x, parent_frame_name: panda_link1, joint_name: xj,"
            " fixed_transform: {position: [0, 0, 0]}}\n",
            r"parent frame 'panda_link1' was removed by set_base_frame 'panda_link3'",
        ),
        (
            "  - set_base_frame: panda_link3\n  - set_base_frame: panda_link0\n",
            r"frame 'panda_link0' was removed by set_base_frame 'panda_link3'",
        ),
        (
            "  - remove_mimic_attributes: {joint_name: panda_finger_joint1}\n",
            r"joint 'panda_finger_joint1' has no <mimic>.*did you mean 'panda_finger_joint2'",
        ),
        (
            "  - remove_mimic_attributes: {joint_name: nope}\n",
            r"joint 'nope' is not a joint of panda.urdf",
        ),
    ],
)
def test_modifier_errors(panda, mods: str, pattern: str) -> None:
    urdf, _ = panda
    with pytest.raises(UrdfError, match=pattern) as e:
        build_kinematic_model(urdf, parse_xrdf(xrdf_with(mods), "m.xrdf"))
    assert e.value.path == "m.xrdf" and e.value.line is not None


def test_mimic_errors() -> None:
    loop = tiny_urdf(
        rev("j1", "a", "b", '<mimic joint="j3"/>')
        + rev("j2", "b", "c", '<mimic joint="j1"/>')
        + rev("j3", "c", "d", '<mimic joint="j2"/>')
    )
    with pytest.raises(UrdfError, match=r"mimic joints form a loop: j1 -> j3 -> j2 -> j1"):
        build_kinematic_model(parse_urdf_string(loop, "loop.urdf"))
    missing = tiny_urdf(
        rev("j1", "a", "b") + rev("j2", "b", "c", '<mimic joint="j11"/>'), ("a", "b", "c")
    )
    with pytest.raises(UrdfError, match=r"loop.urdf:3: joint 'j2' mimics 'j11'.*mean 'j1'"):
        build_kinematic_model(parse_urdf_string(missing, "loop.urdf"))


def test_tree_errors() -> None:
    two_roots = tiny_urdf(rev("j1", "a", "b") + rev("j2", "c", "d"))
    with pytest.raises(UrdfError, match=r"2 links have no parent joint \('a', 'c'\)"):
        build_kinematic_model(parse_urdf_string(two_roots, "t.urdf"))
    # ... but a base frame may pick one of the trees
    m, _ = build_kinematic_model(
        parse_urdf_string(two_roots, "t.urdf"), parse_xrdf(xrdf_with("  - set_base_frame: c\n"))
    )
    assert m.frame_names == ("c", "d")
    two_parents = tiny_urdf(rev("j1", "a", "b") + rev("j2", "c", "b"))
    with pytest.raises(UrdfError, match="link 'b' is the child of two joints"):
        build_kinematic_model(parse_urdf_string(two_parents, "t.urdf"))
    cycle = tiny_urdf(rev("j1", "a", "b") + rev("j2", "b", "a"), ("a", "b"))
    with pytest.raises(UrdfError, match="cycle"):
        build_kinematic_model(parse_urdf_string(cycle, "t.urdf"))
    zero_axis = tiny_urdf(rev("j1", "a", "b").replace("0 0 1", "0 0 0"), ("a", "b"))
    with pytest.raises(UrdfError, match="zero or invalid axis"):
        build_kinematic_model(parse_urdf_string(zero_axis, "t.urdf"))


def test_urdf_file_errors(tmp_path: Path) -> None:
    missing = tmp_path / "nope.urdf"
    with pytest.raises(UrdfError, match="URDF file not found") as e:
        load_urdf(missing)
    assert e.value.path == str(missing)
    with pytest.raises(UrdfError, match="directory"):
        load_urdf(tmp_path)

    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r">\n  <link name="a">\n</robot>\n')
    with pytest.raises(UrdfError, match="malformed XML") as e:
        load_urdf(bad)
    assert e.value.line == 3 and str(e.value).startswith(f"{bad}:3:")
    assert "\n" not in str(e.value)

    empty = tmp_path / "empty.urdf"
    empty.write_text("")
    with pytest.raises(UrdfError, match="malformed XML"):
        load_urdf(empty)


@pytest.mark.parametrize(
    ("text", "pattern", "line"),
    [
        ('<robot name="r">\n<link name="a"/>\n<link name="a"/></robot>', "defined twice", 3),
        ('<robt name="r"/>', "root element must be <robot>", 1),
        ('<robot><link name="a"/></robot>', "no 'name' attribute", 1),
        (
            '<robot name="r"><link name="a"/><link name="b"/>\n'
            '<joint name="j" type="revolut"><parent link="a"/><child link="b"/></joint></robot>',
            "type 'revolut'.*did you mean 'revolute'",
            2,
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/>\n<joint name="j" type="fixed">'
            '<parent link="a"/>\n<child link="bb"/></joint></robot>',
            "unknown child link 'bb'; did you mean 'b'",
            3,
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/>\n<joint name="j" type="fixed">'
            '<parent link="a"/><child link="b"/>\n<origin xyz="0 0"/></joint></robot>',
            r"<origin> xyz='0 0' must be 3 numbers",
            3,
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/>\n<joint name="j" type="fixed">'
            '<parent link="a"/><child link="b"/>\n<limit lower="x"/></joint></robot>',
            "is not a number",
            3,
        ),
        (
            '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
            '<xacro:macro name="m"/></robot>',
            "xacro file",
            2,
        ),
    ],
)
def test_urdf_content_errors(text: str, pattern: str, line: int) -> None:
    with pytest.raises(UrdfError, match=pattern) as e:
        parse_urdf_string(text, "x.urdf")
    assert (e.value.path, e.value.line) == ("x.urdf", line)


def test_parse_urdf_string_with_encoding_declaration() -> None:
    text = '<?xml version="1.0" encoding="UTF-8"?>\n' + tiny_urdf(rev("j", "a", "b"), ("a", "b"))
    urdf = parse_urdf_string(text, "enc.urdf")
    assert links_of(urdf) == ["a", "b"]


def test_package_paths_resolve_meshes(tmp_path: Path) -> None:
    from xrdf_tools.robot.yourdfpy_build import make_filename_handler

    pkg = tmp_path / "my_pkg"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "meshes" / "a.stl").write_text("solid a\nendsolid a\n")
    handler = make_filename_handler(tmp_path / "robot.urdf", {"my_pkg": str(pkg)})
    assert handler("package://my_pkg/meshes/a.stl") == str(pkg / "meshes" / "a.stl")
    # a file the given folder lacks is unresolved, as an unknown package is
    assert handler("package://my_pkg/meshes/b.stl") == "package://my_pkg/meshes/b.stl"
    assert handler("package://unknown_pkg_xyz/a.stl") == "package://unknown_pkg_xyz/a.stl"


def test_mimic_of_unavailable_master_is_held_at_its_offset() -> None:
    fixed_master = tiny_urdf(
        '<joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>\n'
        + rev("j2", "b", "c", '<mimic joint="j1" multiplier="3" offset="0.3"/>'),
        ("a", "b", "c"),
    )
    m, diags = build_kinematic_model(parse_urdf_string(fixed_master, "f.urdf"))
    assert m.actuated_joints == ()
    assert [d.rule for d in diags] == ["joint-held-fixed"]
    assert "held at 0.3: it mimics 'j1', a fixed joint" in diags[0].message
    want = _tf([0.1, 0.2, 0.3], _rpy(0.1, 0.2, 0.3)) @ _tf([0, 0, 0], _rot_z(0.3))
    np.testing.assert_allclose(fk(m, np.zeros(0), ["c"])[0], want, atol=1e-12)

    pruned_master = tiny_urdf(
        rev("j1", "a", "b") + rev("j2", "b", "c", '<mimic joint="j1" offset="0.2"/>'),
        ("a", "b", "c"),
    )
    x = parse_xrdf(xrdf_with("  - set_base_frame: b\n"))
    m, diags = build_kinematic_model(parse_urdf_string(pruned_master, "p.urdf"), x)
    assert m.frame_names == ("b", "c") and m.pruned_joints == ("j1",)
    assert "removed by set_base_frame 'b'" in diags[0].message
    want = _tf([0.1, 0.2, 0.3], _rpy(0.1, 0.2, 0.3)) @ _tf([0, 0, 0], _rot_z(0.2))
    np.testing.assert_allclose(fk(m, np.zeros(0))[1], want, atol=1e-12)


def test_model_pickles(three_link) -> None:
    import pickle

    _, m = three_link
    m2 = pickle.loads(pickle.dumps(m))
    q = random_q(m, 3, 0)
    np.testing.assert_array_equal(fk(m2, q), fk(m, q))
    assert m2.frame_names == m.frame_names and m2.joints == m.joints
