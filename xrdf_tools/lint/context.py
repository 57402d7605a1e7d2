"""What a rule sees: the parsed YAML tree with positions, a lenient view of the XRDF sections,
and (with ``--urdf``) the loaded :class:`~xrdf_tools.robot.core.Robot` with its kinematic model.

Rules never raise on malformed input: every accessor here tolerates wrong types and returns
``None`` or nothing for parts that are not shaped as the spec says (the ``wrong-type`` rule
reports those). Heavy URDF machinery is imported only when a URDF is given.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

from ..diagnostics import RuleInfo, Severity
from ..util.errors import XrdfToolsError, YamlError
from ..util.numbers import MAX_LENGTH, within
from ..xrdf.shape import SUPPORTED_VERSIONS, version_string
from ..yaml.io import YamlDocument, YMap, YNode, YScalar, YSeq, is_finite, key_of, parse_yaml

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..robot.kinematics import KinematicModel
    from ..xrdf.model import Xrdf

#: Section spelled ``collision`` in 1.0 and ``world_collision`` in 2.0.
WORLD_KEYS = ("collision", "world_collision")


@dataclass(frozen=True)
class Problem:
    """One finding of a rule, before the framework adds the rule id and configured severity.

    ``severity`` overrides the rule's default for this one finding (e.g. a rule that is an
    error in general but only informational in a special case).
    """

    line: int | None
    col: int | None
    message: str
    key_path: str = ""
    severity: Severity | None = None


@dataclass(frozen=True)
class SphereRef:
    """A sphere as written: ``geometry.<group>.spheres.<frame>[index]``."""

    group: str
    frame: str
    index: int
    node: YNode
    frame_key: YNode

    @property
    def key_path(self) -> str:
        return f"geometry.{self.group}.spheres.{self.frame}[{self.index}]"

    def field(self, name: str) -> YNode | None:
        return self.node.get(name) if isinstance(self.node, YMap) else None


# --- small node helpers ------------------------------------------------------------------------
def is_null(node: YNode | None) -> bool:
    return node is None or (isinstance(node, YScalar) and node.value is None)


def number(node: YNode | None) -> float | None:
    """The value of a numeric scalar (int or float, not bool), else None."""
    if isinstance(node, YScalar) and isinstance(node.value, (int, float)):
        if isinstance(node.value, bool):
            return None
        if not is_finite(node.value):  # an integer beyond float range: infinite here
            return math.inf if node.value > 0 else -math.inf
        return float(node.value)
    return None


def finite_number(node: YNode | None) -> float | None:
    """A usable number (finite, within ±``MAX_NUMBER``: see :mod:`xrdf_tools.util.numbers`),
    else None (``wrong-type`` reports the others)."""
    v = number(node)
    return v if v is not None and within(v) else None


def length_number(node: YNode | None) -> float | None:
    """A usable length or coordinate in metres (within ±``MAX_LENGTH``), else None."""
    v = number(node)
    return v if v is not None and within(v, MAX_LENGTH) else None


def name(node: YNode | None) -> str | None:
    """A name (frame, joint, group): a non-empty string, or a number written as a name."""
    if isinstance(node, YScalar):
        v = node.value
        if isinstance(v, str) and v:
            return v
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return str(v)
    return None


def pos(node: YNode | None) -> tuple[int | None, int | None]:
    return (node.line, node.col) if node is not None else (None, None)


class LintContext:
    """Everything the rules of one file look at."""

    def __init__(
        self,
        text: str,
        path: str,
        *,
        urdf_loader: Callable[[], Robot] | None = None,
        target: str | None = None,
        allow_missing_meshes: bool = False,
    ) -> None:
        self.text = text
        self.path = path
        #: Mesh files that cannot be found are known to be absent (``--allow-missing-meshes``).
        self.allow_missing_meshes = allow_missing_meshes
        #: The reader the file is meant for (``curobo``, ``cumotion``, ``isaac-sim``) or None.
        self.target = target
        self._urdf_loader = urdf_loader
        self._urdf_error: XrdfToolsError | None = None
        self._modifier_error: XrdfToolsError | None = None
        self._kin: KinematicModel | None = None
        self.syntax_error: YamlError | None = None
        self.doc: YamlDocument | None = None
        try:
            self.doc = parse_yaml(text, path)
        except YamlError as exc:
            self.syntax_error = exc

    # --- document ---------------------------------------------------------------------------
    @property
    def root(self) -> YNode | None:
        return self.doc.root if self.doc is not None else None

    @property
    def top(self) -> YMap | None:
        """The top-level mapping, or None when the document is not a mapping."""
        return self.root if isinstance(self.root, YMap) else None

    def get(self, key: str) -> YNode | None:
        return self.top.get(key) if self.top is not None else None

    def has(self, key: str) -> bool:
        return self.top is not None and key in self.top

    @cached_property
    def version(self) -> str | None:
        """``"1.0"`` or ``"2.0"`` when ``format_version`` names a supported version, else None."""
        v = version_string(self.get("format_version"))
        return v if v in SUPPORTED_VERSIONS else None

    def problem(
        self,
        node: YNode | None,
        message: str,
        key_path: str = "",
        severity: Severity | None = None,
    ) -> Problem:
        line, col = pos(node)
        if node is None and self.root is not None:
            line, col = self.root.line, self.root.col
        return Problem(line, col, message, key_path, severity)

    # --- sections ---------------------------------------------------------------------------
    def world_key(self) -> str:
        """How this version spells the world-collision section."""
        return "collision" if self.version == "1.0" else "world_collision"

    def collision_sections(self) -> list[tuple[str, YMap]]:
        """``(key, section)`` for each collision section that is a mapping (world first)."""
        out = []
        for key in (*WORLD_KEYS, "self_collision"):
            node = self.get(key)
            if isinstance(node, YMap):
                out.append((key, node))
        return out

    @staticmethod
    def group_name(section: YMap) -> str | None:
        """The group a collision section names (also the one-item list form)."""
        g = section.get("geometry")
        if isinstance(g, YSeq) and len(g) == 1:
            return name(g.items[0])
        return name(g)

    @cached_property
    def groups(self) -> dict[str, YNode]:
        """Geometry groups by name (value node, possibly null or malformed)."""
        geo = self.get("geometry")
        if not isinstance(geo, YMap):
            return {}
        out: dict[str, YNode] = {}
        for k, v in geo.pairs:
            n = name(k)
            if n is not None:
                out.setdefault(n, v)
        return out

    def clones_of(self, group: str) -> list[tuple[str, YNode]]:
        """``(cloned group name, its node)`` listed by ``group`` (well-formed entries only)."""
        g = self.groups.get(group)
        clone = g.get("clone") if isinstance(g, YMap) else None
        if not isinstance(clone, YSeq):
            return []
        return [(n, item) for item in clone if (n := name(item)) is not None]

    def clone_closure(self, group: str) -> list[str] | None:
        """``group`` and every group it clones transitively (BFS order), or None when a cloned
        group does not exist or the clones form a cycle (other rules report those)."""
        if group not in self.groups:
            return None
        order: list[str] = []
        seen = {group}
        queue = deque([group])
        while queue:
            g = queue.popleft()
            order.append(g)
            for child, _ in self.clones_of(g):
                if child not in self.groups:
                    return None
                if child not in seen:
                    seen.add(child)
                    queue.append(child)
        if self.cyclic_groups & set(order):
            return None
        return order

    @cached_property
    def cyclic_groups(self) -> set[str]:
        """Groups that lie on a clone cycle (linear time: many groups must not hang lint)."""
        from ..util.graph import nodes_on_cycles

        graph = {g: [c for c, _ in self.clones_of(g) if c in self.groups] for g in self.groups}
        return nodes_on_cycles(graph, graph.__getitem__)

    def iter_spheres(self, group: str | None = None) -> Iterator[SphereRef]:
        """Every sphere written in the file (or in one group, clones not followed)."""
        if group is None:
            for refs in self._spheres_by_group.values():
                yield from refs
        else:
            yield from self._spheres_by_group.get(group, ())

    @cached_property
    def _spheres_by_group(self) -> dict[str, tuple[SphereRef, ...]]:
        """The spheres of each group, made once (several rules walk them all)."""
        out: dict[str, tuple[SphereRef, ...]] = {}
        for gname, gnode in self.groups.items():
            refs: list[SphereRef] = []
            spheres = gnode.get("spheres") if isinstance(gnode, YMap) else None
            if isinstance(spheres, YMap):
                for fkey, fval in spheres.pairs:
                    frame = name(fkey)
                    if frame is None or not isinstance(fval, YSeq):
                        continue
                    spheres_of = enumerate(fval.items)
                    refs.extend(SphereRef(gname, frame, i, s, fkey) for i, s in spheres_of)
            out[gname] = tuple(refs)
        return out

    def resolved_spheres(self, group: str) -> list[SphereRef] | None:
        """Spheres of ``group`` with clones merged, or None when the clones do not resolve."""
        closure = self.clone_closure(group)
        if closure is None:
            return None
        return [s for g in closure for s in self.iter_spheres(g)]

    def sphere_frames(self, group: str) -> set[str] | None:
        """Frames that carry at least one sphere key in ``group`` (clones merged)."""
        closure = self.clone_closure(group)
        if closure is None:
            return None
        out: set[str] = set()
        for g in closure:
            gnode = self.groups[g]
            spheres = gnode.get("spheres") if isinstance(gnode, YMap) else None
            if isinstance(spheres, YMap):
                out.update(n for k, _ in spheres.pairs if (n := name(k)) is not None)
        return out

    @cached_property
    def modifier_items(self) -> list[tuple[int, str, YNode, YNode]]:
        """``(index, kind, key node, value node)`` of each well-shaped modifier entry."""
        mods = self.get("modifiers")
        if not isinstance(mods, YSeq):
            return []
        out = []
        for i, item in enumerate(mods.items):
            if isinstance(item, YMap) and len(item.pairs) == 1:
                k, v = item.pairs[0]
                out.append((i, str(key_of(k)), k, v))
        return out

    @cached_property
    def added_frames(self) -> dict[str, YNode]:
        """Frames added by ``add_frame`` → the node of their ``frame_name``."""
        out: dict[str, YNode] = {}
        for _, kind, _, v in self.modifier_items:
            if kind == "add_frame" and isinstance(v, YMap):
                node = v.get("frame_name")
                n = name(node)
                if n is not None and node is not None:
                    out.setdefault(n, node)
        return out

    def frame_references(self) -> Iterator[tuple[str, YNode, str, str]]:
        """Every frame name the file refers to: ``(frame, node, key_path, what)``.

        Covers sphere frames, buffer_distance and ignore keys and values, tool frames.
        """
        yield from self._sphere_frame_references()
        for key, section in self.collision_sections():
            yield from _buffer_frame_references(key, section)
            if key == "self_collision":
                yield from _ignore_frame_references(section)
        tools = self.get("tool_frames")
        if isinstance(tools, YSeq):
            for j, item in enumerate(tools.items):
                if (n := name(item)) is not None:
                    yield n, item, f"tool_frames[{j}]", "tool frame"

    def _sphere_frame_references(self) -> Iterator[tuple[str, YNode, str, str]]:
        for gname, gnode in self.groups.items():
            spheres = gnode.get("spheres") if isinstance(gnode, YMap) else None
            if isinstance(spheres, YMap):
                for k, _ in spheres.pairs:
                    if (n := name(k)) is not None:
                        kp = f"geometry.{gname}.spheres.{n}"
                        yield n, k, kp, f"group '{gname}': sphere frame"

    def cspace_joint_nodes(self) -> list[tuple[str, YNode]]:
        cs = self.get("cspace")
        names = cs.get("joint_names") if isinstance(cs, YMap) else None
        if not isinstance(names, YSeq):
            return []
        return [(n, item) for item in names.items if (n := name(item)) is not None]

    def default_position_nodes(self) -> list[tuple[str, YNode, YNode]]:
        """``(joint, key node, value node)`` for each default joint position entry."""
        d = self.get("default_joint_positions")
        if not isinstance(d, YMap):
            return []
        return [(n, k, v) for k, v in d.pairs if (n := name(k)) is not None]

    # --- models -----------------------------------------------------------------------------
    @cached_property
    def model(self) -> Xrdf | None:
        """The strict model when the file reads cleanly (repeated keys tolerated), else None."""
        from ..xrdf.io import xrdf_from_document

        if self.doc is None:
            return None
        try:
            return xrdf_from_document(self.doc, check_groups=False)
        except XrdfToolsError:
            return None

    @cached_property
    def modifiers_model(self) -> Xrdf | None:
        """A model holding only the modifiers (enough to build the kinematics), or None when
        the modifiers themselves are malformed."""
        if self.model is not None:
            return self.model
        from ..xrdf.io import xrdf_from_document

        top = self.top
        if top is None:
            return None
        pairs: list[tuple[YNode, YNode]] = [
            (YScalar(1, 1, "format"), YScalar(1, 1, "xrdf")),
            (YScalar(1, 1, "format_version"), YScalar(1, 1, 2.0)),
        ]
        pairs += [(k, v) for k, v in top.pairs if key_of(k) == "modifiers"]
        doc = YamlDocument(self.path, YMap(top.line, top.col, tuple(pairs)), ())
        try:
            return xrdf_from_document(doc, check_groups=False)
        except XrdfToolsError:
            return None

    # --- the URDF ---------------------------------------------------------------------------
    @property
    def has_urdf(self) -> bool:
        return self._urdf_loader is not None

    @cached_property
    def robot(self) -> Robot | None:
        """The ``--urdf`` robot, or None without ``--urdf`` or when it is not a valid robot
        (then :attr:`urdf_error` says why). Loading it applies the file's modifiers
        (:attr:`kin`, or :attr:`modifier_error`). A URDF that cannot be read at all
        propagates (exit 2)."""
        if self._urdf_loader is None:
            return None
        from ..util.errors import UrdfReadError

        try:
            robot = self._urdf_loader()
        except UrdfReadError:
            raise
        except XrdfToolsError as exc:
            self._urdf_error = exc
            return None
        mods = self.modifiers_model
        if mods is None:
            return robot
        try:
            from ..robot.kinematics import build_kinematic_model

            self._kin, _ = build_kinematic_model(robot, mods)
        except XrdfToolsError as exc:
            if exc.path != self.path:
                self._urdf_error = exc
                return None
            self._modifier_error = exc
        return robot

    @property
    def urdf_error(self) -> XrdfToolsError | None:
        """Why the ``--urdf`` robot is not a valid robot (it parsed, but no reader would load
        it: a mimic loop, several roots, ...): a finding, not a usage error."""
        return self._urdf_error if self.robot is None else None

    @property
    def modifier_error(self) -> XrdfToolsError | None:
        """Why the modifiers could not be applied to :attr:`robot` (an error located in the
        XRDF), if so."""
        return self._modifier_error if self.robot is not None else None

    @property
    def kin(self) -> KinematicModel | None:
        """:attr:`robot`'s kinematic model with the file's modifiers applied, or None."""
        return self._kin if self.robot is not None else None


@dataclass(frozen=True)
class Rule:
    """A lint rule: kebab-case ``id``, default ``severity``, ``check`` yielding problems, and
    ``doc`` (the rule module's docstring, which is its documentation)."""

    id: str
    severity: Severity
    check: Callable[[LintContext], Iterator[Problem]]
    doc: str
    needs_urdf: bool = False
    #: The reader whose silent failure this rule predicts (a target id), or None for rules
    #: about the spec itself. Under that target the rule is an error; under another target
    #: it is off; without a target it runs at ``severity``.
    reader: str | None = None

    def level(self, target: str | None) -> Severity | None:
        """Default severity of this rule when linting for ``target`` (None: off)."""
        if self.reader is None or target is None:
            return self.severity
        return Severity.ERROR if target == self.reader else None

    @property
    def summary(self) -> str:
        """First paragraph of the documentation, on one line."""
        para = self.doc.strip().split("\n\n")[0]
        return " ".join(para.split()) or self.id

    @property
    def info(self) -> RuleInfo:
        """The rule's record in the registry of every diagnostic id."""
        return RuleInfo(self.id, self.severity, self.summary, "lint")


def _buffer_frame_references(key: str, section: YMap) -> Iterator[tuple[str, YNode, str, str]]:
    buf = section.get("buffer_distance")
    if isinstance(buf, YMap):
        for k, _ in buf.pairs:
            if (n := name(k)) is not None:
                yield n, k, f"{key}.buffer_distance.{n}", f"{key} buffer_distance frame"


def _ignore_frame_references(section: YMap) -> Iterator[tuple[str, YNode, str, str]]:
    ignore = section.get("ignore")
    if not isinstance(ignore, YMap):
        return
    for k, v in ignore.pairs:
        if (n := name(k)) is None:
            continue
        yield n, k, f"self_collision.ignore.{n}", "ignore frame"
        if isinstance(v, YSeq):
            for j, item in enumerate(v.items):
                if (m := name(item)) is not None:
                    yield m, item, f"self_collision.ignore.{n}[{j}]", "ignore frame"
