"""Every ```python snippet of docs/*.md runs as written, on the example-robot-data Panda and the
bundled Panda XRDF under the file names the snippets use."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.paths import FIXTURES, REPO
from tests.robots import robot_urdf

_SNIPPET = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def _snippets() -> list[tuple[str, str]]:
    """``(doc name and number, code)`` of every snippet; ``edit.md`` last (it saves over
    ``panda.xrdf``)."""
    return [
        (f"{doc.name}#{i}", code)
        for doc in sorted((REPO / "docs").glob("*.md"), key=lambda d: d.name == "edit.md")
        for i, code in enumerate(_SNIPPET.findall(doc.read_text(encoding="utf-8")), 1)
    ]


def test_the_docs_have_python_snippets() -> None:
    names = {name.split("#")[0] for name, _ in _snippets()}
    assert {"diff.md", "index.md", "spheres.md", "viz.md", "edit.md"} <= names


@pytest.mark.slow
def test_every_python_snippet_runs_as_written(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("trimesh")
    pytest.importorskip("matplotlib")
    pytest.importorskip("rerun")
    pytest.importorskip("viser")
    panda = robot_urdf("panda")
    (tmp_path / "panda.urdf").symlink_to(panda)
    xrdf = (FIXTURES / "panda" / "panda.xrdf").read_text()
    for name in ("panda.xrdf", "robot.xrdf", "old.xrdf"):
        (tmp_path / name).write_text(xrdf)
    changed = xrdf.replace("panda_joint1: 0.0", "panda_joint1: 0.1", 1)
    assert changed != xrdf
    (tmp_path / "new.xrdf").write_text(changed)
    monkeypatch.chdir(tmp_path)
    for name, code in _snippets():
        capsys.readouterr()
        try:
            exec(compile(code, name, "exec"), {"__name__": "__snippet__"})
        except Exception as e:  # the snippet's name in the failure, not this test's
            pytest.fail(f"{name} fails: {type(e).__name__}: {e}\n{code}")
        assert capsys.readouterr().out, f"{name} printed nothing"
    assert (tmp_path / "panda.png").stat().st_size > 0
    assert (tmp_path / "panda.rrd").stat().st_size > 0
