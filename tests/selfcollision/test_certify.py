"""xrdf report --certify: proofs of "never" checked against dense sampling, and witnesses for
a pair that touches only in a tiny region of its joint box (sampling misses it)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, REPO
from tests.robots import robot_urdf
from xrdf_tools.cli import app
from xrdf_tools.report import CertifyOptions, Report, self_collision_report
from xrdf_tools.robot.kinematics import build_kinematic_model, full_configuration
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision.collision import colliding_frame_pairs
from xrdf_tools.xrdf.io import load_xrdf, parse_xrdf

SEED = 3  # 200 uniform samples that miss the tiny window
PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"

# base_link and link2 (link2 fixed to link1, turned by joint1) touch only for |joint1 − 1.2345|
# below about 9e-4 rad: 2e-7 m² of squared distance to spare at joint1 = 1.2345, a 1.8e-3 rad
# window in a full turn, away from the box centre. link1 carries a far-away sphere so that
# base_link and link2 are not adjacent; link3 (also on link1) never comes near base_link.
TINY_URDF = """\
<robot name="tiny">
  <link name="base_link"/>
  <link name="link1"/>
  <link name="link2"/>
  <link name="link3"/>
  <joint name="joint1" type="revolute">
    <parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 0" rpy="0 0 -1.2345"/><axis xyz="0 0 1"/>
    <limit lower="-3.14159" upper="3.14159" effort="1" velocity="1"/>
  </joint>
  <joint name="fixed2" type="fixed">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 0" rpy="0 0 0"/>
  </joint>
  <joint name="fixed3" type="fixed">
    <parent link="link1"/><child link="link3"/>
    <origin xyz="0 0 0" rpy="0 0 0"/>
  </joint>
</robot>
"""
TINY_XRDF = """\
format: xrdf
format_version: 1.0
cspace:
  joint_names: [joint1]
  acceleration_limits: [10.0]
  jerk_limits: [100.0]
default_joint_positions: {joint1: 1.0}
collision:
  geometry: g
self_collision:
  geometry: g
geometry:
  g:
    spheres:
      base_link:
        - {center: [0.5, 0.0, 0.099999], radius: 0.05}
      link1:
        - {center: [-0.5, 0.0, 2.0], radius: 0.01}
      link2:
        - {center: [0.5, 0.0, 0.0], radius: 0.05}
      link3:
        - {center: [0.3, 0.0, 0.3], radius: 0.01}
"""


def _collides(report: Report, urdf_path: Path, xrdf_text: str, a: str, b: str) -> bool:
    """The pair's witness configuration collides (plain float64 check, masked pairs too)."""
    p = report.pair(a, b)
    assert p.witness is not None
    xrdf = parse_xrdf(xrdf_text) if not xrdf_text.endswith(".xrdf") else load_xrdf(xrdf_text)
    kin, _ = build_kinematic_model(load_urdf(urdf_path), xrdf)
    names = list(p.witness)
    q = full_configuration(kin, names, [p.witness[n] for n in names], xrdf.default_joint_positions)
    pairs = colliding_frame_pairs(kin, xrdf, q, include_masked=True)
    return any({c.frame_a, c.frame_b} == {a, b} for c in pairs)


def test_tiny_region_pair_gets_a_witness_not_a_proof(tmp_path: Path) -> None:
    urdf = tmp_path / "tiny.urdf"
    urdf.write_text(TINY_URDF)
    xrdf = parse_xrdf(TINY_XRDF, "tiny.xrdf")
    sampled = self_collision_report(load_urdf(urdf), xrdf, samples=200, seed=SEED)
    p = sampled.pair("base_link", "link2")
    assert p.classification == "never" and p.hits == 0  # sampling misses the window
    r = self_collision_report(
        load_urdf(urdf), xrdf, samples=200, seed=SEED, certify=CertifyOptions()
    )
    p = r.pair("base_link", "link2")
    assert p.certificate == "witness" and p.classification == "sometimes"
    assert p.recommendation == "check" and "joint1=" in p.note
    assert p.witness is not None and abs(p.witness["joint1"] - 1.2345) < 1e-3
    assert _collides(r, urdf, TINY_XRDF, "base_link", "link2")
    # the pair that stays apart is proven, and the pair on one body is decided at once
    far = r.pair("base_link", "link3")
    assert far.certificate == "proven" and far.recommendation == "ignore"
    assert r.pair("link2", "link3").certificate == "proven"
    d = r.pairs[0].to_dict()
    assert {"certified", "certificate", "witness", "certify_boxes"} <= set(d)


@pytest.mark.parametrize(
    "opts",
    [
        CertifyOptions(boxes=0, mask_policy="proven"),
        CertifyOptions(mask_policy="proven", budget_s=0),
    ],
    ids=["no-boxes", "no-time"],
)
def test_tiny_region_proof_is_refused_when_budget_is_zero(
    tmp_path: Path, opts: CertifyOptions
) -> None:
    urdf = tmp_path / "tiny.urdf"
    urdf.write_text(TINY_URDF)
    xrdf = parse_xrdf(TINY_XRDF, "tiny.xrdf")
    r = self_collision_report(load_urdf(urdf), xrdf, samples=200, seed=SEED, certify=opts)
    p = r.pair("base_link", "link2")
    assert p.certificate == "undecided" and p.classification == "never"
    assert p.recommendation == "check"  # mask policy "proven": not proven, keep checking
    limit = "--certify-boxes budget" if opts.budget_s is None else "--certify-budget time limit"
    assert limit in p.note
    assert frozenset(("base_link", "link2")) not in {
        frozenset((a, b)) for a, bs in r.recommended_ignore.items() for b in bs
    }


@pytest.mark.slow
def test_panda_certify_with_200_samples_makes_no_false_claim() -> None:
    urdf_path = robot_urdf("panda")
    xrdf = load_xrdf(PANDA_XRDF)
    urdf = load_urdf(urdf_path)
    r = self_collision_report(urdf, xrdf, samples=200, seed=SEED, certify=CertifyOptions())
    dense = self_collision_report(urdf, xrdf, samples=200_000, seed=1)
    proven = [p for p in r.pairs if p.certificate == "proven"]
    witnessed = [p for p in r.pairs if p.certificate == "witness"]
    assert len(proven) >= 15  # most never-colliding pairs are proven, fast
    assert sum(p.certify_boxes or 0 for p in r.pairs) <= CertifyOptions().boxes
    for p in proven:  # a proof is never contradicted by dense sampling
        assert dense.pair(p.frame_a, p.frame_b).hits == 0, (p.frame_a, p.frame_b)
    for p in r.pairs:  # every pair that dense sampling sees colliding was not proven
        if (dense.pair(p.frame_a, p.frame_b).hits or 0) > 0:
            assert p.certificate != "proven"
    assert witnessed  # 200 samples miss rare pairs: --certify finds them
    for p in witnessed:
        assert _collides(r, urdf_path, str(PANDA_XRDF), p.frame_a, p.frame_b)


def test_cli_certify_json_validates(runner: CliRunner, tmp_path: Path) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    urdf = tmp_path / "tiny.urdf"
    urdf.write_text(TINY_URDF)
    xrdf = tmp_path / "tiny.xrdf"
    xrdf.write_text(TINY_XRDF)
    out = tmp_path / "r.json"
    res = runner.invoke(
        app,
        [
            "report",
            str(xrdf),
            "--urdf",
            str(urdf),
            "-n",
            "200",
            "--seed",
            str(SEED),
            "--certify",
            "-f",
            "json",
            "-o",
            str(out),
            "--mask-policy",
            "proven",
        ],
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    jsonschema.validate(doc, json.loads((REPO / "docs" / "report-schema.json").read_text()))
    by = {(p["frame_a"], p["frame_b"]): p for p in doc["pairs"]}
    pair = by[("base_link", "link2")]
    assert pair["certified"] is False and pair["certificate"] == "witness"
    assert set(pair["witness"]) == {"joint1"}
    assert by[("base_link", "link3")]["certified"] is True
    assert pair["certify_boxes"] >= 1
