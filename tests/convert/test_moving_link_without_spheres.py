"""`xrdf convert --fit-spheres` warns when a link a c-space joint moves has visual geometry only.

Such a link is a moving part of the arm, not a camera or a cover (Doosan's M1013 URDF gives
its elbow `link3` and flange `link6` no `<collision>`): left without spheres, the planner
cannot see it. One located warning per link; a visual-only link on a fixed joint is only
counted in the fit summary, as before."""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot

URDF = """<robot name="elbow">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="upper">
    <collision><origin xyz="0 0 0.15"/><geometry><box size="0.06 0.06 0.3"/></geometry></collision>
  </link>
  <link name="elbow">
    <visual><origin xyz="0 0 0.1"/><geometry><box size="0.05 0.05 0.2"/></geometry></visual>
  </link>
  <link name="camera"><visual><geometry><box size="0.05 0.05 0.05"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="elbow"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="cam" type="fixed"><parent link="base"/><child link="camera"/>
    <origin xyz="0.1 0 0.1"/></joint>
</robot>
"""


def _convert(tmp_path: Path, source: str) -> list[tuple[int | None, str]]:
    urdf = tmp_path / "elbow.urdf"
    urdf.write_text(URDF)
    result = convert_robot(
        urdf,
        ConvertOptions(joints=("j1", "j2")),
        fit=FitOptions(per_link=2, source=source),
        mask=MaskOptions(200),
    )
    return [
        (d.line, d.message)
        for d in result.diagnostics
        if d.rule == "convert-moving-link-without-spheres"
    ]


def test_a_moving_link_with_visual_geometry_only_is_a_located_warning(tmp_path: Path) -> None:
    ((line, said),) = _convert(tmp_path, "collision")  # not the camera: a fixed joint
    assert line == 6  # <link name="elbow">
    assert said.startswith("link 'elbow', moved by c-space joint 'j2', has visual geometry only")
    assert "--from auto" in said


def test_no_warning_when_visual_geometry_is_fitted(tmp_path: Path) -> None:
    assert _convert(tmp_path, "auto") == []


def test_past_three_links_one_warning_names_the_rest(tmp_path: Path) -> None:
    """A snake of 6 modules, each a visual-only marker: three located warnings, then one
    located at the fourth naming the other three (each module said the same thing, 64 lines
    for 64 modules)."""
    links = ['<link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry>'
             "</collision></link>"]  # fmt: skip
    joints = []
    for i in range(1, 7):
        links.append(
            f'<link name="m{i}"><visual><geometry><box size="0.02 0.02 0.05"/></geometry>'
            "</visual></link>"
        )
        parent = "base" if i == 1 else f"m{i - 1}"
        joints.append(
            f'<joint name="j{i}" type="revolute"><parent link="{parent}"/>'
            f'<child link="m{i}"/><origin xyz="0 0 0.06"/><axis xyz="0 1 0"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    urdf = tmp_path / "snake.urdf"
    urdf.write_text('<robot name="snake">\n' + "\n".join(links + joints) + "\n</robot>\n")
    result = convert_robot(
        urdf,
        ConvertOptions(joints=tuple(f"j{i}" for i in range(1, 7))),
        fit=FitOptions(per_link=2),
        mask=MaskOptions(200),
    )
    said = [d for d in result.diagnostics if d.rule == "convert-moving-link-without-spheres"]
    assert [d.message.split(",")[0] for d in said[:3]] == ["link 'm1'", "link 'm2'", "link 'm3'"]
    assert len(said) == 4 and said[3].line == 6  # <link name="m4">: line 1 is <robot>
    assert said[3].message.startswith("3 more link(s) moved by c-space joints")
    assert "m4, m5, m6" in said[3].message
