"""``xrdf spheres`` as library calls (:mod:`xrdf_tools.convert.spheres_job`) on a real robot:
fit, merge, the unfitted links and the metrics, without printing or exiting."""

from __future__ import annotations

import pytest

from tests.robots import robot_urdf


def test_fit_spheres_merges_reports_and_measures() -> None:
    from xrdf_tools.convert.spheres_job import (
        SpheresRequest,
        fit_metrics,
        fit_spheres,
        metrics_json,
        metrics_table,
    )
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.spheres.count_policy import CountPolicy

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
    from xrdf_tools.convert.spheres_job import SpheresRequest, fit_spheres
    from xrdf_tools.robot.xacro_source import load_robot
    from xrdf_tools.spheres.count_policy import CountPolicy
    from xrdf_tools.util.errors import XrdfToolsError

    robot = load_robot(robot_urdf("ur5"))
    request = SpheresRequest(CountPolicy(per_link=1), links=["shoulder_link"], clips=["bogus"])
    with pytest.raises(XrdfToolsError):
        fit_spheres(robot, None, request)
