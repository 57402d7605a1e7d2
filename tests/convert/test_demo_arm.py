"""The README's main job on the bundled demo arm: one command to a planning-ready XRDF."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.curobo_loader import loads_as_written
from tests.paths import FIXTURES, REPO
from xrdf_tools.cli import app

DEMO = FIXTURES / "demo_arm"


def test_readme_main_job_names_the_bundled_demo_arm() -> None:
    readme = (REPO / "README.md").read_text()
    assert (
        "xrdf convert fixtures/demo_arm/demo_arm.urdf --srdf fixtures/demo_arm/demo_arm.srdf"
        in readme
    )
    for name in ("demo_arm.urdf", "demo_arm.srdf", "joint_limits.yaml"):
        assert (DEMO / name).is_file()


@pytest.mark.slow
def test_demo_arm_one_command_result_passes_report_lint_and_curobo(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "demo_arm.xrdf"
    urdf = DEMO / "demo_arm.urdf"
    r = runner.invoke(
        app,
        [
            "convert",
            str(urdf),
            "--srdf",
            str(DEMO / "demo_arm.srdf"),
            "--joint-limits",
            str(DEMO / "joint_limits.yaml"),
            "--fit-spheres",
            "--target",
            "curobo",
            "--samples",
            "10000",
            "--per-link",
            "8",
            "-o",
            str(out),
        ],
    )
    assert r.exit_code == 0, r.output
    assert "mesh file not found" not in r.output
    assert "camera_link" in r.output  # the visual-only link is named, and gets no spheres
    text = out.read_text()
    assert "camera_link:" not in text.split("geometry:", 1)[1]
    assert loads_as_written(text, urdf)
    report = runner.invoke(app, ["report", str(out), "--urdf", str(urdf), "-n", "10000"])
    assert report.exit_code == 0, report.output
    lint = runner.invoke(app, ["lint", str(out), "--urdf", str(urdf), "--target", "curobo"])
    assert lint.exit_code == 0, lint.output


def test_output_may_not_be_a_mesh_of_the_robot(runner: CliRunner, tmp_path: Path) -> None:
    """-o on a mesh the URDF names would replace the mesh with the XRDF: refused."""
    (tmp_path / "meshes").mkdir()
    for stl in (DEMO / "meshes").glob("*.stl"):
        (tmp_path / "meshes" / stl.name).write_bytes(stl.read_bytes())
    urdf = tmp_path / "demo_arm.urdf"
    urdf.write_text((DEMO / "demo_arm.urdf").read_text())
    mesh = tmp_path / "meshes" / "base.stl"
    r = runner.invoke(
        app, ["convert", str(urdf), "--srdf", str(DEMO / "demo_arm.srdf"), "-o", str(mesh)]
    )
    assert r.exit_code == 2, r.output
    assert f"{mesh}: refusing to overwrite an input" in r.output
    assert mesh.read_bytes() == (DEMO / "meshes" / "base.stl").read_bytes()
