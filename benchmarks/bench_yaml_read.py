"""Cost of reading a big XRDF: the one-pass reader on libyaml vs on PyYAML's parser, same run.

Usage: ``python benchmarks/bench_yaml_read.py [--mib 16] [--kind spheres|numbers|aliases]
[--what xrdf|yaml] [--readers libyaml,pyyaml] [--reference] [--keep FILE]``

Writes an XRDF of about ``--mib`` MiB (16: just under the default input limit; larger sizes
raise ``XRDF_TOOLS_MAX_INPUT_MB`` for the readers) to a temporary file:

* ``spheres``: the UR10e header and one geometry group of ``- center: [x, y, z]`` /
  ``radius: r`` spheres over seven links (~300,000 spheres in 16 MiB);
* ``aliases``: the spheres, 9,000 of whose radii are an alias of the first one (the whole file
  is then read from PyYAML's parser events, and checked as a document with aliases);
* ``numbers``: the same header, a geometry group of one sphere and an extra top-level key
  holding one long list of numbers (eight to a line).

Each reader then reads it in a fresh child process (``load_xrdf``, or ``load_yaml`` with
``--what yaml``), so that its peak memory is the child's ``ru_maxrss``:

* ``libyaml``: as shipped, on libyaml's events (``yaml.__with_libyaml__``);
* ``pyyaml``: the same one-pass reader on PyYAML's pure-Python parser (libyaml turned off): the
  baseline in the same run;
* ``reference`` (``--reference``; minutes and gigabytes for big files): the reader as it was
  before the one-pass builder: PyYAML's composer and the per-node conversion (the tests'
  reference, ``tests/yaml_reference.py``), and for ``xrdf`` the position index of every node
  that the model used to carry.

Prints ONE JSON line: the file's size, then per reader ``seconds`` (wall), ``cpu_seconds``,
``peak_rss_mib`` and ``import_rss_mib`` (the interpreter with xrdf_tools imported, before
reading), and ``ratio`` = pyyaml / libyaml CPU seconds (``reference_ratio`` likewise). Wall
times are noisy on a shared machine; CPU seconds and ratios less so. ``float_parse_ns``, the time of
``float("0.12345")`` on this machine, says how fast it is (about 60 ns on a recent desktop).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import resource
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path
from typing import Any, TextIO

REPO = Path(__file__).resolve().parent.parent
HEADER = REPO / "fixtures" / "ur10e" / "ur10e.xrdf"
LINKS = ("shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link")
LINKS += ("wrist_3_link", "tool0")
READERS = ("libyaml", "pyyaml", "reference")


def _header() -> str:
    """The UR10e XRDF up to its geometry section, naming the group written below."""
    text = HEADER.read_text().split("\ngeometry:\n")[0]
    return text.replace("ur10e_collision_spheres", "big") + "\n"


def _write_spheres(
    out: TextIO, size: int, rng: random.Random, aliases: int = 0, every: int = 1
) -> None:
    """``aliases``: the first sphere's radius is anchored and every ``every``-th sphere after it
    takes it by alias, ``aliases`` times."""
    out.write("geometry:\n  big:\n    spheres:\n")
    count = 0
    for k, link in enumerate(LINKS):
        out.write(f"      {link}:\n")
        budget = size * (k + 1) // len(LINKS) - size * k // len(LINKS)
        while budget > 0:
            x, y, z = (rng.uniform(-1, 1) for _ in range(3))
            radius = f"{rng.uniform(0.01, 0.1):.4f}"
            if aliases and count == 0:
                radius = "&r " + radius
            elif aliases and count % every == 0 and count // every <= aliases:
                radius = "*r"
            count += 1
            entry = f"        - center: [{x:.5f}, {y:.5f}, {z:.5f}]\n          radius: {radius}\n"
            out.write(entry)
            budget -= len(entry)


def _write_numbers(out: TextIO, size: int, rng: random.Random) -> None:
    out.write("geometry:\n  big:\n    spheres:\n      tool0:\n")  # the group the header names
    out.write("        - center: [0.0, 0.0, 0.0]\n          radius: 0.05\n")
    out.write("numbers: [\n")
    while size > 0:
        line = "  " + ", ".join(f"{rng.uniform(-100, 100):.5f}" for _ in range(8)) + ",\n"
        out.write(line)
        size -= len(line)
    out.write("  0.0]\n")


def write_xrdf(path: Path, mib: float, kind: str) -> int:
    """Write the benchmark file; returns its size in bytes."""
    size = int(mib * (1 << 20)) - (8 << 10)  # room for the header: stay under --mib
    rng = random.Random(0)
    with open(path, "w", encoding="utf-8") as out:
        out.write(_header())
        if kind == "numbers":
            _write_numbers(out, size, rng)
        else:  # aliases: 9,000 spread over the file (at most 10,000 are read)
            aliases = 9_000 if kind == "aliases" else 0
            every = max(1, size // 75 // 9_000)  # a sphere takes about 75 bytes
            _write_spheres(out, size, rng, aliases, every)
    return path.stat().st_size


def _rss_mib() -> float:
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / (1 << 20) if sys.platform == "darwin" else peak / 1024  # bytes / KiB


def child(reader: str, path: str, what: str) -> dict[str, Any]:
    """Read ``path`` once with ``reader`` in this process (run by the parent per reader)."""
    from xrdf_tools.util.frozen import FrozenMap
    from xrdf_tools.xrdf.io import load_xrdf, xrdf_from_document
    from xrdf_tools.yaml import build as yaml_build
    from xrdf_tools.yaml.io import load_yaml, raise_on_duplicates, read_text
    from xrdf_tools.yaml.positions import node_positions

    import_rss = _rss_mib()
    wall, cpu = time.perf_counter(), time.process_time()
    if reader == "reference":
        from tests.yaml_reference import compose_document

        doc = compose_document(read_text(path), path)
        raise_on_duplicates(doc)
        if what == "xrdf":
            model = xrdf_from_document(doc)
            positions = FrozenMap(node_positions(doc.root))
            assert model.geometry is not None or model.extra, len(positions)
    else:
        yaml_build.HAVE_LIBYAML = reader == "libyaml"
        if what == "xrdf":
            load_xrdf(path)
        else:
            load_yaml(path)
    return {
        "seconds": round(time.perf_counter() - wall, 2),
        "cpu_seconds": round(time.process_time() - cpu, 2),
        "peak_rss_mib": round(_rss_mib()),
        "import_rss_mib": round(import_rss),
    }


def run_reader(reader: str, path: Path, what: str, mib: float) -> dict[str, Any]:
    env = dict(os.environ)
    env["XRDF_TOOLS_MAX_INPUT_MB"] = str(max(16, int(mib) + 1))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    cmd = [sys.executable, __file__, "--child", reader, str(path), "--what", what]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"{reader} reader failed:\n{done.stderr}")
    result: dict[str, Any] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def float_parse_ns() -> float:
    """Nanoseconds per ``float("0.12345")``, best of five: a yardstick for the machine."""
    loops = 200_000
    best = min(timeit.timeit("float(t)", setup="t = '0.12345'", number=loops) for _ in range(5))
    return round(best / loops * 1e9)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--mib", type=float, default=16.0, help="file size in MiB (default 16)")
    ap.add_argument("--kind", choices=("spheres", "numbers", "aliases"), default="spheres")
    ap.add_argument("--what", choices=("xrdf", "yaml"), default="xrdf")
    ap.add_argument(
        "--readers", default="libyaml,pyyaml", help="comma-separated, of: " + ", ".join(READERS)
    )
    ap.add_argument(
        "--reference", action="store_true", help="also the reader before the one-pass builder"
    )
    ap.add_argument("--keep", type=Path, help="write the generated file here and keep it")
    ap.add_argument("--child", nargs=2, metavar=("READER", "FILE"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.child[0], args.child[1], args.what)))
        return

    from xrdf_tools.yaml import build as yaml_build

    with tempfile.TemporaryDirectory() as tmp:
        path = args.keep or Path(tmp) / f"big_{args.kind}.xrdf"
        size = write_xrdf(path, args.mib, args.kind)
        chosen = set(args.readers.split(",")) | ({"reference"} if args.reference else set())
        readers = [r for r in READERS if r in chosen]
        if not yaml_build.HAVE_LIBYAML and "libyaml" in readers:
            readers.remove("libyaml")
        out: dict[str, Any] = {
            "benchmark": "yaml_read",
            "kind": args.kind,
            "what": args.what,
            "file_mib": round(size / (1 << 20), 2),
            "libyaml_available": yaml_build.HAVE_LIBYAML,
            "float_parse_ns": float_parse_ns(),
        }
        for reader in readers:
            out[reader] = run_reader(reader, path, args.what, args.mib)
        fast = out.get("libyaml", out.get("pyyaml"))
        for name, key in (("pyyaml", "ratio"), ("reference", "reference_ratio")):
            if fast is not None and name in out and out[name] is not fast:
                cpu = out[name]["cpu_seconds"] / max(fast["cpu_seconds"], 1e-9)
                out[key] = round(cpu, 2)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
