"""Shapes found in public XRDF files (docs/lint.md, "On XRDFs in the wild"), rebuilt small."""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.lint import lint_text

# An arm with a hand; the hand carries a finger (moved by its own joint, outside the c-space)
# with a geometry-less fingertip frame fixed below it, and a camera fixed to the hand.
HAND_URDF = """<robot name="hand">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="arm"><collision><geometry><box size="0.1 0.1 0.4"/></geometry></collision></link>
  <link name="hand"><collision><geometry><box size="0.1 0.1 0.05"/></geometry></collision></link>
  <link name="finger"><collision><geometry><box size="0.02 0.02 0.05"/></geometry>
    </collision></link>
  <link name="fingertip"/>
  <link name="camera"><collision><geometry><box size="0.02 0.1 0.02"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="j2" type="fixed"><parent link="arm"/><child link="hand"/>
    <origin xyz="0 0 0.5"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="hand"/><child link="finger"/>
    <origin xyz="0 0.03 0.05"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="10" velocity="1"/></joint>
  <joint name="tip" type="fixed"><parent link="finger"/><child link="fingertip"/>
    <origin xyz="0 0 0.045"/></joint>
  <joint name="cam" type="fixed"><parent link="hand"/><child link="camera"/>
    <origin xyz="0.08 0 0"/></joint>
</robot>
"""

HAND_XRDF = """format: xrdf
format_version: 1.0
cspace:
  joint_names: [j1]
  acceleration_limits: [10.0]
  jerk_limits: [1000.0]
tool_frames: [fingertip]
collision:
  geometry: spheres
self_collision:
  geometry: spheres
  ignore:
    base: [arm]
geometry:
  spheres:
    spheres:
      base:
        - {center: [0.0, 0.0, 0.0], radius: 0.08}
      arm:
        - {center: [0.0, 0.0, 0.2], radius: 0.08}
      hand:
        - {center: [0.0, 0.0, 0.0], radius: 0.06}
      fingertip:
        - {center: [0.0, 0.0, -0.02], radius: 0.015}
"""


def _findings(tmp_path: Path, xrdf: str, urdf: str, target: str | None) -> list[str]:
    (tmp_path / "robot.urdf").write_text(urdf)
    path, urdf_path = str(tmp_path / "robot.xrdf"), tmp_path / "robot.urdf"
    found = lint_text(xrdf, path, urdf=urdf_path, target=target)
    return [f"{d.severity.value} {d.rule} {d.message}" for d in found]


def test_spheres_on_a_fingertip_frame_cover_the_finger_above_it(tmp_path: Path) -> None:
    # cuMotion's franka.xrdf: the finger spheres sit on panda_leftfingertip, a geometry-less
    # frame fixed below panda_leftfinger; the finger is seen, the camera fixed to the hand
    # (no spheres; the hand's spheres miss it) is not.
    found = _findings(tmp_path, HAND_XRDF, HAND_URDF, "cumotion")
    found = [f for f in found if "mesh-without" in f]
    assert not [f for f in found if "'finger'" in f], found
    assert [f for f in found if f.startswith("error") and "'camera'" in f], found


def test_an_attached_object_slot_on_the_fingertip_covers_nothing(tmp_path: Path) -> None:
    xrdf = HAND_XRDF.replace("radius: 0.015", "radius: -10.0")
    found = _findings(tmp_path, xrdf, HAND_URDF, "cumotion")
    assert [f for f in found if f.startswith("error mesh-without-spheres link 'finger'")], found


REPEATED_IGNORE = """format: xrdf
format_version: 1.0
cspace:
  joint_names: [j1]
  acceleration_limits: [10.0]
  jerk_limits: [1000.0]
tool_frames: [hand]
collision:
  geometry: spheres
self_collision:
  geometry: spheres
  ignore:
    base: [arm]
    arm: [hand]

    base: [arm, hand]
    arm: {arm_again}
geometry:
  spheres:
    spheres:
      base:
        - {{center: [0.0, 0.0, 0.0], radius: 0.08}}
"""


def _duplicates(text: str, target: str | None) -> list[tuple[int, str]]:
    found = lint_text(text, "robot.xrdf", target=target)
    return [(d.line or 0, d.severity.value) for d in found if d.rule == "duplicate-key"]


def test_a_repeat_cuRobo_reads_as_meant_is_a_warning_for_curobo_only() -> None:
    # Isaac ROS cuMotion's ur5e_robotiq_2f_140.xrdf repeats five ignore keys, each later list
    # holding every link of the earlier one: cuRobo's reader keeps the last, nothing is lost.
    text = REPEATED_IGNORE.format(arm_again="[hand]")
    assert _duplicates(text, "curobo") == [(16, "warning"), (17, "warning")]
    assert _duplicates(text, "cumotion") == [(16, "error"), (17, "error")]
    assert _duplicates(text, None) == [(16, "error"), (17, "error")]


def test_a_repeat_that_drops_an_earlier_item_stays_an_error_for_curobo() -> None:
    text = REPEATED_IGNORE.format(arm_again="[base]")  # 'hand' of line 15 would be lost
    assert _duplicates(text, "curobo") == [(16, "warning"), (17, "error")]


def _with_links(extra_links: str) -> str:
    """HAND_URDF with more links fixed to the hand."""
    return HAND_URDF.replace("</robot>", extra_links + "</robot>")


def test_a_placeholder_without_spheres_is_no_error_for_a_planner(tmp_path: Path) -> None:
    """NVIDIA's UR XRDFs give ``ee_link`` (a 1 cm collision box in UR's URDF) no sphere;
    ``lint --target curobo`` called the file's robot invisible there, an error. A placeholder
    (collision primitives under 2 cm across, as the fitter judges one) is a warning that says
    so; a part just past 2 cm, or two tiny boxes 3 cm apart, stay errors."""
    ee = '<box size="0.01 0.01 0.01"/>'
    links = (
        f'<link name="ee_link"><collision><origin xyz="-0.01 0 0"/><geometry>{ee}</geometry>'
        "</collision></link>"
        '<joint name="ee" type="fixed"><parent link="hand"/><child link="ee_link"/></joint>'
        '<link name="nub"><collision><origin rpy="0 1.5708 0"/><geometry>'
        '<cylinder radius="0.005" length="0.008"/></geometry></collision></link>'
        '<joint name="nub" type="fixed"><parent link="hand"/><child link="nub"/></joint>'
        '<link name="plate"><collision><geometry><box size="0.012 0.012 0.012"/></geometry>'
        "</collision></link>"
        '<joint name="plate" type="fixed"><parent link="hand"/><child link="plate"/></joint>'
        '<link name="pair"><collision><origin xyz="0.03 0 0"/><geometry>'
        f"{ee}</geometry></collision><collision><geometry>{ee}</geometry></collision></link>"
        '<joint name="pair" type="fixed"><parent link="hand"/><child link="pair"/></joint>'
    )
    found = _findings(tmp_path, HAND_XRDF, _with_links(links), "curobo")
    unseen = {
        line.split("link '")[1].split("'")[0]: line
        for line in found
        if "mesh-without-spheres" in line
    }
    assert (
        unseen["ee_link"].startswith("warning")
        and "placeholder, 17 mm across" in (unseen["ee_link"])
    )
    assert unseen["nub"].startswith("warning") and "16 mm across" in unseen["nub"]
    assert unseen["plate"].startswith("error")  # a 12 mm cube: 20.8 mm across
    assert unseen["pair"].startswith("error")  # two 1 cm boxes 3 cm apart: 4.3 cm across


def test_a_link_whose_mesh_cannot_be_found_says_so_without_allow_missing_meshes(
    tmp_path: Path,
) -> None:
    # Elephant's MyBuddy: its torso mesh is not in the repository, so convert
    # --allow-missing-meshes fitted no spheres to it; lint without the flag said only "no
    # collision spheres", and fitting again finds the file no better
    camera = '<geometry><box size="0.02 0.1 0.02"/></geometry>'
    urdf = HAND_URDF.replace(camera, '<geometry><mesh filename="gone/camera.stl"/></geometry>')
    (tmp_path / "robot.urdf").write_text(urdf)
    path, urdf_path = str(tmp_path / "robot.xrdf"), tmp_path / "robot.urdf"
    for allowed, severity, why in (
        (False, "error", "cannot be found: gone/camera.stl is not where the URDF names it"),
        (True, "warning", "cannot be found: --allow-missing-meshes)"),
    ):
        found = lint_text(
            HAND_XRDF, path, urdf=urdf_path, target="curobo", allow_missing_meshes=allowed
        )
        (camera_d,) = [d for d in found if d.rule == "mesh-without-spheres"]
        assert camera_d.severity.value == severity and why in camera_d.message, camera_d
        assert "--package-path" not in camera_d.message
    # LEAP Hand names its palm 'palm_lower.stl', beside the URDF: --package-path cannot
    # help such a file, so it is offered only for a package:// mesh, with the package's name
    (tmp_path / "robot.urdf").write_text(
        urdf.replace('"gone/camera.stl"', '"package://cam_description/camera.stl"')
    )
    found = lint_text(HAND_XRDF, path, urdf=urdf_path, target="curobo")
    (camera_d,) = [d for d in found if d.rule == "mesh-without-spheres"]
    assert "pass --package-path cam_description=DIR to fit spheres" in camera_d.message
