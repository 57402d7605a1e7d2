"""What judging the bodies of a screw bag costs: thousands of separate closed boxes in one mesh.

``xrdf spheres`` splits a closed mesh into its bodies to find overlapping shells
(:func:`~xrdf_tools.spheres.mesh_solids.overlapping_bodies`) and, when the whole is a thin
shell, to judge each body alone (:func:`~xrdf_tools.spheres.mesh_solids.closed_parts`). Both
split the mesh into a trimesh per body and asked each whether it encloses a volume, and for its
convex hull: 10-15 ms a body. The bodies are now measured at once (:mod:`.bodies`). For screw
bags of the given numbers of 4 mm cubes 10 mm apart: the seconds of both steps as they are
in this checkout and as they were (kept here, :func:`old_way`, run in this process), and
whether both give the same bodies, solids and kinds. One JSON line per size.

Usage: ``python benchmarks/bench_screw_bag.py [--sizes 1667,10000]``
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import trimesh  # noqa: E402

from tests.odd_meshes import screw_bag  # noqa: E402
from xrdf_tools.spheres import mesh_solids as ms  # noqa: E402


def _old_bodies(mesh: trimesh.Trimesh) -> list[Any]:
    """The bodies as trimesh split them: a submesh per connected component."""
    found = trimesh.graph.connected_components(
        mesh.face_adjacency, nodes=np.arange(len(mesh.faces)), min_len=1
    )
    if len(found) == 1:
        return [mesh]
    bodies = sorted((np.sort(np.asarray(c, dtype=np.intp)) for c in found), key=lambda c: c[0])
    return list(mesh.submesh(bodies, only_watertight=False, repair=True))


def old_way(part: trimesh.Trimesh) -> list[list[Any]]:
    """overlapping_bodies then closed_parts of each body, as they were."""
    out = []
    bodies = _old_bodies(part) if ms.is_volume(part) else [part]
    if len(bodies) > 1 and all(ms.is_volume(b) for b in bodies):
        lo = np.array([b.bounds[0] for b in bodies])
        hi = np.array([b.bounds[1] for b in bodies])
        apart = not ms._boxes_overlap(lo, hi)
    else:
        apart = True
    for whole in [part] if apart else bodies:
        hull = ms.convex_hull(whole)
        if hull is None or not ms.is_thin_shell(whole, hull):
            out.append([(whole, whole, "mesh")])
            continue
        each = _old_bodies(whole)
        if len(each) > 1 and all(ms.is_volume(b) for b in each):
            closed = sum(float(h.volume) for b in each if (h := ms.convex_hull(b)) is not None)
            if closed < ms.THIN_SHELL_RATIO * float(hull.volume):
                out.append([(b, *got) for b in each if (got := ms.closed_part(b)) is not None])
                continue
        out.append([(whole, hull, "thin_shell")])
    return out


def new_way(part: trimesh.Trimesh) -> list[list[Any]]:
    """overlapping_bodies then closed_parts of each body, as they are."""
    return [ms.closed_parts(b) for b in ms.overlapping_bodies(part)]


def _same(a: list[list[Any]], b: list[list[Any]]) -> bool:
    def key(m: trimesh.Trimesh) -> tuple[bytes, bytes]:
        return np.asarray(m.vertices).tobytes(), np.asarray(m.faces).tobytes()

    flat_a = [(key(x), key(y), h) for row in a for x, y, h in row]
    flat_b = [(key(x), key(y), h) for row in b for x, y, h in row]
    return flat_a == flat_b


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1667,10000")
    args = parser.parse_args()
    for n in (int(s) for s in args.sizes.split(",")):
        bag = screw_bag(n)
        t0 = time.perf_counter()
        old = old_way(bag)
        t1 = time.perf_counter()
        new = new_way(bag)
        t2 = time.perf_counter()
        row = {
            "bodies": n,
            "triangles": len(bag.faces),
            "old_s": round(t1 - t0, 2),
            "new_s": round(t2 - t1, 2),
            "same": _same(old, new),
        }
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
