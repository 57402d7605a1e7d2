"""`xrdf viz --mcap` and `--rrd` on a big robot: time and peak memory of writing the
recording, the tool's writers against the writers before (``viz_record_baseline.py``: a dict
and ``json.dumps`` per MCAP message; a rerun ``log`` call per entity and step, the recording
held in memory until written), at several sample counts, in one run.

The robot is TIAGo from example-robot-data (``--chain base_footprint:arm_tool_link``, its
spheres fitted once by ``xrdf convert --fit-spheres`` and cached in ``--cache``, as
``bench_report.py`` does), drawn with its visual meshes. Each measurement runs in a child
process of its own (fresh memory): it builds the scene, then writes it; the child reports the
seconds of the write and its resident memory before it, and the parent takes the child's
peak resident memory from ``wait4``. ``write_mb`` = peak − before: what the write added.
The MCAP files of both writers are compared byte for byte.

Usage: ``python benchmarks/bench_viz_record.py [--samples 500 2000] [--cache DIR]``

Prints one JSON line per target and sample count.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent


def tiago(cache: Path) -> tuple[Path, Path, Path]:
    """TIAGo's URDF, its arm's XRDF (fitted once into ``cache``) and the package root."""
    from bench_report import _convert, _robots_dir

    robots = _robots_dir()
    urdf = robots / "tiago_description/robots/tiago.urdf"
    pkg = ["--package-path", f"example-robot-data={robots.parent}"]
    cache.mkdir(parents=True, exist_ok=True)
    xrdf = _convert(
        cache, "tiago_arm", [str(urdf), "--chain", "base_footprint:arm_tool_link", *pkg]
    )
    return urdf, xrdf, robots.parent


def child(writer: str, target: str, n: int, cache: Path, out: Path) -> None:
    """Build the scene of ``n`` samples, write it with ``writer``; print seconds and RSS."""
    from xrdf_tools.robot.kinematics import build_kinematic_model
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.viz import build_scene, render, sample_configurations
    from xrdf_tools.xrdf.io import load_xrdf

    urdf_path, xrdf_path, share = tiago(cache)
    urdf, xrdf = load_urdf(urdf_path), load_xrdf(xrdf_path)
    kin, _ = build_kinematic_model(urdf, xrdf)
    q = sample_configurations(kin, xrdf, n, 0)
    scene = build_scene(
        urdf,
        xrdf,
        q,
        kinematic_model=kin,
        urdf_path=urdf_path,
        package_paths={"example-robot-data": str(share)},
    )
    import mcap.writer  # noqa: F401  imports are not timed
    import rerun  # noqa: F401

    before = rss_mb()
    start = time.perf_counter()
    if writer == "tool":
        render(scene, target, out)  # type: ignore[arg-type]
    else:
        import viz_record_baseline as old

        old.write_mcap(scene, out) if target == "mcap" else old.write_rrd(scene, out)
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "rss_before_mb": before}))


def rss_mb() -> float:
    """Resident memory of this process now (MB), from /proc (0 where there is none)."""
    status = Path("/proc/self/status")
    if not status.is_file():
        return 0.0
    for line in status.read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return 0.0


def measure(writer: str, target: str, n: int, cache: Path, out: Path) -> dict[str, Any]:
    """One child's figures: seconds of the write, peak RSS and what the write added."""
    cmd = [sys.executable, __file__, "--child", writer, target, str(n), "--cache", str(cache)]
    cmd += ["--out", str(out)]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), str(Path(__file__).parent)])}
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, env=env, cwd=REPO)
    assert proc.stdout is not None
    report = json.loads(proc.stdout.read())
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = status
    assert status == 0, f"{writer} {target} {n} failed"
    peak = usage.ru_maxrss / 1024.0
    return {
        "write_s": round(report["seconds"], 2),
        "peak_rss_mb": round(peak, 1),
        "write_mb": round(peak - report["rss_before_mb"], 1),
        "file_mb": round(out.stat().st_size / 1e6, 1),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, nargs="+", default=[500, 2000])
    ap.add_argument(
        "--cache",
        type=Path,
        default=Path(tempfile.gettempdir()) / "xrdf-bench-report",
        help="where TIAGo's fitted XRDF is kept (shared with bench_report.py)",
    )
    ap.add_argument("--child", nargs=3, metavar=("WRITER", "TARGET", "N"))
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    if args.child:
        writer, target, n = args.child
        child(writer, target, int(n), args.cache, args.out)
        return
    tiago(args.cache)  # fitted once, before anything is timed
    with tempfile.TemporaryDirectory() as tmp:
        for target in ("mcap", "rrd"):
            for n in args.samples:
                paths = {w: Path(tmp) / f"{w}.{target}" for w in ("baseline", "tool")}
                row: dict[str, Any] = {"robot": "tiago_arm", "target": target, "samples": n}
                for writer, path in paths.items():
                    row[writer] = measure(writer, target, n, args.cache, path)
                row["speedup"] = round(row["baseline"]["write_s"] / row["tool"]["write_s"], 1)
                if target == "mcap":
                    same = paths["tool"].read_bytes() == paths["baseline"].read_bytes()
                    row["mcap_bytes_equal"] = same
                print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
