"""A Lula robot description has collision spheres but no self-collision mask (Lula checks no
self-collision): convert says so, and computes the mask when it writes the XRDF."""

from __future__ import annotations

from pathlib import Path

from tests.paths import UR10E_URDF
from xrdf_tools.convert.core import ConvertOptions, convert_files
from xrdf_tools.convert.pipeline import MaskOptions, convert_robot

# Spheres on adjacent links that overlap at the shoulder joint, as Isaac Sim's sphere editor
# writes them for real arms (a Lula description of the AgileX Piper has eight such pairs).
LULA = """api_version: 1.0
cspace: [shoulder_pan_joint, shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint,
  wrist_3_joint]
default_q: [0.0, -1.57, 1.57, -1.57, -1.57, 0.0]
cspace_to_urdf_rules: []
collision_spheres:
  - shoulder_link:
    - "center": [0.0, 0.0, 0.0]
      "radius": 0.09
  - upper_arm_link:
    - "center": [0.0, 0.0, 0.17]
      "radius": 0.09
  - forearm_link:
    - "center": [0.0, 0.0, 0.03]
      "radius": 0.06
"""


def _lula(tmp_path: Path) -> Path:
    p = tmp_path / "ur10e_description.yaml"
    p.write_text(LULA)
    return p


def test_lula_without_mask_is_said(tmp_path: Path) -> None:
    x, diags, _ = convert_files(UR10E_URDF, ConvertOptions(curobo=_lula(tmp_path)))
    (said,) = [d for d in diags if d.rule == "convert-lula-no-mask"]
    assert said.line == 6 and "--write-mask" in said.message
    assert x.self_collision is not None and not x.self_collision.ignore_pairs()


def test_convert_computes_the_mask_a_lula_description_lacks(tmp_path: Path) -> None:
    options = ConvertOptions(curobo=_lula(tmp_path))
    result = convert_robot(UR10E_URDF, options, missing_mask=MaskOptions(samples=2000))
    rules = [d.rule for d in result.diagnostics]
    assert "convert-lula-no-mask" not in rules
    (summary,) = [d for d in result.diagnostics if d.rule == "convert-computed-mask"]
    assert "Lula" in summary.message and "2000 uniform samples" in summary.message
    sc = result.xrdf.self_collision
    assert sc is not None
    pairs = {frozenset(p) for p in sc.ignore_pairs()}
    assert frozenset(("shoulder_link", "upper_arm_link")) in pairs
