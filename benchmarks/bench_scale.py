"""Steps around the engines that must grow in proportion to the input, each against a baseline
measured in the same run.

Usage: ``python benchmarks/bench_scale.py [--pairs 20000] [--links 400] [--subdivisions 7]
[--chain 300] [--tree 100] [--only many_frames]``

* ``srdf_sync``: ``sync_srdf`` (``xrdf export srdf``) of a synthetic robot whose XRDF ignores
  ``--pairs`` pairs, and of one with a quarter of them: ``ratio`` is about 4 when the sync is
  linear in the pairs (it was quadratic: 16).
* ``outside_boxes``: the link boxes of the ``sphere-outside-geometry`` lint rule (``xrdf lint
  --urdf``) for a chain of ``--links`` cylinder links plus one link whose mesh is an icosphere of
  ``--subdivisions`` (7: 330,000 triangles, 16 MB as STL): as shipped (the parts' own bounds
  when each part encloses a volume) against the baseline of the sphere fitter's solids of every
  link (hulls and unions). Both give the same boxes (checked); ``ratio`` = baseline / shipped.
* ``convert_output``: ``xrdf convert`` of the bundled demo arm with ``-o FILE`` (the output is
  checked against the robot's mesh files) against ``-o -`` (no check), in fresh child
  processes; a ratio near 1 means the check costs nothing (reading the mesh names through
  yourdfpy imported trimesh and scipy: about 1.8 against 0.9 seconds).
* ``many_frames``: ``xrdf report``'s build on robots with many sphere frames
  (``tests/many_frames.py``): a serial chain of ``--chain`` joints with one sphere per link
  (300: 45,150 frame pairs) and a branched tree of ``--tree`` links with mimic and prismatic
  joints. Per robot, the engine's construction (``build_s``), the report's pair statistics
  (``pair_stats_s``) and the whole report of 100 samples (``report_s``), as shipped and with
  the baseline's walks per pair (``benchmarks/build_scale_baseline.py``: the layout and the
  joints on each pair's path as they were) in the same process; the layouts and the reports
  are checked equal. ``ratio`` = baseline / shipped.

Prints ONE JSON line of seconds and ratios. Wall times are noisy on a shared machine; the
ratios less so.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

DEMO = REPO / "fixtures" / "demo_arm"


def chain_urdf(links: int, mesh: str | None = None) -> str:
    """A serial chain of ``links`` cylinder links (and a last link with ``mesh``)."""
    out = [
        '<robot name="chain">',
        '  <link name="l0"><collision><geometry>'
        '<box size="0.1 0.1 0.1"/></geometry></collision></link>',
    ]
    names = [f"l{i}" for i in range(links + (1 if mesh else 0))]
    for i in range(1, len(names)):
        shape = (
            f'<mesh filename="{mesh}"/>'
            if mesh and i == len(names) - 1
            else '<cylinder radius="0.02" length="0.1"/>'
        )
        out.append(
            f'  <link name="{names[i]}"><collision><origin xyz="0 0 0.05"/><geometry>{shape}'
            "</geometry></collision></link>"
        )
        out.append(
            f'  <joint name="j{i}" type="revolute"><parent link="{names[i - 1]}"/>'
            f'<child link="{names[i]}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    out.append("</robot>")
    return "\n".join(out) + "\n"


def bench_srdf_sync(pairs: int) -> dict[str, float]:
    from xrdf_tools.export.srdf import sync_srdf
    from xrdf_tools.util.frozen import FrozenMap
    from xrdf_tools.xrdf.model import GeometryGroup, SelfCollisionSection, Xrdf

    def timed(n: int) -> float:
        links = [f"l{i}" for i in range(int((2 * n) ** 0.5) + 2)]
        ignore: dict[str, list[str]] = {}
        count = 0
        for i, a in enumerate(links):
            for b in links[i + 1 :]:
                if count == n:
                    break
                ignore.setdefault(a, []).append(b)
                count += 1
        mask = FrozenMap((k, tuple(v)) for k, v in ignore.items())
        x = Xrdf(
            self_collision=SelfCollisionSection(geometry="g", ignore=mask),
            geometry=FrozenMap({"g": GeometryGroup()}),
        )
        start = time.perf_counter()
        result = sync_srdf(x, robot_name="chain")
        seconds = time.perf_counter() - start
        assert len(result.added) == n
        return seconds

    small, big = timed(pairs // 4), timed(pairs)
    return {"pairs": pairs, "quarter_s": small, "full_s": big, "ratio": big / small}


def bench_outside_boxes(links: int, subdivisions: int) -> dict[str, float]:
    import trimesh

    from xrdf_tools.lint.rules.sphere_outside_geometry import _load_boxes
    from xrdf_tools.robot.xacro_source import load_robot

    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "ball.stl"
        trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1).export(stl)
        urdf = Path(tmp) / "chain.urdf"
        urdf.write_text(chain_urdf(links, stl.name))
        shipped, solids = load_robot(urdf), load_robot(urdf)
        expected = dict(shipped.collision_counts)
        start = time.perf_counter()
        fast = _load_boxes(shipped, expected)
        fast_s = time.perf_counter() - start
        solids.derived["link_solids"] = {}  # as after a fit: the boxes of the solids
        start = time.perf_counter()
        slow = _load_boxes(solids, expected)
        slow_s = time.perf_counter() - start
    assert fast == slow, "the boxes differ"
    return {
        "links": len(expected),
        "shipped_s": fast_s,
        "solids_s": slow_s,
        "ratio": slow_s / fast_s,
    }


def bench_convert_output() -> dict[str, float]:
    def run(out: str) -> float:
        cmd = [sys.executable, "-m", "xrdf_tools", "convert", str(DEMO / "demo_arm.urdf")]
        cmd += ["--srdf", str(DEMO / "demo_arm.srdf"), "-q", "-o", out]
        start = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True, cwd=REPO)
        return time.perf_counter() - start

    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "demo_arm.xrdf")
        run(out)  # warm-up (bytecode, disk cache)
        files = [run(out) for _ in range(3)]
        stdout = [run("-") for _ in range(3)]
    f, s = sorted(files)[1], sorted(stdout)[1]
    return {"file_s": f, "stdout_s": s, "ratio": f / s}


def bench_many_frames(joints: int, links: int) -> dict[str, Any]:
    from tests.many_frames import chain_robot, tree_robot

    out: dict[str, Any] = {}
    for name, (urdf, xrdf) in {
        f"chain_{joints}": chain_robot(joints),
        f"tree_{links}": tree_robot(links),
    }.items():
        shipped = _timed_report(urdf, xrdf, baseline=False)
        base = _timed_report(urdf, xrdf, baseline=True)
        assert base["report"].pairs == shipped["report"].pairs, "the reports differ"
        assert _same_layout(base["engine"].pairs, shipped["engine"].pairs), "the layouts differ"
        row: dict[str, Any] = {
            "frame_pairs": len(shipped["report"].pairs),
            "body_pairs": len(shipped["engine"].pairs),
        }
        for key in ("build_s", "pair_stats_s", "report_s"):
            row[key] = round(shipped[key], 3)
            row[f"baseline_{key}"] = round(base[key], 3)
            row[f"{key[:-2]}_ratio"] = round(base[key] / shipped[key], 1)
        out[name] = row
    return out


def _timed_report(urdf: str, xrdf: str, *, baseline: bool) -> dict[str, Any]:
    """The report of 100 samples, with its engine, the seconds of the engine's construction,
    of the pair statistics and of the whole report."""
    from unittest import mock

    import build_scale_baseline as old

    from xrdf_tools.report import build
    from xrdf_tools.robot.urdf_source import parse_urdf_string
    from xrdf_tools.selfcollision.engine import core
    from xrdf_tools.xrdf.io import parse_xrdf

    robot, doc = parse_urdf_string(urdf, "many.urdf"), parse_xrdf(xrdf, "many.xrdf")
    got: dict[str, Any] = {}

    def timed(key: str, fn: Any) -> Any:
        def run(*args: Any, **kw: Any) -> Any:
            start = time.perf_counter()
            value = fn(*args, **kw)
            got[key] = time.perf_counter() - start
            if key == "build_s":
                got["engine"] = value
            return value

        return run

    layout = old.body_pairs if baseline else core.body_pairs
    on_paths = old.cspace_joints_on_paths if baseline else build._cspace_joints_on_paths
    with (
        mock.patch.object(core, "body_pairs", layout),
        mock.patch.object(build, "_cspace_joints_on_paths", on_paths),
        mock.patch.object(build, "CountEngine", timed("build_s", build.CountEngine)),
        mock.patch.object(build, "_pair_stats", timed("pair_stats_s", build._pair_stats)),
    ):
        start = time.perf_counter()
        got["report"] = build.self_collision_report(robot, doc, samples=100, jobs=1)
        got["report_s"] = time.perf_counter() - start
    return got


def _same_layout(a: list[Any], b: list[Any]) -> bool:
    """Whether two lists of body pairs hold the same values, field by field."""
    import dataclasses

    import numpy as np

    if len(a) != len(b):
        return False
    for x, y in zip(a, b, strict=True):
        for f in dataclasses.fields(x):
            u, v = getattr(x, f.name), getattr(y, f.name)
            same = np.array_equal(u, v) if isinstance(u, np.ndarray) else u == v
            if f.name != "grid" and not same:
                return False
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=20000)
    parser.add_argument("--links", type=int, default=400)
    parser.add_argument("--subdivisions", type=int, default=7)
    parser.add_argument("--chain", type=int, default=300, help="many_frames: chain joints")
    parser.add_argument("--tree", type=int, default=100, help="many_frames: tree links")
    parser.add_argument("--only", help="run one case (srdf_sync, outside_boxes, ...)")
    args = parser.parse_args()
    cases = {
        "srdf_sync": lambda: bench_srdf_sync(args.pairs),
        "outside_boxes": lambda: bench_outside_boxes(args.links, args.subdivisions),
        "convert_output": bench_convert_output,
        "many_frames": lambda: bench_many_frames(args.chain, args.tree),
    }
    figures = {name: run() for name, run in cases.items() if args.only in (None, name)}
    print(json.dumps(figures))


if __name__ == "__main__":
    main()
