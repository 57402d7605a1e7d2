"""The URDF half of ``check_urdf_srdf_readers.py``: urdfdom's model (through pinocchio) of
every example-robot-data URDF and every rtb-data robot xacro (as ``xrdf expand`` writes it)
against ours, and small URDFs urdfdom refuses, which we must refuse or read with a
``urdf-ros-refuses`` warning. Imported by that script once pinocchio is known to be there.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from xrdf_tools.robot.kinematics import build_kinematic_model, fk
from xrdf_tools.robot.urdf_source import parse_robot
from xrdf_tools.robot.xacro_source import load_robot

REPO = Path(__file__).resolve().parents[1]
ERD = "cmeel.prefix/share/example-robot-data/robots"
RTB = "rtbdata/xacro"
TOL = 1e-9

#: rtb-data robot xacros: name -> (xacro below rtbdata/xacro, {package: dir below it})
KUKA = {
    "kr3": "kr3r540",
    "kr5": "kr5_arc",
    "kr6": "kr6r700sixx",
    "kr10": "kr10r1100sixx",
    "kr16": "kr16_2",
    "kr120": "kr120r2500pro",
    "kr150": "kr150_2",
    "kr210": "kr210l150",
    "lbr_iiwa": "lbr_iiwa_14_r820",
}
FRANKIE = "qut_frankie_description"
XACROS: dict[str, tuple[str, dict[str, str]]] = {
    **{
        f"kuka_{k}": (
            f"kuka_description/kuka_{k}/urdf/{f}.xacro",
            {
                f"kuka_{k}_support": f"kuka_description/kuka_{k}",
                "kuka_resources": "kuka_description/kuka_resources",
            },
        )
        for k, f in KUKA.items()
    },
    "abb_irb140": (
        "abb_irb140_description/urdf/irb140.xacro",
        {"abb_irb140": "abb_irb140_description"},
    ),
    "puma560": ("unimation_puma560_description/urdf/puma560_robot.urdf.xacro", {}),
    "ridgeback": ("clearpath_ridgeback_description/urdf/ridgeback.urdf.xacro", {}),
    **{
        f"frankie_{n}": (f"{FRANKIE}/robots/{n}.urdf.xacro", {FRANKIE: FRANKIE})
        for n in (
            *("panda_arm", "panda_arm_hand", "hand", "dual_panda_example", "frankie_arm"),
            *("frankie_arm_hand", "frankieOmni_arm", "frankieOmni_arm_hand"),
        )
    },
    **{
        f"trossen_{n}": (f"trossen_descriptions/urdf/{n}.urdf.xacro", {})
        for n in (
            *("px100", "px150", "pxxls", "rx150", "rx200", "vx250", "vx300", "vx300s"),
            *("vxxmd", "vxxms", "wx200", "wx250", "wx250s", "wxxmd", "wxxms"),
        )
    },
}
SITE: list[Path] = []
#: What a robot's row should say that is no disagreement (filled while checking it).
NOTES: list[str] = []
PY: list[str] = []


def site() -> Path:
    return SITE[0]


def xrdf_cli(*args: str) -> subprocess.CompletedProcess[str]:
    """Our CLI, run by ``--python`` with this checkout first on its path."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    return subprocess.run(
        [PY[0], "-m", "xrdf_tools", *args], capture_output=True, text=True, env=env
    )


def only(ours: set[Any], theirs: set[Any], who: str) -> str:
    """``only ours [...], only WHO [...]`` (pairs as sorted lists)."""
    show = lambda v: sorted(sorted(x) if isinstance(x, frozenset) else x for x in v)  # noqa: E731
    return f"only ours {show(ours - theirs)}, only {who} {show(theirs - ours)}"


def last_line(text: str) -> str:
    lines = [ln for ln in text.strip().splitlines() if ln.strip()]
    return lines[-1][:160] if lines else ""


# ------------------------------------------------------------------------------------------
# URDF: urdfdom's model against ours
# ------------------------------------------------------------------------------------------
def pin_kind(j: Any) -> str:
    """Our joint type for a pinocchio joint model."""
    name = j.shortname()
    if name == "JointModelMimic":
        return "mimic"
    for key, kind in (
        ("RevoluteUnbounded", "continuous"),
        ("RUB", "continuous"),
        ("Revolute", "revolute"),
        ("JointModelR", "revolute"),
        ("Prismatic", "prismatic"),
        ("JointModelP", "prismatic"),
        ("FreeFlyer", "floating"),
        ("Planar", "planar"),
    ):
        if key in name:
            return kind
    return name


def mimic_of(model: Any, j: Any) -> tuple[str, float, float]:
    """``(mimicked joint, multiplier, offset)`` of a pinocchio mimic joint (read from its text:
    the Python binding does not expose them)."""
    text = str(j.extract())
    source = int(re.search(r"Mimicked joint id: (\d+)", text).group(1))  # type: ignore[union-attr]
    mult = float(re.search(r"Mimic scaling: (\S+)", text).group(1))  # type: ignore[union-attr]
    off = float(re.search(r"Mimic offset: (\S+)", text).group(1))  # type: ignore[union-attr]
    return model.names[source], mult, off


def unbounded(model: Any, pj: Any) -> bool:
    """A revolute joint with limits beyond +-1e12, which we read as continuous (documented:
    urdf-limit-unbounded)."""
    lo, hi = model.lowerPositionLimit[pj.idx_q], model.upperPositionLimit[pj.idx_q]
    return bool(min(-lo, hi) >= 1e12)


def _or_inf(v: float | None) -> float:
    return math.inf if v is None else v


def _close(a: float | None, b: float, what: str, out: list[str]) -> None:
    if a is None or not (a == b or math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12)):
        out.append(f"{what}: ours {a}, urdfdom {b}")


def joint_differences(model: Any, robot: Any, mimics: bool = True) -> list[str]:
    out: list[str] = []
    ours = robot.joints
    theirs = {model.names[i]: model.joints[i] for i in range(1, model.njoints)}
    moving = {n for n, j in ours.items() if j.type != "fixed"}
    if moving != set(theirs):
        out.append(f"joints: {only(moving, set(theirs), 'urdfdom')}")
    fixed = {f.name for f in model.frames if f.type == pin.FrameType.FIXED_JOINT} - {"universe"}
    ours_fixed = {n for n, j in ours.items() if j.type == "fixed"}
    if fixed != ours_fixed:
        out.append(f"fixed joints: {only(ours_fixed, fixed, 'urdfdom')}")
    for name in sorted(moving & set(theirs)):
        j, pj = ours[name], theirs[name]
        kind = pin_kind(pj)
        if kind == "mimic":
            src, mult, off = mimic_of(model, pj)
            if (j.mimic_joint, j.mimic_multiplier, j.mimic_offset) != (src, mult, off):
                out.append(
                    f"{name} mimic: ours {j.mimic_joint, j.mimic_multiplier, j.mimic_offset}, "
                    f"urdfdom {src, mult, off}"
                )
            continue
        if j.is_mimic and mimics:
            out.append(f"{name}: ours a mimic of {j.mimic_joint}, urdfdom {kind}")
        if kind != j.type:
            if (j.type, kind) == ("continuous", "revolute") and unbounded(model, pj):
                NOTES.append(
                    f"{name}: limits beyond 1e12 read as continuous (urdf-limit-unbounded)"
                )
            else:
                out.append(f"{name} type: ours {j.type}, urdfdom {kind}")
            continue
        if kind in ("revolute", "prismatic"):
            _close(
                j.lower if j.lower is not None else 0.0,
                model.lowerPositionLimit[pj.idx_q],
                f"{name} lower",
                out,
            )
            _close(
                j.upper if j.upper is not None else 0.0,
                model.upperPositionLimit[pj.idx_q],
                f"{name} upper",
                out,
            )
        if kind in ("revolute", "prismatic", "continuous"):
            # no <limit>: pinocchio says inf, we say None
            _close(_or_inf(j.velocity), model.velocityLimit[pj.idx_v], f"{name} velocity", out)
            _close(_or_inf(j.effort), model.effortLimit[pj.idx_v], f"{name} effort", out)
    return out


def pin_configuration(model: Any, values: dict[str, float]) -> np.ndarray:
    """pinocchio's q for joint values by name (continuous as cos, sin; others neutral)."""
    q = pin.neutral(model)
    for i in range(1, model.njoints):
        j, name = model.joints[i], model.names[i]
        if name not in values or j.nq == 0:
            continue
        v = values[name]
        if pin_kind(j) == "continuous":
            q[j.idx_q], q[j.idx_q + 1] = math.cos(v), math.sin(v)
        elif j.nq == 1:
            q[j.idx_q] = v
    return q


def fk_difference(model: Any, robot: Any, samples: int = 5) -> float:
    """Largest difference of a link pose (4x4 entries: metres and rotation) at the zero and
    ``samples`` random configurations."""
    ours, _ = build_kinematic_model(robot)
    links = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    links = [n for n in links if ours.has_frame(n)]
    data = model.createData()
    rng = np.random.default_rng(0)
    qs = [np.zeros(ours.n_actuated)] + [rng.uniform(ours.lower, ours.upper) for _ in range(samples)]
    worst = 0.0
    for q in qs:
        mine = fk(ours, q, links)
        values = dict(zip(ours.actuated_joints, q.tolist(), strict=True))
        for _ in robot.joints:  # mimic followers, for a model without mimics (chains resolved)
            values.update(
                (n, j.mimic_multiplier * values[j.mimic_joint] + j.mimic_offset)
                for n, j in robot.joints.items()
                if j.is_mimic and j.mimic_joint in values and n not in values
            )
        pin.framesForwardKinematics(model, data, pin_configuration(model, values))
        for k, n in enumerate(links):
            theirs = data.oMf[model.getFrameId(n, pin.FrameType.BODY)].homogeneous
            scale = max(1.0, float(np.abs(theirs[:3, 3]).max()))  # a base moved 1e6 m
            worst = max(worst, float(np.abs(theirs - mine[k]).max()) / scale)
    return worst


def urdf_inputs(names: list[str] | None) -> list[tuple[str, Path, dict[str, str]]]:
    """``(name, robot file, package paths)``: every example-robot-data URDF, then the rtb-data
    xacros."""
    out = []
    for p in sorted((site() / ERD).rglob("*.urdf")):
        out.append(
            (
                p.stem if p.stem not in {o[0] for o in out} else f"{p.parent.parent.name}/{p.stem}",
                p,
                {},
            )
        )
    for name, (rel, pkgs) in XACROS.items():
        out.append((name, site() / RTB / rel, {k: str(site() / RTB / v) for k, v in pkgs.items()}))
    return [o for o in out if not names or o[0] in names]


def check_urdf(name: str, path: Path, pkgs: dict[str, str], out_dir: Path) -> tuple[str, list[str]]:
    """One table row and the disagreements for one robot file."""
    parsed = path
    if path.suffix == ".xacro":
        parsed = out_dir / f"{name}.urdf"
        args = [a for k, v in pkgs.items() for a in ("--package-path", f"{k}={v}")]
        r = xrdf_cli("expand", str(path), *args, "-q", "-o", str(parsed))
        if r.returncode != 0:
            return f"{name:28} expand exit {r.returncode}: {last_line(r.stderr)}", []
    try:
        robot = load_robot(path, package_paths=pkgs)
        build_kinematic_model(robot)
    except Exception as e:
        ours_err = f"{type(e).__name__}: {e}"
        robot = None
    mimics, note = True, ""
    try:
        try:
            model = pin.buildModelFromUrdf(str(parsed), mimic=True)
        except ValueError as e:
            if "mimic" not in str(e):
                raise
            # pinocchio models a mimic only when its source joint comes first in its walk
            model = pin.buildModelFromUrdf(str(parsed))
            mimics, note = (
                False,
                " (mimics as joints: their source comes later in pinocchio's walk)",
            )
    except Exception as e:
        if robot is None:
            return f"{name:28} both refuse (ours: {ours_err[:60]}; urdfdom: {str(e)[:60]})", []
        return f"{name:28} urdfdom REFUSES: {str(e)[:120]}", [f"{name}: urdfdom refuses: {e}"]
    if robot is None and not mimics:
        return f"{name:28} both refuse a mimic (ours: {ours_err[-70:]})", []
    if robot is None:
        return f"{name:28} we REFUSE: {ours_err[:120]}", [f"{name}: we refuse: {ours_err}"]
    NOTES.clear()
    diffs = joint_differences(model, robot, mimics)
    if NOTES:
        note += f" ({len(NOTES)} joint(s) {NOTES[0].split(': ', 1)[1]})"
    dist = fk_difference(model, robot)
    if dist > TOL:
        diffs.append(f"FK differs by {dist:.2e}")
    n_mimic = sum(1 for j in model.joints if j.shortname() == "JointModelMimic")
    row = (
        f"{name:28} {model.njoints - 1:3} joints {n_mimic:2} mimic {len(robot.links):3} links  "
        f"FK max|dT| {dist:.1e}  {'OK' if not diffs else 'DIFFERS'}{note}"
    )
    return row, [f"{name}: {d}" for d in diffs]


# ------------------------------------------------------------------------------------------
# Small URDFs: what urdfdom refuses we refuse, or read with a urdf-ros-refuses warning
# ------------------------------------------------------------------------------------------
_LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
#: name -> the inside of joint j (revolute unless the name starts with another type)
CASES = {
    "complete": _LIMIT,
    "revolute without <limit>": "",
    "prismatic without <limit>": "",
    "continuous without <limit>": "",
    "fixed with <limit lower upper>": '<limit lower="0" upper="1"/>',
    "<limit> without effort": '<limit lower="-1" upper="1" velocity="1"/>',
    "<limit> without velocity": '<limit lower="-1" upper="1" effort="1"/>',
    "<limit> without lower, upper": '<limit effort="1" velocity="1"/>',
    "safety_controller without k_velocity": _LIMIT + '<safety_controller k_position="1"/>',
    "dynamics without damping, friction": _LIMIT + "<dynamics/>",
    "mimic without joint": _LIMIT + "<mimic/>",
    "axis of 2 numbers": _LIMIT + '<axis xyz="0 1"/>',
    "origin rpy of 2 numbers": _LIMIT + '<origin rpy="0 1"/>',
    "limit lower nan": '<limit lower="nan" upper="1" effort="1" velocity="1"/>',
}


def _case_urdf(name: str, inside: str) -> str:
    jtype = (
        name.split()[0] if name.split()[0] in ("prismatic", "continuous", "fixed") else "revolute"
    )
    return (
        f'<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="{jtype}">'
        f'<parent link="a"/><child link="b"/>{inside}</joint></robot>'
    )


def _quiet_urdfdom(text: str) -> bool:
    """Whether urdfdom reads ``text`` (its console messages to stderr silenced)."""
    saved = os.dup(2)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 2)
        try:
            pin.buildModelFromXML(text)
            return True
        except Exception:
            return False
        finally:
            os.dup2(saved, 2)
            os.close(saved)


def check_cases() -> list[tuple[str, list[str]]]:
    """One row and the disagreements per case of :data:`CASES`."""
    out = []
    for name, inside in CASES.items():
        text = _case_urdf(name, inside)
        theirs = _quiet_urdfdom(text)
        try:
            rules = {w.rule for w in parse_robot(text, "case.urdf").warnings}
            ours = "warns urdf-ros-refuses" if "urdf-ros-refuses" in rules else "reads"
        except Exception as e:
            ours = f"refuses ({str(e).split(': ', 1)[-1][:50]})"
        bad = not theirs and ours == "reads"
        row = f"{name:38} urdfdom {'reads' if theirs else 'REFUSES':8} xrdf-tools {ours}"
        out.append((row + ("  DIFFERS" if bad else ""), [f"case {name}: we read it"] * bad))
    return out
