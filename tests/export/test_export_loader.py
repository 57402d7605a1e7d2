"""`xrdf export curobo` writes nothing when cuRobo's loader would raise on what it writes.

Each case is checked against the loader model (tests/curobo_loader.py): the YAML the export
would write is rejected by it, and the command exits 1 with the located reason instead.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.curobo_loader import CuroboRejects, from_config
from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.export.curobo import to_curobo
from xrdf_tools.export.curobo_loader import WRITTEN_AWAY, loader_errors
from xrdf_tools.lint import RULES
from xrdf_tools.robot.xacro_source import load_robot
from xrdf_tools.xrdf.io import parse_xrdf

runner = CliRunner()


def _export(xrdf: str, urdf: str, out: Path, *args: str) -> Result:
    return runner.invoke(app, ["export", "curobo", xrdf, "--urdf", urdf, "-o", str(out), *args])


def _broken_urdf(tmp_path: Path, old: str, new: str) -> Path:
    """The UR10e URDF with the first ``old`` of its shoulder_pan_joint made ``new``."""
    text = UR10E_URDF.read_text()
    start = text.index('<joint name="shoulder_pan_joint"')
    head, joint = text[:start], text[start:]
    assert old in joint
    urdf = tmp_path / "ur10e.urdf"
    urdf.write_text(head + joint.replace(old, new, 1))
    return urdf


TILTED = ('<axis xyz="0 0 1"/>', '<axis xyz="0 0.6 0.8"/>')


@pytest.mark.parametrize(
    ("old", "new", "rule", "said", "args"),
    [
        ('effort="330.0"', 'effort="0"', "curobo-zero-velocity", 'effort="0"', ()),
        (*TILTED, "curobo-joint-axis", "0 0.6 0.8", ("--keep-axes",)),
        (
            'lower="-6.283185307179586" upper="6.283185307179586"',
            'lower="0" upper="0"',
            "cspace-joint-held",
            "[0, 0]",
            (),
        ),
    ],
    ids=["effort-0", "tilted-axis-kept", "held"],
)
def test_export_stops_where_curobos_loader_raises(
    tmp_path: Path, old: str, new: str, rule: str, said: str, args: tuple[str, ...]
) -> None:
    """KUKA iiwa 14's URDF writes effort="0" on every joint: `lint --target curobo` and
    `convert --target curobo` stopped on it, `export curobo` wrote a YAML cuRobo's loader
    raises on, exit 0. Now it stops too: exit 1, the error at the c-space joint of the XRDF
    naming the URDF line, no file written."""
    urdf = _broken_urdf(tmp_path, old, new)
    x = parse_xrdf(UR10E_XRDF.read_text(), str(UR10E_XRDF))
    text, _ = to_curobo(x, load_robot(urdf), urdf_path=urdf)  # what the export wrote
    written = tmp_path / "old.yml"
    written.write_text(text)
    with pytest.raises(CuroboRejects):
        from_config(written, urdf)

    out = tmp_path / "robot.yml"
    r = _export(str(UR10E_XRDF), str(urdf), out, *args)
    assert r.exit_code == 1, r.output
    assert not out.exists()
    line = next(ln for ln in r.stderr.splitlines() if f" error {rule} " in ln)
    assert re.match(rf"{re.escape(str(UR10E_XRDF))}:\d+:\d+: error {rule} ", line)
    assert "'shoulder_pan_joint' (line " in line and said in line
    assert r.stderr.strip().splitlines()[-1].startswith("error: cuRobo's loader would raise")


def test_a_tilted_axis_is_rewritten_in_a_urdf_curobos_loader_takes(tmp_path: Path) -> None:
    """The same tilted shoulder_pan_joint without --keep-axes: the export writes a URDF with
    its axis rewritten beside the YAML, and the model of cuRobo's loader builds the robot the
    XRDF describes from the pair (it rejected the YAML the export wrote with the URDF as is)."""
    urdf = _broken_urdf(tmp_path, *TILTED)
    out = tmp_path / "cfg" / "robot.yml"
    out.parent.mkdir()
    r = _export(str(UR10E_XRDF), str(urdf), out)
    assert r.exit_code == 0, r.output
    assert "shoulder_pan_joint (36.87° off)" in r.output
    assert _export(str(UR10E_XRDF), str(UR10E_URDF), tmp_path / "as_is.yml").exit_code == 0
    as_is = from_config(tmp_path / "as_is.yml", UR10E_URDF)
    assert from_config(out, out.with_suffix(".urdf")) == as_is


def test_a_xacro_urdf_that_stops_the_export_is_not_expanded_beside_it(tmp_path: Path) -> None:
    """With a xacro --urdf, nothing is written either: not the YAML, not the expanded URDF."""
    urdf = _broken_urdf(tmp_path, 'effort="330.0"', 'effort="0"')
    xacro = tmp_path / "ur10e.urdf.xacro"
    xacro.write_text(urdf.read_text().replace("<robot ", '<robot xmlns:xacro="x" ', 1))
    out = tmp_path / "cfg" / "robot.yml"
    out.parent.mkdir()
    r = _export(str(UR10E_XRDF), str(xacro), out)
    assert r.exit_code == 1, r.output
    assert list(out.parent.iterdir()) == []


def test_world_collision_only_stops_the_export(tmp_path: Path) -> None:
    """A world-only XRDF (no self_collision): the export can only mask every pair, and cuRobo's
    loader then finds no pair to check. It was a warning and the YAML was written."""
    text = UR10E_XRDF.read_text()
    xrdf = tmp_path / "world_only.xrdf"
    xrdf.write_text(re.sub(r"\nself_collision:\n(  .*\n)+", "\n", text))
    assert "self_collision" not in xrdf.read_text()
    out = tmp_path / "robot.yml"
    r = _export(str(xrdf), str(UR10E_URDF), out)
    assert r.exit_code == 1, r.output
    assert not out.exists()
    assert re.search(rf"{re.escape(str(xrdf))}:\d+:\d+: error export-no-pair ", r.stderr)


def test_what_the_export_writes_away_does_not_stop_it(tmp_path: Path) -> None:
    """An XRDF that cuRobo's XRDF reader raises on for what the export writes its own way (a
    2.0 file, its version quoted): exported as before, and cuRobo loads the YAML."""
    text = UR10E_XRDF.read_text().replace("format_version: 2.0", 'format_version: "2.0"')
    xrdf = tmp_path / "odd.xrdf"
    xrdf.write_text(text)
    robot = load_robot(UR10E_URDF)
    lint_rules = {d.rule for d in _lint(text, str(xrdf))}
    assert {"curobo-quoted-version", "curobo-format-version"} <= lint_rules
    assert loader_errors(text, str(xrdf), robot) == []
    out = tmp_path / "robot.yml"
    r = _export(str(xrdf), str(UR10E_URDF), out)
    assert r.exit_code == 0, r.output
    from_config(out, UR10E_URDF)


def _lint(text: str, label: str) -> list[object]:
    from xrdf_tools.lint import lint_text

    return list(lint_text(text, label, urdf=UR10E_URDF, target="curobo"))


def test_every_rule_the_export_lets_pass_is_a_curobo_rule() -> None:
    """The audit table names real rules: a renamed rule cannot silently start or stop the
    export."""
    curobo = {r.id for r in RULES if r.reader == "curobo"}
    assert set(WRITTEN_AWAY) <= curobo
    assert curobo - set(WRITTEN_AWAY) == {
        "curobo-floating-joint",
        "curobo-joint-axis",
        "curobo-joint-outside-tree",
        "curobo-zero-velocity",
    }
