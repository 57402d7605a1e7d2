"""A pair that never collided in the samples but came within the clearance margin stays
checked in the recommended mask (and so in convert's computed mask): a configuration between
the samples may close the gap. Two FR3 arms from franka_description: left link4 / right link2
was 4.5 mm apart at the closest in 100,000 samples, was ignored as "never", and collides where
--certify looked."""

from __future__ import annotations

from pathlib import Path

from xrdf_tools.report import self_collision_report
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import parse_xrdf

# An arm turning about z over a post, both hanging from the base (so not adjacent): the arm's
# sphere passes the post's at its closest when the joint is at 0, farther everywhere else.
URDF = """<robot name="pass">
  <link name="base"/><link name="post"/><link name="arm"/>
  <joint name="fix" type="fixed"><parent link="base"/><child link="post"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""


def _xrdf(height: float) -> str:
    return f"""format: xrdf
format_version: 1.0
cspace:
  joint_names: [j1]
  acceleration_limits: [10.0]
  jerk_limits: [100.0]
default_joint_positions: {{j1: 2.0}}
collision:
  geometry: g
self_collision:
  geometry: g
  ignore: {{}}
geometry:
  g:
    spheres:
      base:
        - {{center: [0.0, 0.0, -0.5], radius: 0.01}}
      post:
        - {{center: [0.3, 0.0, 0.0], radius: 0.05}}
      arm:
        - {{center: [0.3, 0.0, {height}], radius: 0.05}}
"""


def _pair(tmp_path: Path, height: float):  # type: ignore[no-untyped-def]
    urdf = tmp_path / "pass.urdf"
    urdf.write_text(URDF)
    r = self_collision_report(load_urdf(urdf), parse_xrdf(_xrdf(height)), samples=2000, seed=0)
    (pair,) = [p for p in r.pairs if {p.frame_a, p.frame_b} == {"post", "arm"}]
    return r, pair


def test_a_pair_that_never_collided_but_came_within_the_margin_stays_checked(
    tmp_path: Path,
) -> None:
    r, pair = _pair(tmp_path, 0.105)  # 5 mm apart at best
    assert pair.hits == 0 and pair.classification == "never"
    assert pair.min_clearance is not None and 0.005 <= pair.min_clearance < 0.006
    assert pair.recommendation == "check"
    assert "5.0 mm apart at the closest, within the 10 mm margin: keep checking" in pair.note
    assert "arm" not in r.recommended_ignore.get("post", ()) + tuple(
        r.recommended_ignore.get("arm", ())
    )
    # convert's summary of its computed mask names it, with how near it came
    from xrdf_tools.convert.mask_notes import mask_summary

    said = mask_summary(r, parse_xrdf(_xrdf(0.105))).message
    assert "1 pair(s) checked although they never collided" in said
    assert "(post/arm 5.0 mm)" in said and "--certify --write-mask" in said


def test_a_pair_that_stays_beyond_the_margin_may_be_ignored(tmp_path: Path) -> None:
    r, pair = _pair(tmp_path, 0.115)  # 15 mm apart at best
    assert pair.hits == 0 and pair.recommendation == "may-ignore"
    ignored = {frozenset((a, b)) for a, bs in r.recommended_ignore.items() for b in bs}
    assert frozenset(("post", "arm")) in ignored


def test_pairs_of_prefixed_names_are_told_apart(tmp_path: Path) -> None:
    """A LoCoBot's links are named 'locobot/...': its pairs printed as
    'locobot/post/locobot/arm', which cannot be split back into two names. A pair whose names
    hold a '/' is written 'a <-> b' (and 'a/b' as before otherwise)."""
    from typer.testing import CliRunner

    from xrdf_tools.cli import app

    named = URDF.replace('"post"', '"bot/post"').replace('"arm"', '"bot/arm"')
    urdf = tmp_path / "pass.urdf"
    urdf.write_text(named)
    xrdf = tmp_path / "pass.xrdf"
    text = _xrdf(0.0).replace("post:", "bot/post:").replace("arm:", "bot/arm:")
    xrdf.write_text(text.replace("{j1: 2.0}", "{j1: 0.0}"))  # the two spheres overlap at 0
    r = CliRunner().invoke(app, ["report", str(xrdf), "--urdf", str(urdf), "-n", "200"])
    (line,) = [x for x in r.output.splitlines() if "IN SELF-COLLISION" in x]
    assert "bot/arm <-> bot/post" in line or "bot/post <-> bot/arm" in line, line
    assert "post/bot" not in line


def test_a_near_pair_that_no_cspace_joint_moves_is_ignored(tmp_path: Path) -> None:
    """TIAGo++: its left arm's tool link and gripper, fixed to each other 2 mm apart, and six
    pairs of its held right arm were kept checked as near misses ("a configuration between
    the samples may close the gap"), though their clearance is the same in every
    configuration; `export srdf --merge` then removed MoveIt's ignore entries for the held
    arm. A pair no c-space joint moves is as far apart everywhere as at the default pose."""
    urdf = tmp_path / "pass.urdf"
    urdf.write_text(
        URDF.replace(
            '<link name="arm"/>',
            '<link name="arm"/><link name="tip"/><link name="flange"/>'
            '<joint name="fix2" type="fixed"><parent link="arm"/><child link="tip"/></joint>'
            '<joint name="fix3" type="fixed"><parent link="arm"/><child link="flange"/></joint>',
        )
    )
    text = _xrdf(0.3).replace(
        "      arm:\n",
        "      tip:\n        - {center: [0.3, 0.0, 0.405], radius: 0.05}\n"
        "      flange:\n        - {center: [0.3, 0.0, 0.51], radius: 0.05}\n      arm:\n",
    )
    r = self_collision_report(load_urdf(urdf), parse_xrdf(text), samples=2000, seed=0)
    (pair,) = [p for p in r.pairs if {p.frame_a, p.frame_b} == {"flange", "tip"}]
    assert pair.joints_on_path == 0 and pair.hits == 0
    assert pair.min_clearance is not None and pair.min_clearance < 0.01  # 5 mm: within the margin
    assert pair.classification == "never" and pair.recommendation == "ignore"
    assert "no c-space joint moves these frames against each other, 5.0 mm apart" in pair.note
    ignored = {frozenset((a, b)) for a, bs in r.recommended_ignore.items() for b in bs}
    assert frozenset(("flange", "tip")) in ignored
