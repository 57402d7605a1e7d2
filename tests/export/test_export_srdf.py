"""``xrdf export srdf``: the XRDF ignore pairs synced back into a MoveIt SRDF.

Real robots from example-robot-data: panda's SRDF is converted, its mask changed by
``xrdf report --write-mask`` and synced back; unchanged robots round-trip byte for byte.
"""

from __future__ import annotations

import dataclasses
import difflib
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import robot_urdf, robots_dir
from xrdf_tools.cli import app
from xrdf_tools.convert.core import ConvertOptions, convert_files, with_spheres
from xrdf_tools.convert.sources.srdf import Srdf, parse_srdf
from xrdf_tools.export.curobo import to_srdf
from xrdf_tools.export.srdf import reasons_from_report, sync_srdf
from xrdf_tools.export.srdf_xml import XmlDocument
from xrdf_tools.util.errors import SourceError
from xrdf_tools.util.frozen import FrozenMap
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf
from xrdf_tools.xrdf.model import Xrdf

SRDFS = {
    "panda": "panda_description/srdf/panda.srdf",
    "ur5": "ur_description/srdf/ur5.srdf",
    "xarm7": "xarm_description/srdf/xarm7.srdf",
    "anymal": "anymal_b_simple_description/srdf/anymal.srdf",  # <a /> style
    "pr2": "pr2_description/srdf/pr2.srdf",  # 1163 pairs, both empty-tag styles
}
#: The documented mapping of report classifications to SRDF reasons (docs/convert.md).
REASON_OF_CLASS = {
    "adjacent": "Adjacent",
    "default": "Default",
    "always": "Always",
    "never": "Never",
    "sometimes": "User",
}


def _srdf(name: str) -> Path:
    robot_urdf(name)  # skips when example-robot-data is missing
    root = robots_dir()
    assert root is not None
    return root / SRDFS[name]


def _disabled(s: Srdf) -> dict[frozenset[str], tuple[str, str, str]]:
    return {frozenset((a, b)): (a, b, r) for a, b, r, _ in s.disable_collisions}


def _semantic(s: Srdf) -> tuple[object, ...]:
    """Everything but the collision mask, without line numbers."""

    def strip(items: object) -> object:
        if isinstance(items, dict):
            return {k: strip(v) for k, v in items.items()}
        if isinstance(items, tuple) and items and dataclasses.is_dataclass(items[0]):
            return tuple(dataclasses.replace(i, line=None) for i in items)  # type: ignore[type-var]
        return items

    return (
        s.robot_name,
        strip({k: dataclasses.replace(g, line=None) for k, g in s.groups.items()}),
        strip(s.group_states),
        strip(s.end_effectors),
        tuple((v.name, v.type) for v in s.virtual_joints),
        s.passive_joints,
    )


def _decorate(srdf: bytes) -> bytes:
    """panda.srdf with a comment, DOCTYPE + entity, PI before <robot>, a comment inside and
    after it: what a sync must keep byte for byte."""
    head, body = srdf.split(b"<robot ", 1)
    prolog = (
        head
        + b"<!-- Franka Panda, kept by xrdf export srdf -->\n"
        + b'<!DOCTYPE robot [\n  <!ENTITY ee "end_effector">\n]>\n'
        + b'<?xml-stylesheet href="srdf.xsl"?>\n\n'
    )
    body = body.replace(b'end_effector name="end_effector"', b'end_effector name="&ee;"')
    body = body.replace(
        b"    <disable_collisions", b"    <!-- collision matrix -->\n    <disable_collisions", 1
    )
    return prolog + b"<robot " + body + b"<!-- end of file -->\n"


def _export(runner: CliRunner, *args: str) -> tuple[int, str, str]:
    r = runner.invoke(app, ["export", "srdf", *args])
    return r.exit_code, r.stdout, r.stderr


def _convert(urdf: Path, srdf: Path) -> Xrdf:
    x, _, _ = convert_files(urdf, ConvertOptions(srdf=srdf))
    return x


def _without(x: Xrdf, a: str, b: str) -> Xrdf:
    sc = x.self_collision
    assert sc is not None and sc.is_ignored(a, b)
    ignore = FrozenMap((k, tuple(o for o in v if {k, o} != {a, b})) for k, v in sc.ignore.items())
    return x.replace(self_collision=dataclasses.replace(sc, ignore=ignore))


# ------------------------------------------------------------------------------------------
# The whole flow on panda: convert, report --write-mask, sync back
# ------------------------------------------------------------------------------------------
def test_panda_report_mask_synced_back(runner: CliRunner, tmp_path: Path) -> None:
    urdf = robot_urdf("panda")
    original = _decorate(_srdf("panda").read_bytes())
    srdf_in = tmp_path / "panda.srdf"
    srdf_in.write_bytes(original)
    # the SRDF's mask, with cuRobo's panda spheres so that the report has something to judge
    x = _convert(urdf, srdf_in)
    spheres = load_xrdf(FIXTURES / "panda" / "panda.xrdf").world_collision_spheres()
    xrdf = tmp_path / "panda.xrdf"
    xrdf.write_text(dump_xrdf(with_spheres(x, dict(spheres))))
    masked, report = tmp_path / "masked.xrdf", tmp_path / "report.json"
    args = ["report", str(xrdf), "--urdf", str(urdf), "-n", "1000", "-f", "json"]
    r = runner.invoke(app, [*args, "-o", str(report), "--write-mask", str(masked)])
    assert r.exit_code in (0, 1), r.output
    rep = json.loads(report.read_text())
    added_by_report = {frozenset(p) for p in rep["mask_change"]["added"]}
    removed_by_report = {frozenset(p) for p in rep["mask_change"]["removed"]}
    assert added_by_report and removed_by_report  # the sync has work in both directions

    out = tmp_path / "out.srdf"
    code, stdout, stderr = _export(
        runner, str(masked), "--merge", str(srdf_in), "--urdf", str(urdf), "--report", str(report)
    )
    assert code == 0, stderr
    code, _, stderr = _export(runner,
        str(masked), "--merge", str(srdf_in), "--urdf", str(urdf), "--report", str(report),
        "-o", str(out),
    )  # fmt: skip
    assert code == 0, stderr
    assert out.read_bytes() == stdout.encode()
    before, after = parse_srdf(original), parse_srdf(out.read_bytes())
    want = load_xrdf(masked).self_collision
    assert want is not None

    # the disable set is exactly the XRDF's ignore set, less the pairs its mask could not
    # judge: across the finger joints it held closed (link5/finger can collide: MoveIt's own
    # panda.srdf checks it), said in one warning
    held = _held(load_xrdf(masked), urdf) - set(_disabled(before))  # those already in stay
    assert frozenset(("panda_link5", "panda_leftfinger")) in held
    assert stderr.count("warning export-srdf-held-joint") == 1
    got = _disabled(after)
    assert set(got) == want.ignore_pairs() - held
    assert len(after.disable_collisions) == len(got)  # no pair twice
    # removed pairs are gone and reported, one diagnostic each, with the SRDF line
    for pair in removed_by_report:
        assert pair not in got
        a, b, reason = _disabled(before)[pair]
        line = next(ln for x1, x2, _, ln in before.disable_collisions if {x1, x2} == pair)
        assert f"{srdf_in}:{line}: warning export-srdf-removed {a}/{b} (reason {reason})" in stderr
    assert stderr.count("export-srdf-removed") == len(removed_by_report)
    # kept pairs: same element (link order, reason)
    for pair in set(got) & set(_disabled(before)):
        assert got[pair] == _disabled(before)[pair]
    # added pairs: the reason the report's classification gives
    classes = {frozenset((p["frame_a"], p["frame_b"])): p["classification"] for p in rep["pairs"]}
    assert set(got) - set(_disabled(before)) == added_by_report - held
    for pair in added_by_report - held:
        assert got[pair][2] == REASON_OF_CLASS[classes[pair]]
    # everything else is kept
    assert _semantic(after) == _semantic(before)
    assert after.end_effectors[0].name == "end_effector"  # the entity, still resolvable
    text = out.read_bytes()
    prolog = original[: original.index(b"<robot ")]
    assert text.startswith(prolog)  # declaration, comment, DOCTYPE, PI, blank line
    assert b'name="&ee;"' in text and text.endswith(b"</robot>\n<!-- end of file -->\n")
    changed = [
        ln
        for ln in difflib.unified_diff(original.decode().splitlines(), text.decode().splitlines())
        if ln[:1] in "+-" and not ln.startswith(("+++", "---"))
    ]
    assert len(changed) == len(added_by_report - held) + len(removed_by_report)
    assert all("<disable_collisions " in ln for ln in changed)
    # and MoveIt's mask read back by convert is the XRDF's mask
    back = _convert(urdf, out).self_collision
    assert back is not None and back.ignore_pairs() == want.ignore_pairs() - held


def _held(x: Xrdf, urdf: Path) -> frozenset[frozenset[str]]:
    from xrdf_tools.export.srdf import _ordered_pairs
    from xrdf_tools.export.srdf_held import held_pairs
    from xrdf_tools.robot.xacro_source import load_robot

    return held_pairs(x, load_robot(urdf).tree, _ordered_pairs(x)).keys()


# ------------------------------------------------------------------------------------------
# Round trip and formatting
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["panda", "ur5", "xarm7", "anymal", "pr2"])
def test_unchanged_robot_round_trips_byte_identical(
    runner: CliRunner, name: str, tmp_path: Path
) -> None:
    urdf, srdf = robot_urdf(name), _srdf(name)
    xrdf = tmp_path / f"{name}.xrdf"
    r = runner.invoke(app, ["convert", str(urdf), "--srdf", str(srdf), "-o", str(xrdf)])
    assert r.exit_code == 0, r.output
    assert _disabled(parse_srdf(srdf.read_bytes()))  # there is a mask to carry
    out = tmp_path / "out.srdf"
    code, _, stderr = _export(
        runner, str(xrdf), "--merge", str(srdf), "--urdf", str(urdf), "-o", str(out)
    )
    assert code == 0 and stderr == ""
    assert out.read_bytes() == srdf.read_bytes()


def test_every_example_srdf_is_written_back_unchanged() -> None:
    robot_urdf("panda")
    root = robots_dir()
    assert root is not None
    files = sorted(root.glob("*/srdf/*.srdf"))
    assert len(files) > 10
    for f in files:
        raw = f.read_bytes()
        assert XmlDocument.parse(raw, str(f)).serialize() == raw, f


XRDF_ABCD = parse_xrdf(
    """format: xrdf
format_version: 2.0
self_collision:
  geometry: g
  ignore:
    a: [b, d]
    c: [a]
geometry:
  g:
    spheres: {}
"""
)


def test_lxml_formatting_is_undone_and_only_the_pairs_change() -> None:
    src = (
        b"<?xml version='1.0' encoding='UTF-8'?>\r\n"
        b"<robot  name='r' >\r\n"
        b"    <group name=\"g\"><![CDATA[<x/>]]><link name='a' /><link\r\n"
        b'      name="b"  /></group>\r\n'
        b'    <disable_collisions link1="b" link2="a" reason="Never" />\r\n'
        b'    <disable_collisions link1="b" link2="c" reason="Adjacent" />\r\n'
        b"</robot>\r\n"
    )
    unchanged = XmlDocument.parse(src, "t.srdf")
    assert unchanged.serialize() == src
    result = sync_srdf(XRDF_ABCD, src)
    expected = src.replace(
        b'    <disable_collisions link1="b" link2="c" reason="Adjacent" />\r\n',
        b'    <disable_collisions link1="a" link2="d" reason="User" />\r\n'
        b'    <disable_collisions link1="c" link2="a" reason="User" />\r\n',
    )
    assert result.data == expected
    assert [(c.link1, c.link2, c.reason) for c in result.removed] == [("b", "c", "Adjacent")]
    assert [c.line for c in result.removed] == [6]


def test_new_pairs_go_to_the_end_indented_like_the_file() -> None:
    src = (
        "<robot name='r'>\n"
        "    <group name='g'/>\n"
        "\n"
        "    <end_effector name='e' parent_link='a' group='g'/>\n"
        "</robot>\n"
    )
    assert sync_srdf(XRDF_ABCD, src).text == (
        "<robot name='r'>\n"
        "    <group name='g'/>\n"
        "\n"
        "    <end_effector name='e' parent_link='a' group='g'/>\n"
        "\n"
        '    <disable_collisions link1="a" link2="b" reason="User"/>\n'
        '    <disable_collisions link1="a" link2="d" reason="User"/>\n'
        '    <disable_collisions link1="c" link2="a" reason="User"/>\n'
        "</robot>\n"
    )
    assert sync_srdf(XRDF_ABCD, '<robot name="r"/>').text == (
        '<robot name="r">\n'
        '  <disable_collisions link1="a" link2="b" reason="User"/>\n'
        '  <disable_collisions link1="a" link2="d" reason="User"/>\n'
        '  <disable_collisions link1="c" link2="a" reason="User"/>\n'
        "</robot>"
    )


def test_removing_the_last_pairs_keeps_the_layout() -> None:
    src = (
        '<robot name="r">\n'
        '  <disable_collisions link1="a" link2="b"/>\n'
        '  <disable_collisions link1="x" link2="y"/>\n'
        "\n"
        '  <disable_collisions link1="y" link2="z"/>\n'
        "</robot>\n"
    )
    xrdf = parse_xrdf(dump_xrdf(XRDF_ABCD).replace("a: [b, d]\n    c: [a]", "a: [b]"))
    assert sync_srdf(xrdf, src).text == (
        '<robot name="r">\n  <disable_collisions link1="a" link2="b"/>\n</robot>\n'
    )


def test_names_with_spaces_around_are_the_links_moveit_reads() -> None:
    """MoveIt's SRDF reader trims names: ``link1=" a"`` is link ``a``, so the pair is kept
    (not removed as another pair and added again)."""
    src = (
        '<robot name="r">\n'
        '  <disable_collisions link1=" a" link2="b " reason="Adjacent"/>\n'
        '  <disable_collisions link1="a" link2=" d" reason="Never"/>\n'
        '  <disable_collisions link1="c\t" link2="a" reason="Never"/>\n'
        "</robot>\n"
    )
    result = sync_srdf(XRDF_ABCD, src)
    assert result.text == src
    pairs = parse_srdf(src).disable_collisions
    assert [(a, b) for a, b, _, _ in pairs] == [("a", "b"), ("a", "d"), ("c", "a")]


# ------------------------------------------------------------------------------------------
# disable_default_collisions
# ------------------------------------------------------------------------------------------
def test_disable_default_collisions_is_kept_and_overridden_per_pair(
    runner: CliRunner, tmp_path: Path
) -> None:
    urdf = robot_urdf("panda")
    text = _srdf("panda").read_text()
    lines = [ln for ln in text.splitlines(keepends=True) if 'link1="panda_hand"' not in ln]
    anchor = next(i for i, ln in enumerate(lines) if "<disable_collisions" in ln)
    lines.insert(anchor, '    <disable_default_collisions link="panda_hand"/>\n')
    srdf = tmp_path / "panda.srdf"
    srdf.write_text("".join(lines))
    x = _convert(urdf, srdf)
    # unchanged: no explicit pair is added for what the default covers
    same = tmp_path / "same.srdf"
    xrdf = tmp_path / "p.xrdf"
    xrdf.write_text(dump_xrdf(x))
    code, _, err = _export(
        runner, str(xrdf), "--merge", str(srdf), "--urdf", str(urdf), "-o", str(same)
    )
    assert code == 0 and err == ""
    assert same.read_bytes() == srdf.read_bytes()
    # the XRDF now checks panda_hand/panda_link5: an enable_collisions, reported as removed
    xrdf.write_text(dump_xrdf(_without(x, "panda_hand", "panda_link5")))
    out = tmp_path / "out.srdf"
    code, _, err = _export(
        runner, str(xrdf), "--merge", str(srdf), "--urdf", str(urdf), "-o", str(out)
    )
    assert code == 0
    assert "export-srdf-removed panda_hand/panda_link5" in err and "enable_collisions" in err
    result = parse_srdf(out.read_bytes())
    assert [(a, b) for a, b, _ in result.enable_collisions] == [("panda_hand", "panda_link5")]
    assert [link for link, _ in result.disable_default] == ["panda_hand"]
    back = _convert(urdf, out).self_collision
    want = _without(x, "panda_hand", "panda_link5").self_collision
    assert back is not None and want is not None
    assert back.ignore_pairs() == want.ignore_pairs()


# ------------------------------------------------------------------------------------------
# <robot name>
# ------------------------------------------------------------------------------------------
def test_robot_name_is_the_urdf_name(runner: CliRunner, tmp_path: Path) -> None:
    # example-robot-data's z1.srdf says 'z1' where its URDF says 'z1_description' (and has
    # broken groups): the same mismatch, on the Panda
    urdf, panda_srdf = robot_urdf("panda"), _srdf("panda")
    srdf = tmp_path / "z1.srdf.in"
    srdf.write_bytes(panda_srdf.read_bytes().replace(b'<robot name="panda">', b'<robot name="z1">'))
    assert b'<robot name="z1">' in srdf.read_bytes()  # the URDF says panda
    xrdf = tmp_path / "z1.xrdf"
    xrdf.write_text(dump_xrdf(_convert(urdf, srdf)))
    out = tmp_path / "z1.srdf"
    code, _, err = _export(
        runner, str(xrdf), "--merge", str(srdf), "--urdf", str(urdf), "-o", str(out)
    )
    assert code == 0
    assert "warning export-srdf-robot-name" in err and "'panda'" in err
    assert out.read_bytes() == srdf.read_bytes().replace(
        b'<robot name="z1">', b'<robot name="panda">'
    )
    # a new SRDF takes the URDF's name; without --urdf the fallback is said in a note
    code, stdout, err = _export(runner, str(xrdf), "--urdf", str(urdf))
    assert code == 0 and parse_srdf(stdout).robot_name == "panda"
    assert "export-srdf-robot-name" not in err
    code, stdout, err = _export(runner, str(xrdf))
    assert code == 0 and parse_srdf(stdout).robot_name == "z1"  # the file stem
    assert "info export-srdf-robot-name" in err and "--urdf" in err
    code, stdout, _ = _export(runner, str(xrdf), "--robot-name", "arm")
    assert parse_srdf(stdout).robot_name == "arm"
    # without --urdf, a merge keeps the SRDF's name and says it was not checked
    code, stdout, err = _export(runner, str(xrdf), "--merge", str(srdf))
    assert parse_srdf(stdout).robot_name == "z1" and "not checked" in err


def test_ignore_links_not_in_the_urdf_are_an_error(runner: CliRunner, tmp_path: Path) -> None:
    panda = tmp_path / "panda.xrdf"
    panda.write_text(dump_xrdf(_convert(robot_urdf("panda"), _srdf("panda"))))
    out = tmp_path / "out.srdf"
    code, stdout, err = _export(
        runner, str(panda), "--urdf", str(robot_urdf("ur5")), "-o", str(out)
    )
    assert code == 2 and stdout == "" and not out.exists()
    assert err.count("\n") == 1 and err.startswith("error: ")
    assert "'panda_hand'" in err and "'ur5'" in err and "Traceback" not in err


# ------------------------------------------------------------------------------------------
# Output safety and inputs
# ------------------------------------------------------------------------------------------
def test_output_equal_to_an_input_is_refused(runner: CliRunner, tmp_path: Path) -> None:
    urdf = robot_urdf("ur5")
    srdf = tmp_path / "ur5.srdf"
    srdf.write_bytes(_srdf("ur5").read_bytes())
    xrdf = tmp_path / "ur5.xrdf"
    xrdf.write_text(dump_xrdf(_without(_convert(urdf, srdf), "base_link", "shoulder_link")))
    report = tmp_path / "report.json"
    report.write_text('{"pairs": []}')
    before = srdf.read_bytes()
    base = [str(xrdf), "--merge", str(srdf), "--urdf", str(urdf), "--report", str(report)]
    sub = tmp_path / "sub"
    sub.mkdir()
    for target in (srdf, sub / ".." / "ur5.srdf", report, urdf, xrdf):
        code, stdout, err = _export(runner, *base, "-o", str(target))
        assert code == 2, target
        assert err.count("\n") == 1 and "refusing to overwrite an input file" in err
        assert stdout == ""
    assert srdf.read_bytes() == before
    code, _, err = _export(runner, *base, "-o", str(tmp_path / "new.srdf"))
    assert code == 0 and "export-srdf-removed base_link/shoulder_link" in err


def test_an_srdf_xacro_is_not_merged_into_but_its_expansion_is(
    runner: CliRunner, tmp_path: Path
) -> None:
    """Baxter's MoveIt config keeps its disable_collisions in included xacros: merging into
    the top file added all 373 pairs again beside the includes and removed none. It is an
    input error naming the way (expand, then merge), and the expansion merges."""
    (tmp_path / "pairs.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="pairs">\n'
        '<disable_collisions link1="a" link2="b" reason="Adjacent"/>\n'
        '<disable_collisions link1="a" link2="c" reason="Never"/>\n'
        "</xacro:macro></robot>\n"
    )
    srdf = tmp_path / "bot.srdf.xacro"
    srdf.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="pairs.xacro"/>\n  <xacro:pairs/>\n</robot>\n'
    )
    xrdf = tmp_path / "bot.xrdf"
    xrdf.write_text(
        "format: xrdf\nformat_version: 1.0\n"
        "cspace: {joint_names: [j], acceleration_limits: [1.0], jerk_limits: [1.0]}\n"
        "tool_frames: [b]\n"
        "collision: {geometry: g}\n"
        "self_collision: {geometry: g, ignore: {a: [b]}}\n"
        "geometry: {g: {spheres: {a: [{center: [0, 0, 0], radius: 0.1}]}}}\n"
    )
    code, stdout, err = _export(runner, str(xrdf), "--merge", str(srdf))
    assert code == 2 and stdout == ""
    assert err.startswith(f"error: {srdf}:2:3: a xacro file") and "xrdf expand" in err
    expanded = tmp_path / "bot.srdf"
    assert runner.invoke(app, ["expand", str(srdf), "-o", str(expanded)]).exit_code == 0
    code, stdout, err = _export(runner, str(xrdf), "--merge", str(expanded))
    assert code == 0 and "export-srdf-removed a/c" in err
    assert parse_srdf(stdout).disable_collisions[0][:2] == ("a", "b")
    assert len(parse_srdf(stdout).disable_collisions) == 1


def test_report_reasons() -> None:
    pairs = [
        {"frame_a": "a", "frame_b": "b", "classification": "adjacent"},
        {"frame_a": "a", "frame_b": "c", "classification": "sometimes"},
        {"frame_a": "d", "frame_b": "a", "classification": "never"},
        # without classification: derived from the measured fields, in the report's order
        {"frame_a": "x", "frame_b": "y", "adjacent": True, "default_clearance": -1.0},
        {"frame_a": "x", "frame_b": "z", "adjacent": False, "default_clearance": -0.1},
        {"frame_a": "y", "frame_b": "z", "default_clearance": 0.1, "rate": 0.99, "hits": 99},
        {"frame_a": "w", "frame_b": "z", "default_clearance": 0.1, "rate": 0.0, "hits": 0},
        {"frame_a": "w", "frame_b": "y", "default_clearance": 0.1, "rate": 0.5, "hits": 5},
    ]
    reasons = reasons_from_report({"pairs": pairs})
    assert reasons == {
        frozenset("ab"): "Adjacent",
        frozenset("ac"): "User",
        frozenset("ad"): "Never",
        frozenset("xy"): "Adjacent",
        frozenset("xz"): "Default",
        frozenset("yz"): "Always",
        frozenset("wz"): "Never",
        frozenset("wy"): "User",
    }
    result = sync_srdf(XRDF_ABCD, reasons=reasons)
    assert {(c.link1, c.link2, c.reason) for c in result.added} == {
        ("a", "b", "Adjacent"),
        ("a", "d", "Never"),
        ("c", "a", "User"),
    }
    with pytest.raises(SourceError, match="no 'pairs' list"):
        reasons_from_report({"diagnostics": []}, "r.json")


def test_bad_report_or_srdf_is_a_one_line_error(runner: CliRunner, tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text("not json")
    xrdf = tmp_path / "a.xrdf"
    xrdf.write_text(dump_xrdf(XRDF_ABCD))
    code, _, err = _export(runner, str(xrdf), "--report", str(bad))
    assert code == 2 and err.count("\n") == 1 and "not JSON" in err
    broken = tmp_path / "broken.srdf"
    broken.write_text("<robot name='r'>")
    code, _, err = _export(runner, str(xrdf), "--merge", str(broken))
    assert code == 2 and err.count("\n") == 1 and "malformed SRDF XML" in err
    code, _, err = _export(runner, str(xrdf), "--merge", str(tmp_path / "missing.srdf"))
    assert code == 2 and err.count("\n") == 1 and "SRDF file not found" in err


def test_library_is_pure_and_to_srdf_still_works(capsys: pytest.CaptureFixture[str]) -> None:
    result = sync_srdf(XRDF_ABCD, '<robot name="r">\n</robot>\n')
    assert to_srdf(XRDF_ABCD, "ignored", '<robot name="r">\n</robot>\n') == result.text
    assert {d.rule for d in result.diagnostics} == {"export-srdf-robot-name", "export-srdf-added"}
    assert capsys.readouterr() == ("", "")


def test_added_frames_are_not_written(tmp_path: Path) -> None:
    x = parse_xrdf(
        dump_xrdf(XRDF_ABCD)
        .replace(
            "self_collision:",
            "modifiers:\n  - add_frame:\n      frame_name: tcp\n      parent_frame_name: a\n"
            "      joint_name: tcp_joint\n      fixed_transform:\n"
            "        position: [0.0, 0.0, 0.1]\n"
            "        orientation: {w: 1.0, xyz: [0.0, 0.0, 0.0]}\n"
            "self_collision:",
        )
        .replace("c: [a]", "c: [a, tcp]")
    )
    assert x.added_frames()
    result = sync_srdf(x)
    assert "tcp" not in result.text
    assert any(
        d.rule == "export-srdf-added-frame" and "tcp" in d.message for d in result.diagnostics
    )


def test_an_srdf_xacro_is_refused_and_its_expansion_merged(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A MoveIt 2 config's SRDF xacro writes its pairs in an included macro: a sync of its own
    text would add every pair again as 'User' and write the expanded robot name over
    ``$(arg name)``. It is refused, located, and the expansion it names merges."""
    from tests.paths import UR10E_URDF, UR10E_XRDF

    top = tmp_path / "ur10e.srdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://wiki.ros.org/xacro" '
        'name="$(arg name)">\n  <xacro:arg name="prefix" default=""/>\n'
        '  <xacro:include filename="pairs.srdf.xacro"/>\n  <xacro:pairs prefix=""/>\n</robot>\n'
    )
    (tmp_path / "pairs.srdf.xacro").write_text(
        '<robot xmlns:xacro="http://wiki.ros.org/xacro">\n'
        '  <xacro:macro name="pairs" params="prefix">\n'
        '    <disable_collisions link1="${prefix}upper_arm_link" '
        'link2="${prefix}forearm_link" reason="Adjacent"/>\n'
        "  </xacro:macro>\n</robot>\n"
    )
    out = tmp_path / "out.srdf"
    code, stdout, err = _export(
        runner, str(UR10E_XRDF), "--merge", str(top), "--urdf", str(UR10E_URDF), "-o", str(out)
    )
    assert code == 2 and stdout == "" and not out.exists()
    assert err.startswith(f"error: {top}:3:3: a xacro file: "), err
    assert err.count("\n") == 1 and f"xrdf expand {top}" in err
    expanded = tmp_path / "ur10e.srdf"
    args = ["expand", str(top), "--xacro-arg", "name:=ur10e_robot", "-o", str(expanded)]
    assert runner.invoke(app, args).exit_code == 0
    code, _, err = _export(
        runner, str(UR10E_XRDF), "--merge", str(expanded), "--urdf", str(UR10E_URDF), "-o", str(out)
    )
    assert code == 0, err
    merged = _disabled(parse_srdf(out.read_text()))
    assert merged[frozenset(("upper_arm_link", "forearm_link"))][2] == "Adjacent"
    assert parse_srdf(out.read_text()).robot_name == "ur10e_robot"
    assert "export-srdf-robot-name" not in err


def test_pairs_naming_a_link_the_urdf_lacks_are_kept_and_said_once_per_link(
    runner: CliRunner, tmp_path: Path
) -> None:
    """PR2's MoveIt SRDF disables pairs of its Kinect links, which the default pr2.urdf.xacro
    does not have: the sync removed each with "no longer ignored by the XRDF" (200 lines),
    though no XRDF of that URDF can say anything of them. They are kept as they are (the SRDF
    may serve a variant with the Kinect), with one info per such link at its first pair; the
    pairs the XRDF stopped ignoring are removed with their own warning."""
    urdf = tmp_path / "bot.urdf"
    urdf.write_text(
        '<robot name="bot"><link name="a"/><link name="b"/><link name="c"/>\n'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>\n'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        '<joint name="k" type="fixed"><parent link="b"/><child link="c"/></joint></robot>\n'
    )
    srdf = tmp_path / "bot.srdf"
    srdf.write_text(
        '<robot name="bot">\n'
        '<disable_collisions link1="a" link2="b" reason="Adjacent"/>\n'
        '<disable_collisions link1="a" link2="c" reason="Never"/>\n'
        '<disable_collisions link1="a" link2="kinect" reason="Never"/>\n'
        '<disable_collisions link1="kinect" link2="c" reason="Never"/>\n'
        '<disable_collisions link1="prosilica" link2="kinect" reason="Never"/>\n'
        "</robot>\n"
    )
    xrdf = tmp_path / "bot.xrdf"
    xrdf.write_text(
        "format: xrdf\nformat_version: 1.0\n"
        "cspace: {joint_names: [j], acceleration_limits: [1.0], jerk_limits: [1.0]}\n"
        "tool_frames: [c]\n"
        "collision: {geometry: g}\n"
        "self_collision: {geometry: g, ignore: {a: [b]}}\n"
        "geometry: {g: {spheres: {a: [{center: [0, 0, 0], radius: 0.1}]}}}\n"
    )
    code, stdout, err = _export(runner, str(xrdf), "--merge", str(srdf), "--urdf", str(urdf))
    assert code == 0, err
    said = [ln for ln in err.splitlines() if "export-srdf-" in ln]
    assert said == [
        f"{srdf}:3: warning export-srdf-removed a/c (reason Never) is no longer ignored by the "
        "XRDF: removed",
        f"{srdf}:4: info export-srdf-unknown-link 'kinect' is not a link of the URDF 'bot': 3 "
        "disable_collisions naming it kept (first a/kinect); no XRDF of this URDF can say "
        "whether to check them",
        f"{srdf}:6: info export-srdf-unknown-link 'prosilica' is not a link of the URDF 'bot': "
        "1 disable_collisions naming it kept (first prosilica/kinect); no XRDF of this URDF "
        "can say whether to check them",
    ]
    assert [p[:2] for p in parse_srdf(stdout).disable_collisions] == [
        ("a", "b"),
        ("a", "kinect"),
        ("kinect", "c"),
        ("prosilica", "kinect"),
    ]


def test_every_pair_of_a_big_mask_is_added_once_and_replaces_an_enable() -> None:
    """PR2's 1163 pairs synced into an SRDF that enables one of them: each pair is added once
    (as a ``disable_collisions``, the ``enable_collisions`` dropped), in the XRDF's order."""
    x = _convert(robot_urdf("pr2"), _srdf("pr2"))
    sc = x.self_collision
    assert sc is not None
    wanted = sc.ignore_pairs()
    a, b = sorted(next(iter(sorted(wanted, key=sorted))))
    existing = f'<robot name="pr2">\n  <enable_collisions link1="{b}" link2="{a}" reason="User"/>\n'
    result = sync_srdf(x, existing + "</robot>\n")
    added = [frozenset((c.link1, c.link2)) for c in result.added]
    assert len(added) == len(wanted) > 1000 and set(added) == wanted
    assert all(c.element == "disable_collisions" for c in result.added)
    assert "enable_collisions" not in result.text
    fresh = [frozenset((c.link1, c.link2)) for c in sync_srdf(x).added]
    assert added == fresh  # the enabled pair keeps its place in the XRDF's order
