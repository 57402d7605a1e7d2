"""The one command, the report and lint for cuRobo on the arm of a mobile manipulator (TIAGo)
and of a humanoid (Talos, whose meshes are ``package:///`` URIs): every link with collision
geometry gets spheres, and the file is planning-ready."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.robots import robots_dir
from xrdf_tools.cli import app
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import load_xrdf

CASES = {
    "tiago-arm": (
        "tiago_description/robots/tiago.urdf",
        None,
        ["--chain", "base_footprint:arm_tool_link"],
    ),
    "talos-left-arm": (
        "talos_data/robots/talos_full_v2.urdf",
        "talos_data/srdf/talos.srdf",
        ["--group", "l_arm"],
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(CASES))
def test_one_command_report_and_lint_on_a_big_robot(
    runner: CliRunner, case: str, tmp_path: Path
) -> None:
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    urdf_rel, srdf_rel, choice = CASES[case]
    urdf = root / urdf_rel
    args = ["convert", str(urdf), *choice, "--fit-spheres", "-q", "-o", str(tmp_path / "r.xrdf")]
    if srdf_rel is not None:
        args += ["--srdf", str(root / srdf_rel)]
    done = runner.invoke(app, args)
    assert done.exit_code == 0, done.output
    x = load_xrdf(tmp_path / "r.xrdf")
    with_spheres = {k for k, v in x.self_collision_spheres().items() if v}
    with_geometry = set(load_robot(urdf).collision_counts)
    assert with_geometry and with_geometry <= with_spheres, sorted(with_geometry - with_spheres)
    report = runner.invoke(
        app, ["report", str(tmp_path / "r.xrdf"), "--urdf", str(urdf), "-n", "2000", "-q"]
    )
    assert report.exit_code in (0, 1), report.output
    lint = runner.invoke(
        app, ["lint", str(tmp_path / "r.xrdf"), "--urdf", str(urdf), "--target", "curobo"]
    )
    assert lint.exit_code == 0, lint.output
