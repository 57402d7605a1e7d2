"""The repository's own `.pre-commit-hooks.yaml`, run by pre-commit against a scratch repo."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, REPO
from xrdf_tools.cli import app


@pytest.mark.slow
def test_pre_commit_try_repo_runs_the_xrdf_lint_hook(tmp_path: Path) -> None:
    pre_commit = Path(sys.executable).with_name("pre-commit")
    if not pre_commit.exists() or shutil.which("git") is None:
        pytest.skip("pre-commit or git not available")
    work = tmp_path / "work"
    work.mkdir()
    shutil.copy(FIXTURES / "ur10e" / "ur10e.xrdf", work / "good.xrdf")
    shutil.copy(FIXTURES / "lint" / "sphere-radius" / "fail.xrdf", work / "bad.xrdf")
    env = {
        **os.environ,
        "PRE_COMMIT_HOME": str(tmp_path / "cache"),
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@example.invalid",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@example.invalid",
    }

    def git(*args: str) -> None:
        subprocess.run(["git", *args], cwd=work, env=env, check=True, capture_output=True)

    git("init", "-q")
    git("add", ".")
    git("commit", "-q", "-m", "robots")

    def run(*files: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [str(pre_commit), "try-repo", str(REPO), "xrdf-lint", "--files", *files],
            cwd=work,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
            check=False,
        )

    ok = run("good.xrdf")
    assert ok.returncode == 0, ok.stdout + ok.stderr
    bad = run("good.xrdf", "bad.xrdf")
    assert bad.returncode == 1, bad.stdout + bad.stderr
    assert "bad.xrdf:35:19: error sphere-radius" in bad.stdout


_ARM_XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="p" value="my_"/>
  <xacro:macro name="segment" params="name parent">
    <link name="${p}${name}"/>
    <joint name="${p}${name}_joint" type="revolute">
      <parent link="${p}${parent}"/><child link="${p}${name}"/>
      <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
      <limit lower="-2" upper="2" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
  <link name="${p}base"/>
  <xacro:segment name="upper" parent="base"/>
  <xacro:segment name="fore" parent="upper"/>
</robot>
"""


def test_the_config_urdf_map_expands_a_xacro(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A MoveIt package's robot is a xacro: mapped in .xrdf-lint.yaml (what the xrdf-lint hook
    reads), it was parsed as a plain URDF, macros unexpanded, and every joint and frame of a
    good XRDF was an error. It is expanded like --urdf expands it; one that needs xacro
    arguments (which the map cannot pass) is one error at the entry saying what to do."""
    xacro = tmp_path / "arm.urdf.xacro"
    xacro.write_text(_ARM_XACRO)
    xrdf = tmp_path / "arm.xrdf"
    r = runner.invoke(app, ["convert", str(xacro), "-q", "-o", str(xrdf)])
    assert r.exit_code == 0, r.output
    cfg = tmp_path / ".xrdf-lint.yaml"
    cfg.write_text('urdf:\n  "*.xrdf": arm.urdf.xacro\n')
    monkeypatch.chdir(tmp_path)
    r = runner.invoke(app, ["lint", "arm.xrdf", "--format", "json"])
    assert r.exit_code == 0, r.output
    found = [d["rule"] for d in json.loads(r.stdout)["diagnostics"]]
    assert found == ["empty-collision-group"]  # no spheres: the only finding
    xacro.write_text(_ARM_XACRO.replace('value="my_"', 'value="$(arg prefix)"'))
    r = runner.invoke(app, ["lint", "arm.xrdf"])
    assert r.exit_code == 2, r.output
    assert r.stderr.startswith(
        f"error: {cfg}:2:13: the xacro this entry names cannot be expanded: {xacro}:"
    )
    assert "Undefined substitution argument prefix" in r.stderr
    assert r.stderr.rstrip().endswith(
        "the urdf map passes no xacro arguments: map the expanded URDF (xrdf expand XACRO "
        "--xacro-arg NAME:=VALUE -o ROBOT.urdf) or lint with --urdf XACRO --xacro-arg "
        "NAME:=VALUE"
    )
