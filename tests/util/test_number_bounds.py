"""Every number read is bounded once, where it is read, with the same limits for every command
(:mod:`xrdf_tools.util.numbers`); values read differently by a reader's YAML library."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app
from xrdf_tools.util.numbers import MAX_LENGTH, MAX_NUMBER, bound_problem, within

ARM = FIXTURES / "lint" / "sphere-outside-geometry"


def _cli(runner: CliRunner, *args: str) -> tuple[int, str]:
    res = runner.invoke(app, list(args))
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        raise AssertionError(f"traceback: {res.exception!r}\n{res.output}") from res.exception
    return res.exit_code, res.output


def _replace(src: Path, dest: Path, old: str, new: str) -> Path:
    text = src.read_text(encoding="utf-8")
    assert old in text, old
    dest.write_text(text.replace(old, new, 1), encoding="utf-8")
    return dest


def test_within_is_exact_for_any_value() -> None:
    assert within(MAX_NUMBER) and not within(MAX_NUMBER * 1.0000001)
    assert within(-MAX_LENGTH, MAX_LENGTH) and not within(MAX_LENGTH + 1, MAX_LENGTH)
    assert not within(math.nan) and not within(math.inf) and not within(10**400)
    assert bound_problem(10**400) == "is about 1e400; numbers must be finite and within ±1e+12"
    assert bound_problem(1e308, metres=True) == (
        "is 1e+308; lengths must be finite and within ±1e+06 m"
    )


@pytest.mark.parametrize("value", ["1e308", "9223372036854775808", "1e7"])
@pytest.mark.parametrize("key", ["radius", "buffer_distance"])
def test_lint_and_report_refuse_the_same_lengths(
    runner: CliRunner, tmp_path: Path, key: str, value: str
) -> None:
    """One bound for every command: what report refuses, lint reports (it passed them)."""
    old = "radius: 0.1\n" if key == "radius" else "buffer_distance: 0.0"
    text = (ARM / "pass.xrdf").read_text()
    if key == "buffer_distance" and old not in text:
        text = text.replace("world_collision:\n", "world_collision:\n  buffer_distance: 0.0\n", 1)
    x = tmp_path / "big.xrdf"
    x.write_text(text.replace(old, old.replace(old.split(": ")[1].strip(), value), 1))
    (tmp_path / "arm.urdf").write_text((ARM / "arm.urdf").read_text())
    code, out = _cli(runner, "report", str(x), "--urdf", str(tmp_path / "arm.urdf"), "-n", "10")
    assert code == 2 and "lengths must be finite and within ±1e+06 m" in out, out
    code, out = _cli(runner, "lint", str(x), "--urdf", str(tmp_path / "arm.urdf"))
    assert code == 1 and "internal-error" not in out, out
    assert "error wrong-type" in out and "lengths must be finite and within ±1e+06 m" in out, out


def test_a_huge_sphere_centre_is_a_finding_not_a_crash(runner: CliRunner, tmp_path: Path) -> None:
    x = _replace(
        ARM / "pass.xrdf",
        tmp_path / "c.xrdf",
        "center: [0.1, 0.0, 0.0]",
        "center: [1e308, 0.0, 0.0]",
    )
    (tmp_path / "arm.urdf").write_text((ARM / "arm.urdf").read_text())
    code, out = _cli(runner, "lint", str(x), "--urdf", str(tmp_path / "arm.urdf"))
    assert code == 1 and "internal-error" not in out and "center[0] is 1e+308" in out, out


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('effort="10" velocity="2"', 'effort="10" velocity="2e308"', "velocity='2e308': numbers"),
        ('origin xyz="0 0 0.1"', 'origin xyz="0 0 1e308"', "xyz='0 0 1e308': lengths must be"),
        ('<box size="0.2 0.2 0.1"/>', '<box size="0.2 0.2 1e7"/>', "size='0.2 0.2 1e7': lengths"),
    ],
)
def test_urdf_numbers_past_the_bounds_are_input_errors(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    """±1e308 limits overflowed the sampler (report, --certify, convert --fit-spheres)."""
    urdf = _replace(ARM / "arm.urdf", tmp_path / "arm.urdf", old, new)
    x = ARM / "pass.xrdf"
    for args in (
        ["report", str(x), "--urdf", str(urdf), "-n", "10"],
        ["report", str(x), "--urdf", str(urdf), "-n", "10", "--certify"],
        ["convert", str(urdf), "--fit-spheres", "-n", "10"],
    ):
        code, out = _cli(runner, *args)
        assert code == 2 and message in out and f"{urdf}:" in out, (args, out)


def test_revolute_limits_of_1e308_turn_freely_and_overflow_nothing(
    runner: CliRunner, tmp_path: Path
) -> None:
    """±1e308 limits overflowed the sampler; beyond ±1e12 a revolute limit bounds nothing:
    the joint is read as continuous (a located warning) and every command samples it."""
    urdf = _replace(
        ARM / "arm.urdf",
        tmp_path / "arm.urdf",
        'lower="-2" upper="2"',
        'lower="-1e308" upper="1e308"',
    )
    x = ARM / "pass.xrdf"
    for args in (
        ["report", str(x), "--urdf", str(urdf), "-n", "10"],
        ["report", str(x), "--urdf", str(urdf), "-n", "10", "--certify"],
        ["convert", str(urdf), "--fit-spheres", "-n", "10", "--allow-missing-meshes"],
    ):
        code, out = _cli(runner, *args)
        assert code in (0, 1) and "Traceback" not in out, (args, out)
        assert f"{urdf}:" in out and "urdf-limit-unbounded" in out, (args, out)
        assert "lower='-1e308' upper='1e308'" in out, (args, out)


def test_a_robot_without_links_says_so(runner: CliRunner, tmp_path: Path) -> None:
    urdf = tmp_path / "empty.urdf"
    urdf.write_text('<robot name="r"></robot>\n')
    code, out = _cli(runner, "convert", str(urdf))
    assert code == 2 and "has no <link>" in out and "cycle" not in out, out


def test_a_nan_mesh_vertex_is_reported_not_dropped(runner: CliRunner, tmp_path: Path) -> None:
    """trimesh drops a NaN vertex and its faces when it processes a mesh: the link would be
    fitted to the rest, silently."""
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box((0.05, 0.05, 0.05))
    vertices = box.vertices.copy()
    vertices[0, 0] = np.nan
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "camera.stl").write_bytes(
        trimesh.Trimesh(vertices, box.faces, process=False).export(file_type="stl")
    )
    (tmp_path / "arm.urdf").write_text((ARM / "arm.urdf").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, out = _cli(
            runner,
            "spheres",
            str(tmp_path / "arm.urdf"),
            "--links",
            "camera",
            "-o",
            str(tmp_path / "s.xrdf"),
        )
    assert "camera.stl: a vertex is not finite" in out, out


def test_a_null_robot_cfg_beside_kinematics_is_read(runner: CliRunner, tmp_path: Path) -> None:
    """``robot_cfg:`` (null) beside a top-level ``kinematics`` (cuRobo's other layout)."""
    src = (FIXTURES / "curobo_classic" / "ur10e_inline.yml").read_text()
    body = src[src.index("robot_cfg:\n") + len("robot_cfg:\n") :]
    dedented = "\n".join(ln[2:] if ln.startswith("  ") else ln for ln in body.splitlines())
    cfg = tmp_path / "c.yml"
    cfg.write_text("robot_cfg:\n" + dedented + "\n")
    code, out = _cli(
        runner, "convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(tmp_path / "o.xrdf")
    )
    assert code == 0 and "NoneType" not in out, out
    assert (tmp_path / "o.xrdf").is_file()


# --- values a reader's YAML library reads differently ------------------------------------------
def test_export_writes_numbers_every_yaml_reader_reads_alike(
    runner: CliRunner, tmp_path: Path
) -> None:
    """A value written ``017`` or ``1e-3`` in the XRDF is written so that PyYAML (YAML 1.1,
    cuRobo) and YAML 1.2 read the same number."""
    yaml = pytest.importorskip("yaml")
    from xrdf_tools.yaml.io import parse_yaml, to_python

    text = UR10E_XRDF.read_text()
    assert "acceleration_limits: [" in text and "shoulder_pan_joint: 0.0" in text
    text = text.replace("shoulder_pan_joint: 0.0", "shoulder_pan_joint: 1e-3", 1)
    x = tmp_path / "x.xrdf"
    x.write_text(text)
    out = tmp_path / "robot.yml"
    code, log = _cli(runner, "export", "curobo", str(x), "--urdf", str(UR10E_URDF), "-o", str(out))
    assert code == 0, log
    written = out.read_text()
    assert "[0.001, " in written
    assert to_python(parse_yaml(written, "robot.yml").root) == yaml.safe_load(written)
