"""The repository's own `.pre-commit-hooks.yaml`, run by pre-commit against a scratch repo."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.paths import FIXTURES, REPO


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
