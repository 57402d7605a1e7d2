"""The ``$ xrdf …`` transcripts of README.md and docs/*.md print what the product prints.

A transcript is a fenced block whose lines start with ``$ `` (the command) followed by what it
printed. Each command is run here in a folder holding the inputs the docs name (the
example-robot-data robots linked as docs/index.md links them, the bundled fixtures), and its
output must contain every line the docs show, in order (a line wrapped in the docs, or an
excerpt with lines left out, still matches: each shown line is a run of words of the output,
each after the one before). A ``# exit N`` comment after a command is its exit code. Every
transcript is either run here or listed with why not, so a new one is one or the other."""

from __future__ import annotations

import re
import shlex
import shutil
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import REPO, SEED_XRDF
from tests.robots import robots_dir
from xrdf_tools.cli import app

_FENCED = re.compile(r"^```[a-z]*\n(.*?)^```", re.S | re.M)


@dataclass(frozen=True)
class Transcript:
    page: str
    command: str  # as written after "$ ", its comment included
    shown: tuple[str, ...]  # the lines the docs show it printing

    @property
    def argv(self) -> list[str]:
        return shlex.split(self.command, comments=True)

    @property
    def exit_code(self) -> int | None:
        m = re.search(r"#\s*exit (\d)", self.command)
        return int(m.group(1)) if m else None


def _transcripts() -> list[Transcript]:
    found = []
    for doc in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        for block in _FENCED.findall(doc.read_text(encoding="utf-8")):
            command: str | None = None
            shown: list[str] = []
            for line in [*block.splitlines(), "$ "]:
                if line.startswith("$ "):
                    if command is not None:
                        found.append(Transcript(doc.name, command, tuple(shown)))
                    command, shown = line[2:].strip() or None, []
                elif command is not None and line.strip():
                    shown.append(line)
    return found


def _key(t: Transcript) -> str:
    return " ".join(shlex.split(t.command, comments=True))


#: Transcripts not run here, and why.
NOT_RUN = {
    "cp ur5_robot.urdf ur5.srdf /tmp/away/ && cd /tmp/away": (
        "the shell step before the next command (test_meshes_that_cannot_be_found)"
    ),
    "xrdf convert iiwa14_spheres_collision.urdf --tool-frame iiwa_frame_ee -o iiwa.xrdf": (
        "Drake's models are no dependency (tests/convert: the Drake frame error)"
    ),
    "xrdf spheres panda.urdf -o panda.xrdf": "shows no output (tests/spheres fit the Panda)",
    "xrdf spheres panda.urdf --xrdf panda.xrdf --links panda_hand --per-link 6 -o panda2.xrdf": (
        "shows no output (tests/spheres: --xrdf merges)"
    ),
    "xrdf spheres robot.urdf.xacro --count 60 --package-path my_robot=~/ws/src/my_robot"
    " -o r.xrdf": "a robot of the reader's own",
}

#: The commands run here (the key: the command as split, without its comment).
RUN_FAST = {
    "xrdf inspect ur5_robot.urdf",
    "xrdf diff ur10e.xrdf ur10e_2_0.xrdf",
    "xrdf convert ur5_robot.urdf --srdf ur5.srdf --fit-spheres -o ur5.xrdf",
    "xrdf spheres r.urdf -o r.xrdf",
}
#: The convert.md walkthrough on the Panda (a whole fit and mask: seconds), in page order.
RUN_WALKTHROUGH = (
    "xrdf convert panda.urdf --srdf panda.srdf --fit-spheres -o panda.xrdf",
    "xrdf report panda.xrdf --urdf panda.urdf",
    "xrdf lint panda.xrdf --urdf panda.urdf",
    "xrdf viz panda.xrdf --urdf panda.urdf --png panda.png",
)

#: spheres.md's slender rod, as the page describes it.
ROD_URDF = (
    '<robot name="r"><link name="rod"><collision><geometry>'
    '<cylinder radius="0.001" length="0.5"/></geometry></collision></link></robot>\n'
)


def _by_key() -> dict[str, Transcript]:
    return {_key(t): t for t in _transcripts()}


def test_every_transcript_is_run_here_or_says_why_not() -> None:
    keys = set(_by_key())
    assert {"xrdf inspect ur5_robot.urdf", RUN_WALKTHROUGH[0]} <= keys  # the parser finds them
    run = RUN_FAST | set(RUN_WALKTHROUGH)
    assert keys - run - set(NOT_RUN) == set(), "classify the new transcripts"
    assert (run | set(NOT_RUN)) - keys == set(), "transcripts gone from the docs"


def _words_in_order(shown: tuple[str, ...], output: str) -> Iterator[str]:
    """The shown lines that are not a run of words of ``output`` after the line before."""
    words = output.split()
    at = 0
    for line in shown:
        run = line.split()
        for start in range(at, len(words) - len(run) + 1):
            if words[start : start + len(run)] == run:
                at = start + len(run)
                break
        else:
            yield line


def test_the_order_check_allows_wrapping_and_excerpts_not_changed_words() -> None:
    output = "a b c\nd e f\ng h\n"
    assert list(_words_in_order(("a b", "c d", "g h"), output)) == []
    assert list(_words_in_order(("a b", "x"), output)) == ["x"]
    assert list(_words_in_order(("d e", "a b"), output)) == ["a b"]  # out of order


def _robots(folder: Path) -> None:
    """The example-robot-data robots linked as docs/index.md links them."""
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    for name, below in {
        "panda.urdf": "panda_description/urdf/panda.urdf",
        "panda.srdf": "panda_description/srdf/panda.srdf",
        "ur5_robot.urdf": "ur_description/urdf/ur5_robot.urdf",
        "ur5.srdf": "ur_description/srdf/ur5.srdf",
    }.items():
        (folder / name).symlink_to(root / below)


def _run(t: Transcript, runner: CliRunner, expected_exit: int, away: str | None = None) -> None:
    argv = t.argv
    assert argv[0] == "xrdf"
    r = runner.invoke(app, argv[1:])
    assert t.exit_code in (None, expected_exit)
    assert r.exit_code == expected_exit, f"{t.page}: $ {t.command}\n{r.output}"
    shown = tuple(line.replace("/tmp/away", away) for line in t.shown) if away else t.shown
    missing = list(_words_in_order(shown, r.output))
    assert missing == [], f"{t.page}: $ {t.command}\nprints:\n{r.output}"


def test_inspect_ur5(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, runner: CliRunner) -> None:
    _robots(tmp_path)
    monkeypatch.chdir(tmp_path)
    _run(_by_key()["xrdf inspect ur5_robot.urdf"], runner, 0)


def test_diff_of_the_seed_ur10e_and_its_2_0_form(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, runner: CliRunner
) -> None:
    monkeypatch.chdir(tmp_path)
    shutil.copy(SEED_XRDF, "ur10e.xrdf")
    r = runner.invoke(app, ["export", "xrdf", "ur10e.xrdf", "--format-version", "2.0"])
    assert r.exit_code == 0, r.output
    Path("ur10e_2_0.xrdf").write_text(r.stdout)
    _run(_by_key()["xrdf diff ur10e.xrdf ur10e_2_0.xrdf"], runner, 1)


def test_meshes_that_cannot_be_found(monkeypatch: pytest.MonkeyPatch, runner: CliRunner) -> None:
    """convert.md copies the UR5 away from its meshes, into a folder right below the
    temporary directory (the package search stops there)."""
    with tempfile.TemporaryDirectory() as away:
        _robots(Path(away))
        for name in ("ur5_robot.urdf", "ur5.srdf"):
            link = Path(away, name)
            target = link.resolve()
            link.unlink()
            shutil.copy(target, link)
        monkeypatch.chdir(away)
        key = "xrdf convert ur5_robot.urdf --srdf ur5.srdf --fit-spheres -o ur5.xrdf"
        _run(_by_key()[key], runner, 2, away=away)


@pytest.mark.slow  # a fit of 48 spheres: about 4 s
def test_slender_rod(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, runner: CliRunner) -> None:
    pytest.importorskip("trimesh")
    monkeypatch.chdir(tmp_path)
    Path("r.urdf").write_text(ROD_URDF)
    _run(_by_key()["xrdf spheres r.urdf -o r.xrdf"], runner, 0)


@pytest.mark.slow  # a fit, 100,000 samples for the mask, a report: about 8 s
def test_the_convert_walkthrough_on_the_panda(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, runner: CliRunner
) -> None:
    pytest.importorskip("trimesh")
    pytest.importorskip("matplotlib")
    _robots(tmp_path)
    monkeypatch.chdir(tmp_path)
    transcripts = _by_key()
    for key in RUN_WALKTHROUGH:
        _run(transcripts[key], runner, 0)
    assert Path("panda.png").stat().st_size > 0
