"""The README's main job on the bundled demo arm: one command to a planning-ready XRDF."""

from __future__ import annotations

import re
import shlex
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


def _readme_setup_commands() -> list[list[str]]:
    """The ``xrdf`` commands of README's set-up line, as written (the venv and pip install
    before them left out): the arguments after ``xrdf``."""
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    line = next(m for m in re.findall(r"^```sh\n(.*?)\n```", readme, re.S | re.M) if "xrdf" in m)
    words = [shlex.split(part) for part in line.split("&&")]
    return [w[1:] for w in words if w[0] == ".venv/bin/xrdf"]


@pytest.mark.slow
def test_readme_setup_commands_run_as_written_and_pass_lint_and_curobo(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """README's main job, its commands exactly as written (run in a folder holding the
    fixtures): a planning-ready XRDF that the report, lint and cuRobo's loader accept."""
    commands = _readme_setup_commands()
    assert [c[0] for c in commands] == ["convert", "report"]
    (tmp_path / "fixtures").symlink_to(FIXTURES)
    monkeypatch.chdir(tmp_path)
    outputs = []
    for args in commands:
        r = runner.invoke(app, args)
        assert r.exit_code == 0, f"xrdf {shlex.join(args)}\n{r.output}"
        outputs.append(r.output)
    converted, reported = outputs
    assert "mesh file not found" not in converted
    assert "camera_link" in converted  # the visual-only link is named, and gets no spheres
    assert "findings: none" in reported
    out, urdf = tmp_path / "out" / "demo_arm.xrdf", DEMO / "demo_arm.urdf"
    text = out.read_text()
    assert "camera_link:" not in text.split("geometry:", 1)[1]
    assert loads_as_written(text, urdf)
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
