"""The steps of ``xrdf report``, ``xrdf viz`` and ``xrdf spheres`` as library calls, on real
robots: they return what the commands print and write, without printing or exiting."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.paths import UR10E_URDF, UR10E_XRDF
from tests.robots import robot_urdf
from xrdf_tools.robot.core import Robot
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Xrdf


@pytest.fixture(scope="module")
def ur10e() -> tuple[Robot, Xrdf]:
    return load_urdf(UR10E_URDF), load_xrdf(UR10E_XRDF)


# ------------------------------------------------------------------------------------------
# report
# ------------------------------------------------------------------------------------------
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


# ------------------------------------------------------------------------------------------
# viz
# ------------------------------------------------------------------------------------------
def test_a_scene_draws_the_given_or_the_sampled_configurations(
    ur10e: tuple[Robot, Xrdf], tmp_path: Path
) -> None:
    from xrdf_tools.selfcollision.configurations import sample_configurations
    from xrdf_tools.viz import scene_configurations

    robot, x = ur10e
    kin, _ = build_kinematic_model(robot, x)
    assert scene_configurations(kin, x) is None
    sampled = scene_configurations(kin, x, samples=4, seed=2)
    assert sampled is not None and sampled.shape == (4, len(kin.actuated_joints))
    assert np.array_equal(sampled, sample_configurations(kin, x, 4, 2))
    path = tmp_path / "q.npy"
    np.save(path, sampled[:2])
    given = scene_configurations(kin, x, configs=path, samples=0)
    assert given is not None and np.allclose(given, sampled[:2])


def test_a_scenes_diagnostics_are_said_once(ur10e: tuple[Robot, Xrdf]) -> None:
    from xrdf_tools.diagnostics import Diagnostic, Severity
    from xrdf_tools.viz import build_scene, scene_diagnostics

    robot, x = ur10e
    kin, kdiags = build_kinematic_model(robot, x)
    scene = build_scene(robot, x, kinematic_model=kin, meshes="none")
    extra = Diagnostic(str(UR10E_XRDF), 3, 1, "viz-test", Severity.WARNING, "said twice")
    got = scene_diagnostics(scene, [*kdiags, extra], [extra])
    keys = [(d.rule, d.message) for d in got]
    assert len(keys) == len(set(keys))
    assert ("viz-test", "said twice") in keys
    assert got == sorted(got)
    assert {(d.rule, d.message) for d in [*kdiags, *scene.diagnostics]} <= set(keys)


# ------------------------------------------------------------------------------------------
# spheres
# ------------------------------------------------------------------------------------------
def test_fit_spheres_merges_reports_and_measures() -> None:
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.spheres.pipeline import (
        SpheresRequest,
        fit_metrics,
        fit_spheres,
        metrics_json,
        metrics_table,
    )
    from xrdf_tools.spheres.robot_fit import CountPolicy

    robot = load_robot(robot_urdf("ur5"))
    links = ["shoulder_link", "upper_arm_link"]
    request = SpheresRequest(
        CountPolicy(per_link=2), links=links, clips=["shoulder_link:0,0,1,0"], seed=1
    )
    calls: list[str] = []
    fitted = fit_spheres(robot, None, request, progress=lambda link, i, n: calls.append(link))
    assert sorted(fitted.fit.spheres) == sorted(links) and fitted.unfitted == []
    assert all(len(s) == 2 for s in fitted.fit.spheres.values())
    assert calls  # progress per link
    assert all(s.center[2] + 1e-9 >= 0 for s in fitted.fit.spheres["shoulder_link"])
    groups = fitted.xrdf.geometry  # the drafted XRDF carries the new spheres
    assert any(links[0] in g.spheres for g in groups.values())
    rules = {d.rule for d in fitted.diagnostics}
    assert "convert-no-spheres" not in rules and "spheres-adjacent-ignored" in rules
    per, overall = fit_metrics(fitted.fit, seed=1)
    assert list(per) == links and overall.sphere_count == 4
    table = metrics_table(per, overall)
    assert table.splitlines()[2].startswith("shoulder_link") and "overall" in table
    assert '"overall"' in metrics_json(per, overall)


def test_a_bad_clip_plane_is_an_input_error() -> None:
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.spheres.pipeline import SpheresRequest, fit_spheres
    from xrdf_tools.spheres.robot_fit import CountPolicy
    from xrdf_tools.util.errors import XrdfToolsError

    robot = load_robot(robot_urdf("ur5"))
    request = SpheresRequest(CountPolicy(per_link=1), links=["shoulder_link"], clips=["bogus"])
    with pytest.raises(XrdfToolsError):
        fit_spheres(robot, None, request)
