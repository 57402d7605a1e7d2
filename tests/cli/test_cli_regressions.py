"""Crashes found by the fuzz suite and tracebacks seen on bad input, kept as regression tests:
sorted diagnostics, a negative seed or protrusion, repeated and non-finite values in viz."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import MIMIC_URDF, MIMIC_XRDF, copy_replacing, run_cli
from tests.paths import UR10E_URDF, UR10E_XRDF
from xrdf_tools.diagnostics import Diagnostic, Severity


def test_planar_joint_in_viz_sorts_its_diagnostics(runner: CliRunner, tmp_path: Path) -> None:
    urdf = copy_replacing(
        UR10E_URDF,
        tmp_path / "planar.urdf",
        '<joint name="camera_mount_joint" type="fixed">',
        '<joint name="camera_mount_joint" type="planar">',
    )
    pytest.importorskip("mcap")
    out_file = str(tmp_path / "o.mcap")
    # the fixture's meshes are not bundled: their warnings sort with the joint's
    code, out = run_cli(
        runner,
        "viz",
        str(UR10E_XRDF),
        "--urdf",
        str(urdf),
        "--mcap",
        out_file,
        "--allow-missing-meshes",
    )
    assert code == 0 and "joint-held-fixed" in out and "mesh-not-loaded" in out


def test_diagnostics_with_and_without_a_line_sort() -> None:
    a = Diagnostic("f", None, None, "r", Severity.WARNING, "m")
    b = Diagnostic("f", 3, None, "r", Severity.WARNING, "m")
    assert sorted([b, a]) == [a, b]


@pytest.mark.parametrize("command", ["report", "viz"])
def test_negative_seed_is_a_usage_error(runner: CliRunner, tmp_path: Path, command: str) -> None:
    extra = ["--png", str(tmp_path / "o.png"), "-n", "2"] if command == "viz" else ["-n", "2"]
    code, out = run_cli(
        runner, command, str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--seed", "-1", *extra
    )
    assert code == 2 and "--seed" in out


def test_negative_seed_of_convert_is_a_usage_error(runner: CliRunner) -> None:
    """``convert --fit-spheres --seed -1`` was taken, then the sampler raised a traceback."""
    code, out = run_cli(
        runner, "convert", str(MIMIC_URDF), "--fit-spheres", "--seed", "-1", "-n", "2"
    )
    assert code == 2 and "--seed" in out


def test_negative_max_protrusion_is_a_usage_error(runner: CliRunner) -> None:
    """``spheres --max-protrusion -1`` fitted spheres covering nothing and exited 0."""
    code, out = run_cli(runner, "spheres", str(MIMIC_URDF), "--max-protrusion", "-1")
    assert code == 2 and "--max-protrusion" in out


# Crashes found by benchmarks/fuzz_cli.py (seed 0), kept as regression tests.
def test_fuzz_case_5907_repeated_cspace_joint_in_viz(runner: CliRunner, tmp_path: Path) -> None:
    x = copy_replacing(
        MIMIC_XRDF, tmp_path / "m.xrdf", "    - joint2\n", "    - joint2\n    - joint2\n"
    )
    code, out = run_cli(
        runner,
        "viz",
        str(x),
        "--urdf",
        str(MIMIC_URDF),
        "--png",
        str(tmp_path / "o.png"),
        "-n",
        "2",
    )
    assert code == 2 and "joint 'joint2' is listed twice" in out and f"{x}:" in out


def test_fuzz_case_9969_nan_default_position_in_viz_mcap(runner: CliRunner, tmp_path: Path) -> None:
    pytest.importorskip("mcap")
    x = copy_replacing(UR10E_XRDF, tmp_path / "n.xrdf", "elbow_joint: 1.9", "elbow_joint: .nan")
    code, out = run_cli(
        runner,
        "viz",
        str(x),
        "--urdf",
        str(UR10E_URDF),
        "--mcap",
        str(tmp_path / "o.mcap"),
        "-n",
        "2",
    )
    assert code == 2 and "is nan; numbers must be finite" in out
    assert not (tmp_path / "o.mcap").exists()


@pytest.mark.parametrize("value", ["9" * 400, "1e300", "-1e13"])
def test_fuzz_seed_641_case_227_a_joint_limit_no_float_holds(
    runner: CliRunner, tmp_path: Path, value: str
) -> None:
    """A max_acceleration of 400 digits (an int no float holds: OverflowError) or beyond
    ±1e12 is dropped with a located warning; the other joints' limits are kept."""
    from tests.paths import FIXTURES

    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        f"  shoulder_pan_joint: {{has_acceleration_limits: true, max_acceleration: {value}}}\n"
        "  shoulder_lift_joint: {has_acceleration_limits: true, max_acceleration: 5.0}\n"
    )
    out = tmp_path / "o.xrdf"
    code, text = run_cli(
        runner,
        "convert",
        str(UR10E_URDF),
        "--srdf",
        str(FIXTURES / "fuzz" / "ur10e.srdf"),
        "--joint-limits",
        str(limits),
        "-o",
        str(out),
    )
    assert code == 0, text
    assert f"{limits}:2:" in text and "'shoulder_pan_joint' max_acceleration is" in text, text
    assert "numbers must be finite and within ±1e+12; dropped" in text
    assert "Traceback" not in text
    from xrdf_tools.xrdf.io import load_xrdf

    cspace = load_xrdf(out).cspace
    assert cspace is not None
    accel = dict(zip(cspace.joint_names, cspace.acceleration_limits, strict=True))
    assert accel["shoulder_lift_joint"] == 5.0 and accel["shoulder_pan_joint"] != float(value)


@pytest.mark.parametrize(
    "args",
    [
        ("lint", str(MIMIC_XRDF)),  # the lint configuration is searched from there
        ("export", "curobo", str(MIMIC_XRDF), "--urdf", str(MIMIC_URDF)),  # paths relative to it
    ],
)
def test_a_removed_working_directory_is_one_line_exit_2(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    args: tuple[str, ...],
) -> None:
    from xrdf_tools import cli

    gone = tmp_path / "gone"
    gone.mkdir()
    monkeypatch.chdir(gone)
    gone.rmdir()
    monkeypatch.setattr("sys.argv", ["xrdf", *args])
    with pytest.raises(SystemExit) as exc:
        cli._run()
    err = capsys.readouterr().err
    assert exc.value.code == 2, err
    assert err.count("\n") == 1 and "current directory" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "args",
    [
        ("report", str(MIMIC_XRDF), "--urdf", str(MIMIC_URDF), "-n", "8", "--clearance-margin"),
        ("report", str(MIMIC_XRDF), "--urdf", str(MIMIC_URDF), "-n", "8", "--min-rate"),
        ("report", str(MIMIC_XRDF), "--urdf", str(MIMIC_URDF), "--certify", "--certify-budget"),
        ("spheres", str(MIMIC_URDF), "--links", "finger", "--max-protrusion"),
        ("spheres", str(MIMIC_URDF), "--links", "finger", "--target-coverage"),
        ("convert", str(MIMIC_URDF), "--acceleration"),
        ("convert", str(MIMIC_URDF), "--jerk"),
    ],
    ids=lambda a: a[-1],
)
@pytest.mark.parametrize("value", ["nan", "inf"])
def test_a_number_option_refuses_nan_and_inf(
    runner: CliRunner, args: tuple[str, ...], value: str
) -> None:
    """typer reads 'nan' as a float that passes every range check: with --clearance-margin nan
    the report saw no pair collide (every pair 'never'), --max-protrusion nan crashed the fit."""
    code, out = run_cli(runner, *args, value)
    said = (f"{value} is not a finite number", f"{value} is not in the range")  # inf > a max
    assert code == 2 and any(s in out for s in said), out


def test_a_huge_sphere_density_is_the_per_link_ceiling(runner: CliRunner) -> None:
    """--density 1e308 times a link volume overflows to inf (it raised OverflowError): the
    count is capped at the per-link ceiling instead."""
    from xrdf_tools.spheres.count_policy import MAX_PER_LINK

    args = ("spheres", str(MIMIC_URDF), "--links", "finger", "--seed", "1", "-q")
    code, huge = run_cli(runner, *args, "--density", "1e308")
    assert code == 0, huge
    code, most = run_cli(runner, *args, "--per-link", str(MAX_PER_LINK))
    assert code == 0 and huge == most


@pytest.mark.parametrize("uri", ["file://{dir}/a%00.stl", "package://pkg/a%00.stl"])
def test_a_mesh_uri_decoding_to_a_nul_byte_is_a_mesh_not_found(
    runner: CliRunner, tmp_path: Path, uri: str
) -> None:
    """``convert`` and ``spheres`` raised 'ValueError: embedded null byte' (a traceback) on a
    ``file://`` name with ``%00``: now the mesh cannot be found, said in one line."""
    mesh = uri.format(dir=tmp_path)
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"/><link name="tip"><collision><geometry>'
        f'<mesh filename="{mesh}"/></geometry></collision></link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    code, out = run_cli(runner, "convert", str(urdf), "-q", "-o", str(tmp_path / "r.xrdf"))
    assert code == 0 and "Traceback" not in out, out
    code, out = run_cli(runner, "spheres", str(urdf), "-q", "-o", str(tmp_path / "s.xrdf"))
    assert code == 2 and "Traceback" not in out, out
    assert "a path with a NUL byte (%00), which no file name holds" in out
    assert not (tmp_path / "s.xrdf").exists()


@pytest.mark.parametrize(
    "args",
    [
        ["expand", "{long}"],  # it was a traceback (ENAMETOOLONG from Path.is_file)
        ["lint", "{long}"],
        ["convert", "{long}", "-o", "{out}"],
        ["inspect", "{long}"],
        ["export", "curobo", str(UR10E_XRDF), "--urdf", "{long}", "-o", "{out}"],
    ],
    ids=lambda a: a[0],
)
def test_a_file_name_too_long_to_look_at_is_one_line(
    runner: CliRunner, tmp_path: Path, args: list[str]
) -> None:
    long = str(tmp_path / ("a" * 5000))
    given = [a.format(long=long, out=tmp_path / "o") for a in args]
    code, out = run_cli(runner, *given)
    assert code == 2 and out.startswith("error: ") and len(out.strip().splitlines()) == 1, out
