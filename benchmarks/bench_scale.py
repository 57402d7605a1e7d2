"""Steps around the engines that must grow in proportion to the input, each against a baseline
measured in the same run.

Usage: ``python benchmarks/bench_scale.py [--pairs 20000] [--links 400] [--subdivisions 7]``

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=20000)
    parser.add_argument("--links", type=int, default=400)
    parser.add_argument("--subdivisions", type=int, default=7)
    args = parser.parse_args()
    figures = {
        "srdf_sync": bench_srdf_sync(args.pairs),
        "outside_boxes": bench_outside_boxes(args.links, args.subdivisions),
        "convert_output": bench_convert_output(),
    }
    print(json.dumps(figures))


if __name__ == "__main__":
    main()
