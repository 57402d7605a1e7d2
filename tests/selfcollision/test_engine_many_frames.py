"""The engine and the report on robots with many sphere frames (tests/many_frames.py): the
counts and clearances of a branched tree against the reference counter, its joints on each
pair's path against a walk, and the build's walks along the tree growing with the frame
pairs times the depth, not with the frame pairs times the depth squared."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from tests.many_frames import chain_robot, tree_robot
from tests.selfcollision.test_engine_differential import report_against_reference
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import parse_urdf_string
from xrdf_tools.selfcollision.engine import core
from xrdf_tools.xrdf.io import parse_xrdf


def test_a_branched_tree_counts_like_the_reference(tmp_path: Path) -> None:
    urdf_text, xrdf_text = tree_robot(100)
    urdf = tmp_path / "tree.urdf"
    urdf.write_text(urdf_text)
    report = report_against_reference(urdf, xrdf_text, 300)
    assert sum(p.hits or 0 for p in report.pairs) > 0
    kin, _ = build_kinematic_model(parse_urdf_string(urdf_text, "t.urdf"))
    cspace = set(parse_xrdf(xrdf_text, "t.xrdf").cspace.joint_names)  # type: ignore[union-attr]
    for p in report.pairs:
        up_a = kin.ancestors(p.frame_a)
        up_b = kin.ancestors(p.frame_b)
        walked = {kin.joint_of_frame[f] for f in set(up_a) ^ set(up_b)}
        master = {j: kin.joints[j].mimic_joint or j for j in walked if j is not None}
        assert p.joints_on_path == len(cspace & set(master.values())), (p.frame_a, p.frame_b)


class _Steps:
    """Counts the reads of a tree's parent links (bodies' and frames')."""

    n = 0


class _CountedTuple(tuple[int, ...]):
    def __getitem__(self, i):  # type: ignore[no-untyped-def, override]
        _Steps.n += 1
        return tuple.__getitem__(self, i)


class _CountedArray(np.ndarray):  # type: ignore[type-arg]
    def __getitem__(self, i):  # type: ignore[no-untyped-def]
        _Steps.n += 1
        return super().__getitem__(i)


def _tree_steps(n: int, monkeypatch: pytest.MonkeyPatch) -> int:
    """Parent reads of ``xrdf report``'s build (engine and pair statistics) on a chain of
    ``n`` joints with one sphere per link."""
    from xrdf_tools.report import build, self_collision_report

    make_bodies, make_kin = core.build_bodies, build.build_kinematic_model

    def bodies(*args, **kw):  # type: ignore[no-untyped-def]
        b = make_bodies(*args, **kw)
        return dataclasses.replace(b, parent=_CountedTuple(b.parent))

    def kinematics(*args, **kw):  # type: ignore[no-untyped-def]
        kin, diags = make_kin(*args, **kw)
        object.__setattr__(kin, "parent", kin.parent.view(_CountedArray))
        return kin, diags

    monkeypatch.setattr(core, "build_bodies", bodies)
    monkeypatch.setattr(build, "build_kinematic_model", kinematics)
    urdf_text, xrdf_text = chain_robot(n)
    urdf, xrdf = parse_urdf_string(urdf_text, "c.urdf"), parse_xrdf(xrdf_text, "c.xrdf")
    _Steps.n = 0
    self_collision_report(urdf, xrdf, samples=10, jobs=1)
    return _Steps.n


def test_the_build_walks_the_tree_once_per_body_not_once_per_pair(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A chain of n joints has n²/2 frame pairs n/3 joints apart on average: walking the
    chain per pair (the reach balls, the common ancestors, the joints on each pair's path)
    is n³/6 steps and took 45 s at n = 300; walking it once per body is n²/2."""
    small, large = _tree_steps(30, monkeypatch), _tree_steps(60, monkeypatch)
    assert large < 2 * 60**2
    assert large / small < 5.0  # quadratic: 4; a walk per pair: 8
