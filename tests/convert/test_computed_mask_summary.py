"""`xrdf convert --fit-spheres` names the pairs of the input's mask it stops ignoring.

A MoveIt SRDF may disable a pair ('Never') that the fitted spheres see collide (Denso Cobotta's
SRDF disables J4/base_link, which collide in 3 % of samples): the computed mask checks it
again, and the summary says which pair, and how often it collided, so the author can judge
the SRDF or the spheres."""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.convert.core import ConvertOptions
from xrdf_tools.convert.pipeline import FitOptions, MaskOptions, convert_robot

# An arm turning about z sweeps through a post fixed to the base a quarter turn away.
URDF = """<robot name="post">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.05"/></geometry></collision></link>
  <link name="arm">
    <collision><origin xyz="0.2 0 0.1"/><geometry><box size="0.3 0.04 0.04"/></geometry></collision>
  </link>
  <link name="post">
    <collision><origin xyz="0 0 0.1"/><geometry><box size="0.04 0.04 0.2"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="fix" type="fixed"><parent link="base"/><child link="post"/>
    <origin xyz="0 0.25 0"/></joint>
</robot>
"""

SRDF = """<robot name="post">
  <group name="arm"><joint name="j1"/></group>
  <disable_collisions link1="arm" link2="post" reason="Never"/>
</robot>
"""


def test_the_input_pairs_the_samples_see_collide_are_named(tmp_path: Path) -> None:
    urdf, srdf = tmp_path / "post.urdf", tmp_path / "post.srdf"
    urdf.write_text(URDF)
    srdf.write_text(SRDF)
    result = convert_robot(
        urdf, ConvertOptions(srdf=srdf), fit=FitOptions(per_link=3), mask=MaskOptions(2000)
    )
    (summary,) = [d for d in result.diagnostics if d.rule == "convert-computed-mask"]
    said = summary.message
    removed = "1 pair(s) of the inputs removed (they sometimes collide, or came within the margin)"
    assert f"{removed}: arm/post (in " in said
    assert said.endswith("% of samples)")
    sc = result.xrdf.self_collision
    assert sc is not None and not sc.is_ignored("arm", "post")


def test_a_rare_collision_rate_is_not_rounded_to_zero() -> None:
    """Motoman SDA10F: 'torso_link_b1/arm_left_link_2_l (in 0.0% of samples)' said a pair
    removed from the mask for colliding never collided; a rate under 0.1 % keeps two digits."""
    from xrdf_tools.convert.mask_notes import _share

    assert _share(0.00042) == "0.042%"
    assert _share(0.00001) == "0.001%"
    assert _share(0.033) == "3.3%"
