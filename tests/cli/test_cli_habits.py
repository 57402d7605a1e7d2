"""The everyday habits of every command: ``-q``/``-v``, ``-`` for stdin/stdout, one progress
bar, one output writer, and the ``viz --png`` legend, camera and title on a large robot."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from tests.paths import UR10E_URDF, UR10E_XRDF
from tests.robots import robot_urdf
from xrdf_tools.cli import app
from xrdf_tools.cli.commands import plain, typer_common

COMMANDS = [
    ["convert"],
    ["lint"],
    ["diff"],
    ["report"],
    ["viz"],
    ["spheres"],
    ["expand"],
    ["export", "curobo"],
    ["export", "srdf"],
    ["export", "xrdf"],
]

XACRO = """<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default="a_"/>
  <link name="$(arg prefix)base"/>
  <link name="$(arg prefix)tip"/>
  <joint name="$(arg prefix)j" type="revolute"><parent link="$(arg prefix)base"/>
    <child link="$(arg prefix)tip"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def _run(runner: CliRunner, *args: str, stdin: str | None = None) -> Any:
    return runner.invoke(app, list(args), input=stdin)


# ------------------------------------------------------------------------------------------
# -q / -v
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("cmd", COMMANDS, ids=" ".join)
def test_every_command_has_quiet_and_verbose(runner: CliRunner, cmd: list[str]) -> None:
    r = _run(runner, *cmd, "--help")
    assert r.exit_code == 0, r.output
    for flag in ("-q", "--quiet", "-v", "--verbose"):
        assert flag in r.stdout


def test_quiet_and_verbose_together_is_a_usage_error(runner: CliRunner) -> None:
    r = _run(runner, "lint", "-q", "-v", str(UR10E_XRDF))
    assert r.exit_code == 2
    assert "cannot be combined" in r.stderr


def test_quiet_drops_warnings_keeps_the_output(runner: CliRunner) -> None:
    loud = _run(runner, "convert", str(UR10E_URDF))
    quiet = _run(runner, "convert", "-q", str(UR10E_URDF))
    assert loud.exit_code == quiet.exit_code == 0
    assert "warning convert-chosen-group" in loud.stderr
    assert quiet.stderr == ""
    assert quiet.stdout == loud.stdout and quiet.stdout.startswith("format: xrdf")


def test_quiet_keeps_errors(runner: CliRunner, tmp_path: Path) -> None:
    bad = tmp_path / "bad.xrdf"
    bad.write_text("format: xrdf\nformat_version: 2.0\ncspace: [\n")
    r = _run(runner, "export", "xrdf", "-q", str(bad))
    assert r.exit_code == 2
    assert f"{bad}:" in r.stderr


def test_quiet_keeps_lint_findings_they_are_the_output(runner: CliRunner) -> None:
    r = _run(runner, "lint", "-q", str(UR10E_XRDF))
    assert r.exit_code == 0
    assert "warning curobo-format-version" in r.stdout  # a 2.0 file: a finding, not a note


def test_quiet_drops_notes_verbose_adds_timings(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "r.txt"
    args = ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "200", "-j", "1"]
    normal = _run(runner, *args, "-o", str(out))
    assert normal.exit_code == 0, normal.output
    assert f"report written to {out}" in normal.stderr
    quiet = _run(runner, *args, "-o", str(out), "-q")
    assert quiet.exit_code == 0 and quiet.stderr == ""
    verbose = _run(runner, *args, "-o", str(out), "-v")
    assert verbose.exit_code == 0
    assert "sampling 200 configuration(s)" in verbose.stderr
    assert "sampling: " in verbose.stderr and "s in all" in verbose.stderr


def test_verbosity_does_not_outlive_its_run(runner: CliRunner) -> None:
    assert _run(runner, "convert", "-q", str(UR10E_URDF)).stderr == ""
    assert "warning" in _run(runner, "convert", str(UR10E_URDF)).stderr
    assert plain.verbosity() is plain.Verbosity.NORMAL


# ------------------------------------------------------------------------------------------
# '-' for standard input and output
# ------------------------------------------------------------------------------------------
def test_lint_reads_stdin(runner: CliRunner) -> None:
    text = UR10E_XRDF.read_text()
    from_file = _run(runner, "lint", "--format", "json", str(UR10E_XRDF))
    from_stdin = _run(runner, "lint", "--format", "json", "-", stdin=text)
    assert from_stdin.exit_code == from_file.exit_code == 0
    assert from_stdin.stdout == from_file.stdout.replace(str(UR10E_XRDF), "<stdin>")


def test_lint_library_reads_stdin(monkeypatch: pytest.MonkeyPatch) -> None:
    import io
    import sys

    from xrdf_tools.lint import lint

    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"format: xrdf\n")))
    diags = lint(["-"])
    assert diags and {d.path for d in diags} == {"<stdin>"}


def test_two_stdin_inputs_are_an_error(runner: CliRunner) -> None:
    text = UR10E_XRDF.read_text()
    r = _run(runner, "diff", "-", "-", stdin=text)
    assert r.exit_code == 2
    assert "standard input" in r.stderr and "A.xrdf and B.xrdf" in r.stderr
    r = _run(runner, "lint", "-", str(UR10E_XRDF), "-", stdin=text)
    assert r.exit_code == 2 and "FILES (2 times)" in r.stderr


def test_diff_reads_one_side_from_stdin(runner: CliRunner) -> None:
    r = _run(runner, "diff", str(UR10E_XRDF), "-", stdin=UR10E_XRDF.read_text())
    assert r.exit_code == 0, r.output
    r = _run(
        runner, "diff", str(UR10E_XRDF), "-", stdin=UR10E_XRDF.read_text().replace("0.06", "0.07")
    )
    assert r.exit_code == 1


def test_export_reads_stdin_and_writes_stdout(runner: CliRunner) -> None:
    direct = _run(runner, "export", "xrdf", "--target", "cumotion", str(UR10E_XRDF))
    piped = _run(
        runner,
        "export",
        "xrdf",
        "--target",
        "cumotion",
        "-",
        "-o",
        "-",
        stdin=UR10E_XRDF.read_text(),
    )
    assert piped.exit_code == direct.exit_code == 0
    assert piped.stdout == direct.stdout and piped.stdout.startswith("format: xrdf")
    cur = _run(
        runner, "export", "curobo", "-", "--urdf", str(UR10E_URDF), stdin=UR10E_XRDF.read_text()
    )
    assert cur.exit_code == 0 and "robot_cfg" in cur.stdout


def test_stdin_errors_name_stdin(runner: CliRunner) -> None:
    r = _run(runner, "export", "xrdf", "-", stdin="format: xrdf\ncspace: [\n")
    assert r.exit_code == 2
    assert r.stderr.startswith("error: <stdin>:")


def test_report_reads_stdin_and_dash_o_is_stdout(runner: CliRunner) -> None:
    args = ["--urdf", str(UR10E_URDF), "-n", "200", "-j", "1", "--format", "json"]
    a = _run(runner, "report", str(UR10E_XRDF), *args)
    b = _run(runner, "report", "-", *args, "-o", "-", stdin=UR10E_XRDF.read_text())
    assert a.exit_code == b.exit_code == 0, b.output
    ja, jb = json.loads(a.stdout), json.loads(b.stdout)
    assert jb["xrdf"] == "<stdin>" and jb["samples"] == 200
    for key in ("pairs", "recommended_ignore", "classification_counts", "sphere_counts"):
        assert ja[key] == jb[key], key
    clash = _run(runner, "report", str(UR10E_XRDF), *args, "--write-mask", "-")
    assert clash.exit_code == 2 and "given for both" in clash.stderr


def test_convert_and_expand_dash_o(runner: CliRunner, tmp_path: Path) -> None:
    r = _run(runner, "convert", "-q", str(UR10E_URDF), "-o", "-")
    assert r.exit_code == 0 and r.stdout.startswith("format: xrdf")
    assert not Path("-").exists()
    r = _run(runner, "convert", str(UR10E_URDF), "--check", "-o", "-")
    assert r.exit_code == 2 and "--check needs -o FILE" in r.stderr
    xacro = tmp_path / "r.urdf.xacro"
    xacro.write_text(XACRO)
    r = _run(runner, "expand", str(xacro), "--xacro-arg", "prefix:=b_", "-o", "-")
    assert r.exit_code == 0 and 'name="b_tip"' in r.stdout


def test_viz_reads_stdin(runner: CliRunner, tmp_path: Path) -> None:
    from tests.paths import FIXTURES

    out = tmp_path / "p.png"
    xrdf = (FIXTURES / "panda" / "panda.xrdf").read_text()
    r = _run(runner, "viz", "-", "--urdf", str(robot_urdf("panda")), "--png", str(out), stdin=xrdf)
    assert r.exit_code == 0, r.output
    assert out.read_bytes()[:4] == b"\x89PNG"
    r = _run(runner, "viz", "-", "--urdf", str(robot_urdf("panda")), "--png", "-", stdin=xrdf)
    assert r.exit_code == 2 and "needs a file name" in r.stderr


# ------------------------------------------------------------------------------------------
# One output writer
# ------------------------------------------------------------------------------------------
def test_write_output_names_the_users_path(tmp_path: Path, capsys: Any) -> None:
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    target = blocker / "out.xrdf"
    with pytest.raises(typer.Exit) as exc:
        typer_common.write_output("data", target)
    assert exc.value.exit_code == 2
    err = capsys.readouterr().err
    assert f"{target}:" in err and "cannot write" in err and ".tmp" not in err


def test_write_output_stdout_and_file(tmp_path: Path, capsys: Any) -> None:
    typer_common.write_output("text\n", None)
    typer_common.write_output(b"bytes\n", Path("-"))
    assert capsys.readouterr().out == "text\nbytes\n"
    typer_common.write_output(b"\x00\x01", tmp_path / "sub" / "o.bin")
    assert (tmp_path / "sub" / "o.bin").read_bytes() == b"\x00\x01"


def test_cli_write_error_names_the_path(runner: CliRunner, tmp_path: Path) -> None:
    blocker = tmp_path / "file.txt"
    blocker.write_text("x")
    r = _run(runner, "export", "xrdf", str(UR10E_XRDF), "-o", str(blocker / "o.xrdf"))
    assert r.exit_code == 2
    assert f"{blocker / 'o.xrdf'}:" in r.stderr


# ------------------------------------------------------------------------------------------
# One progress bar
# ------------------------------------------------------------------------------------------
def test_progress_bar_only_on_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    with typer_common.progress_bar() as bar:
        assert bar is None  # pytest's stderr is not a terminal
    monkeypatch.setattr(typer_common, "stderr_is_terminal", lambda: True)
    with typer_common.progress_bar() as bar:
        assert bar is not None
        bar("working", 1, 2)
    with typer_common.progress_bar(enabled=False) as bar:
        assert bar is None


@pytest.mark.parametrize("quiet", [False, True])
def test_commands_draw_the_common_bar_unless_quiet(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch, quiet: bool
) -> None:
    import rich.progress

    started: list[int] = []
    monkeypatch.setattr(typer_common, "stderr_is_terminal", lambda: True)
    original = rich.progress.Progress.start
    monkeypatch.setattr(
        rich.progress.Progress, "start", lambda self: (started.append(1), original(self))[1]
    )
    args = ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "300", "-j", "1"]
    r = _run(runner, *args, *(["-q"] if quiet else []))
    assert r.exit_code == 0, r.output
    assert bool(started) is not quiet


def test_one_progress_style_in_the_commands() -> None:
    import xrdf_tools.cli.commands as pkg

    root = Path(pkg.__file__).parent
    for f in root.glob("*.py"):
        if f.name == "typer_common.py":
            continue
        text = f.read_text()
        assert "rich.progress" not in text and "typer.progressbar" not in text, f.name
        assert "write_atomic" not in text, f.name


# ------------------------------------------------------------------------------------------
# viz --png on a large robot: legend, camera, title counts
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def pr2(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The PR2 (82 links) with one sphere on every link and its adjacent pairs ignored."""
    from xrdf_tools.convert.core import ConvertOptions, convert
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.spheres import ignore_adjacent
    from xrdf_tools.xrdf.io import dump_xrdf, parse_xrdf

    urdf = robot_urdf("pr2")
    u = load_urdf(urdf)
    x, _ = convert(u, ConvertOptions())
    block = "".join(
        f"      {n}:\n        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n"
        for n in u.link_map
    )
    text = dump_xrdf(x).replace("    spheres: {}\n", "    spheres:\n" + block)
    assert text != dump_xrdf(x)
    masked, _ = ignore_adjacent(parse_xrdf(text), urdf, urdf=u)
    path = tmp_path_factory.mktemp("pr2") / "pr2.xrdf"
    path.write_text(dump_xrdf(masked))
    return urdf, path


def _pr2_scene(pr2: tuple[Path, Path]) -> Any:
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.viz import build_scene
    from xrdf_tools.xrdf.io import load_xrdf

    return build_scene(load_urdf(pr2[0]), load_xrdf(pr2[1]), meshes="none")


def test_pr2_title_counts_the_frame_pairs(pr2: tuple[Path, Path]) -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.selfcollision.collision import build_sphere_set, colliding_frame_pairs
    from xrdf_tools.viz.png import png_title
    from xrdf_tools.xrdf.io import load_xrdf

    u, x = load_urdf(pr2[0]), load_xrdf(pr2[1])
    kin, _ = build_kinematic_model(u, x)
    every, _ = build_sphere_set(kin, x, include_masked=True)
    ignored = int(np.count_nonzero(every.frame_pair_masked))
    checked = every.n_frame_pairs - ignored
    q0 = default_configuration(kin, x.default_joint_positions)
    colliding = colliding_frame_pairs(kin, x, q0)
    assert ignored == 81  # the PR2's tree: one adjacent pair per joint
    assert checked == 82 * 81 // 2 - 81 and colliding

    scene = _pr2_scene(pr2)
    assert (scene.frame_pairs_checked, scene.frame_pairs_ignored) == (checked, ignored)
    title = png_title(scene)
    # the colliding pairs are among the checked ones (Nextage: a pair colliding at the default
    # pose but masked read as "0 colliding" beside "ignored")
    assert f"{checked} checked ({len(colliding)} colliding at the default pose" in title
    assert title.endswith(f"), {ignored} ignored")


def test_pr2_legend_stays_inside_the_image(pr2: tuple[Path, Path], tmp_path: Path) -> None:
    from xrdf_tools.viz.png import LEGEND_COLUMNS_FROM, draw_png, parse_view

    scene = _pr2_scene(pr2)
    assert sum(1 for link in scene.links if link.n_spheres) >= LEGEND_COLUMNS_FROM
    for view in ("iso", "front", "side", "top", "30,-60"):
        fig = draw_png(scene, view=parse_view(view))
        renderer = fig.canvas.get_renderer()
        (legend,) = fig.legends
        box = legend.get_window_extent(renderer)
        width, height = fig.bbox.width, fig.bbox.height
        assert legend._ncols > 1  # columns, not one long list
        assert box.x0 >= 0 and box.y0 >= 0 and box.x1 <= width and box.y1 <= height, view
        assert min(t.get_fontsize() for t in legend.get_texts()) < 7
        # the picture keeps its square above the legend
        axes = fig.axes[0].get_window_extent(renderer)
        assert axes.y0 >= box.y1 - 1
        assert height > width
    fig = draw_png(scene, legend="off")
    assert not fig.legends and fig.bbox.height == fig.bbox.width


def test_cli_viz_view_and_legend_options(
    runner: CliRunner, pr2: tuple[Path, Path], tmp_path: Path
) -> None:
    out = tmp_path / "pr2.png"
    base = ["viz", str(pr2[1]), "--urdf", str(pr2[0]), "--png", str(out), "--meshes", "none"]
    r = _run(runner, *base, "--view", "top", "--legend", "off", "-v")
    assert r.exit_code == 0, r.output
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert "frame pairs: 3240 checked (" in r.stderr and "), 81 ignored" in r.stderr
    r = _run(runner, *base, "--view", "sideways")
    assert r.exit_code == 2 and "iso, front, side, top or ELEV,AZIM" in r.stderr


def test_parse_view() -> None:
    from xrdf_tools.util.errors import XrdfToolsError
    from xrdf_tools.viz.png import VIEWS, parse_view

    assert parse_view("TOP") == VIEWS["top"]
    assert parse_view(" 30, -60 ") == (30.0, -60.0)
    for bad in ("", "1,2,3", "nan,1", "a,b"):
        with pytest.raises(XrdfToolsError):
            parse_view(bad)
