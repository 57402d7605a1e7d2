"""Sources → XRDF: a URDF plus a MoveIt SRDF (+ joint_limits.yaml) or a cuRobo robot YAML.

:func:`convert` is pure: it reads the given files, returns the :class:`~xrdf_tools.xrdf.model.Xrdf`
and a list of diagnostics — one for every value that was not taken from the inputs (default
limits, chosen group/state/tool frame, dropped keys, unknown names, missing spheres). Mapping
rules and behaviour: ``docs/convert.md``; the readers: ``docs/format.md``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic, Severity
from ..robot.core import as_robot
from ..util.errors import SourceError, did_you_mean
from ..util.frozen import FrozenMap
from ..util.text import name_list
from ..xrdf.model import (
    AddFrame,
    CollisionSection,
    CSpace,
    GeometryGroup,
    SelfCollisionSection,
    Xrdf,
)
from ..xrdf.readers import choose_version, parse_target
from ..xrdf.versions import to_version
from .base_frame import LinkPlace, based_tree, check_reachable
from .sources import Draft, Reporter, RobotTree

if TYPE_CHECKING:
    import yourdfpy

    from ..robot.core import Robot
    from ..robot.packages import PackagePaths
    from ..robot.tool_frame import ToolFrameGuess

__all__ = [
    "DEFAULT_ACCELERATION",
    "DEFAULT_JERK",
    "ConvertOptions",
    "convert",
    "convert_files",
]

DEFAULT_ACCELERATION = 10.0  # rad/s², what MoveIt's Ruckig smoothing uses for unbounded joints
DEFAULT_JERK = 1000.0  # rad/s³


@dataclass(frozen=True)
class ConvertOptions:
    """Inputs and choices of a conversion (the CLI flags of ``xrdf convert``)."""

    srdf: str | os.PathLike[str] | None = None
    joint_limits: str | os.PathLike[str] | None = None
    curobo: str | os.PathLike[str] | None = None
    group: str | None = None
    state: str | None = None
    tool_frames: tuple[str, ...] = ()
    acceleration: float | None = None
    jerk: float | None = None
    #: XRDF version to write; None chooses: the version every reader (or the target) loads.
    format_version: str | None = None
    geometry_name: str | None = None
    #: The program that will read the file (``curobo``, ``cumotion``, ``isaac-sim``).
    target: str | None = None
    #: Several SRDF planning groups: the c-space is their union, in this order (``--group``
    #: repeated); ``group`` is the single-group form.
    groups: tuple[str, ...] = ()
    #: The c-space without an SRDF group: these actuated joints (``--joints``) ...
    joints: tuple[str, ...] = ()
    #: ... or the actuated joints of these ``(base_link, tip_link)`` chains (``--chain``).
    chains: tuple[tuple[str, str], ...] = ()

    def planning_groups(self) -> tuple[str, ...]:
        """``groups``, or ``(group,)``, or nothing."""
        if self.group is not None and self.group not in self.groups:
            return (self.group, *self.groups)
        return self.groups


def convert_files(
    robot: str | os.PathLike[str],
    options: ConvertOptions,
    *,
    xacro_args: dict[str, str] | None = None,
    package_paths: PackagePaths | None = None,
) -> tuple[Xrdf, list[Diagnostic], yourdfpy.URDF]:
    """Load ``robot`` (URDF or xacro) and :func:`convert`; also returns the loaded URDF."""
    from ..robot.xacro_source import load_robot

    loaded = load_robot(robot, xacro_args=xacro_args, package_paths=package_paths)
    x, diags = convert(loaded, options)
    return x, diags, loaded.urdf


def convert(
    urdf: Robot | yourdfpy.URDF | RobotTree, options: ConvertOptions
) -> tuple[Xrdf, list[Diagnostic]]:
    """Build an XRDF from a loaded robot and the source files named in ``options``."""
    robot = None if isinstance(urdf, RobotTree) else as_robot(urdf)
    tree = urdf if isinstance(urdf, RobotTree) else as_robot(urdf).tree
    collision_links = None if robot is None else frozenset(robot.collision_counts)
    if options.format_version not in (None, "1.0", "2.0"):
        raise SourceError(
            f"unsupported format version '{options.format_version}'; choose 1.0 or 2.0"
        )
    parse_target(options.target)  # an unknown target fails before any file is read
    if options.srdf is not None and options.curobo is not None:
        raise SourceError("give either an SRDF or a cuRobo config, not both")
    draft = Draft()
    given = _cspace_choice(tree, options, draft, collision_links)
    if options.curobo is not None:
        from .sources.curobo import read_curobo

        if given:
            raise SourceError("--joints/--chain choose the c-space; a cuRobo config has its own")
        read_curobo(options.curobo, tree, draft)
        if options.planning_groups() or options.state is not None:
            raise SourceError("--group and --state apply to an SRDF, not to a cuRobo config")
    elif options.srdf is not None:
        from .sources.cspace import report_unplannable_joints
        from .sources.srdf import load_srdf, read_srdf

        srdf = load_srdf(
            options.srdf,
            xacro_args=None if robot is None else robot.xacro_args,
            package_paths=None if robot is None else robot.package_paths,
        )
        read_srdf(
            srdf,
            tree,
            group=options.planning_groups(),
            state=options.state,
            draft=draft,
            choose=not given,
        )
        used = draft.group.split("+") if draft.group else []
        draft.diagnostics.extend(report_unplannable_joints(srdf, used, tree).diagnostics)
    elif options.planning_groups() or options.state is not None:
        raise SourceError("--group and --state need --srdf")
    if options.joint_limits is not None:
        from .sources.moveit_limits import read_joint_limits

        xacro_args = None if robot is None else robot.xacro_args
        read_joint_limits(options.joint_limits, tree, draft, xacro_args)
    if robot is not None:
        from .sources.drake import read_drake

        read_drake(robot, tree, draft)
    place = None if robot is None else partial(robot.place, "link")
    return complete(draft, tree, options, collision_links, place)


def complete(
    draft: Draft,
    tree: RobotTree,
    options: ConvertOptions,
    collision_links: Collection[str] | None = None,
    place: LinkPlace | None = None,
) -> tuple[Xrdf, list[Diagnostic]]:
    """Fill what the sources did not say (each fill reported) and build the model.

    ``collision_links`` (the links with collision geometry) refine the tool-frame guess;
    ``place`` says where a link is written (for errors about the tree)."""
    from .sources.cspace import apply_default_cspace
    from .targets import order_for_target

    rep = Reporter(tree.path)
    diags = list(draft.diagnostics)
    tree = based_tree(tree, draft, rep, place)

    # --- c-space
    default_tool = None
    if draft.cspace is None:
        default_tool = apply_default_cspace(
            tree, draft, rep, collision_links, srdf_given=options.srdf is not None
        )
    cspace = order_for_target(list(draft.cspace or []), tree, options.target, rep)
    if not cspace:
        rep.report(
            "convert-empty-cspace",
            "the c-space is empty: no reader can plan for this robot; choose its joints with "
            "--joints, --chain or --srdf (and --group)",
        )

    diags.extend(_uncarried_limits(draft, cspace))
    accel = _limits("acceleration", cspace, draft, options.acceleration, tree, rep)
    jerk = _limits("jerk", cspace, draft, options.jerk, tree, rep)
    defaults = _default_positions(draft, tree, cspace, rep)
    tool_frames = _tool_frames(draft, tree, options, cspace, rep, collision_links, default_tool)
    geometry, world, self_c = _collision(draft, tree, options, rep, collision_links)

    x = Xrdf(
        # 1.0 holds everything the sources can say (negative radii included); converting to
        # 2.0 below reports what 2.0 cannot express.
        format_version="1.0",
        cspace=CSpace(tuple(cspace), tuple(accel), tuple(jerk)),
        modifiers=tuple(draft.modifiers),
        default_joint_positions=FrozenMap(defaults),
        tool_frames=tuple(tool_frames),
        world_collision=world,
        self_collision=self_c,
        geometry=geometry,
    )
    check_reachable(x, tree)
    version, why = choose_version(x, options.format_version, parse_target(options.target))
    if why:
        rep.report("convert-version", why)
    x, vdiags = to_version(x, version)
    return x, [*diags, *rep.diagnostics, *vdiags]


_DEFAULT_LIMIT = {"acceleration": DEFAULT_ACCELERATION, "jerk": DEFAULT_JERK}


def _limits(
    kind: str,
    cspace: list[str],
    draft: Draft,
    cli: float | None,
    tree: RobotTree,
    rep: Reporter,
) -> list[float]:
    """One limit per c-space joint: the sources', else ``--KIND``, else the default (reported;
    at the joint limits file when it turns the limit off for those joints)."""
    given = draft.limits(kind)
    missing = [j for j in cspace if j not in given]
    value = cli if cli is not None else _DEFAULT_LIMIT[kind]
    if missing:
        origin = f"--{kind}" if cli is not None else "the default"
        sev = Severity.INFO if cli is not None else Severity.WARNING
        unit = _limit_unit(kind, [tree.joints[j].type for j in missing])
        turned_off = [j for j in missing if (kind, j) in draft.limits_off]
        why = ""
        if turned_off:
            why = (
                f"; the joint limits file turns it off (has_{kind}_limits: false) for "
                f"{name_list(turned_off, 6)}, and an XRDF needs one"
            )
        rep.report(
            f"convert-default-{kind}",
            f"no {kind} limit in the inputs for {name_list(missing, 12)}: using {origin} "
            f"{value:g} {unit}" + ("" if cli is not None else f" (set --{kind})") + why,
            severity=sev,
            at=draft.limits_off[(kind, turned_off[0])] if turned_off else None,
        )
    return [given.get(j, value) for j in cspace]


def _uncarried_limits(draft: Draft, cspace: list[str]) -> list[Diagnostic]:
    """One warning, at the first such joint of the joint limits file, naming the c-space joints
    whose MoveIt velocity or position limits are tighter than the URDF's: the XRDF cannot
    carry them and its readers take the URDF's."""
    found = [(j, draft.uncarried_limits[j]) for j in cspace if j in draft.uncarried_limits]
    if not found:
        return []
    first = min((d for _, d in found), key=lambda d: (d.line or 0, d.col or 0))
    listed = name_list((f"{j}: {d.message}" for j, d in found), 8, sep="; ")
    message = (
        f"MoveIt limits tighter than the URDF's are lost for {len(found)} c-space joint(s): "
        f"{listed}. An XRDF holds no velocity or position limits and its readers take the "
        "URDF's, so the planner may move these joints faster or farther than MoveIt does; to "
        "keep them, set them in the URDF's <limit>"
    )
    return [replace(first, message=message)]


def _limit_unit(kind: str, types: list[str]) -> str:
    """The unit of an acceleration or jerk limit for joints of these types (a prismatic
    joint's is in metres)."""
    power = "²" if kind == "acceleration" else "³"
    if all(t == "prismatic" for t in types):
        return f"m/s{power}"
    if any(t == "prismatic" for t in types):
        return f"rad/s{power} (m/s{power} for the prismatic ones)"
    return f"rad/s{power}"


def _default_positions(
    draft: Draft, tree: RobotTree, cspace: list[str], rep: Reporter
) -> dict[str, float]:
    """Default positions: the sources', else 0 (or the middle of limits that exclude 0),
    clamped to the URDF limits; c-space joints first, then the others in tree order."""
    defaults: dict[str, float] = {}
    missing = []
    for j in cspace:
        if j in draft.defaults:
            defaults[j] = draft.defaults[j]
        else:
            defaults[j] = _neutral_position(tree, j)
            missing.append(j)
    for j, v in draft.defaults.items():
        if j not in defaults:
            defaults[j] = v
    if missing:
        rep.report(
            "convert-default-positions",
            f"no default position in the inputs for {name_list(missing, 12)}: using 0 (or the "
            "middle of the limits when 0 is outside them)",
        )
    for j, v in list(defaults.items()):
        defaults[j] = _clamped(tree, j, v, rep, draft.default_at.get(j))
    defaults |= _locked_off_zero(tree, defaults, rep)
    order = tree.joint_order()
    aux = sorted((j for j in defaults if j not in cspace), key=lambda j: order.get(j, 1 << 30))
    return {j: defaults[j] for j in [*cspace, *aux]}


def _locked_off_zero(
    tree: RobotTree, defaults: Mapping[str, float], rep: Reporter
) -> dict[str, float]:
    """Defaults for the actuated joints outside the c-space whose limits exclude 0 (a leg's
    knee, a lift's column): the XRDF means 0 clamped to the limits for them, but cuRobo's
    reader locks a joint without a default at 0.0, outside its limits, a pose nothing was
    checked in; written out, every reader holds them where the mask was computed. A joint
    whose limits are reversed has no position that fits (the URDF check warns): none is
    written, which the XRDF's lint would refuse."""
    off = {
        j: info.unset_position
        for j, info in ((j, tree.joints[j]) for j in tree.actuated_joints())
        if j not in defaults and info.unset_position != 0.0 and not info.limits_reversed
    }
    if off:
        values = [f"{j} = {v:g}" for j, v in off.items()]
        rep.report(
            "convert-locked-default",
            f"{len(off)} joint(s) outside the c-space have limits that exclude 0: "
            f"{name_list(values, 6)}; written as default positions (0 clamped to the limits, "
            "what an absent default means), as cuRobo locks a joint without one at 0.0, "
            "outside its limits",
            severity=Severity.INFO,
        )
    return off


def _neutral_position(tree: RobotTree, joint: str) -> float:
    info = tree.joints[joint]
    lo = info.lower if info.lower is not None else 0.0
    hi = info.upper if info.upper is not None else 0.0
    if info.type != "continuous" and lo <= hi and not lo <= 0.0 <= hi:
        return (lo + hi) / 2
    return 0.0


def _clamped(
    tree: RobotTree,
    joint: str,
    value: float,
    rep: Reporter,
    at: tuple[str, int | None] | None = None,
) -> float:
    """``value`` inside the joint's URDF limits, reported (at ``at``, where the value was read,
    when known) when it was not."""
    info = tree.joints[joint]
    low, high = info.lower, info.upper
    if info.type == "continuous" or low is None or high is None or low > high:
        return value
    if low <= value <= high:
        return value
    turned = _turned_into(value, low, high) if info.type == "revolute" else None
    if turned is not None:
        rep.report(
            "convert-clamped-default",
            f"default position {value:g} of '{joint}' is outside its URDF limits [{low:g}, "
            f"{high:g}]; the same angle a full turn away, {turned:g}, is inside them: taken "
            "(the same pose)",
            at=at,
        )
        return turned
    clamped = min(max(value, low), high)
    rep.report(
        "convert-clamped-default",
        f"default position {value:g} of '{joint}' is outside its URDF limits [{low:g}, "
        f"{high:g}]; clamped to {clamped:g}",
        at=at,
    )
    return clamped


def _turned_into(value: float, low: float, high: float) -> float | None:
    """``value`` turned by whole turns into ``[low, high]`` (the nearest such angle), or None
    when no whole turn lands there: a revolute joint at ``value`` and at the result has the
    same pose (an SRDF state written as -90° for a joint limited to [0.33, 5.95] rad)."""
    if not math.isfinite(value):
        return None
    turn = 2.0 * math.pi
    k = math.ceil((low - value) / turn) if value < low else math.floor((high - value) / turn)
    turned = value + k * turn
    return turned if low <= turned <= high else None


def _tool_frames(
    draft: Draft,
    tree: RobotTree,
    options: ConvertOptions,
    cspace: list[str],
    rep: Reporter,
    collision_links: Collection[str] | None,
    default_tool: ToolFrameGuess | None,
) -> list[str]:
    """``--tool-frame`` (checked), else the sources', else a guess at the end of each branch
    of the c-space."""
    from .sources.cspace import guessed_tool_frames

    frames = set(tree.links) | {m.frame_name for m in draft.modifiers if isinstance(m, AddFrame)}
    # a frame given twice (--tool-frame tool0 --tool-frame tool0) is one tool frame
    tool_frames = list(dict.fromkeys(options.tool_frames)) or list(draft.tool_frames)
    for t in options.tool_frames:
        if t in draft.offered_frames and t not in frames:
            from .sources.drake import take_offered_frame

            take_offered_frame(draft, tree, t, rep)
            frames.add(t)
        if t not in frames:
            raise SourceError(
                f"--tool-frame '{t}' is not a link of the URDF{did_you_mean(t, frames)}"
            )
    if not tool_frames and cspace:
        tool_frames = guessed_tool_frames(tree, cspace, rep, collision_links, default_tool)
    return tool_frames


def _collision(
    draft: Draft,
    tree: RobotTree,
    options: ConvertOptions,
    rep: Reporter,
    collision_links: Collection[str] | None = None,
) -> tuple[FrozenMap[str, GeometryGroup], CollisionSection, SelfCollisionSection]:
    """The geometry group of the sources' spheres and the two collision sections."""
    name = options.geometry_name or draft.geometry_name or f"{_robot_stem(tree)}_collision_spheres"
    spheres = {k: tuple(v) for k, v in (draft.spheres or {}).items() if v}
    if not spheres:
        fit = "--fit-spheres"
        if collision_links:  # a URDF of <sphere> collisions has them, and nothing says so
            fit += (
                f": it fits them to the collision geometry of the URDF's {len(collision_links)}"
                " link(s) that have it and takes <sphere> elements as they are"
            )
        rep.report(
            "convert-no-spheres",
            "NO COLLISION SPHERES in the inputs: the XRDF has an empty geometry group, so "
            f"cuRobo/cuMotion will not check collisions for this robot. Add spheres ({fit}; "
            "or the Isaac Sim sphere editor, or the SRDF/cuRobo source)",
        )
    ignore = {a: tuple(bs) for a, bs in draft.ignore.items() if bs}
    geometry = FrozenMap({name: GeometryGroup(FrozenMap(spheres))})
    world = CollisionSection(name, FrozenMap(draft.world_buffer))
    self_c = SelfCollisionSection(name, FrozenMap(draft.self_buffer), FrozenMap(ignore))
    return geometry, world, self_c


def _cspace_choice(
    tree: RobotTree,
    options: ConvertOptions,
    draft: Draft,
    collision_links: Collection[str] | None,
) -> bool:
    """Apply ``--joints``/``--chain`` to ``draft``; whether one was given."""
    if not options.joints and not options.chains:
        return False
    if options.planning_groups():
        raise SourceError("give either --group or --joints/--chain, not both")
    from .sources.cspace import apply_cspace_choice

    return apply_cspace_choice(
        tree,
        draft,
        joints=options.joints,
        chains=options.chains,
        collision_links=collision_links,
    )


def with_spheres(x: Xrdf, spheres: dict[str, Sequence[object]]) -> Xrdf:
    """``x`` with the spheres of its world-collision group replaced (for ``--fit-spheres``)."""
    from ..xrdf.model import Sphere

    if x.geometry is None or x.world_collision is None:
        return x
    name = x.world_collision.geometry
    clean = {k: tuple(s for s in v if isinstance(s, Sphere)) for k, v in spheres.items() if v}
    return x.replace(geometry=x.geometry.set(name, GeometryGroup(FrozenMap(clean))))


def _robot_stem(tree: RobotTree) -> str:
    name = tree.name or Path(tree.path).stem
    for suffix in ("_robot", "_description"):
        if name.endswith(suffix) and len(name) > len(suffix):
            name = name[: -len(suffix)]
    return name.strip("/") or "robot"
