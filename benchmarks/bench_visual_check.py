"""What the visual check of a sphere fit costs on real robots with COLLADA visual meshes.

For the Panda, UR5, TIAGo and Talos (example-robot-data), in one process: the seconds to read
every visual ``.dae`` file of the robot through trimesh (what ``--visual-check all`` paid for
each, and what ``fast`` skipped) and through the XML reader that ``fast`` now uses
(:func:`xrdf_tools.robot.collada_points.collada_vertices`), the largest difference between
their boxes (relative to the box's size), the seconds of the whole check
(:func:`~xrdf_tools.spheres.visual_agreement.visual_disagreements`, ``fast``), and with
``--fit`` the seconds of the fit itself (``fit_robot``, default counts, check off), so the
check's share of the fit. One JSON line per robot; a last line does the same for binary glTF:
the Panda's visual meshes written as GLB files under turned nodes, read through trimesh and
through :func:`xrdf_tools.robot.gltf_points.glb_vertices`.

Usage: ``python benchmarks/bench_visual_check.py [--fit]`` (needs example-robot-data).
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

from tests.robots import robots_dir  # noqa: E402
from xrdf_tools.robot.collada_points import collada_vertices  # noqa: E402
from xrdf_tools.robot.element_bounds import mesh_file_vertices  # noqa: E402
from xrdf_tools.robot.xacro_source import load_robot  # noqa: E402
from xrdf_tools.spheres.geometry import load_link_geometry  # noqa: E402
from xrdf_tools.spheres.visual_agreement import visual_disagreements  # noqa: E402

ROBOTS = {
    "panda": "panda_description/urdf/panda.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "tiago": "tiago_description/robots/tiago.urdf",
    "talos": "talos_data/robots/talos_full_v2.urdf",
}


def visual_dae_files(robot: object) -> list[Path]:
    """The distinct visual ``.dae`` files of ``robot``."""
    resolver = robot.mesh_resolver()  # type: ignore[attr-defined]
    base = Path(robot.path).resolve().parent  # type: ignore[attr-defined]
    found: set[Path] = set()
    for link in robot.urdf.link_map.values():  # type: ignore[attr-defined]
        for visual in link.visuals or ():
            mesh = visual.geometry.mesh if visual.geometry is not None else None
            if mesh is not None and (mesh.filename or "").lower().endswith(".dae"):
                found.add(resolver.resolve_uri(mesh.filename, base))
    return sorted(found)


def timed(read: object, files: list[Path]) -> tuple[float, list[np.ndarray]]:
    start = time.perf_counter()
    boxes = []
    for path in files:
        v = read(path)  # type: ignore[operator]
        boxes.append(np.array([v.min(axis=0), v.max(axis=0)]))
    return time.perf_counter() - start, boxes


def measure(name: str, urdf: Path, fit: bool) -> dict[str, object]:
    robot = load_robot(urdf)
    files = visual_dae_files(robot)
    trimesh_s, expected = timed(mesh_file_vertices, files)
    xml_s, got = timed(lambda p: collada_vertices(p.read_bytes()), files)
    worst = max(
        (
            float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-12))
            for a, b in zip(got, expected, strict=True)
        ),
        default=0.0,
    )
    geoms, _ = load_link_geometry(robot, source="collision")
    start = time.perf_counter()
    said = visual_disagreements(robot, geoms, check="fast")
    check_s = time.perf_counter() - start
    row: dict[str, object] = {
        "robot": name,
        "dae_files": len(files),
        "trimesh_s": round(trimesh_s, 3),
        "xml_reader_s": round(xml_s, 3),
        "speedup": round(trimesh_s / xml_s, 1) if files else None,
        "worst_relative_box_difference": worst,
        "check_fast_s": round(check_s, 3),
        "diagnostics": [d.rule for d in said],
    }
    if fit:
        from xrdf_tools.spheres.robot_fit import fit_robot

        start = time.perf_counter()
        fit_robot(urdf, visual_check="off")
        row["fit_s"] = round(time.perf_counter() - start, 2)
        row["check_share_of_fit"] = round(check_s / float(row["fit_s"]), 3)  # type: ignore[arg-type]
    return row


def measure_glb(urdf: Path, folder: Path) -> dict[str, object]:
    """The Panda's visual meshes written as GLB files (each under a turned, shifted node, as
    robots converted from USD or MuJoCo ship them), read through trimesh and through
    :func:`~xrdf_tools.robot.gltf_points.glb_vertices`."""
    import trimesh

    from xrdf_tools.robot.gltf_points import glb_vertices

    files = []
    for i, dae in enumerate(visual_dae_files(load_robot(urdf))):
        scene = trimesh.Scene()
        turn = trimesh.transformations.rotation_matrix(0.3 * (i + 1), (1, 2, 3), (0.1, 0, 0))
        for mesh in trimesh.load(dae, force="scene").dump():
            scene.add_geometry(mesh, transform=turn)
        path = folder / f"{dae.stem}.glb"
        path.write_bytes(scene.export(file_type="glb"))
        files.append(path)
    trimesh_s, expected = timed(mesh_file_vertices, files)
    numpy_s, got = timed(lambda p: glb_vertices(p.read_bytes()), files)
    worst = max(
        float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-12))
        for a, b in zip(got, expected, strict=True)
    )
    return {
        "robot": "panda as GLB",
        "glb_files": len(files),
        "trimesh_s": round(trimesh_s, 3),
        "glb_reader_s": round(numpy_s, 3),
        "speedup": round(trimesh_s / numpy_s, 1),
        "worst_relative_box_difference": worst,
    }


def main() -> None:
    import tempfile

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit", action="store_true", help="also time the fit itself")
    args = parser.parse_args()
    root = robots_dir()
    if root is None:
        sys.exit("example-robot-data is not installed")
    for name, urdf in ROBOTS.items():
        print(json.dumps(measure(name, root / urdf, args.fit)), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        print(json.dumps(measure_glb(root / ROBOTS["panda"], Path(folder))), flush=True)


if __name__ == "__main__":
    main()
