"""What the exact surface distance costs on CAD slivers and ordinary links, against testing
every point against every triangle.

The protrusion and gap metrics ask the distance from many points near a link's surface to
it. For a closed fan cone and a cylinder with fan caps (CAD style, from
``bench_slivers.py``), a 2 m rod of 1 mm radius (long side triangles), and the UR5's and the
Panda's collision links: 20,000 points near the surface (surface samples moved up to 5 mm
along the normal, seeded), timed with ``spheres.distance.surface_distance`` and with a
plain loop over every triangle in blocks (the baseline, in this process; on a tenth of the
points where that takes long, scaled and said by ``"scaled_from"``), with the ratio and
whether both give the same distances (to 1e-12 m). One JSON line per mesh.

Usage: ``python benchmarks/bench_surface_distance.py [--points 20000] [--no-ordinary]``
(needs example-robot-data for the ordinary links).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

import trimesh  # noqa: E402
from bench_slivers import fan_capped_cylinder  # noqa: E402

from tests.odd_meshes import fan_cone  # noqa: E402
from tests.robots import robots_dir  # noqa: E402
from xrdf_tools.spheres.distance import _point_triangle_distance, surface_distance  # noqa: E402


def every_pair(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """The baseline: each point against every triangle, in blocks of about 4 M pairs."""
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    out = np.empty(len(points))
    step = max(1, 4_000_000 // len(tri))
    for s0 in range(0, len(points), step):
        p = points[s0 : s0 + step]
        d = _point_triangle_distance(np.repeat(p, len(tri), 0), np.tile(tri, (len(p), 1, 1)))
        out[s0 : s0 + step] = d.reshape(len(p), len(tri)).min(1)
    return out


def near_points(mesh: trimesh.Trimesh, count: int) -> np.ndarray:
    rng = np.random.default_rng(1)
    samples, face = trimesh.sample.sample_surface(mesh, count, seed=1)
    return samples + mesh.face_normals[face] * rng.uniform(-0.005, 0.005, (count, 1))


def compare(name: str, mesh: trimesh.Trimesh, count: int) -> None:
    points = near_points(mesh, count)
    t0 = time.perf_counter()
    ours = surface_distance(mesh, points)
    t_ours = time.perf_counter() - t0
    part = count if len(mesh.faces) * count <= 2e8 else count // 10
    t0 = time.perf_counter()
    base = every_pair(mesh, points[:part])
    t_base = (time.perf_counter() - t0) * count / part
    line = {
        "mesh": name,
        "triangles": len(mesh.faces),
        "points": count,
        "seconds": round(t_ours, 3),
        "every_pair_seconds": round(t_base, 3),
        "ratio": round(t_base / max(t_ours, 1e-9), 1),
        "same": bool(np.allclose(ours[:part], base, rtol=0, atol=1e-12)),
    }
    if part != count:
        line["scaled_from"] = part
    print(json.dumps(line), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=20_000)
    parser.add_argument("--no-ordinary", action="store_true", help="only the sliver meshes")
    args = parser.parse_args()
    rod = trimesh.creation.cylinder(radius=0.001, height=2.0, sections=5000)
    for name, mesh in (
        ("fan cone", fan_cone(5000)),
        ("fan-capped cylinder", fan_capped_cylinder(4000)),
        ("2 m rod, 1 mm radius", rod),
    ):
        compare(name, mesh, args.points)
    if args.no_ordinary:
        return
    root = robots_dir()
    if root is None:
        sys.exit("example-robot-data is not installed (or pass --no-ordinary)")
    for folder in ("ur_description/meshes/ur5", "panda_description/meshes"):
        for path in sorted((root / folder / "collision").glob("*.stl")):
            compare(path.stem, trimesh.load(path), args.points)


if __name__ == "__main__":
    main()
