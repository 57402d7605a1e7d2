"""The light default install: what works without the extras, and the one-line message of a
command that needs one (the extras' packages hidden from a subprocess)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.paths import FIXTURES, UR10E_URDF, UR10E_XRDF

#: every package of the fit and viz extras
HIDDEN = ("yourdfpy", "trimesh", "scipy", "manifold3d", "rtree", "matplotlib", "rerun", "mcap")


def _run_without_extras(argv: list[str]) -> subprocess.CompletedProcess[str]:
    code = (
        "import sys\n"
        f"for name in {HIDDEN!r}:\n"
        "    sys.modules[name] = None  # import fails as if not installed\n"
        "from xrdf_tools.cli import main\n"
        f"sys.argv = ['xrdf', *{argv!r}]\n"
        "main()\n"
    )
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize(
    ("argv", "extra"),
    [
        (["spheres", str(UR10E_URDF), "-o", "-"], "fit"),
        (["convert", str(UR10E_URDF), "--fit-spheres", "-o", "-"], "fit"),
        (["viz", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "--png", "x.png"], "viz"),
        (
            ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "50", "--plot", "x.png"],
            "viz",
        ),
    ],
    ids=["spheres", "convert-fit", "viz-png", "report-plot"],
)
def test_a_command_that_needs_an_extra_names_it_in_one_line(argv: list[str], extra: str) -> None:
    done = _run_without_extras(argv)
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert f"'{extra}' extra" in lines[0] and f'pip install "xrdf-tools[{extra}]"' in lines[0]


@pytest.mark.parametrize(
    "argv",
    [
        ["report", str(UR10E_XRDF), "--urdf", str(UR10E_URDF), "-n", "200", "-q"],
        ["convert", str(UR10E_URDF), "-q", "-o", "-"],
        ["lint", str(FIXTURES / "panda" / "panda.xrdf")],
        ["diff", str(UR10E_XRDF), str(UR10E_XRDF)],
    ],
    ids=["report", "convert", "lint", "diff"],
)
def test_the_default_install_runs_the_commands_that_read_no_geometry(argv: list[str]) -> None:
    done = _run_without_extras(argv)
    assert done.returncode in (0, 1), done.stderr
    assert "Traceback" not in done.stderr and "extra" not in done.stderr
