"""Read our outputs with a real ROS parser: pinocchio (urdfdom and its SRDF reader).

Usage (with a Python that has pinocchio -- ``pip install pin``, kept out of the project's
dependencies: it is heavy -- and xrdf-tools' core dependencies; example-robot-data and rtb-data
are taken from the site-packages of ``--python``, the Python that makes the outputs)::

    python -m venv /tmp/pinvenv && /tmp/pinvenv/bin/pip install pin -e .
    /tmp/pinvenv/bin/python benchmarks/check_urdf_srdf_readers.py [--python PY] [--out DIR]
        [--part urdf|srdf] [--robot NAME ...]

Without pinocchio it prints why and exits 0. It prints a table per part and exits 1 when
pinocchio and we disagree:

* ``urdf``: every URDF of example-robot-data and every robot xacro of rtb-data (expanded by
  ``xrdf expand``) is parsed by urdfdom (``pinocchio.buildModelFromUrdf``, mimic joints as
  mimics); its joints (name, type, mimic source, multiplier and offset), position, velocity and
  effort limits and the pose of every link at the zero and five random configurations are
  compared with ours (``load_robot``, ``build_kinematic_model``, ``fk``).
* ``srdf``: for each robot with a MoveIt SRDF, ``xrdf convert --srdf`` (no spheres: the mask is
  the SRDF's) and pinocchio's ``removeCollisionPairs`` must disable the same link pairs, and
  every ``group_state`` must read the same values (``loadReferenceConfigurations``; a continuous
  joint's angle modulo 2 pi); the XRDF's default positions must be the chosen state's. Then the
  XRDF's mask is changed (every third pair dropped, up to five pairs added) and ``xrdf export
  srdf --merge`` syncs it into the SRDF: pinocchio must disable exactly the pairs the XRDF
  ignores, and read the same states as from the original SRDF, whose other elements must be
  unchanged. Pairs are compared where pinocchio can see them: between links with collision
  geometry on different pinocchio joints (``addAllCollisionPairs`` skips pairs on one joint).
"""

from __future__ import annotations

import argparse
import math
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - depends on the machine
    print("skipped: pinocchio is not installed here (pip install pin, in its own venv)")
    sys.exit(0)

sys.path.insert(0, str(Path(__file__).parent))
from pinocchio_urdf import (  # noqa: E402
    ERD,
    NOTES,
    PY,
    SITE,
    check_cases,
    check_urdf,
    last_line,
    only,
    pin_kind,
    site,
    urdf_inputs,
    xrdf_cli,
)

from xrdf_tools.convert.sources.srdf_parse import parse_srdf  # noqa: E402
from xrdf_tools.xrdf.model import SelfCollisionSection  # noqa: E402
from xrdf_tools.xrdf.read import load_xrdf  # noqa: E402
from xrdf_tools.xrdf.write import dump_xrdf  # noqa: E402

Pair = frozenset[str]

#: robots with a MoveIt SRDF: name, URDF and SRDF below example-robot-data's robots/
SRDFS: dict[str, tuple[str, str]] = {
    line.split()[0]: (line.split()[1], line.split()[2])
    for line in """
panda panda_description/urdf/panda.urdf panda_description/srdf/panda.srdf
ur5 ur_description/urdf/ur5_robot.urdf ur_description/srdf/ur5.srdf
ur5_gripper ur_description/urdf/ur5_gripper.urdf ur_description/srdf/ur5_gripper.srdf
ur3_gripper ur_description/urdf/ur3_gripper.urdf ur_description/srdf/ur3_gripper.srdf
kinova kinova_description/robots/kinova.urdf kinova_description/srdf/kinova.srdf
xarm7 xarm_description/urdf/xarm7.urdf xarm_description/srdf/xarm7.srdf
z1 z1_description/urdf/z1.urdf z1_description/srdf/z1.srdf
talos talos_data/robots/talos_full_v2.urdf talos_data/srdf/talos.srdf
pr2 pr2_description/urdf/pr2.urdf pr2_description/srdf/pr2.srdf
baxter baxter_description/urdf/baxter.urdf baxter_description/srdf/baxter_manipulation.srdf
romeo romeo_description/urdf/romeo.urdf romeo_description/srdf/romeo.srdf
anymal_kinova anymal_b_simple_description/robots/anymal-kinova.urdf {anymal-kinova.srdf}
b1_z1 b1_description/urdf/b1-z1.urdf b1_description/srdf/b1-z1.srdf
icub icub_description/robots/icub.urdf icub_description/srdf/icub.srdf
solo solo_description/robots/solo.urdf solo_description/srdf/solo.srdf
finger_edu finger_edu_description/robots/finger_edu.urdf finger_edu_description/srdf/finger_edu.srdf
""".replace("{anymal-kinova.srdf}", "anymal_b_simple_description/srdf/anymal-kinova.srdf")
    .strip()
    .splitlines()
}


# ------------------------------------------------------------------------------------------
# SRDF: pinocchio's reading of our SRDF and of the SRDF we read
# ------------------------------------------------------------------------------------------
def geometry(model: Any, urdf: Path) -> Any:
    geom = pin.buildGeomFromUrdf(
        model,
        str(urdf),
        pin.GeometryType.COLLISION,
        package_dirs=[str(site() / "cmeel.prefix/share")],
    )
    geom.addAllCollisionPairs()
    return geom


def link_pairs(model: Any, geom: Any) -> set[Pair]:
    """The link pairs of ``geom``'s collision pairs."""
    frame = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    return {frozenset((frame[cp.first], frame[cp.second])) for cp in geom.collisionPairs}


def pin_disabled(model: Any, urdf: Path, srdf: str) -> tuple[set[Pair], set[Pair]]:
    """``(pairs pinocchio can see, pairs the SRDF text disables among them)``."""
    geom = geometry(model, urdf)
    every = link_pairs(model, geom)
    pin.removeCollisionPairsFromXML(model, geom, srdf)
    return every, every - link_pairs(model, geom)


def pin_states(model: Any, path: Path) -> dict[str, np.ndarray]:
    m = model.copy()
    pin.loadReferenceConfigurations(m, str(path))
    refs = m.referenceConfigurations
    return {e.key(): np.array(e.data()) for e in refs}


def state_value(model: Any, q: np.ndarray, joint: str) -> float | None:
    if not model.existJointName(joint):
        return None
    j = model.joints[model.getJointId(joint)]
    if pin_kind(j) == "continuous":
        return math.atan2(q[j.idx_q + 1], q[j.idx_q])
    return float(q[j.idx_q]) if j.nq == 1 else None


def same_angle(a: float, b: float, continuous: bool) -> bool:
    if continuous:
        return abs(math.remainder(a - b, 2 * math.pi)) < 1e-9
    return math.isclose(a, b, abs_tol=1e-12)


def state_differences(model: Any, srdf_path: Path) -> tuple[int, list[str]]:
    """Every group_state as we read it against pinocchio's (the first of a name, as it keeps)."""
    ours = parse_srdf(srdf_path.read_bytes(), str(srdf_path))
    theirs = pin_states(model, srdf_path)
    out, seen = [], set()
    for st in ours.group_states:
        if st.name in seen:
            continue
        seen.add(st.name)
        q = theirs.get(st.name)
        if q is None:
            out.append(f"group_state {st.name}: pinocchio has none")
            continue
        for joint, value in st.values:
            v = state_value(model, q, joint)
            if v is None:
                continue
            cont = pin_kind(model.joints[model.getJointId(joint)]) == "continuous"
            if not same_angle(value, v, cont):
                out.append(f"group_state {st.name} {joint}: ours {value}, pinocchio {v}")
    return len(seen), out


def default_differences(model: Any, xrdf: Path, srdf_path: Path, stderr: str) -> list[str]:
    """The XRDF's default positions against pinocchio's reading of the states convert chose
    (``convert-chosen-state``): a joint's value is that of the first chosen state setting it,
    brought into its URDF limits (``convert-clamped-default``: a revolute joint's turned by
    whole turns where that lands inside, the same pose; else clamped)."""
    chosen = re.findall(
        r"convert-chosen-state default positions (?:of .*? )?from group_state '([^']+)'", stderr
    )
    x = load_xrdf(xrdf)
    if not chosen or not x.default_joint_positions:
        return []
    ours = {
        st.name: dict(st.values) for st in reversed(parse_srdf(srdf_path.read_bytes()).group_states)
    }
    theirs = pin_states(model, srdf_path)
    out = []
    for joint, value in x.default_joint_positions.items():
        state = next((n for n in chosen if joint in ours.get(n, {})), None)
        v = state_value(model, theirs[state], joint) if state in theirs else None
        if v is None:
            continue
        j = model.joints[model.getJointId(joint)]
        cont = pin_kind(j) == "continuous"
        if not cont:
            lo, hi = model.lowerPositionLimit[j.idx_q], model.upperPositionLimit[j.idx_q]
            if not lo <= v <= hi and value == min(max(v, lo), hi):
                NOTES.append(f"{joint}: {v} of '{state}' clamped to {value}")
                continue
            if not lo <= v <= hi and lo <= value <= hi and same_angle(value, v, True):
                NOTES.append(f"{joint}: {v} of '{state}' turned by whole turns to {value}")
                continue
        if not same_angle(value, v, cont):
            out.append(f"default {joint}: XRDF {value}, pinocchio {v} (state {state})")
    return out


def perturbed(x: Any, visible: set[Pair]) -> Any:
    """``x`` with every third ignore pair dropped and up to five visible pairs added."""
    sc = x.self_collision
    pairs = sorted(sorted(p) for p in sc.ignore_pairs())
    keep = [p for k, p in enumerate(pairs) if k % 3 != 2]
    have = {frozenset(p) for p in pairs}
    keep += [sorted(p) for p in sorted(visible - have, key=sorted)[:5]]
    ignore: dict[str, list[str]] = {}
    for a, b in keep:
        ignore.setdefault(a, []).append(b)
    section = SelfCollisionSection(
        sc.geometry, sc.buffer_distance, {k: tuple(v) for k, v in ignore.items()}
    )
    return x.replace(self_collision=section)


def xml_without_pairs(text: bytes) -> list[bytes]:
    from lxml import etree

    root = etree.fromstring(text, etree.XMLParser(resolve_entities=False, remove_comments=True))
    skip = {"disable_collisions", "enable_collisions"}
    return [
        etree.tostring(el, with_tail=False)
        for el in root
        if isinstance(el.tag, str) and el.tag not in skip
    ]


def check_srdf(name: str, out_dir: Path) -> tuple[str, list[str]]:
    urdf_rel, srdf_rel = SRDFS[name]
    urdf, srdf = site() / ERD / urdf_rel, site() / ERD / srdf_rel
    model = pin.buildModelFromUrdf(str(urdf))
    NOTES.clear()
    xrdf = out_dir / f"{name}.xrdf"
    r = xrdf_cli("convert", str(urdf), "--srdf", str(srdf), "-o", str(xrdf))
    if r.returncode != 0:
        return f"{name:14} convert exit {r.returncode}: {last_line(r.stderr)}", []
    diffs: list[str] = []
    # 3. what convert read from the SRDF, as pinocchio reads it
    visible, disabled = pin_disabled(model, urdf, srdf.read_text())
    x = load_xrdf(xrdf)
    ignored = set(x.self_collision.ignore_pairs()) if x.self_collision else set()
    read = ignored & visible
    if read != disabled:
        diffs.append(f"convert: {only(read, disabled, 'pinocchio')}")
    n_states, sd = state_differences(model, srdf)
    diffs += sd + default_differences(model, xrdf, srdf, r.stderr)
    # 2. the sync back, as pinocchio reads it
    notes = list(NOTES)
    changed = perturbed(x, visible)
    mod = out_dir / f"{name}.changed.xrdf"
    mod.write_text(dump_xrdf(changed))
    synced = out_dir / f"{name}.synced.srdf"
    r = xrdf_cli(
        "export",
        "srdf",
        str(mod),
        "--merge",
        str(srdf),
        "--urdf",
        str(urdf),
        "-q",
        "-o",
        str(synced),
    )
    if r.returncode != 0:
        return f"{name:14} export srdf exit {r.returncode}: {last_line(r.stderr)}", diffs
    _, after = pin_disabled(model, urdf, synced.read_text())
    want = set(changed.self_collision.ignore_pairs()) & visible
    if after != want:
        diffs.append(f"export: {only(want, after, 'pinocchio')}")
    before_states, after_states = pin_states(model, srdf), pin_states(model, synced)
    if before_states.keys() != after_states.keys() or any(
        not np.array_equal(before_states[k], after_states[k]) for k in before_states
    ):
        diffs.append("export: pinocchio reads other group_states from the synced SRDF")
    if xml_without_pairs(srdf.read_bytes()) != xml_without_pairs(synced.read_bytes()):
        diffs.append("export: elements other than the collision pairs changed")
    row = (
        f"{name:14} {len(visible):5} visible pairs  convert: {len(read):4} disabled  "
        f"states {n_states:2}  export: {len(want):4} disabled "
        f"({len(want - read)} added, {len(read - want)} removed)  "
        + ("OK" if not diffs else "DIFFERS")
    )
    if notes:
        row += f" (default {notes[0]})"
    return row, [f"{name}: {d}" for d in diffs]


# ------------------------------------------------------------------------------------------
def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("/tmp/xrdf_reader_check"))
    ap.add_argument("--part", choices=("urdf", "cases", "srdf"), action="append")
    ap.add_argument("--robot", action="append", help="only these robots (table names)")
    default_py = REPO / ".venv/bin/python"
    ap.add_argument(
        "--python",
        default=str(default_py if default_py.exists() else sys.executable),
        help="the Python with xrdf-tools' dependencies, example-robot-data and rtb-data",
    )
    args = ap.parse_args()
    PY.append(args.python)
    code = "import sysconfig; print(sysconfig.get_paths()['purelib'])"
    SITE.append(
        Path(
            subprocess.run(
                [args.python, "-c", code], check=True, capture_output=True, text=True
            ).stdout.strip()
        )
    )
    args.out.mkdir(parents=True, exist_ok=True)
    parts = args.part or ["urdf", "cases", "srdf"]
    problems: list[str] = []
    if "urdf" in parts:
        print(f"URDF: urdfdom (pinocchio {pin.__version__}) against xrdf-tools")
        for name, path, pkgs in urdf_inputs(args.robot):
            row, diffs = check_urdf(name, path, pkgs, args.out)
            print(row, flush=True)
            problems += diffs
    if "cases" in parts:
        print("\nSmall URDFs: what urdfdom refuses, we refuse or read with urdf-ros-refuses")
        for row, diffs in check_cases():
            print(row)
            problems += diffs
    if "srdf" in parts:
        print(
            f"\nSRDF: pinocchio {pin.__version__}'s SRDF reader against convert --srdf, export srdf"
        )
        for name in SRDFS:
            if args.robot and name not in args.robot:
                continue
            row, diffs = check_srdf(name, args.out)
            print(row, flush=True)
            problems += diffs
    for p in problems:
        print("DISAGREE", p)
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
