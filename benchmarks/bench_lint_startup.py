"""Start-up of ``xrdf lint FILE`` (no ``--urdf``) and of a short ``xrdf report`` (1,000 samples)
against yamllint on the same file.

Usage: ``python benchmarks/bench_lint_startup.py [--runs 21] [FILE]``

With example-robot-data installed, also ``xrdf report`` of franka (the Panda with cuRobo's 61
spheres, ``report_franka_ratio``). The commands run as fresh subprocesses of this
interpreter (``python -m xrdf_tools lint FILE``, ``python -m yamllint FILE``, ...),
alternately, so that all see the same machine load; a warm-up run of each comes first (it
also writes the compiled bytecode of this checkout, as an installed package has it). Prints
one JSON line: the median and minimum wall time of each in milliseconds, the median CPU time
(user + system, steadier than wall time on a busy machine) and the ratios to yamllint of the
medians (goals: lint at most 1, the report at most 3). The default file is the bundled
``fixtures/ur10e/ur10e.xrdf``. yamllint is in the ``dev`` extra.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
FIXTURE = REPO / "fixtures" / "ur10e" / "ur10e.xrdf"
REPORT_XRDF = FIXTURE
REPORT_URDF = REPO / "fixtures" / "ur10e" / "ur10e.urdf"
#: franka: cuRobo's 61 spheres on the example-robot-data Panda (when that package is installed)
FRANKA_XRDF = REPO / "fixtures" / "panda" / "panda.xrdf"
FRANKA_URDF = Path(
    "cmeel.prefix",
    "share",
    "example-robot-data",
    "robots",
    "panda_description",
    "urdf",
    "panda.urdf",
)


def franka_urdf() -> Path | None:
    import sysconfig

    for key in ("purelib", "platlib"):
        path = Path(sysconfig.get_paths()[key]) / FRANKA_URDF
        if path.is_file():
            return path
    return None


def timed_run(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds of one run of ``cmd`` (its output is discarded; findings are not
    failures)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(
        cmd, cwd=REPO, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return wall, cpu


def ms(seconds: float) -> float:
    return round(seconds * 1000, 1)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("file", nargs="?", type=Path, default=FIXTURE)
    ap.add_argument("--runs", type=int, default=21, help="timed runs of each command")
    args = ap.parse_args()
    args.file = args.file.resolve()
    env = dict(os.environ)
    # the warm-up writes the bytecode an installed package has: not compiling every module on
    # every run, as PYTHONDONTWRITEBYTECODE without a __pycache__ would
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    # the checkout this script belongs to, ahead of any installed copy (and the working
    # directory of the runs, which ``python -m`` puts first on the path)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    commands = {
        "xrdf": [sys.executable, "-m", "xrdf_tools", "lint", str(args.file)],
        "yamllint": [sys.executable, "-m", "yamllint", str(args.file)],
        "xrdf_report": [
            *(sys.executable, "-m", "xrdf_tools", "report", str(REPORT_XRDF)),
            *("--urdf", str(REPORT_URDF), "--samples", "1000", "-q"),
        ],
    }
    panda = franka_urdf()
    if panda is not None:
        commands["xrdf_report_franka"] = [
            *(sys.executable, "-m", "xrdf_tools", "report", str(FRANKA_XRDF)),
            *("--urdf", str(panda), "--samples", "1000", "-q"),
        ]
    probe = subprocess.run([*commands["yamllint"][:3], "--version"], capture_output=True)
    if probe.returncode != 0:
        sys.exit("yamllint is not installed: pip install -e '.[dev]'")
    walls: dict[str, list[float]] = {name: [] for name in commands}
    cpus: dict[str, list[float]] = {name: [] for name in commands}
    for name, cmd in commands.items():  # warm-up: the file cache, compiled bytecode
        warm = subprocess.run(cmd, cwd=REPO, env=env, capture_output=True, text=True)
        if warm.returncode not in (0, 1):  # 0 clean, 1 findings: anything else is no lint run
            sys.exit(f"{name} failed ({warm.returncode}): {warm.stderr.strip()}")
    for _ in range(args.runs):
        for name, cmd in commands.items():
            wall, cpu = timed_run(cmd, env)
            walls[name].append(wall)
            cpus[name].append(cpu)
    wall_med = {name: statistics.median(t) for name, t in walls.items()}
    cpu_med = {name: statistics.median(t) for name, t in cpus.items()}
    out: dict[str, object] = {"benchmark": "lint_startup", "file": os.path.relpath(args.file, REPO)}
    out["runs"] = args.runs
    for name in commands:
        out[f"{name}_median_ms"] = ms(wall_med[name])
        out[f"{name}_min_ms"] = ms(min(walls[name]))
        out[f"{name}_cpu_median_ms"] = ms(cpu_med[name])
    out["ratio"] = round(wall_med["xrdf"] / wall_med["yamllint"], 2)
    out["cpu_ratio"] = round(cpu_med["xrdf"] / cpu_med["yamllint"], 2)
    out["report_ratio"] = round(wall_med["xrdf_report"] / wall_med["yamllint"], 2)
    out["report_cpu_ratio"] = round(cpu_med["xrdf_report"] / cpu_med["yamllint"], 2)
    if "xrdf_report_franka" in wall_med:
        out["report_franka_ratio"] = round(wall_med["xrdf_report_franka"] / wall_med["yamllint"], 2)
    out["python"] = platform.python_version()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
