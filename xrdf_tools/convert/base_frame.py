"""Which part of the URDF is the robot: the tree walked from the base the sources choose.

A URDF with disconnected parts (cuRobo ships some) is usable when a base is chosen (a cuRobo
config's ``base_link``: ``set_base_frame``); the links it cannot reach are reported. Without a
chosen base such a URDF is an input error placed at the smallest part's root (a link copied in
by mistake, or a sensor frame left unattached). A URDF whose root holds the robot by a floating
or planar joint gets the base below it.
"""

from __future__ import annotations

from collections.abc import Callable

from ..util.errors import SourceError
from ..util.text import name_list
from ..xrdf.model import SetBaseFrame, Xrdf
from .sources import Draft, Reporter, RobotTree

__all__ = ["LinkPlace", "based_tree", "check_reachable"]

#: Where a link is written: ``link -> (file, line)`` (:meth:`Robot.place` of a link).
LinkPlace = Callable[[str], tuple[str, int | None]]


def based_tree(
    tree: RobotTree, draft: Draft, rep: Reporter, place: LinkPlace | None = None
) -> RobotTree:
    """The tree walked from the base the sources chose (``set_base_frame``), else the root.

    A URDF whose root holds the robot by a floating or planar joint gets the base below it
    (:func:`_floating_base`). ``place`` locates the error of a URDF of several parts.
    """
    base = next((m.frame for m in draft.modifiers if isinstance(m, SetBaseFrame)), None)
    if base is None and len(tree.roots) == 1:
        base = _floating_base(tree, draft, rep)
    if base is None or base not in tree.links:
        if len(tree.roots) > 1:
            stray = smallest_part(tree)
            path, line = place(stray) if place is not None else (tree.path, None)
            raise SourceError(
                f"the URDF is not one tree: {len(tree.roots)} links have no parent joint "
                f"({name_list(tree.roots, 5)}; the smallest part starts at '{stray}'); a "
                "cuRobo config's base_link chooses the part to use",
                path=path,
                line=line,
            )
        return tree
    based = tree.with_root(base)
    reach = {base, *based.descendants(base)}
    lost = [link for link in tree.links if link not in reach]
    if len(tree.roots) > 1 and lost:
        shown = name_list(lost)
        rep.report(
            "convert-unreachable-links",
            f"the URDF is not one tree: {len(lost)} link(s) cannot be reached from the base "
            f"'{base}' and are not part of the robot ({shown})",
        )
    return based


def smallest_part(tree: RobotTree) -> str:
    """The root of the part of fewest links (the later one in the file on a tie): the part
    least likely to be the robot."""
    sizes = [(len(tree.descendants(root)), -i, root) for i, root in enumerate(tree.roots)]
    return min(sizes)[2]


def _floating_base(tree: RobotTree, draft: Draft, rep: Reporter) -> str | None:
    """The child of the lowest floating or planar joint on the single path down from the
    root (a humanoid's 'world' to 'pelvis', a mobile base's 'odom' to 'base_footprint'), made
    the XRDF's base with ``set_base_frame`` (reported), or None.

    No reader moves such a joint and cuRobo cannot load a robot whose base is above one
    ("Joint type not supported"); the robot below it is what a planner plans for.
    """
    link, found = tree.root, None
    while len(kids := tree.child_joints.get(link, ())) == 1:
        joint = tree.joints[kids[0]]
        if joint.type in ("floating", "planar"):
            found = joint
        link = joint.child
    if found is None:
        return None
    draft.modifiers.insert(0, SetBaseFrame(found.child))
    above = list(reversed(tree.ancestors(found.child)))  # all of them: the path is single
    rep.report(
        "convert-floating-base",
        f"'{found.name}' is a {found.type} joint above the robot, which no reader moves "
        f"(cuRobo cannot load it): the XRDF's base is '{found.child}' (set_base_frame), "
        f"without {name_list(above)} above it",
    )
    return found.child


def check_reachable(x: Xrdf, tree: RobotTree) -> None:
    """The sources name only frames below the chosen base (else :class:`SourceError`)."""
    from ..robot.binding import unreachable_frames

    lost = sorted({f for f, _ in unreachable_frames(x, tree)})
    if lost:
        raise SourceError(
            f"frames used by the XRDF cannot be reached from the base '{tree.root}': "
            f"{name_list(lost)}",
            path=tree.path,
        )
