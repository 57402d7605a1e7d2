"""Memory linear in spheres per link, ceilings on spheres, frames and samples, progress."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES
from tests.robots import robot_urdf
from tests.selfcollision.test_collision import THREE_LINK, THREE_LINK_XRDF
from xrdf_tools.cli import app
from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
from xrdf_tools.robot.urdf_source import load_urdf
from xrdf_tools.selfcollision import collision
from xrdf_tools.selfcollision.collision import (
    SphereLimitError,
    build_sphere_set,
    contacts,
    frame_pair_clearances,
    sphere_world_centers,
)
from xrdf_tools.selfcollision.engine import CountEngine
from xrdf_tools.xrdf.io import parse_xrdf

N = 2000  # spheres on each of two links: 4 M sphere pairs between them


def _many(n: int) -> str:
    """The three-link XRDF with ``n`` spheres on link1 and on link2 (seeded positions)."""
    rng = np.random.default_rng(0)
    out = THREE_LINK_XRDF.split("      link1:\n")[0]
    for link in ("link1", "link2"):
        out += f"      {link}:\n"
        for c in rng.uniform(-0.05, 0.3, size=(n, 3)):
            out += f"        - {{center: [{c[0]:.4f}, {c[1]:.4f}, {c[2]:.4f}], radius: 0.01}}\n"
    return out


@pytest.fixture(scope="module")
def many():  # type: ignore[no-untyped-def]
    xrdf = parse_xrdf(_many(N), "many.xrdf")
    kin, _ = build_kinematic_model(load_urdf(THREE_LINK), xrdf)
    return kin, xrdf


def test_default_pose_check_memory_is_linear_in_spheres(many) -> None:  # type: ignore[no-untyped-def]
    kin, xrdf = many
    tracemalloc.start()
    spheres, _ = build_sphere_set(kin, xrdf, include_masked=True)
    c = sphere_world_centers(kin, spheres, default_configuration(kin, {}))
    clear = frame_pair_clearances(spheres, c)
    found = contacts(spheres, c)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert spheres.n_pairs > N * N  # one index array of them alone would take 32 MB
    assert peak < 16 * 2**20
    # the same answers as every sphere pair at once, on the frame pair link1/link2
    k = next(i for i, p in enumerate(spheres.frame_pair_names()) if set(p) == {"link1", "link2"})
    i, j, rs = spheres.frame_pair_sphere_pairs(k)
    d = np.linalg.norm(c[i] - c[j], axis=1) - rs
    assert clear[k] == d.min()
    hit = next(x for x in found if {x.frame_a, x.frame_b} == {"link1", "link2"})
    assert hit.n_sphere_pairs == int(np.count_nonzero(d < 0))


@pytest.mark.slow
def test_engine_count_memory_is_linear_in_spheres(many) -> None:  # type: ignore[no-untyped-def]
    kin, xrdf = many
    spheres, _ = build_sphere_set(kin, xrdf)
    q0 = default_configuration(kin, {})
    eng = CountEngine(kin, spheres, [0, 1], q0, margin=0.01)
    tracemalloc.start()
    eng.count(np.array([[0.0, 0.0], [0.5, -0.5], [1.0, 1.0]]))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 32 * 2**20  # the 4 M sphere pairs are evaluated in bounded blocks


def test_too_many_spheres_is_a_located_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(collision.spheres, "MAX_SPHERES", 100)
    xrdf = parse_xrdf(_many(60), "many.xrdf")
    kin, _ = build_kinematic_model(load_urdf(THREE_LINK), xrdf)
    with pytest.raises(SphereLimitError) as err:
        build_sphere_set(kin, xrdf)
    assert str(err.value).startswith("many.xrdf:")
    assert "at most 100" in str(err.value)


def test_report_and_lint_past_the_ceiling(
    runner: CliRunner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(collision.spheres, "MAX_SPHERE_FRAMES", 2)
    path = tmp_path / "many.xrdf"
    path.write_text(_many(5))
    res = runner.invoke(app, ["report", str(path), "--urdf", str(THREE_LINK), "-n", "10"])
    assert res.exit_code == 2, res.output
    assert f"{path}:" in res.output and "at most 2" in res.output
    assert "Traceback" not in res.output
    res = runner.invoke(app, ["lint", str(path), "--urdf", str(THREE_LINK)])
    assert "default pose not checked" in res.output
    assert "internal-error" not in res.output
    png = tmp_path / "many.png"
    res = runner.invoke(app, ["viz", str(path), "--urdf", str(THREE_LINK), "--png", str(png)])
    assert res.exit_code == 2, res.output
    assert f"{path}:" in res.output and "at most 2" in res.output and not png.exists()


@pytest.mark.slow
def test_viz_contacts_memory_is_linear_in_spheres(many) -> None:  # type: ignore[no-untyped-def]
    """The picture's colliding sphere pairs come per frame pair in blocks (4 M pairs)."""
    from xrdf_tools.viz.contacts import sphere_contacts

    kin, xrdf = many
    q = default_configuration(kin, {})[None, :]
    tracemalloc.start()
    found, _, _ = sphere_contacts(kin, xrdf, q, None, [])
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    pairs, frame_contacts = found[0]
    assert frame_contacts and len(pairs) >= sum(c.n_sphere_pairs for c in frame_contacts)
    assert peak < 32 * 2**20  # every sphere pair at once: 4 M x (hits, clearances, indices)


def test_samples_past_the_ceiling_are_refused(runner: CliRunner) -> None:
    res = runner.invoke(
        app,
        [
            "report",
            str(FIXTURES / "panda" / "panda.xrdf"),
            "--urdf",
            str(robot_urdf("panda")),
            "-n",
            "99999999999999999999999",
        ],
    )
    assert res.exit_code == 2, res.output
    assert "not in the range 1<=x<=10000000000" in res.output and "Traceback" not in res.output


def _three_link_report(tmp_path: Path, samples: int) -> list[str]:
    path = tmp_path / "three.xrdf"
    path.write_text(THREE_LINK_XRDF)
    return ["report", str(path), "--urdf", str(THREE_LINK), "-n", str(samples), "-j", "1"]


def test_report_progress_lines_with_verbose_off_a_terminal(
    runner: CliRunner, tmp_path: Path
) -> None:
    """CI has no terminal: with -v one line per 10 % of the samples, quiet otherwise."""
    args = _three_link_report(tmp_path, 50000)
    out = tmp_path / "r.txt"
    res = runner.invoke(app, [*args, "-v", "-o", str(out)])
    lines = [ln for ln in res.output.splitlines() if ln.startswith("sampling: ") and "%" in ln]
    assert [ln.split()[1] for ln in lines] == [str(p) for p in range(10, 101, 10)], res.output
    assert "(50,000/50,000)" in lines[-1]
    res = runner.invoke(app, [*args, "-o", str(out)])
    assert "%" not in res.output


def test_certify_progress_lines_with_verbose_off_a_terminal(
    runner: CliRunner, tmp_path: Path
) -> None:
    """--certify can take minutes on a big robot: with -v, lines follow the pairs decided."""
    args = _three_link_report(tmp_path, 2000)
    res = runner.invoke(app, [*args, "--certify", "-v", "-o", str(tmp_path / "r.txt")])
    assert res.exit_code in (0, 1) and "Traceback" not in res.output, res.output  # 1: findings
    lines = [ln for ln in res.output.splitlines() if ln.startswith("certify: ")]
    assert lines and lines[-1].startswith("certify: 100 % ("), res.output
    done, total = lines[-1].split("(")[1].split(")")[0].split("/")
    assert done == total and int(total) >= 1


def test_certify_memory_is_linear_in_spheres(many) -> None:  # type: ignore[no-untyped-def]
    """--certify visits a frame pair's sphere pairs in blocks: the 4 M pairs of link1/link2
    are never listed, for any number of boxes at once."""
    from xrdf_tools.selfcollision.certify import certify_pair

    kin, xrdf = many
    spheres, _ = build_sphere_set(kin, xrdf)
    q0 = default_configuration(kin, {})
    eng = CountEngine(kin, spheres, [0, 1], q0, margin=0.01)
    names = spheres.frame_names
    k = next(
        k
        for k in range(spheres.n_frame_pairs)
        if {names[spheres.frame_pair_a[k]], names[spheres.frame_pair_b[k]]} == {"link1", "link2"}
    )
    tracemalloc.start()
    cert = certify_pair(eng, k, max_boxes=2_000)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert cert.verdict in ("proven", "witness", "undecided")
    assert peak < 200 * 2**20  # one list of the pairs and a [64, 4 M] distance block: > 2 GB
