"""cuRobo configurations convert cannot use: values of the wrong shape, numbers beyond float
range, an output that would overwrite the spheres file the configuration reads."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.cli_checks import CUROBO_CLASSIC, copy_replacing, run_cli
from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF
from xrdf_tools.cli import app


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("link_names: [tool0, flange]", "link_names: 5", "link_names must be a list of names"),
        (
            "    collision_link_names:\n",
            "    collision_link_names: 5\n    x:\n",
            "collision_link_names must be",
        ),
        (
            "upper_arm_link: [forearm_link, shoulder_link]",
            "upper_arm_link: 7",
            "self_collision_ignore.upper_arm_link must be",
        ),
        ("      joint_names:\n", "      joint_names: 3\n      x:\n", "cspace.joint_names must be"),
        ("  kinematics:\n", "  kinematics: 4\n  x:\n", "robot_cfg.kinematics must be a mapping"),
        (
            "link_names: [tool0, flange]",
            "link_names: [tool0, {a: b}]",
            "link_names[1] must be a name",
        ),
        ("link_names: [tool0, flange]", "? {a: 1}\n    : 1", "a mapping is used as a mapping key"),
    ],
)
def test_curobo_shape_errors(
    runner: CliRunner, tmp_path: Path, old: str, new: str, message: str
) -> None:
    cfg = copy_replacing(CUROBO_CLASSIC, tmp_path / "cfg.yml", old, new)
    (tmp_path / "spheres").mkdir()
    (tmp_path / "spheres" / "ur10e.yml").write_bytes(
        (CUROBO_CLASSIC.parent / "spheres" / "ur10e.yml").read_bytes()
    )
    code, out = run_cli(runner, "convert", str(UR10E_URDF), "--curobo", str(cfg))
    assert code == 2 and message in out and f"{cfg}:" in out, out


def test_a_curobo_sphere_beyond_float_range_is_reported(runner: CliRunner, tmp_path: Path) -> None:

    cfg = tmp_path / "ur10e.yml"
    text = (FIXTURES / "curobo_classic" / "ur10e_inline.yml").read_text()
    assert '"radius": 0.05' in text or "radius: 0.05" in text
    cfg.write_text(text.replace("0.05", "9" * 400, 1))
    code, out = run_cli(
        runner, "convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(tmp_path / "o")
    )
    assert code in (0, 2) and "Traceback" not in out, out


def test_convert_refuses_to_overwrite_the_spheres_file_its_config_reads(
    runner: CliRunner, tmp_path: Path
) -> None:
    import shutil

    cfg_dir = tmp_path / "cfg"
    shutil.copytree(FIXTURES / "curobo_classic", cfg_dir)
    spheres = cfg_dir / "spheres" / "ur10e.yml"
    before = spheres.read_bytes()
    code, out = run_cli(
        runner,
        "convert",
        str(UR10E_URDF),
        "--curobo",
        str(cfg_dir / "ur10e_classic.yml"),
        "-o",
        str(spheres),
    )
    assert code == 2 and "refusing to overwrite an input file" in out
    assert spheres.read_bytes() == before


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize(
    ("kind", "said"),
    [
        ("dir", "is a directory"),
        ("fifo", "is a FIFO (named pipe), not a regular file"),
        ("missing", "not found (looked in"),
    ],
)
def test_a_spheres_file_that_is_no_file_says_what_it_is(
    runner: CliRunner, tmp_path: Path, kind: str, said: str
) -> None:
    """A collision_spheres path naming a directory or a FIFO is not "not found": the error
    says what is there, at the configuration's line."""
    cfg = copy_replacing(
        CUROBO_CLASSIC,
        tmp_path / "cfg.yml",
        "collision_spheres: spheres/ur10e.yml",
        "collision_spheres: odd.yml",
    )
    if kind == "dir":
        (tmp_path / "odd.yml").mkdir()
    elif kind == "fifo":
        os.mkfifo(tmp_path / "odd.yml")
    code, out = run_cli(runner, "convert", str(UR10E_URDF), "--curobo", str(cfg))
    line = CUROBO_CLASSIC.read_text().split("collision_spheres: spheres/")[0].count("\n") + 1
    assert code == 2 and f"{cfg}:{line}: collision_spheres file 'odd.yml'" in out, out
    assert said in out, out


def test_convert_without_a_robot_takes_the_config_s_urdf_path(tmp_path: Path) -> None:
    """``xrdf convert --curobo cfg.yml`` after ``export curobo``: the robot is the config's
    ``urdf_path`` (beside the config), said, and the XRDF is the one given the robot (it
    stopped on Typer's "Missing argument"). No robot and no config, or a config whose
    ``urdf_path`` is no file beside it, is one located line, exit 2."""

    runner = CliRunner()
    cfg = tmp_path / "cfg" / "ur10e.yml"
    r = runner.invoke(
        app, ["export", "curobo", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-o", str(cfg)]
    )
    assert r.exit_code == 0, r.output
    given, taken = tmp_path / "given.xrdf", tmp_path / "taken.xrdf"
    r = runner.invoke(app, ["convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(given)])
    assert r.exit_code == 0, r.output
    r = runner.invoke(app, ["convert", "--curobo", str(cfg), "-o", str(taken)])
    assert r.exit_code == 0, r.output
    assert "(the config's urdf_path)" in r.stderr and "ur10e.urdf" in r.stderr
    assert taken.read_bytes() == given.read_bytes()
    r = runner.invoke(app, ["convert", "-o", str(taken)])
    assert r.exit_code == 2 and r.stderr.startswith("error: give the robot to convert")
    moved = tmp_path / "cfg" / "moved.yml"  # its urdf_path names a file that is not there
    moved.write_text(cfg.read_text().replace("ur10e.urdf", "gone.urdf"))
    r = runner.invoke(app, ["convert", "--curobo", str(moved), "-o", str(taken)])
    assert r.exit_code == 2 and len(r.stderr.strip().splitlines()) == 1
    assert f"{moved}:" in r.stderr and "no file beside it" in r.stderr


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("[a.urdf]", "has urdf_path a list, not a file name"),
        ("42", "has urdf_path 42, not a file name"),
        ("{a: 1}", "has urdf_path a mapping, not a file name"),
        ('"."', "names '.', a directory beside it"),
        ("a" * 5000, "no file beside it"),  # a name too long to look at: it was a traceback
    ],
)
def test_an_urdf_path_that_names_no_robot_says_what_it_is(
    tmp_path: Path, value: str, said: str
) -> None:
    cfg = tmp_path / "cfg.yml"
    cfg.write_text(f"robot_cfg:\n  kinematics:\n    urdf_path: {value}\n")
    code, out = run_cli(CliRunner(), "convert", "--curobo", str(cfg), "-o", str(tmp_path / "o"))
    assert code == 2 and f"{cfg}:3:5: no robot given, and the config" in out, out
    assert said in out and len(out.strip().splitlines()) == 1, out


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("- a\n- b\n", "is no cuRobo robot configuration"),
        ("robot_cfg: {}\n", "is no cuRobo robot configuration"),
        ((FIXTURES / "curobo_classic" / "ur10e_lula.yaml").read_text(), "is a Lula robot desc"),
    ],
)
def test_a_file_that_is_no_curobo_config_names_no_robot(
    tmp_path: Path, text: str, said: str
) -> None:
    cfg = tmp_path / "cfg.yml"
    cfg.write_text(text)
    code, out = run_cli(CliRunner(), "convert", "--curobo", str(cfg), "-o", str(tmp_path / "o"))
    assert code == 2 and said in out and "give ROBOT.urdf|xacro" in out, out


def test_a_spheres_file_name_too_long_to_look_at_is_not_found(tmp_path: Path) -> None:
    name = "a" * 5000  # the system refuses to look it up (ENAMETOOLONG): it was a traceback
    old = "collision_spheres: spheres/"
    cfg = copy_replacing(CUROBO_CLASSIC, tmp_path / "c.yml", old, f"collision_spheres: {name}/")
    code, out = run_cli(
        CliRunner(), "convert", str(UR10E_URDF), "--curobo", str(cfg), "-o", str(tmp_path / "o")
    )
    assert code == 2 and f"{cfg}:" in out and "not found" in out, out
