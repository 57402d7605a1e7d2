"""``xrdf report``'s steps as library calls (:mod:`xrdf_tools.report.job`) on a real robot:
they return what the command prints and writes, without printing or exiting."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.robot.core import Robot
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Xrdf


@pytest.fixture(scope="module")
def ur10e() -> tuple[Robot, Xrdf]:
    return load_urdf(UR10E_URDF), load_xrdf(UR10E_XRDF)


def test_run_report_is_the_report_of_its_request(ur10e: tuple[Robot, Xrdf]) -> None:
    from xrdf_tools.report import ReportRequest, run_report, self_collision_report

    robot, x = ur10e
    request = ReportRequest(samples=400, seed=5, sampler="halton", clearance_margin=0.02)
    got = run_report(robot, x, request, urdf_path=str(UR10E_URDF))
    want = self_collision_report(
        robot,
        x,
        samples=400,
        seed=5,
        sampler="halton",
        clearance_margin=0.02,
        urdf_path=str(UR10E_URDF),
    )
    assert [(p.frame_a, p.frame_b, p.hits) for p in got.pairs] == [
        (p.frame_a, p.frame_b, p.hits) for p in want.pairs
    ]
    assert got.samples == 400 and any(p.hits for p in got.pairs)


def test_given_configurations_are_checked_one_by_one(
    ur10e: tuple[Robot, Xrdf], tmp_path: Path
) -> None:
    from xrdf_tools.report import ReportRequest, given_configurations, run_report

    robot, x = ur10e
    rows = np.array([[0.0, -1.57, 0.0, -1.57, 0.0, 0.0], [0.0, 0.0, 3.1, 0.0, 0.0, 0.0]])
    path = tmp_path / "q.npy"
    np.save(path, rows)
    q = given_configurations(robot, x, path, urdf_path=str(UR10E_URDF))
    assert q.shape == (2, 6) and np.allclose(q, rows)
    report = run_report(
        robot,
        x,
        ReportRequest(),
        urdf_path=str(UR10E_URDF),
        configs=q,
    )
    assert report.samples == 2 and report.source == "configs"
    assert report.trajectory is not None
    assert {h.index for h in report.trajectory} <= {0, 1}


def test_the_recommended_mask_is_an_xrdf_with_the_reports_ignore_list(
    ur10e: tuple[Robot, Xrdf],
) -> None:
    from xrdf_tools.report import ReportRequest, recommended_mask_yaml, run_report

    robot, x = ur10e
    report = run_report(
        robot,
        x,
        ReportRequest(samples=300),
        urdf_path=str(UR10E_URDF),
    )
    new = parse_xrdf(recommended_mask_yaml(x, report), "<mask>")
    assert new.self_collision is not None
    ignored = {frozenset((a, b)) for a, others in new.self_collision.ignore.items() for b in others}
    change = report.mask_change
    assert all(frozenset(p) in ignored for p in change.added)
    assert not any(frozenset(p) in ignored for p in change.removed)
