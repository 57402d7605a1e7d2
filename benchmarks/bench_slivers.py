"""What the inside test costs on meshes of long slivers, against the bounding-box grid it had.

A CAD exporter tessellates a disc or a cone as a fan of slivers from one centre. The inside
test's triangle grid listed each triangle in every cell of its xy *box*: a sliver's box
covers a large share of the grid, so the grid was made coarser until every cell held
thousands of triangles, each tested against every point of the cell. It now lists a triangle
only in the cells its projection touches (row by row). For a closed fan cone and a
cylinder with fan caps (CAD style) of 5,000, 20,000 and 200,000 triangles, and for ordinary
meshes (the UR5's and the Panda's collision links, and the Panda's ``link3.stl`` subdivided to
1.2 million triangles as in ``bench_big_mesh.py``): the seconds to build the grid and to test
20,000 points once it is built, with the grid of this checkout and with the old bounding-box
grid (kept here, :class:`BoxGrid`), run in this process; the candidate (point, triangle)
pairs per point; and whether both answers are the same. One JSON line per mesh and grid.
The old grid on the 200,000-triangle meshes is timed on a tenth of the points and scaled
(``"scaled_from"``): it takes minutes.

Usage: ``python benchmarks/bench_slivers.py [--points 20000] [--sizes 5000,20000,200000]
[--no-ordinary] [--levels 6]`` (needs example-robot-data for the ordinary meshes).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import trimesh  # noqa: E402

from tests import odd_meshes  # noqa: E402
from tests.odd_meshes import fan_cone  # noqa: E402
from tests.robots import robots_dir  # noqa: E402
from xrdf_tools.spheres import inside  # noqa: E402

#: The old grid on fan meshes of more triangles is timed on a tenth of the points.
SCALE_PAST = 100_000


class BoxGrid(inside.FaceGrid):
    """The grid as it was: each triangle listed in every cell of its xy box, coarser while
    the (triangle, cell) pairs exceed 8 a triangle or more than 64 triangles cover more
    than 256 cells (those then tested against every point)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = vertices, faces
        lo, hi, _ = inside._xy_boxes(vertices, faces)
        self.lo = lo.min(0)
        self.span = np.maximum(hi.max(0) - self.lo, 1e-12)
        cells = max(1, int(np.sqrt(len(faces) / 2.0)))
        while True:
            self._resolution(cells)
            span = self._cell_of(hi) - self._cell_of(lo) + 1
            covered = span[:, 0] * span[:, 1]
            wide = covered > 256
            listed = int(covered[~wide].sum())
            if cells == 1 or (listed <= 8 * len(faces) and wide.sum() <= 64):
                break
            cells = max(1, cells // 2)
        keys, tris = [], []
        for s0 in range(0, len(faces), 1 << 17):
            sl = slice(s0, s0 + (1 << 17))
            key, tri = self._cells_of(self._cell_of(lo[sl]), self._cell_of(hi[sl]), wide[sl])
            keys.append(key.astype(np.int32))
            tris.append((tri + s0).astype(np.int32))
        key = np.concatenate(keys)
        order = np.argsort(key, kind="stable")
        self.tri_of_cell = np.concatenate(tris)[order]
        counts = np.bincount(key, minlength=int(self.shape[0] * self.shape[1]))
        self.start = np.concatenate([[0], np.cumsum(counts)])
        self.wide = np.flatnonzero(wide)


def fan_capped_cylinder(triangles: int) -> trimesh.Trimesh:
    """A fan-capped cylinder of about ``triangles`` triangles."""
    return odd_meshes.fan_capped_cylinder((triangles + 4) // 4)


def ordinary(levels: int) -> Iterator[tuple[str, trimesh.Trimesh]]:
    root = robots_dir()
    if root is None:
        sys.exit("example-robot-data is not installed (or pass --no-ordinary)")
    for robot, folder in (
        ("ur5", "ur_description/meshes/ur5"),
        ("panda", "panda_description/meshes"),
    ):
        for path in sorted((root / folder / "collision").glob("*.stl")):
            yield f"{robot} {path.stem}", trimesh.load(path)
    mesh = trimesh.load(root / "panda_description/meshes/collision/link3.stl")
    for _ in range(levels):
        mesh = mesh.subdivide()
    yield f"panda link3 subdivided x{levels}", mesh


def timed(
    mesh: trimesh.Trimesh, grid_class: type[inside.FaceGrid], points: np.ndarray, scale: int
) -> dict:
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    start = time.perf_counter()
    grid = grid_class(vertices, faces)
    built = time.perf_counter() - start
    inside._GRIDS[mesh] = (hash(mesh), grid)
    part = points[: len(points) // scale]
    start = time.perf_counter()
    answer = inside.points_inside(mesh, part)
    seconds = (time.perf_counter() - start) * scale
    cell = grid._cell_of(part[:, :2])
    key = cell[:, 0] * grid.shape[1] + cell[:, 1]
    per_point = (grid.start[key + 1] - grid.start[key]).mean() + len(grid.wide)
    del inside._GRIDS[mesh]
    row = {"grid_s": round(built, 3), "inside_s": round(seconds, 3)}
    row |= {"pairs_per_point": round(float(per_point), 1), "cells": grid.shape.tolist()}
    row |= {"listed": len(grid.tri_of_cell), "wide": len(grid.wide)}
    if scale > 1:
        row["scaled_from"] = len(part)
    return row | {"_answer": answer}


def compare(name: str, mesh: trimesh.Trimesh, count: int, scale_old: bool = False) -> None:
    rng = np.random.default_rng(0)
    points = rng.uniform(mesh.bounds[0] - 0.01, mesh.bounds[1] + 0.01, size=(count, 3))
    scale = 10 if scale_old and len(mesh.faces) > SCALE_PAST else 1
    rows = {"box grid (before)": timed(mesh, BoxGrid, points, scale)}
    rows["grid (now)"] = timed(mesh, inside.FaceGrid, points, 1)
    old, new = (r.pop("_answer") for r in rows.values())
    same = bool(np.array_equal(old, new[: len(old)]))
    for which, row in rows.items():
        head = {"mesh": name, "triangles": len(mesh.faces), "points": count, "grid": which}
        print(json.dumps(head | row | {"same_answer": same}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=20_000)
    parser.add_argument("--sizes", default="5000,20000,200000", help="triangles of the fans")
    parser.add_argument("--no-ordinary", action="store_true", help="only the fan meshes")
    parser.add_argument("--levels", type=int, default=6, help="subdivisions of link3.stl")
    options = parser.parse_args()
    for size in (int(s) for s in options.sizes.split(",") if s):
        compare("fan cone", fan_cone(size), options.points, scale_old=True)
        compare("cylinder, fan caps", fan_capped_cylinder(size), options.points, scale_old=True)
    if not options.no_ordinary:
        for name, mesh in ordinary(options.levels):
            compare(name, mesh, options.points)


if __name__ == "__main__":
    main()
