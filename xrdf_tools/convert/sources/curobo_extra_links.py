"""cuRobo ``extra_links`` → XRDF ``add_frame`` modifiers.

An XRDF ``add_frame`` is a frame fixed to a parent frame. A cuRobo extra link can do more:
move on its own joint (``joint_type`` ``X_PRISM`` … ``Z_ROT_NEG``: the virtual floating base of
cuRobo's Unitree G1 config) and take a URDF link as its child (``child_link_name``: that link
and everything below it then hang from the extra link). Neither fits an XRDF, so:

* a moving extra link is written FIXED at its zero pose and its joint is left out of the
  c-space (one warning per link; the c-space and the locks do not repeat it);
* a re-parented link that the extra links between leave where the URDF puts it (identity
  transforms, as G1's) stays on its URDF parent, which is said; one they move is refused:
  no XRDF places that link where cuRobo does.

Keys an extra link may carry that no XRDF holds (a mass, an inertia) are said dropped; the keys
that describe only how it moves (limits, axis, mimic) go with the moving link's warning.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from typing import Any

from ...diagnostics import Severity
from ...util.errors import did_you_mean
from ...util.rotations import Matrix3, matrix_from_quat
from ...xrdf.model import AddFrame, Orientation
from . import known_frame
from .curobo_kin import KinSection
from .curobo_spheres import is_num

__all__ = ["read_extra_links"]

#: A rigid transform: rotation matrix and translation.
Pose = tuple[Matrix3, tuple[float, float, float]]

#: What an XRDF add_frame takes from an extra link (``child_link_name`` is checked apart).
FRAME_KEYS = frozenset(
    {"parent_link_name", "link_name", "joint_name", "joint_type", "fixed_transform"}
)
#: How an extra link moves: lost with a moving link (said there), unread on a fixed one.
MOTION_KEYS = frozenset(
    {
        "joint_limits",
        "joint_velocity_limits",
        "joint_axis",
        "joint_offset",
        "joint_effort_limit",
        "mimic_joint_name",
    }
)
#: A re-parenting closer than this to the URDF's own placement leaves the link in place.
SAME_PLACE_M = 1e-9
SAME_PLACE_RAD = 1e-9


def read_extra_links(k: KinSection) -> None:
    """Add a frame per extra link, each after its parent; say what an XRDF cannot hold."""
    links = k.mapping("extra_links")
    poses: dict[str, tuple[str, Pose]] = {}  # added frame -> (parent, its fixed transform)
    for name, spec in _parents_first(links, k.frames):
        added = _read_one(k, name, spec)
        if added is not None:
            k.d.modifiers.append(added)
            k.frames.append(added.frame_name)
            poses[added.frame_name] = (added.parent_frame_name, _pose(added))
    for name, spec in links.items():
        child = spec.get("child_link_name")
        if child is not None:
            link = str(spec.get("link_name") or name)
            _read_child(k, str(name), link, str(child), poses)


def _parents_first(links: Mapping[str, Any], frames: Collection[str]) -> list[tuple[str, Any]]:
    """The extra links, each after the extra link it hangs from (cuRobo builds its tree from
    them in any order; an XRDF adds a frame only to one that exists), else in the file's order;
    those whose parent never comes (no such frame, a loop) last, where they are said."""
    known = set(frames)
    pending = [(str(n), spec) for n, spec in links.items()]
    out: list[tuple[str, Any]] = []
    while pending:
        ready = [
            (n, spec)
            for n, spec in pending
            if not isinstance(spec, Mapping) or str(spec.get("parent_link_name", "")) in known
        ]
        if not ready:
            break
        out += ready
        known |= {str(spec.get("link_name") or n) for n, spec in ready if isinstance(spec, Mapping)}
        pending = [item for item in pending if item not in ready]
    return out + pending


def _read_one(k: KinSection, name: str, spec: Any) -> AddFrame | None:
    w = k.kp("extra_links", name)
    if not isinstance(spec, Mapping):
        raise k.fail(f"extra_links.{name} must be a mapping", "extra_links", name)
    parent = str(spec.get("parent_link_name", ""))
    link = str(spec.get("link_name") or name)
    if not known_frame(parent, k.frames, k.rep, f"{w}.parent_link_name", "extra link parent"):
        return None
    ft = spec.get("fixed_transform") or [0, 0, 0, 1, 0, 0, 0]
    if not (isinstance(ft, list) and len(ft) == 7 and all(is_num(v) for v in ft)):
        raise k.fail(
            f"extra_links.{name}.fixed_transform must be [x, y, z, qw, qx, qy, qz]",
            "extra_links",
            name,
            "fixed_transform",
        )
    for key in spec:
        if key not in FRAME_KEYS and key not in MOTION_KEYS and key != "child_link_name":
            k.rep.report(
                "convert-dropped-key",
                f"extra_links.{name}.{key} has no XRDF equivalent; dropped",
                f"{w}.{key}",
            )
    x, y, z, qw, qx, qy, qz = (float(v) for v in ft)
    if qw == qx == qy == qz == 0.0:
        raise k.fail(
            f"extra_links.{name}.fixed_transform: the quaternion (qw, qx, qy, qz) is all "
            "zeros, which is no rotation; write 1, 0, 0, 0 for none",
            "extra_links",
            name,
            "fixed_transform",
        )
    if link in k.frames:
        where = "in the URDF" if link in k.tree.links else "as an earlier extra link"
        k.rep.report(
            "convert-duplicate-frame", f"extra link '{link}' already exists {where}; not added", w
        )
        return None
    joint = str(spec.get("joint_name") or f"{link}_joint")
    _check_joint_name(k, name, joint, "joint_name" in spec)
    joint_type = str(spec.get("joint_type", "FIXED"))
    if joint_type.upper() != "FIXED":
        _report_moving(k, name, joint, joint_type, spec.get("joint_limits"))
    return AddFrame(
        frame_name=link,
        parent_frame_name=parent,
        joint_name=joint,
        position=(x, y, z),
        orientation=Orientation.from_wxyz(qw, qx, qy, qz),
        joint_type="FIXED",
    )


def _check_joint_name(k: KinSection, name: str, joint: str, written: bool) -> None:
    """Refuse, where it is written, a joint name the URDF or an earlier extra link has."""
    earlier = [
        m.frame_name for m in k.d.modifiers if isinstance(m, AddFrame) and m.joint_name == joint
    ]
    if joint not in k.tree.joints and not earlier:
        return
    owner = f"of extra link '{earlier[0]}'" if earlier else "of the URDF"
    raise k.fail(
        f"extra_links.{name}: joint '{joint}' is already a joint {owner}; give this extra "
        "link a joint_name of its own",
        "extra_links",
        name,
        "joint_name" if written else "link_name",
    )


def _report_moving(k: KinSection, name: str, joint: str, joint_type: str, limits: Any) -> None:
    k.moving_joints[joint] = name
    span = ""
    if isinstance(limits, list) and len(limits) == 2 and all(is_num(v) for v in limits):
        span = f", limits [{float(limits[0])!r}, {float(limits[1])!r}]"
    k.rep.report(
        "convert-dropped-key",
        f"extra link '{name}' moves in cuRobo (joint '{joint}', {joint_type}{span}); an XRDF "
        f"add_frame cannot move, so it is written FIXED at its zero pose and '{joint}' is left "
        "out of the c-space",
        k.kp("extra_links", name, "joint_type"),
    )


def _read_child(
    k: KinSection, name: str, link: str, child: str, poses: Mapping[str, tuple[str, Pose]]
) -> None:
    """``child_link_name``: said when the URDF already puts the child where cuRobo does,
    refused when it does not."""
    where = k.kp("extra_links", name, "child_link_name")
    joint = k.tree.parent_joint.get(child)
    if link not in poses:
        return  # the extra link itself was not added, and that is said
    if joint is None:
        why = (
            "is the URDF's root"
            if child in k.tree.links
            else f"is not a link of the URDF{did_you_mean(child, k.tree.links)}"
        )
        k.rep.report(
            "convert-dropped-key",
            f"extra link '{name}' takes '{child}' as its child (child_link_name), which {why}; "
            "dropped",
            where,
        )
        return
    urdf_parent = k.tree.joints[joint].parent
    top, offset = _chain_to_urdf(link, poses)
    moved = top != urdf_parent or _moves(offset)
    if moved:
        raise k.fail(
            f"extra link '{name}' takes URDF link '{child}' as its child (child_link_name), "
            f"{_how_far(top, urdf_parent, offset)} from where the URDF's joint '{joint}' puts "
            f"it: an XRDF add_frame cannot re-parent a link, so no XRDF places '{child}' and "
            f"the links below it where cuRobo does; move that offset into joint '{joint}' of "
            "the URDF",
            "extra_links",
            name,
            "child_link_name",
        )
    k.rep.report(
        "convert-dropped-key",
        f"extra link '{name}' takes URDF link '{child}' as its child (child_link_name); an "
        f"XRDF add_frame cannot re-parent a link, so '{child}' stays on '{urdf_parent}' "
        f"(joint '{joint}'): the same place, the extra links between being identity "
        "transforms at their zero pose",
        where,
        severity=Severity.INFO,
    )


def _pose(frame: AddFrame) -> Pose:
    return matrix_from_quat(frame.orientation.as_wxyz()), frame.position


def _compose(a: Pose, b: Pose) -> Pose:
    """``a`` then ``b`` (``b`` given in ``a``'s frame)."""
    (ra, ta), (rb, tb) = a, b
    rot = tuple(
        tuple(sum(ra[i][m] * rb[m][j] for m in range(3)) for j in range(3)) for i in range(3)
    )
    t = tuple(sum(ra[i][m] * tb[m] for m in range(3)) + ta[i] for i in range(3))
    return rot, t  # type: ignore[return-value]


def _chain_to_urdf(link: str, poses: Mapping[str, tuple[str, Pose]]) -> tuple[str, Pose]:
    """The first frame above ``link`` that is not an extra link, and ``link``'s pose in it."""
    pose: Pose = (((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0))
    frame = link
    for _ in range(len(poses) + 1):  # the parents were added first: no cycle
        if frame not in poses:
            break
        parent, local = poses[frame]
        pose = _compose(local, pose)
        frame = parent
    return frame, pose


def _moves(pose: Pose) -> bool:
    return math.hypot(*pose[1]) > SAME_PLACE_M or _angle(pose) > SAME_PLACE_RAD


def _angle(pose: Pose) -> float:
    rot = pose[0]
    cos = (rot[0][0] + rot[1][1] + rot[2][2] - 1.0) / 2.0
    return math.acos(max(-1.0, min(1.0, cos)))


def _how_far(top: str, urdf_parent: str, pose: Pose) -> str:
    if top != urdf_parent:
        return f"under '{top}' instead of '{urdf_parent}'"
    mm, deg = math.hypot(*pose[1]) * 1000.0, math.degrees(_angle(pose))
    return f"{mm:.3g} mm and {deg:.3g}° away"
