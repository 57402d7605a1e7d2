"""xrdf report: classification, findings, recommended mask, trajectory check, CLI outputs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, REPO, UR10E_URDF, UR10E_XRDF
from tests.robots import robot_urdf
from tests.selfcollision.test_collision import THREE_LINK, THREE_LINK_XRDF
from xrdf_tools.cli import app
from xrdf_tools.report import (
    adjacent_frame_pairs,
    never_upper_bound,
    recommended_xrdf,
    self_collision_report,
)
from xrdf_tools.report.render import render_html, render_markdown, render_text, report_to_dict
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.xrdf.io import dump_xrdf, load_xrdf, parse_xrdf

PANDA_XRDF = FIXTURES / "panda" / "panda.xrdf"
SCHEMA = REPO / "docs" / "report-schema.json"


def three_link_report(**kw: object):  # type: ignore[no-untyped-def]
    xrdf = parse_xrdf(THREE_LINK_XRDF, "three_link.xrdf")
    return xrdf, self_collision_report(load_urdf(THREE_LINK), xrdf, **kw)  # type: ignore[arg-type]


def test_never_upper_bound_is_the_exact_binomial_bound() -> None:
    assert never_upper_bound(100_000) == pytest.approx(1 - 0.05 ** (1 / 100_000), rel=1e-12)
    assert never_upper_bound(100_000) == pytest.approx(3 / 100_000, rel=0.01)
    assert never_upper_bound(1) == pytest.approx(0.95)
    assert never_upper_bound(0) == 1.0


def test_adjacency_collapses_frames_without_spheres() -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model

    xrdf = load_xrdf(PANDA_XRDF)
    kin, _ = build_kinematic_model(load_urdf(robot_urdf("panda")), xrdf)
    frames = list(xrdf.self_collision_spheres())
    adj = adjacent_frame_pairs(kin, frames)
    # link7 -> link8 (no spheres) -> hand: adjacent; fingers are siblings of each other via
    # the hand, which has spheres, so they are not adjacent to each other
    assert frozenset(("panda_link7", "panda_hand")) in adj
    assert frozenset(("panda_hand", "panda_leftfinger")) in adj
    assert frozenset(("panda_leftfinger", "panda_rightfinger")) not in adj
    assert frozenset(("panda_link5", "panda_hand")) not in adj
    assert len(adj) == 10


def test_three_link_report_classifies_and_finds() -> None:
    _, r = three_link_report(samples=4000, seed=3)
    assert r.samples == 4000 and r.source == "sampled"
    by = {frozenset((p.frame_a, p.frame_b)): p for p in r.pairs}
    # masked adjacent pair: not sampled
    p = by[frozenset(("base_link", "link1"))]
    assert p.adjacent and p.masked and not p.sampled and p.hits is None
    assert p.classification == "adjacent" and p.recommendation == "ignore"
    # rates are consistent with the counts, never-pairs carry the bound
    for p in r.pairs:
        if p.sampled:
            assert p.rate == p.hits / 4000
        if p.hits == 0:
            assert p.classification in ("never", "adjacent", "default")
            assert p.rate_upper_95 == pytest.approx(never_upper_bound(4000))
    # link3/tool (fixed joint, spheres overlapping by construction) collide at default and
    # always; adjacent wins in the classification, and an unmasked always-colliding pair is
    # an error finding
    p = by[frozenset(("link3", "tool"))]
    assert p.adjacent and not p.masked and p.hits == 4000
    rules = [d.rule for d in r.diagnostics]
    assert "report-always-colliding" in rules
    assert "report-default-colliding" in rules
    assert rules.count("report-unknown-mask-frame") == 1
    unknown = next(d for d in r.diagnostics if d.rule == "report-unknown-mask-frame")
    assert "no_such_frame" in unknown.message and unknown.line is not None
    assert "sphere-frame-unknown" in rules
    assert not r.default_ok
    assert {frozenset((c.frame_a, c.frame_b)) for c in r.default_contacts} >= {
        frozenset(("link3", "tool"))
    }


def test_mask_hides_collision_and_recommended_mask(tmp_path: Path) -> None:
    text = THREE_LINK_XRDF.replace("base_link: [link1]", "base_link: [link1, link3]")
    xrdf = parse_xrdf(text, "masked.xrdf")
    r = self_collision_report(load_urdf(THREE_LINK), xrdf, samples=4000, seed=1)
    p = r.pair("link3", "base_link")
    assert p.masked and not p.adjacent and p.classification == "sometimes"
    assert p.hits is not None and 0 < p.hits < 4000
    hides = [d for d in r.diagnostics if d.rule == "report-mask-hides-collision"]
    assert len(hides) == 1 and "'link3'" in hides[0].message
    assert hides[0].key_path == "self_collision.ignore.base_link[1]"
    assert ("base_link", "link3") in r.mask_change.removed
    assert r.mask_change.dropped_unknown == ("no_such_frame",)
    new = recommended_xrdf(xrdf, r)
    assert new.self_collision is not None
    assert not new.self_collision.is_ignored("base_link", "link3")
    for q in r.pairs:
        assert new.self_collision.is_ignored(q.frame_a, q.frame_b) == (q.recommendation != "check")
    # canonical and loadable
    out = tmp_path / "new.xrdf"
    out.write_text(dump_xrdf(new))
    assert load_xrdf(out) == new


def test_a_robot_with_spheres_on_fewer_than_two_frames_is_said_to_be_unchecked() -> None:
    """An XRDF converted with --allow-missing-meshes from a URDF away from its meshes has
    spheres on one frame, or none at all: the report found nothing because it checked
    nothing, and says so (a warning for one frame, an error for none)."""
    one_frame = THREE_LINK_XRDF[: THREE_LINK_XRDF.index("      link1:")]
    none = one_frame[: one_frame.index("    spheres:")] + "    spheres: {}\n"
    for text, rule, severity in (
        (one_frame, "report-nothing-checked", "WARNING"),
        (none, "report-no-spheres", "ERROR"),
    ):
        xrdf = parse_xrdf(text, "x.xrdf")
        r = self_collision_report(load_urdf(THREE_LINK), xrdf, samples=100, seed=1)
        assert len(r.pairs) == 0
        said = {d.rule for d in r.diagnostics} & {"report-nothing-checked", "report-no-spheres"}
        assert said == {rule}
        (found,) = [d for d in r.diagnostics if d.rule == rule]
        assert found.severity.name == severity
        assert found.key_path == "self_collision.geometry" and found.line == 11
    r = self_collision_report(load_urdf(THREE_LINK), parse_xrdf(THREE_LINK_XRDF), samples=100)
    assert "report-nothing-checked" not in {d.rule for d in r.diagnostics}


def test_a_robot_with_world_collision_only_is_not_said_to_have_no_sphere() -> None:
    """cuMotion's two_link_arm.xrdf has world-collision spheres and no self_collision section
    (here a 1.0 file with collision only): the report checks nothing, and said 'the XRDF holds
    no collision sphere' and to fit some."""
    text = THREE_LINK_XRDF[: THREE_LINK_XRDF.index("self_collision:")]
    text += THREE_LINK_XRDF[THREE_LINK_XRDF.index("geometry:\n") :]
    xrdf = parse_xrdf(text, "x.xrdf")
    assert xrdf.self_collision is None and xrdf.world_collision is not None
    n_world = sum(len(s) for s in xrdf.world_collision_spheres().values())
    r = self_collision_report(load_urdf(THREE_LINK), xrdf, samples=100, seed=1)
    (found,) = [d for d in r.diagnostics if d.rule == "report-no-spheres"]
    assert f"no self_collision section: its {n_world} world-collision spheres" in found.message
    assert "fit spheres" not in found.message and found.key_path == "collision"
    assert found.line is not None


def test_trajectory_check_names_colliding_configurations(tmp_path: Path) -> None:
    xrdf = parse_xrdf(THREE_LINK_XRDF, "three_link.xrdf")
    urdf = load_urdf(THREE_LINK)
    base = self_collision_report(urdf, xrdf, samples=2000, seed=0)
    assert base.trajectory is None
    rng = np.random.default_rng(0)
    q = rng.uniform([-2, -3, 0.05], [2, 3, 0.4], size=(300, 3))
    r = self_collision_report(urdf, xrdf, configs=q, chunk=64)
    assert r.source == "configs" and r.samples == 300
    assert r.trajectory is not None
    # link3/tool always collide (unmasked), so every configuration is listed
    assert [h.index for h in r.trajectory] == list(range(300))
    assert all(
        any({c.frame_a, c.frame_b} == {"link3", "tool"} for c in h.contacts) for h in r.trajectory
    )
    # always-colliding pairs masked: exactly the configurations with another contact remain
    fixed = parse_xrdf(
        THREE_LINK_XRDF.replace(
            "link3: [finger, no_such_frame]",
            "link3: [finger, tool]\n    link1: [link2]\n    finger: [tool]",
        ),
        "x.xrdf",
    )
    r2 = self_collision_report(urdf, fixed, configs=q, chunk=64)
    from xrdf_tools.robot.kinematics import build_kinematic_model, full_configuration
    from xrdf_tools.selfcollision.collision import colliding_frame_pairs

    kin, _ = build_kinematic_model(urdf, fixed)
    full = full_configuration(kin, ["joint1", "joint2", "joint3"], q)
    expect = [i for i in range(300) if colliding_frame_pairs(kin, fixed, full[i])]
    assert r2.trajectory is not None
    assert [h.index for h in r2.trajectory] == expect
    assert 0 < len(expect) < 300


def test_cspace_configs_from_npy_and_csv_with_header(tmp_path: Path) -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.selfcollision.configurations import load_cspace_configurations
    from xrdf_tools.util.errors import SourceError

    urdf, xrdf = load_urdf(THREE_LINK), parse_xrdf(THREE_LINK_XRDF)
    kin, _ = build_kinematic_model(urdf, xrdf)
    names = list(xrdf.cspace.joint_names) if xrdf.cspace else []
    q = np.array([[0.1, 0.2, 0.03], [0.4, 0.5, 0.06]])
    np.save(tmp_path / "q.npy", q)
    np.testing.assert_array_equal(load_cspace_configurations(tmp_path / "q.npy", kin, xrdf), q)
    header = [names[2], names[0], names[1]]
    (tmp_path / "q.csv").write_text(
        ",".join(header) + "\n" + "\n".join(",".join(str(v) for v in r[[2, 0, 1]]) for r in q)
    )
    np.testing.assert_array_equal(load_cspace_configurations(tmp_path / "q.csv", kin, xrdf), q)
    (tmp_path / "short.csv").write_text("0.1,0.2\n")
    with pytest.raises(SourceError, match="has 2 values"):
        load_cspace_configurations(tmp_path / "short.csv", kin, xrdf)
    (tmp_path / "bad.csv").write_text(f"{names[0]},nope,{names[2]}\n1,2,3\n")
    with pytest.raises(SourceError, match="nope"):
        load_cspace_configurations(tmp_path / "bad.csv", kin, xrdf)


@pytest.mark.parametrize(
    ("name", "content", "line"),
    [
        ("none.csv", "", 1),
        ("header.csv", "\njoint1 joint2 joint3\n", 2),
        ("comments.txt", "# nothing yet\n\n", 1),
        ("none.yaml", "[]\n", 1),
        ("none.npy", None, None),  # binary: no line
    ],
)
def test_a_configurations_file_without_a_row_is_an_input_error(
    runner: CliRunner, tmp_path: Path, name: str, content: str | None, line: int | None
) -> None:
    """No configuration checked would classify every pair as never colliding (and
    ``--write-mask`` would ignore them all): a file without a row is refused."""
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.selfcollision.configurations import load_configurations
    from xrdf_tools.util.errors import SourceError

    configs = tmp_path / name
    if content is None:
        np.save(configs, np.zeros((0, 3)))
    else:
        configs.write_text(content)
    urdf, xrdf = load_urdf(THREE_LINK), parse_xrdf(THREE_LINK_XRDF)
    kin, _ = build_kinematic_model(urdf, xrdf)
    with pytest.raises(SourceError, match="holds no configuration") as exc:
        load_configurations(configs, kin, xrdf)
    assert exc.value.line == line
    xfile = tmp_path / "r.xrdf"
    xfile.write_text(THREE_LINK_XRDF)
    mask = tmp_path / "masked.xrdf"
    args = [str(xfile), "--urdf", str(THREE_LINK), "--configs", str(configs)]
    r = runner.invoke(app, ["report", *args, "--write-mask", str(mask)])
    assert r.exit_code == 2 and not mask.exists()


def test_renderers_agree_on_content() -> None:
    _, r = three_link_report(samples=1000)
    text, md, page = render_text(r), render_markdown(r), render_html(r)
    for p in r.pairs:
        assert p.frame_a in text and p.frame_a in md and p.frame_a in page
    assert "report-always-colliding" in text and "report-always-colliding" in md
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    d = report_to_dict(r)
    assert d["samples"] == 1000 and len(d["pairs"]) == len(r.pairs)
    json.dumps(d, allow_nan=False)  # strict JSON: no NaN or Infinity


def test_markdown_shows_names_as_text(tmp_path: Path) -> None:
    """A link name holding a table separator, a line break or HTML stays one cell of one row,
    shown as written (and no markup) where the Markdown is rendered."""
    name = "<img src=x onerror=alert(1)> a|b\nc"
    attr = name.replace("<", "&lt;").replace(">", "&gt;").replace("\n", "&#10;")
    urdf = tmp_path / "odd.urdf"
    urdf.write_text(THREE_LINK.read_text().replace('"link2"', f'"{attr}"'))
    x = parse_xrdf(THREE_LINK_XRDF.replace("link2", "placeholder"), "odd.xrdf")
    doc = dump_xrdf(x).replace("placeholder", json.dumps(name))
    r = self_collision_report(load_urdf(urdf), parse_xrdf(doc, "odd.xrdf"), samples=50)
    assert name in r.sphere_counts
    md = render_markdown(r)
    prose = [line for line in md.splitlines() if not line.startswith("    ")]  # code blocks: as is
    assert not any("<img" in line for line in prose)
    assert "&lt;img src=x onerror=alert(1)&gt; a\\|b c" in md
    header = next(line for line in md.splitlines() if line.startswith("| frame A"))
    cells = header.count(" | ")
    rows = [line for line in md.splitlines() if line.startswith("| ") and "&lt;img" in line]
    assert rows and all(row.replace("\\|", "").count(" | ") in (1, cells) for row in rows)


def _validate(doc: object) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(doc, json.loads(SCHEMA.read_text()))


def test_cli_json_validates_against_schema_panda(runner: CliRunner, tmp_path: Path) -> None:
    urdf = robot_urdf("panda")
    out = tmp_path / "r.json"
    res = runner.invoke(
        app,
        [
            "report",
            str(PANDA_XRDF),
            "--urdf",
            str(urdf),
            "-n",
            "20000",
            "-f",
            "json",
            "-o",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output  # cuRobo's mask has only warnings
    doc = json.loads(out.read_text())
    _validate(doc)
    assert doc["samples"] == 20000 and doc["default_ok"] is True
    hides = {tuple(sorted(p[:2])) for p in doc["mask_change"]["removed"]}
    assert ("panda_hand", "panda_link5") in hides
    assert any(d["rule"] == "report-mask-hides-collision" for d in doc["diagnostics"])


def test_cli_trajectory_exit_code_and_schema(runner: CliRunner, tmp_path: Path) -> None:
    xrdf_path = tmp_path / "three.xrdf"
    xrdf_path.write_text(THREE_LINK_XRDF)
    q = tmp_path / "traj.csv"
    q.write_text("joint1,joint2,joint3\n0,0,0.1\n1.5,2.5,0.3\n")
    res = runner.invoke(
        app,
        ["report", str(xrdf_path), "--urdf", str(THREE_LINK), "--configs", str(q), "-f", "json"],
    )
    assert res.exit_code == 1
    doc = json.loads(res.stdout)
    _validate(doc)
    assert [h["index"] for h in doc["trajectory"]] == [0, 1]


def test_cli_write_mask_plot_and_refusals(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "ur10e.masked.xrdf"
    png = tmp_path / "m.png"
    args = ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "5000"]
    res = runner.invoke(app, [*args, "--write-mask", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "recommended ignore list" in res.stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    new = load_xrdf(out)
    assert new.self_collision is not None
    assert dump_xrdf(new) == out.read_text()  # canonical
    # refuses to overwrite an input, and bad input is a one-line error with exit 2
    res = runner.invoke(app, [*args, "--write-mask", str(UR10E_XRDF)])
    assert res.exit_code == 2 and "refusing to overwrite" in res.output
    res = runner.invoke(app, ["report", str(UR10E_XRDF), "--urdf", str(tmp_path / "nope.urdf")])
    assert res.exit_code == 2 and "Traceback" not in res.output
    res = runner.invoke(app, [*args, "--configs", str(tmp_path / "nope.npy")])
    assert res.exit_code == 2 and "not found" in res.output


def test_halton_and_uniform_agree_roughly() -> None:
    _, u = three_link_report(samples=4000, sampler="uniform", seed=1)
    _, h = three_link_report(samples=4000, sampler="halton", seed=1)
    for pu, ph in zip(u.pairs, h.pairs, strict=True):
        if pu.rate is not None and ph.rate is not None:
            assert math.isclose(pu.rate, ph.rate, abs_tol=0.05)


def test_jobs_give_the_same_report(runner: CliRunner, monkeypatch: pytest.MonkeyPatch) -> None:
    import xrdf_tools.selfcollision.engine.jobs as engine  # where count_sampled reads the threshold

    monkeypatch.setattr(engine, "MIN_SAMPLES_PER_JOB", 1000)  # two workers on a small sample
    _, one = three_link_report(samples=6000, seed=2, chunk=1000)
    _, two = three_link_report(samples=6000, seed=2, chunk=1000, jobs=2)
    d1, d2 = report_to_dict(one), report_to_dict(two)
    for d in (d1, d2):
        d.pop("elapsed_s", None)
        d.pop("configs_per_s", None)
    assert d1 == d2
    # the CLI takes --jobs
    res = runner.invoke(
        app,
        ["report", str(PANDA_XRDF), "--urdf", str(robot_urdf("panda")), "-n", "3000", "-j", "2"],
    )
    assert res.exit_code == 0, res.output


def test_the_report_does_not_depend_on_the_chunks_and_reports_progress_within_one() -> None:
    """The Panda (more than ten body pairs): 20,000 samples in one chunk, in chunks of 4,096
    and of 700 give the same report; in one chunk, progress still comes every tenth."""
    xrdf, urdf = load_xrdf(PANDA_XRDF), load_urdf(robot_urdf("panda"))
    reports = []
    for chunk in (65536, 4096, 700):
        calls: list[int] = []
        r = self_collision_report(
            urdf,
            xrdf,
            samples=20000,
            seed=3,
            chunk=chunk,
            progress=lambda d, n, seen=calls: seen.append(d),
        )
        d = report_to_dict(r)
        d.pop("elapsed_s", None)
        d.pop("configs_per_s", None)
        reports.append(d)
        assert calls == sorted(calls) and calls[-1] == 20000
        if chunk == 65536:
            assert len(calls) == 10 and calls[0] <= 2000
    assert reports[0] == reports[1] == reports[2]
    assert any(p["min_clearance_is_bound"] for p in reports[0]["pairs"])  # bounds agree too


def test_joints_on_path_counts_the_joints_that_move_a_pair() -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model

    urdf = load_urdf(THREE_LINK)
    kin, _ = build_kinematic_model(urdf, parse_xrdf(THREE_LINK_XRDF, "t.xrdf"))
    # base_link -> joint1 -> link1 -> joint2 -> link2 -> joint3 -> link3 -> tool (fixed)
    assert kin.joints_on_path("base_link", "link1") == ("joint1",)
    assert kin.joints_on_path("link1", "tool") == ("joint2", "joint3")
    assert kin.joints_on_path("link3", "tool") == ()
    # the finger mimics joint1: it moves with joint1 (its master), not on its own
    assert "joint1" in kin.joints_on_path("base_link", "finger")
    _, r = three_link_report(samples=500)
    by_pair = {frozenset((p.frame_a, p.frame_b)): p.joints_on_path for p in r.pairs}
    assert by_pair[frozenset(("link1", "tool"))] == 2
    assert report_to_dict(r)["pairs"][0]["joints_on_path"] >= 0


def test_report_views_filter_what_is_shown_but_not_the_json(tmp_path: Path) -> None:
    from xrdf_tools.report.render import ReportView

    _, r = three_link_report(samples=2000)
    full = render_text(r)
    assert any(line.startswith("frame A") and " joints " in line for line in full.splitlines())
    rated = [p for p in r.pairs if p.rate]
    threshold = max(p.rate for p in rated)  # type: ignore[type-var]
    only_top = render_text(r, ReportView(min_rate=threshold))
    assert "below --min-rate not shown" in only_top
    kept = [p for p in r.pairs if p.rate is not None and p.rate >= threshold]
    assert len(kept) >= 1 and f"({len(r.pairs) - len(kept)} pair(s)" in only_top
    findings = render_text(r, ReportView(only="findings"))
    assert "frame A" not in findings and "findings" in findings
    pairs = render_text(r, ReportView(only="pairs"))
    assert "frame A" in pairs and "findings:" not in pairs
    assert len(report_to_dict(r)["pairs"]) == len(r.pairs)  # JSON keeps everything


def test_moveit_default_pose_is_zero_within_limits_else_mid_range() -> None:
    from xrdf_tools.robot.kinematics import build_kinematic_model, moveit_default_configuration

    kin, _ = build_kinematic_model(load_urdf(THREE_LINK), parse_xrdf(THREE_LINK_XRDF, "t.xrdf"))
    q = dict(zip(kin.actuated_joints, moveit_default_configuration(kin), strict=True))
    # joint3 is prismatic with limits [0.05, 0.4]: zero is outside, so mid-range
    assert q["joint1"] == 0.0 and q["joint3"] == pytest.approx(0.225)
    _, r = three_link_report(samples=200, moveit=True)
    assert r.default_configuration["joint3"] == pytest.approx(0.225)


@pytest.mark.slow
def test_coverage_comes_from_the_sphere_tools_with_their_diagnostics() -> None:
    from xrdf_tools.spheres import CoverageSummary

    _, r = three_link_report(samples=200, coverage=True)
    assert isinstance(r.coverage, CoverageSummary)  # one class, no bridge
    per = r.coverage.per_frame
    assert set(per) >= {"base_link", "link1", "link2", "link3"}
    assert all(0.0 <= m["coverage"] <= 1.0 for m in per.values())
    doc = report_to_dict(r)["coverage"]
    assert doc["per_frame"] == per and "coverage" in doc["overall"]
    assert "sphere coverage:" in render_text(r)


def test_every_report_format_is_one_renderer_of_the_report_or_of_its_findings() -> None:
    from xrdf_tools.cli.commands.plain import OutputFormat
    from xrdf_tools.cli.commands.report import ReportFormat
    from xrdf_tools.report.render import RENDERERS

    findings_only = {f.value for f in ReportFormat} - set(RENDERERS)
    assert findings_only == {"github", "sarif"} <= {f.value for f in OutputFormat}
    assert set(RENDERERS) < {f.value for f in ReportFormat}


def test_a_long_pair_table_ends_with_how_to_see_what_matters(tmp_path: Path) -> None:
    """A report of a big robot scrolled its whole pair table past (TIAGo's arm: 1,830
    lines) and ended without saying how to see less; past about a screen of pairs the text
    ends with the options that do. A short table (the UR10e) and a filtered one do not."""
    from tests.many_frames import chain_robot

    urdf_text, xrdf_text = chain_robot(12)  # 13 frames, 78 frame pairs
    urdf, xrdf = tmp_path / "chain.urdf", tmp_path / "chain.xrdf"
    urdf.write_text(urdf_text)
    xrdf.write_text(xrdf_text)
    runner = CliRunner()
    long = runner.invoke(app, ["report", str(xrdf), "--urdf", str(urdf), "-n", "200", "-q"])
    assert long.exit_code in (0, 1), long.output
    last = long.stdout.rstrip().splitlines()[-1]
    assert last.startswith("(78 frame pairs in the table above: --only findings"), last
    assert "--min-rate 0.001" in last
    # spheres 10 times as big: every pair collides, and --min-rate 0.5 still lists 72 pairs;
    # the hint then names a higher rate, not the lower one that shows more
    xrdf.write_text(xrdf_text.replace("radius: 0.02}", "radius: 0.2}"))
    args = ["report", str(xrdf), "--urdf", str(urdf), "-n", "200", "-q", "--min-rate", "0.5"]
    filtered = runner.invoke(app, args)
    last = filtered.stdout.rstrip().splitlines()[-1]
    assert last.startswith("(72 frame pairs in the table above: --only findings"), last
    assert "a --min-rate above 0.5 fewer pairs" in last and "0.001" not in last
    xrdf.write_text(xrdf_text)
    for args in (
        [str(xrdf), "--urdf", str(urdf), "--min-rate", "0.5"],
        [str(xrdf), "--urdf", str(urdf), "--only", "findings"],
        [str(UR10E_XRDF), "--urdf", str(UR10E_URDF)],
    ):
        short = runner.invoke(app, ["report", *args, "-n", "200", "-q"])
        assert short.exit_code in (0, 1), short.output
        assert "in the table above" not in short.stdout
