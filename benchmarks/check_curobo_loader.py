"""Load our outputs with a real cuRobo source checkout and compare with tests/curobo_loader.py.

Usage (with a Python that has cuRobo's dependencies -- torch, yourdfpy, warp-lang, trimesh,
scipy, lxml, numpy-quaternion -- and xrdf-tools installed; no GPU needed)::

    python benchmarks/check_curobo_loader.py /path/to/curobo [--out DIR] [--robot NAME ...]

For each robot (example-robot-data Panda, UR5, Kinova, TIAGo's arm, Talos' left arm, PR2's
two arms; rtb-data's dual Panda) it makes ``xrdf convert --fit-spheres --target curobo`` and
``xrdf export curobo`` outputs into ``--out`` (kept: a second run reuses them), loads each with
cuRobo (its XRDF converter, then its kinematics builder on the CPU) and prints, per robot and
output: whether it loads, and every field where what cuRobo built differs from our model of it
(``tests/curobo_loader.py``), plus the largest FK and sphere-centre distance between cuRobo's
kinematic tensors and ``xrdf_tools.robot.kinematics.fk`` at four configurations.

cuRobo's kinematics builder is written for a GPU; three things are changed to run it on a CPU,
none of which decides a compared field: the default device is the CPU, the link
centre-of-mass transform (built on ``cuda`` in the URDF parser) is built on the CPU, and the
forward kinematics that bakes locked joints into fixed transforms (a CUDA kernel) is evaluated
by :func:`cpu_fk` on the same tensors (a link's pose is its parent's times its fixed transform
times the joint motion at ``multiplier * q + offset``, as the kernel does). The FK comparison
uses :func:`cpu_fk` too: it checks cuRobo's parsing of the URDF (origins, axes, signs, mimics,
locked joints), not its kernel.
"""

from __future__ import annotations

import argparse
import logging
import subprocess
import sys
from collections.abc import Mapping
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from tests.curobo_loader import SLOT, CuroboRobot, from_config, from_xrdf  # noqa: E402
from xrdf_tools.robot.kinematics import build_kinematic_model, fk  # noqa: E402
from xrdf_tools.robot.xacro_source import load_robot  # noqa: E402
from xrdf_tools.xrdf.read import load_xrdf  # noqa: E402

ERD = "cmeel.prefix/share/example-robot-data/robots"
RTB = "rtbdata/xacro/qut_frankie_description"
DUAL = ",".join(f"panda_{a}_joint{j}" for a in (1, 2) for j in range(1, 8))
#: name -> (robot file below site-packages, convert arguments)
ROBOTS: dict[str, tuple[str, list[str]]] = {
    "panda": (f"{ERD}/panda_description/urdf/panda.urdf", ["--srdf", "SRDF:panda"]),
    "ur5": (f"{ERD}/ur_description/urdf/ur5_robot.urdf", ["--srdf", "SRDF:ur5"]),
    "kinova": (f"{ERD}/kinova_description/robots/kinova.urdf", ["--srdf", "SRDF:kinova"]),
    "tiago_arm": (
        f"{ERD}/tiago_description/robots/tiago.urdf",
        ["--chain", "base_footprint:arm_tool_link"],
    ),
    "talos_larm": (
        f"{ERD}/talos_data/robots/talos_full_v2.urdf",
        ["--srdf", "SRDF:talos", "--group", "l_arm"],
    ),
    "pr2_arms": (
        f"{ERD}/pr2_description/urdf/pr2.urdf",
        ["--srdf", "SRDF:pr2", "--group", "left_arm", "--group", "right_arm"],
    ),
    "dual_panda": (f"{RTB}/robots/dual_panda_example.urdf.xacro", ["--joints", DUAL]),
}
SRDF = {
    "panda": f"{ERD}/panda_description/srdf/panda.srdf",
    "ur5": f"{ERD}/ur_description/srdf/ur5.srdf",
    "kinova": f"{ERD}/kinova_description/srdf/kinova.srdf",
    "talos": f"{ERD}/talos_data/srdf/talos.srdf",
    "pr2": f"{ERD}/pr2_description/srdf/pr2.srdf",
}


_SITE: list[Path] = []


def site_packages() -> Path:
    """The site-packages holding example-robot-data and rtb-data (those of our CLI's Python)."""
    return _SITE[0]


def find_site_packages(python: str) -> Path:
    code = "import sysconfig; print(sysconfig.get_paths()['purelib'])"
    return Path(
        subprocess.run(
            [python, "-c", code], check=True, capture_output=True, text=True
        ).stdout.strip()
    )


def make_outputs(name: str, out: Path, xrdf_cmd: list[str]) -> tuple[Path, Path, Path]:
    """``(xrdf, yml, urdf)`` for robot ``name``, made with our CLI unless already in ``out``."""
    sp = site_packages()
    rel, args = ROBOTS[name]
    robot = sp / rel
    pkg = ["--package-path", f"qut_frankie_description={sp / RTB}"]
    args = [str(sp / SRDF[a[5:]]) if a.startswith("SRDF:") else a for a in args]
    xrdf, yml, urdf = out / f"{name}.xrdf", out / f"{name}.yml", robot
    if robot.suffix == ".xacro":
        urdf = out / f"{name}.urdf"
        if not urdf.is_file():
            subprocess.run([*xrdf_cmd, "expand", str(robot), *pkg, "-o", str(urdf)], check=True)
        args += pkg
    if not xrdf.is_file():
        cmd = [*xrdf_cmd, "convert", str(robot), *args, "--fit-spheres", "--target", "curobo"]
        subprocess.run([*cmd, "-q", "-o", str(xrdf)], check=True)
    if not yml.is_file():
        cmd = [*xrdf_cmd, "export", "curobo", str(xrdf), "--urdf", str(urdf), "--absolute-paths"]
        subprocess.run([*cmd, "-q", "-o", str(yml)], check=True)
    return xrdf, yml, urdf


def cpu_patches() -> None:
    """Run cuRobo's kinematics builder on the CPU (see the module docstring)."""
    import torch
    from curobo._src.robot.loader import kinematics_loader
    from curobo._src.robot.parser import parser_urdf
    from curobo._src.types import device_cfg
    from curobo._src.types.pose import Pose

    init = device_cfg.DeviceCfg.__init__
    init.__defaults__ = (torch.device("cpu"), *(init.__defaults__ or ())[1:])

    class CpuTorch:
        def __getattr__(self, name: str) -> Any:
            return getattr(torch, name)

        def as_tensor(self, *a: Any, device: Any = None, **k: Any) -> Any:
            return torch.as_tensor(*a, device="cpu" if device == "cuda" else device, **k)

    parser_urdf.torch = CpuTorch()  # type: ignore[assignment]
    parser_urdf.DeviceCfg = lambda device=None, dtype=torch.float32: device_cfg.DeviceCfg(
        device=torch.device("cpu"), dtype=dtype
    )

    def link_poses(self: Any, q: Any, names: list[str], kin: Any) -> Any:
        mats = cpu_fk(kin, q.view(-1).double())
        idx = [self._name_to_idx_map[n] for n in names]
        sel = torch.as_tensor(np.stack([mats[i] for i in idx]), dtype=torch.float32)
        poses = Pose.from_matrix(sel)
        n = len(names)
        return Pose(
            position=poses.position.view(1, n, 3), quaternion=poses.quaternion.view(1, n, 4)
        )

    kinematics_loader.KinematicsLoader._get_link_poses = link_poses  # type: ignore[method-assign]


def cpu_fk(kin: Any, q: Any) -> list[np.ndarray]:
    """4x4 pose of every link of cuRobo's kinematic tensors ``kin`` at ``q`` (its joint order)."""
    ft = kin.fixed_transforms.double().cpu().numpy().reshape(-1, 3, 4)
    parent = kin.link_map.cpu().numpy()
    jmap = kin.joint_map.cpu().numpy()
    jtype = kin.joint_map_type.cpu().numpy()
    off = kin.joint_offset_map.double().cpu().numpy().reshape(-1, 2)
    qn = np.asarray(q, dtype=float)
    out: list[np.ndarray] = []
    for i in range(ft.shape[0]):
        local = np.eye(4)
        local[:3] = ft[i]
        t = int(jtype[i])
        if t >= 0:
            v = off[i, 0] * qn[jmap[i]] + off[i, 1]
            motion = np.eye(4)
            if t <= 2:
                motion[t, 3] = v
            else:
                a, b = [(1, 2), (2, 0), (0, 1)][t - 3]
                c, s = np.cos(v), np.sin(v)
                motion[a, a], motion[a, b], motion[b, a], motion[b, b] = c, -s, s, c
            local = local @ motion
        out.append(local if i == 0 else out[int(parent[i])] @ local)
    return out


def built_robot(g: Any, buffers: Mapping[str, float]) -> CuroboRobot:
    """What cuRobo's kinematics builder ``g`` holds, in our model's terms (radii without the
    world buffer ``buffers``, which is reported apart)."""
    spheres_t = g._link_spheres_tensor[0].double().cpu().numpy()
    owner = g._link_sphere_idx_map.cpu().numpy()
    by_idx = {i: n for n, i in g._name_to_idx_map.items()}
    spheres: dict[str, tuple[Any, ...]] = {}
    for row, li in zip(spheres_t, owner, strict=True):
        name = by_idx[int(li)]
        r = float(row[3]) - buffers.get(name, 0.0)
        r = SLOT if r <= -1.0 else r  # an attached-object slot, whatever its negative radius
        spheres[name] = (*spheres.get(name, ()), (tuple(float(c) for c in row[:3]), r))
    if g.total_spheres == 0:
        spheres = {}
    sc = g.self_collision_config
    pad: dict[str, float] = {}
    checked: set[frozenset[str]] = set()
    if sc is not None and g.total_spheres:
        links = [by_idx[int(li)] for li in owner]
        for i, p in enumerate(sc.sphere_padding.cpu().numpy()):
            if float(p) != 0.0:
                pad[links[i]] = float(p)
        for i, j in sc.collision_pairs.cpu().numpy():
            checked.add(frozenset((links[i], links[j])))
    ignore = {frozenset((a, b)) for a in spheres for b in spheres if a != b} - checked
    cs = g.cspace
    dof = list(cs.joint_names)
    lock = g.lock_jointstate
    locked = {}
    if lock is not None:
        locked = dict(zip(lock.joint_names, lock.position.view(-1).tolist(), strict=True))
    extra = {}
    for k, lp in (g.extra_links or {}).items():
        extra[k] = (
            lp.parent_link_name,
            lp.joint_name,
            tuple(map(float, np.ravel(lp.fixed_transform))),
        )
    return CuroboRobot(
        active_joints=tuple(g.joint_names),
        locked=locked,
        defaults=dict(zip(dof, cs.default_joint_position.tolist(), strict=True)),
        acceleration=dict(zip(dof, cs.max_acceleration.tolist(), strict=True)),
        jerk=dict(zip(dof, cs.max_jerk.tolist(), strict=True)),
        base_link=g.base_link,
        ee_link=g.tool_frames[0],
        link_names=frozenset(g.tool_frames),
        extra_links=extra,
        spheres=spheres,
        world_buffer={k: v for k, v in buffers.items() if v and k in spheres},
        self_buffer=pad,
        ignore=frozenset(ignore),
    )


def _matrix(t: tuple[float, ...]) -> tuple[float, ...]:
    """A cuRobo ``fixed_transform`` ``[x, y, z, qw, qx, qy, qz]`` as a flat 3x4 matrix."""
    x, y, z, w, a, b, c = t
    r = [
        [1 - 2 * (b * b + c * c), 2 * (a * b - c * w), 2 * (a * c + b * w), x],
        [2 * (a * b + c * w), 1 - 2 * (a * a + c * c), 2 * (b * c - a * w), y],
        [2 * (a * c - b * w), 2 * (b * c + a * w), 1 - 2 * (a * a + b * b), z],
    ]
    return tuple(v for row in r for v in row)


def _close(a: Any, b: Any, tol: float = 2e-5) -> bool:
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        return a.keys() == b.keys() and all(_close(a[k], b[k], tol) for k in a)
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return len(a) == len(b) and all(_close(x, y, tol) for x, y in zip(a, b, strict=True))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return abs(float(a) - float(b)) <= tol * max(1.0, abs(float(b)))
    return bool(a == b)


def differences(real: CuroboRobot, model: CuroboRobot, *, built: bool = False) -> list[str]:
    """One line per field where cuRobo's build and our model (or, ``built``, another of
    cuRobo's builds) differ."""
    lines = []
    for f in fields(CuroboRobot):
        a, b = getattr(real, f.name), getattr(model, f.name)
        if f.name == "extra_links" and not built:
            b = {k: (p, j, _matrix(t)) for k, (p, j, t) in b.items()}
        if f.name in ("locked", "defaults", "acceleration", "jerk") and b is None:
            continue
        if not _close(a, b):
            lines.append(f"{f.name}: cuRobo {_short(a)} | model {_short(b)}")
    return lines


def _short(v: Any) -> str:
    if isinstance(v, (set, frozenset)):
        v = sorted(sorted(x) if isinstance(x, frozenset) else x for x in v)
    if isinstance(v, Mapping) and any(isinstance(x, tuple) for x in v.values()):
        v = {k: (len(x) if isinstance(x, tuple) else x) for k, x in v.items()}
    text = repr(v)
    return text if len(text) < 400 else text[:400] + "..."


def fk_distance(g: Any, xrdf: Path, urdf: Path, pkg: Mapping[str, str]) -> tuple[float, float]:
    """Largest distance (m) between cuRobo's and our FK over tool frames, sphere links and
    sphere centres, at cuRobo's default configuration and three random ones."""
    import torch

    robot = load_robot(urdf, package_paths=pkg)
    ours, _ = build_kinematic_model(robot, load_xrdf(xrdf))
    x = load_xrdf(xrdf)
    hold = {**dict(x.default_joint_positions or {})}
    if g.lock_jointstate is not None:
        hold.update(
            zip(
                g.lock_jointstate.joint_names,
                g.lock_jointstate.position.view(-1).tolist(),
                strict=True,
            )
        )
    names = list(g.joint_names)
    by_idx = {i: n for n, i in g._name_to_idx_map.items()}
    rng = np.random.default_rng(0)
    lo = {j: ours.lower[k] for k, j in enumerate(ours.actuated_joints)}
    hi = {j: ours.upper[k] for k, j in enumerate(ours.actuated_joints)}
    qs = [g.cspace.default_joint_position.double().cpu().numpy()]
    qs += [np.array([rng.uniform(lo[j], hi[j]) for j in names]) for _ in range(3)]
    worst_frame = worst_sphere = 0.0
    frames = sorted(
        {*g.tool_frames, *(by_idx[int(i)] for i in g._link_sphere_idx_map.cpu().numpy())}
    )
    frames = [f for f in frames if f in ours.frame_names]
    sph = g._link_spheres_tensor[0].double().cpu().numpy()
    owner = [by_idx[int(i)] for i in g._link_sphere_idx_map.cpu().numpy()]
    for q in qs:
        mats = cpu_fk(g.kinematics_config, torch.as_tensor(q))
        val = {**hold, **dict(zip(names, q, strict=True))}
        qo = np.array([val.get(j, 0.0) for j in ours.actuated_joints])
        mine = fk(ours, qo, frames)
        for k, f in enumerate(frames):
            theirs = mats[g._name_to_idx_map[f]]
            worst_frame = max(worst_frame, float(np.abs(theirs - mine[k]).max()))
        if g.total_spheres:
            for s, link in zip(sph, owner, strict=True):
                if link not in frames:
                    continue
                c1 = mats[g._name_to_idx_map[link]] @ np.array([*s[:3], 1.0])
                c2 = mine[frames.index(link)] @ np.array([*s[:3], 1.0])
                worst_sphere = max(worst_sphere, float(np.linalg.norm(c1[:3] - c2[:3])))
    return worst_frame, worst_sphere


def check(name: str, out: Path, xrdf_cmd: list[str]) -> None:
    import torch
    from curobo._src.robot.loader.kinematics_loader import KinematicsLoader
    from curobo._src.robot.loader.kinematics_loader_cfg import KinematicsLoaderCfg
    from curobo._src.robot.loader.util import load_robot_yaml
    from curobo._src.types.content_path import ContentPath
    from curobo._src.types.device_cfg import DeviceCfg

    xrdf, yml, urdf = make_outputs(name, out, xrdf_cmd)
    pkg = {"qut_frankie_description": str(site_packages() / RTB)}
    cpu = DeviceCfg(device=torch.device("cpu"))
    built: dict[str, Any] = {}
    for kind, path in (("xrdf", xrdf), ("yml", yml)):
        try:
            if kind == "xrdf":
                cp = ContentPath(
                    robot_urdf_absolute_path=str(urdf), robot_xrdf_absolute_path=str(xrdf)
                )
            else:
                cp = ContentPath(robot_config_absolute_path=str(path))
            kin = load_robot_yaml(cp)["robot_cfg"]["kinematics"]
            kin.pop("device_cfg", None)
            buf = kin.get("collision_sphere_buffer") or 0.0
            g = KinematicsLoader(KinematicsLoaderCfg(**kin, device_cfg=cpu))
        except Exception as e:
            print(f"{name} {kind}: does NOT load: {type(e).__name__}: {e}")
            continue
        buffers = (
            {s: float(buf) for s in g._name_to_idx_map} if isinstance(buf, float) else dict(buf)
        )
        real = built_robot(g, buffers)
        built[kind] = real
        model = from_xrdf(xrdf.read_text(), urdf) if kind == "xrdf" else from_config(yml, urdf)
        diffs = differences(real, model)
        fd, sd = fk_distance(g, xrdf, urdf, pkg)
        print(
            f"{name} {kind}: loads; {len(real.active_joints)} dof, "
            f"{sum(len(v) for v in real.spheres.values())} spheres; "
            f"FK max |dT| {fd:.1e}, sphere centres {sd:.1e} m"
        )
        for line in diffs:
            print(f"  {kind} differs from model: {line}")
    if len(built) == 2:
        for line in differences(built["yml"], built["xrdf"], built=True):
            print(f"  yml vs xrdf (both cuRobo): {line}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("curobo", type=Path, help="cuRobo source checkout (holds curobo/)")
    ap.add_argument("--out", type=Path, default=Path("/tmp/xrdf_curobo_check"))
    ap.add_argument("--robot", action="append", choices=sorted(ROBOTS))
    ap.add_argument(
        "--python",
        default=str(REPO / ".venv/bin/python"),
        help="the Python with xrdf-tools, example-robot-data and rtb-data that makes the outputs",
    )
    args = ap.parse_args()
    _SITE.append(find_site_packages(args.python))
    sys.path.insert(0, str(args.curobo))
    logging.disable(logging.WARNING)
    cpu_patches()
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.robot or list(ROBOTS):
        check(name, args.out, [args.python, "-m", "xrdf_tools"])


if __name__ == "__main__":
    main()
