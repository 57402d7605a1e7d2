"""The engine on a real robot whose c-space leaves most bodies static (Talos, left arm only).

Bodies the c-space does not move are folded into one static body, sphere pairs that can never
come within the margin are dropped at build time (:mod:`xrdf_tools.selfcollision.engine.reach`)
and large sides are cut into frames. None of it may change a count: the engine is compared
with the plain double loop and with the reference counter.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.collision_reference import count_chunk
from tests.robots import robot_urdf
from tests.selfcollision.test_collision import fixed_configs, panda
from tests.selfcollision.test_engine import check_against_brute_force, engine_for
from tests.sphere_xrdf import Spheres, sphere_xrdf
from xrdf_tools.robot.kinematics import KinematicModel, build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import parse_xrdf
from xrdf_tools.xrdf.model import Xrdf

ARM = [f"arm_left_{i}_joint" for i in range(1, 8)]


def _talos_xrdf(kin: KinematicModel, per_link: int) -> str:
    """Spheres around every frame of Talos (seeded), the left arm as the c-space."""
    rng = np.random.default_rng(3)
    spheres: Spheres = {}
    for name in kin.frame_names[1:]:
        spheres[name] = []
        for _ in range(per_link):
            c = rng.uniform(-0.08, 0.08, 3)
            r = rng.uniform(0.02, 0.06)
            spheres[name].append((round(c[0], 4), round(c[1], 4), round(c[2], 4), round(r, 4)))
    return sphere_xrdf(ARM, spheres)


def talos_left_arm(per_link: int) -> tuple[KinematicModel, Xrdf]:
    """Talos with its left arm as the c-space and ``per_link`` spheres on every link."""
    urdf = load_urdf(robot_urdf("talos"))
    probe = parse_xrdf(
        "format: xrdf\nformat_version: 1.0\ncspace:\n  joint_names: [arm_left_1_joint]\n"
        "  acceleration_limits: [10.0]\n  jerk_limits: [100.0]\n",
        "probe.xrdf",
    )
    kin0, _ = build_kinematic_model(urdf, probe)
    xrdf = parse_xrdf(_talos_xrdf(kin0, per_link), "talos_left_arm.xrdf")
    kin, _ = build_kinematic_model(urdf, xrdf)
    return kin, xrdf


@pytest.fixture(scope="module")
def talos() -> tuple[KinematicModel, Xrdf]:
    return talos_left_arm(3)


def test_static_bodies_fold_and_far_pairs_are_never_evaluated(
    talos: tuple[KinematicModel, Xrdf],
) -> None:
    kin, xrdf = talos
    arm = [kin.actuated_index(j) for j in ARM]
    eng, spheres, _ = engine_for(kin, xrdf, True, arm, margin=0.01)
    assert eng.bodies.n == 8  # the static rest of the robot and one body per arm joint
    n_const = len(eng.const_k)
    assert n_const > spheres.n_frame_pairs // 2  # legs, torso, head, right arm: decided once
    evaluated = {k for bp in eng.pairs for k, _, _ in bp.blocks}
    names = list(spheres.frame_pair_names())
    dropped = [names[k] for k in range(spheres.n_frame_pairs) if np.isfinite(eng.reach_bound[k])]
    # the left hand can never reach the right foot: that pair is not evaluated at all
    far = next(
        k
        for k, (a, b) in enumerate(names)
        if {a, b} == {"gripper_left_base_link", "leg_right_6_link"}
    )
    assert far not in evaluated and eng.reach_bound[far] > 0.01  # beyond the margin
    assert len(dropped) > 100


@pytest.mark.slow
def test_counts_equal_brute_force_with_a_static_robot(talos: tuple[KinematicModel, Xrdf]) -> None:
    kin, xrdf = talos
    arm = [kin.actuated_index(j) for j in ARM]
    q = fixed_configs(kin, 30, seed=5)[:, arm]
    totals = check_against_brute_force(kin, xrdf, q, True, arm, margin=0.01)
    assert totals.hits.sum() > 0


def test_counts_equal_reference_counter_with_a_static_robot(
    talos: tuple[KinematicModel, Xrdf],
) -> None:
    kin, xrdf = talos
    arm = [kin.actuated_index(j) for j in ARM]
    eng, spheres, q0 = engine_for(kin, xrdf, True, arm, margin=0.01)
    qv = fixed_configs(kin, 3000, seed=9)[:, arm]
    q = np.repeat(q0[None, :], len(qv), axis=0)
    q[:, arm] = qv
    ref = count_chunk(kin, spheres, q, margin=0.01)
    hits = eng.count(qv)
    np.testing.assert_array_equal(hits, ref.hits)
    assert 0 < hits.sum() < hits.size


_MOBILE_BASE = """
  <link name="floor"/><link name="base_yaw"/><link name="base_x"/>
  <joint name="base_turn" type="revolute"><parent link="floor"/><child link="base_yaw"/>
    <axis xyz="0 0 1"/><limit lower="-999999" upper="999999" effort="1" velocity="1"/></joint>
  <joint name="base_drive" type="prismatic"><parent link="base_yaw"/><child link="base_x"/>
    <axis xyz="1 0 0"/><limit lower="-999999" upper="999999" effort="1" velocity="1"/></joint>
  <joint name="base_mount" type="revolute"><parent link="base_x"/><child link="panda_link0"/>
    <axis xyz="0 0 1"/><limit lower="-999999" upper="999999" effort="1" velocity="1"/></joint>
</robot>"""


def test_a_mobile_base_under_the_whole_arm_changes_no_count_and_is_not_modelled(
    tmp_path: Path,
) -> None:
    """A Panda on a mobile base whose three joints (±999999: "no limit") are in the c-space:
    they carry every sphere alike, so the engine holds them (their range would swamp the
    float32 error bounds and send most entries to float64) and the counts and exact
    clearances are those of the arm alone on the same arm configurations."""
    from xrdf_tools.robot.kinematics import default_configuration
    from xrdf_tools.selfcollision.collision import build_sphere_set
    from xrdf_tools.selfcollision.engine import CountEngine, EngineTotals

    kin_arm, xrdf = panda()
    urdf = tmp_path / "mobile_panda.urdf"
    urdf.write_text(robot_urdf("panda").read_text().replace("</robot>", _MOBILE_BASE))
    kin, _ = build_kinematic_model(load_urdf(urdf), xrdf)
    base = [kin.actuated_index(j) for j in ("base_turn", "base_drive", "base_mount")]
    arm = [kin.actuated_index(f"panda_joint{i}") for i in range(1, 8)]
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    eng = CountEngine(kin, spheres, base + arm, q0, margin=0.01)
    assert eng.varying.tolist() == arm and eng.columns.tolist() == list(range(3, 10))
    idx_arm = [kin_arm.actuated_index(f"panda_joint{i}") for i in range(1, 8)]
    q_arm = fixed_configs(kin_arm, 3000, seed=31)[:, idx_arm]
    rng = np.random.default_rng(5)
    q_base = rng.uniform(-999999.0, 999999.0, size=(len(q_arm), 3))
    totals = EngineTotals.empty(eng.K)
    hits = eng.count(np.hstack([q_base, q_arm]), totals)
    arm_spheres, _ = build_sphere_set(kin_arm, xrdf, include_masked=True)
    q0_arm = default_configuration(kin_arm, xrdf.default_joint_positions)
    ref = CountEngine(kin_arm, arm_spheres, idx_arm, q0_arm, margin=0.01)
    ref_totals = EngineTotals.empty(ref.K)
    ref_hits = ref.count(q_arm, ref_totals)
    assert list(spheres.frame_pair_names()) == list(arm_spheres.frame_pair_names())
    np.testing.assert_array_equal(hits, ref_hits)
    assert hits.any() and totals.rechecked <= ref_totals.rechecked + 10
    exact = ref_totals.min_clearance < 0.01
    np.testing.assert_allclose(
        totals.min_clearance[exact], ref_totals.min_clearance[exact], atol=1e-12
    )
