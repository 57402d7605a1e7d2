"""What CAD-sized meshes cost: a Panda link's collision mesh subdivided to 0.3, 1.2 and 4.9
million triangles (binary STL, written to a temporary directory), on a one-link robot.

For each size, in a fresh process (``os.wait4`` gives its peak memory): ``xrdf spheres`` (the
default fit) and ``xrdf viz --mcap`` of the mesh drawn as the link's visual; seconds and peak
MiB, the seconds per million triangles (a linear cost keeps that flat), and the size of the
MCAP file. Then, in this
process, on the largest mesh: the inside test of 3,000 points (what a fit asks a dozen times,
and the metrics again) the first time (the triangle grid built) and again (the grid kept), and
the same test with the grid built anew each time (the cost each query paid before the grid was
kept); and the triangles ``viz``/``edit`` draw of the mesh (simplified past 100,000) against
the mesh's own, with the seconds of simplifying. One JSON line per figure.

Usage: ``python benchmarks/bench_big_mesh.py [--sizes 5,6,7] [--baseline CHECKOUT]``
(subdivision levels of the 300-triangle ``link3.stl``: 5 = 0.3 M, 6 = 1.2 M, 7 = 4.9 M
triangles; needs example-robot-data). ``--baseline`` runs each command also with the
xrdf-tools of another checkout (a worktree of an older commit), one after the other.
Figures measured: docs/spheres.md, "CAD-sized meshes".
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

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from tests.robots import robots_dir  # noqa: E402

ROBOT = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm">
    <visual><geometry><mesh filename="{mesh}"/></geometry></visual>
    <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

XRDF = """format: xrdf
format_version: 1.0
modifiers: []
default_joint_positions: {j: 0.0}
cspace: {joint_names: [j], acceleration_limits: [10.0], jerk_limits: [1000.0]}
tool_frames: [arm]
collision:
  geometry: arm_spheres
self_collision:
  geometry: arm_spheres
  ignore: {}
geometry:
  arm_spheres:
    spheres:
      arm: [{center: [0.0, 0.0, 0.0], radius: 0.05}]
"""


def subdivided(levels: int, out: Path) -> int:
    """``link3.stl`` subdivided ``levels`` times, written to ``out``; its triangle count."""
    import trimesh

    root = robots_dir()
    if root is None:
        sys.exit("example-robot-data is not installed")
    mesh = trimesh.load(root / "panda_description/meshes/collision/link3.stl")
    for _ in range(levels):
        mesh = mesh.subdivide()
    mesh.export(out)
    return len(mesh.faces)


def run(args: list[str], code: Path, cwd: Path) -> tuple[float, float, int]:
    """Seconds, peak MiB and exit code of ``xrdf ARGS`` in a fresh process, with the
    xrdf-tools of the checkout ``code`` (run in ``cwd``: ``python -c`` imports from the
    current directory first)."""
    cmd = [sys.executable, "-c", "from xrdf_tools.cli import main; main()", *args]
    env = dict(os.environ, PYTHONPATH=str(code))
    start = time.perf_counter()
    proc = subprocess.Popen(
        cmd, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    return seconds, usage.ru_maxrss / 1024.0, os.waitstatus_to_exitcode(status)


def commands(tmp: Path, levels: int, baseline: Path | None) -> None:
    mesh = tmp / f"part{levels}.stl"
    faces = subdivided(levels, mesh)
    urdf = tmp / f"r{levels}.urdf"
    urdf.write_text(ROBOT.format(mesh=mesh.name))
    xrdf = tmp / "r.xrdf"
    xrdf.write_text(XRDF)
    jobs = {
        "spheres": ["spheres", str(urdf), "--links", "arm", "-o", str(tmp / "out.xrdf")],
        "viz --mcap": ["viz", str(xrdf), "--urdf", str(urdf), "--mcap", str(tmp / "o.mcap")],
    }
    codes = {"this": REPO} | ({"baseline": baseline} if baseline else {})
    for name, args in jobs.items():
        for which, checkout in codes.items():
            (tmp / "o.mcap").unlink(missing_ok=True)
            seconds, mib, code = run(args, checkout, tmp)
            row = {"command": name, "code": which, "triangles": faces, "exit": code}
            row |= {"seconds": round(seconds, 2), "peak_mib": round(mib)}
            row |= {"seconds_per_million": round(seconds / faces * 1e6, 2)}
            if name.startswith("viz"):
                row["output_mb"] = round((tmp / "o.mcap").stat().st_size / 1e6, 1)
            print(json.dumps(row), flush=True)


def inside_queries(mesh_path: Path) -> None:
    import trimesh

    from xrdf_tools.spheres import inside

    mesh = trimesh.load(mesh_path)
    points = np.random.default_rng(0).uniform(*mesh.bounds, size=(3000, 3))
    times = []
    for _ in range(3):
        start = time.perf_counter()
        inside.points_inside(mesh, points)
        times.append(time.perf_counter() - start)
    start = time.perf_counter()
    for _ in range(3):
        inside._GRIDS.clear()  # the grid built anew for each query
        inside.points_inside(mesh, points)
    anew = (time.perf_counter() - start) / 3
    row = {"figure": "inside test, 3000 points", "triangles": len(mesh.faces)}
    row |= {"first_s": round(times[0], 3), "kept_grid_s": round(min(times[1:]), 3)}
    row |= {"grid_built_each_time_s": round(anew, 3)}
    print(json.dumps(row), flush=True)


def drawn(mesh_path: Path) -> None:
    import trimesh

    from xrdf_tools.viz.meshes import DRAWN_TRIANGLES, simplified

    mesh = trimesh.load(mesh_path)
    start = time.perf_counter()
    _, faces = simplified(mesh.vertices, mesh.faces, DRAWN_TRIANGLES)
    row = {"figure": "drawn (viz, edit)", "triangles": len(mesh.faces), "drawn": len(faces)}
    row |= {"simplify_s": round(time.perf_counter() - start, 2)}
    print(json.dumps(row), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="5,6,7", help="subdivision levels of link3.stl")
    parser.add_argument("--baseline", type=Path, help="also run the commands from this checkout")
    options = parser.parse_args()
    levels = [int(x) for x in options.sizes.split(",")]
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for level in levels:
            commands(tmp, level, options.baseline)
        largest = tmp / f"part{max(levels)}.stl"
        inside_queries(largest)
        drawn(largest)


if __name__ == "__main__":
    main()
