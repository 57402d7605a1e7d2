"""The engine's layout of big sides: two moving hands of many small frames each (a two-armed
mobile manipulator's hands, fingers not in the c-space) are packed into a few parts a side
instead of one body pair per finger pair, and the counts still equal the brute force."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from tests.selfcollision.test_collision import fixed_configs
from tests.selfcollision.test_engine import check_against_brute_force, engine_for
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import parse_xrdf

FINGERS = 20


def _two_hands(tmp_path: Path) -> tuple[Path, str]:
    """Two palms turning about parallel axes 0.35 m apart, each carrying ``FINGERS`` fixed
    finger frames of three spheres in a fan; the hands meet in part of the turns."""
    links = ['<link name="base"/>']
    joints = []
    geometry = []
    for side, x in (("l", 0.0), ("r", 0.35)):
        links.append(f'<link name="{side}_palm"/>')
        joints.append(
            f'<joint name="{side}_turn" type="revolute"><parent link="base"/>'
            f'<child link="{side}_palm"/><origin xyz="{x} 0 0"/><axis xyz="0 0 1"/>'
            '<limit lower="-3.1" upper="3.1" effort="1" velocity="1"/></joint>'
        )
        for i in range(FINGERS):
            name = f"{side}_finger{i}"
            angle = (i - FINGERS / 2) * 0.05
            links.append(f'<link name="{name}"/>')
            joints.append(
                f'<joint name="{name}_fixed" type="fixed"><parent link="{side}_palm"/>'
                f'<child link="{name}"/><origin xyz="0 0 0" rpy="0 0 {angle:.3f}"/></joint>'
            )
            geometry.append(
                f"      {name}:\n"
                + "".join(
                    f"        - center: [{r:.2f}, 0.0, 0.0]\n          radius: 0.012\n"
                    for r in (0.12, 0.16, 0.2)
                )
            )
    urdf = tmp_path / "two_hands.urdf"
    urdf.write_text('<robot name="two_hands">' + "".join(links + joints) + "</robot>")
    xrdf = (
        "format: xrdf\nformat_version: 1.0\n"
        "cspace:\n  joint_names: [l_turn, r_turn]\n"
        "  acceleration_limits: [10.0, 10.0]\n  jerk_limits: [1000.0, 1000.0]\n"
        "tool_frames: [l_palm]\n"
        "collision:\n  geometry: hands\n"
        "self_collision:\n  geometry: hands\n  ignore: {}\n"
        "geometry:\n  hands:\n    spheres:\n" + "".join(geometry)
    )
    return urdf, xrdf


def test_two_moving_hands_of_many_fingers_are_packed_and_count_exactly(tmp_path: Path) -> None:
    urdf, text = _two_hands(tmp_path)
    xrdf = parse_xrdf(text, "two_hands.xrdf")
    kin, _ = build_kinematic_model(load_urdf(urdf), xrdf)
    varying = [kin.actuated_index("l_turn"), kin.actuated_index("r_turn")]
    eng, _, _ = engine_for(kin, xrdf, False, varying)
    across = [bp for bp in eng.pairs if {bp.a, bp.b} == {1, 2}]
    # 60 spheres a side in frames of 3: packed 16 spheres (5 fingers) a part, 4 parts a side
    assert 0 < len(across) <= 16, len(across)  # one per finger pair would be 400
    assert all(len(bp.ia) <= 16 and len(bp.ib) <= 16 for bp in across)
    q = fixed_configs(kin, 150, seed=3)[:, varying]
    totals = check_against_brute_force(kin, xrdf, q, False, varying)
    assert totals.hits.sum() > 0  # the hands do meet
    assert np.count_nonzero(totals.hits) < len(totals.hits)  # and not every finger pair
