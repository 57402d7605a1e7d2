"""``xrdf viz``'s configuration choice and diagnostics as library calls, on a real robot."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.robot.core import Robot
from xrdf_tools.robot.kinematics import build_kinematic_model
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import load_xrdf
from xrdf_tools.xrdf.model import Xrdf


@pytest.fixture(scope="module")
def ur10e() -> tuple[Robot, Xrdf]:
    return load_urdf(UR10E_URDF), load_xrdf(UR10E_XRDF)


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
