"""Load our ``xrdf export curobo`` files with a cuRobo v2 loader that runs on a CPU.

``check_curobo_loader.py`` runs cuRobo's own loader on our files and compares the fields it
builds; this script goes one step further, to the robot those fields make: cuRobo's kinematics
needs CUDA, but ``curobo-metal`` reimplements cuRobo v2's portable Python API
(``curobo.kinematics.KinematicsCfg.from_robot_yaml_file``, ``Kinematics.compute_kinematics``)
on PyTorch, CPU included, with cuRobo's own loader rules for ``lock_joints``, ``extra_links``,
``tool_frames`` and ``collision_spheres``. It needs PyTorch and owns the ``curobo`` namespace,
so it lives in its own virtual environment, which this script calls as a subprocess::

    python -m venv /tmp/cm && /tmp/cm/bin/pip install torch curobo-metal
    python benchmarks/check_curobo_portable.py --curobo-python /tmp/cm/bin/python [--cache DIR]

Without ``--curobo-python`` (or when that Python cannot import ``curobo.kinematics``) it says
why and exits 0. For the Panda (cuRobo's own spheres) and the big robots of ``bench_report.py``
(Talos' left arm, TIAGo's arm, PR2's two arms, two Pandas from xacro; fitted once into
``--cache``), and the UR10e with a frame added on its flange (moved and turned, with a sphere,
the tool frame) and its last joint held at 0.7 rad, it exports the XRDF with
``--absolute-paths``, loads it there, and compares with ours (``build_kinematic_model``,
``sphere_world_centers``): the c-space joints in order, their default positions (locked joints
held at theirs), the tool frames, and every sphere's centre and radius at the default and 20
random configurations, sphere by sphere (link and place in the link's list). It prints one line
per robot and exits 1 on a disagreement.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(Path(__file__).parent))

from bench_report import XRDF as PANDA_XRDF  # noqa: E402
from bench_report import big_robots, panda_urdf  # noqa: E402

#: Centres and radii agree to this (cuRobo computes in float32: ~1e-7 of a metre-sized robot).
TOLERANCE_M = 2e-6

#: Runs in the cuRobo Python: load the export, pose it, print what it built as JSON.
CUROBO_SIDE = r"""
import json, sys, torch
from curobo.kinematics import Kinematics, KinematicsCfg
from curobo.types import DeviceCfg, JointState
request = json.loads(sys.stdin.read())
cfg = KinematicsCfg.from_robot_yaml_file(request["yml"], device_cfg=DeviceCfg(torch.device("cpu")))
robot = Kinematics(cfg)
q = torch.tensor(request["q"], dtype=torch.float32)
state = robot.compute_kinematics(JointState.from_position(q, joint_names=request["joints"]))
spheres = state.robot_spheres.detach().cpu().numpy().reshape(len(request["q"]), -1, 4)
print(json.dumps({
    "joints": list(robot.joint_names),
    "defaults": [float(v) for v in cfg.cspace.default_joint_position],
    "tool_frames": list(cfg.tool_frames),
    "sphere_links": [s.link_name for s in cfg.collision_spheres],
    "spheres": spheres.tolist(),
}))
"""


def ur10e_with_a_probe(tmp: Path) -> tuple[str, Path, Path]:
    """The UR10e fixture with what cuRobo builds from extra links and locks: a probe frame
    added on the flange (moved and turned), carrying a sphere and made the tool frame, and the
    last wrist joint left out of the c-space, held at 0.7 rad."""
    import yaml

    doc = yaml.safe_load((REPO / "fixtures/ur10e/ur10e.xrdf").read_text())
    doc["modifiers"].append(
        {
            "add_frame": {
                "frame_name": "probe_tip",
                "parent_frame_name": "wrist_3_link",
                "joint_name": "probe_joint",
                "joint_type": "FIXED",
                "fixed_transform": {
                    "position": [0.03, -0.02, 0.15],
                    "orientation": {"w": 0.9238795, "xyz": [0.0, 0.3826834, 0.0]},
                },
            }
        }
    )
    cspace = doc["cspace"]
    cspace["joint_names"] = cspace["joint_names"][:5]
    cspace["acceleration_limits"] = cspace["acceleration_limits"][:5]
    cspace["jerk_limits"] = cspace["jerk_limits"][:5]
    doc["default_joint_positions"]["wrist_3_joint"] = 0.7
    doc["tool_frames"] = ["probe_tip"]
    group = doc["geometry"][doc["self_collision"]["geometry"]]
    group["spheres"]["probe_tip"] = [{"center": [0.0, 0.01, 0.02], "radius": 0.015}]
    xrdf = tmp / "ur10e_probe.xrdf"
    xrdf.write_text(yaml.safe_dump(doc, sort_keys=False))
    return "ur10e_probe", REPO / "fixtures/ur10e/ur10e.urdf", xrdf


def curobo_usable(python: str | None) -> str | None:
    """Why the cuRobo side cannot run (None: it can)."""
    if python is None:
        return "no --curobo-python given (a Python with torch and curobo-metal)"
    probe = subprocess.run(
        [python, "-c", "import curobo.kinematics"], capture_output=True, text=True, check=False
    )
    if probe.returncode != 0:
        return f"{python} cannot import curobo.kinematics: {probe.stderr.strip().splitlines()[-1:]}"
    return None


def ours(urdf: Path, xrdf: Path) -> dict[str, Any]:
    """Our c-space, defaults, tool frames and sphere centres at 21 configurations."""
    from xrdf_tools.robot.kinematics import build_kinematic_model, default_configuration
    from xrdf_tools.robot.urdf_source import load_urdf
    from xrdf_tools.selfcollision.collision import build_sphere_set
    from xrdf_tools.selfcollision.collision.distances import sphere_world_centers
    from xrdf_tools.xrdf.io import parse_xrdf

    x = parse_xrdf(xrdf.read_text(), str(xrdf))
    kin, _ = build_kinematic_model(load_urdf(urdf), x)
    spheres, _ = build_sphere_set(kin, x, include_masked=True)
    assert x.cspace is not None
    joints = list(x.cspace.joint_names)
    idx = np.array([kin.actuated_index(j) for j in joints])
    q0 = default_configuration(kin, x.default_joint_positions)
    lo, hi = kin.lower[idx], kin.upper[idx]
    lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
    q = np.vstack([q0[idx], np.random.default_rng(0).uniform(lo, hi, size=(20, len(idx)))])
    full = np.repeat(q0[None], len(q), axis=0)
    full[:, idx] = q
    names = spheres.frame_names
    return {
        "joints": joints,
        "defaults": [float(v) for v in q0[idx]],
        "tool_frames": list(x.tool_frames),
        "q": q,
        "centres": sphere_world_centers(kin, spheres, full),
        "radii": spheres.radii,
        "keys": [
            (names[f], int(i))
            for f, i in zip(spheres.frame_of_sphere, spheres.sphere_index, strict=True)
        ],
    }


def theirs(python: str, yml: Path, mine: dict[str, Any]) -> dict[str, Any]:
    request = {"yml": str(yml), "q": mine["q"].tolist(), "joints": mine["joints"]}
    run = subprocess.run(
        [python, "-c", CUROBO_SIDE],
        input=json.dumps(request),
        capture_output=True,
        text=True,
        check=False,
    )
    if run.returncode != 0:
        raise RuntimeError(f"cuRobo could not load {yml.name}: {run.stderr.strip()[-400:]}")
    return json.loads(run.stdout.splitlines()[-1])  # type: ignore[no-any-return]


def compare(mine: dict[str, Any], other: dict[str, Any]) -> list[str]:
    """What differs (empty: nothing)."""
    out = []
    for key in ("joints", "tool_frames"):
        if mine[key] != other[key]:
            out.append(f"{key}: ours {mine[key]} cuRobo {other[key]}")
    if not np.allclose(mine["defaults"], other["defaults"], atol=1e-6):
        out.append(f"defaults: ours {mine['defaults']} cuRobo {other['defaults']}")
    seen: dict[str, int] = {}
    keys = []
    for link in other["sphere_links"]:
        keys.append((link, seen.get(link, 0)))
        seen[link] = seen.get(link, 0) + 1
    where = {k: i for i, k in enumerate(keys)}
    missing = [k for k in mine["keys"] if k not in where]
    if missing or len(keys) != len(mine["keys"]):
        out.append(f"spheres: ours {len(mine['keys'])} cuRobo {len(keys)}; missing {missing[:3]}")
        return out
    s = np.asarray(other["spheres"])[:, [where[k] for k in mine["keys"]]]
    centre_err = float(np.abs(s[..., :3] - mine["centres"]).max())
    radius_err = float(np.abs(s[0, :, 3] - mine["radii"]).max())
    if centre_err > TOLERANCE_M or radius_err > TOLERANCE_M:
        out.append(f"spheres differ: centres by {centre_err:.3g} m, radii by {radius_err:.3g} m")
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--curobo-python", help="a Python with torch and curobo-metal")
    default_cache = Path(tempfile.gettempdir()) / "xrdf-bench-report"
    parser.add_argument("--cache", type=Path, default=default_cache)
    args = parser.parse_args()
    why = curobo_usable(args.curobo_python)
    if why is not None:
        print(f"skipped: {why}")
        return 0
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        robots = [
            ("panda", panda_urdf(), PANDA_XRDF),
            ur10e_with_a_probe(Path(tmp)),
            *big_robots(args.cache),
        ]
        for name, urdf, xrdf in robots:
            yml = Path(tmp) / f"{name}.yml"
            cmd = [sys.executable, "-m", "xrdf_tools", "export", "curobo", str(xrdf)]
            cmd += ["--urdf", str(urdf), "--absolute-paths", "-q", "-o", str(yml)]
            subprocess.run(cmd, check=True, cwd=REPO)
            mine = ours(urdf, xrdf)
            problems = compare(mine, theirs(args.curobo_python, yml, mine))
            verdict = "agree" if not problems else "DISAGREE: " + "; ".join(problems)
            print(f"{name}: {len(mine['joints'])} joints, {len(mine['keys'])} spheres: {verdict}")
            failed += bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
