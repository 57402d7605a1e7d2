"""Wall and CPU time of the one command (``xrdf convert --fit-spheres``) on real robots.

Prints one JSON line per robot: the Panda (the arm the product was built on, the baseline),
TIAGo's arm (``--chain base_footprint:arm_tool_link``, a mobile manipulator of 61 links with
geometry) and Talos' left arm (SRDF group ``l_arm``, a humanoid whose meshes are
``package:///`` URIs), each run as a fresh subprocess with one BLAS/OpenMP thread. Figures:
``wall_s``, ``cpu_s`` (user + system of the child alone), the spheres written, and
``cpu_ratio_to_panda`` measured in the same run. The bar for TIAGo's and Talos' arms is 30 s
on one core.

Usage: ``python benchmarks/bench_convert.py [--runs 1]`` (needs the example-robot-data
package, part of the ``dev`` extra).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.robots import robots_dir  # noqa: E402

#: name -> (URDF, SRDF or None, the c-space choice)
ROBOTS: dict[str, tuple[str, str | None, list[str]]] = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_description/srdf/panda.srdf", []),
    "tiago-arm": (
        "tiago_description/robots/tiago.urdf",
        None,
        ["--chain", "base_footprint:arm_tool_link"],
    ),
    "talos-left-arm": (
        "talos_data/robots/talos_full_v2.urdf",
        "talos_data/srdf/talos.srdf",
        ["--group", "l_arm"],
    ),
}


def run_once(root: Path, name: str, out: Path) -> tuple[float, float]:
    """Wall and CPU seconds of one convert run (the child's own resource usage)."""
    urdf, srdf, choice = ROBOTS[name]
    cmd = [sys.executable, "-m", "xrdf_tools", "convert", str(root / urdf), *choice]
    if srdf is not None:
        cmd += ["--srdf", str(root / srdf)]
    cmd += ["--fit-spheres", "-q", "-o", str(out)]
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env[var] = "1"
    start = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        err = proc.stderr.read().decode() if proc.stderr else ""
        sys.exit(f"{name}: convert failed: {err.strip()[-400:]}")
    return wall, usage.ru_utime + usage.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--runs", type=int, default=1, help="runs per robot (medians are printed)")
    args = ap.parse_args()
    root = robots_dir()
    if root is None:
        sys.exit("example-robot-data is not installed: pip install -e '.[dev]'")
    cpu_of: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in ROBOTS:
            out = Path(tmp) / f"{name}.xrdf"
            runs = [run_once(root, name, out) for _ in range(args.runs)]
            wall = statistics.median(r[0] for r in runs)
            cpu = statistics.median(r[1] for r in runs)
            cpu_of[name] = cpu
            spheres = out.read_text().count("radius")
            line = {
                "benchmark": "convert_fit_spheres",
                "robot": name,
                "runs": args.runs,
                "wall_s": round(wall, 2),
                "cpu_s": round(cpu, 2),
                "spheres": spheres,
                "cpu_ratio_to_panda": round(cpu / cpu_of["panda"], 2),
            }
            print(json.dumps(line), flush=True)


if __name__ == "__main__":
    main()
