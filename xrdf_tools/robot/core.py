"""One loaded robot as one frozen value: where it came from and every view of it.

A :class:`Robot` is built once by the loader (:func:`xrdf_tools.robot.urdf_source.load_urdf`,
:func:`xrdf_tools.robot.xacro_source.load_robot`) and carries the path, the URDF text it was
parsed from (an expanded xacro: the expansion), the line of every ``<link>`` and ``<joint>``,
the ``package_paths`` it was loaded with, which geometry elements are capsules and the checked
XML tree. The plain views — the joints as :class:`~xrdf_tools.robot.urdf_joints.JointInfo`, the link
names (and which have collision geometry), the :class:`~xrdf_tools.robot.tree.RobotTree` — are
computed on first use and kept. Modules above keep what they derive from the robot in
:attr:`Robot.derived` (the :class:`~xrdf_tools.robot.kinematics.KinematicModel` per XRDF modifiers):
the robot itself imports only the plain views below it.

The views are read from the project's own checked XML parse: a command that reads no geometry
(report, lint, convert without spheres) never imports yourdfpy or trimesh. The yourdfpy object
(:attr:`Robot.urdf`, for geometry) is built from the same tree on first use.

Functions that still receive a bare ``yourdfpy.URDF`` call :func:`as_robot`: the loader leaves
a reference to its :class:`Robot` on the yourdfpy object, so the provenance travels with the
object itself (no global registry); a yourdfpy object built elsewhere gets a :class:`Robot`
without provenance (path ``"<urdf>"``, no lines).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

from ..util.frozen import FrozenMap
from ..util.text import name_list
from .tree import RobotTree
from .urdf_joints import JointInfo, joint_from_xml, joint_info

if TYPE_CHECKING:
    import yourdfpy

    from ..diagnostics import Diagnostic
    from .packages import PackagePaths, PackageResolver


__all__ = ["Robot", "as_robot"]

#: Attribute of a loaded yourdfpy object that holds its :class:`Robot`.
_ATTR = "_xrdf_tools_robot"


@dataclass(frozen=True, eq=False)
class Robot:
    """A loaded URDF (never with meshes) and its provenance; the views are cached.

    ``document`` is the checked ``<robot>`` element the loader parsed (capsules already held
    as cylinders); ``prebuilt`` a yourdfpy object built elsewhere (no document). Exactly one
    of the two is set.
    """

    document: Any = None
    path: str = "<urdf>"
    #: The text the URDF was parsed from (``None`` for a yourdfpy object built elsewhere).
    text: str | None = None
    #: True when :attr:`text` is the expansion of a xacro file.
    expanded: bool = False
    link_lines: Mapping[str, int] = field(default_factory=FrozenMap)
    joint_lines: Mapping[str, int] = field(default_factory=FrozenMap)
    #: ``(kind, name) -> (file, line)`` of the links and joints of a xacro robot that a macro
    #: of an included file writes (not in :attr:`link_lines`/:attr:`joint_lines`, which are
    #: lines of :attr:`path`): see :mod:`xrdf_tools.robot.xacro_places`.
    include_places: Mapping[tuple[str, str], tuple[str, int]] = field(default_factory=FrozenMap)
    #: Every file a xacro robot's expansion included (empty for a plain URDF).
    included_files: tuple[str, ...] = ()
    package_paths: PackagePaths = field(default_factory=FrozenMap)
    #: The xacro arguments a xacro robot was expanded with (an SRDF xacro takes the same).
    xacro_args: Mapping[str, str] = field(default_factory=FrozenMap)
    #: ``(link, "collision" | "visual", index)`` of the elements whose geometry is a
    #: ``<capsule>`` (not standard URDF): yourdfpy holds them as cylinders of the same radius
    #: and length (see :func:`xrdf_tools.robot.link_geometry.capsules_as_cylinders`).
    capsules: frozenset[tuple[str, str, int]] = frozenset()
    prebuilt: yourdfpy.URDF | None = None
    #: Whether :attr:`urdf` builds yourdfpy's scene graph.
    build_scene_graph: bool = False
    #: Defects found while loading in parts no command plans with (a malformed material
    #: colour), located in the URDF: the commands show them as warnings.
    warnings: tuple[Diagnostic, ...] = ()
    #: Results other modules derive from the robot and keep with it, by their own keys (the
    #: kinematic model per XRDF modifiers:
    #: :func:`xrdf_tools.robot.kinematics.build_kinematic_model`).
    derived: dict[Any, Any] = field(default_factory=dict, repr=False, compare=False)

    # --- views ---------------------------------------------------------------------------
    @cached_property
    def urdf(self) -> yourdfpy.URDF:
        """The yourdfpy object (no meshes loaded), built on first use: geometry readers need it,
        the plain views below do not."""
        if self.prebuilt is not None:
            return self.prebuilt
        from .yourdfpy_build import build_yourdfpy

        urdf = build_yourdfpy(self.document, self.path, self.package_paths, self.build_scene_graph)
        setattr(urdf, _ATTR, self)
        return urdf

    @property
    def name(self) -> str:
        if self.document is not None:
            return str(self.document.get("name"))
        return str(self.urdf.robot.name)

    @property
    def file_name(self) -> str:
        """The robot file's name without its folders, for messages (``/`` and ``\\`` alike)."""
        return self.path.replace("\\", "/").rsplit("/", 1)[-1]

    @property
    def xacro_text(self) -> str | None:
        """The expanded URDF text when the robot was read from a xacro file, else ``None``."""
        return self.text if self.expanded else None

    @cached_property
    def links(self) -> tuple[str, ...]:
        """Link names in document order."""
        if self.document is not None:
            return tuple(str(e.get("name")) for e in self.document.findall("link"))
        return tuple(str(link.name) for link in self.urdf.robot.links)

    @cached_property
    def collision_counts(self) -> Mapping[str, int]:
        """The number of ``<collision>`` elements of each link that has any, in link order."""
        if self.document is not None:
            counts = ((str(e.get("name")), len(e.findall("collision"))) for e in self._links())
        else:
            counts = ((str(k.name), len(k.collisions)) for k in self.urdf.robot.links)
        return FrozenMap((name, n) for name, n in counts if n)

    def _links(self) -> list[Any]:
        return list(self.document.findall("link"))

    @cached_property
    def joints(self) -> Mapping[str, JointInfo]:
        """Every ``<joint>`` as :class:`JointInfo`, keyed by name, in document order."""
        if self.document is not None:
            elements = self.document.findall("joint")
            return FrozenMap(
                (str(e.get("name")), joint_from_xml(e, self.joint_lines.get(str(e.get("name")))))
                for e in elements
            )
        return FrozenMap(
            (str(j.name), joint_info(j, self.joint_lines.get(str(j.name))))
            for j in self.urdf.robot.joints
        )

    @cached_property
    def tree(self) -> RobotTree:
        """The URDF as a tree of names (:class:`~xrdf_tools.robot.tree.RobotTree`)."""
        return RobotTree.from_parts(self.name, self.path, self.links, self.joints)

    def mesh_resolver(self, package_paths: PackagePaths | None = None) -> PackageResolver:
        """The package resolver of this robot's meshes: from its file, with its own package
        paths, or ``package_paths`` in their place."""
        from pathlib import Path

        from .packages import PackageResolver

        pkgs = self.package_paths if package_paths is None else package_paths
        return PackageResolver(Path(self.path), dict(pkgs))

    def source_line(self, kind: Literal["link", "joint"], name: str) -> int | None:
        """Line of the ``<link>``/``<joint>`` element named ``name`` (None if unknown)."""
        return (self.link_lines if kind == "link" else self.joint_lines).get(name)

    def place(self, kind: Literal["link", "joint"], name: str) -> tuple[str, int | None]:
        """File and line where the ``<link>``/``<joint>`` named ``name`` is written: a line of
        :attr:`path`, else of the included xacro file that writes it, else ``(path, None)``."""
        line = self.source_line(kind, name)
        if line is None and (kind, name) in self.include_places:
            return self.include_places[(kind, name)]
        return self.path, line

    def root_link(self) -> str:
        """The one link that is no joint's child; :class:`UrdfError` when not exactly one."""
        from ..util.errors import UrdfError

        children = {j.child for j in self.joints.values()}
        roots = [link for link in self.links if link not in children]
        if len(roots) != 1:
            raise UrdfError(
                f"the URDF must form one tree; root links: {name_list(roots) or 'none'}",
                path=self.path,
            )
        return roots[0]


def as_robot(urdf: Robot | yourdfpy.URDF) -> Robot:
    """``urdf`` as a :class:`Robot`: itself, the one its loader made, or one without
    provenance for a yourdfpy object built elsewhere (kept on the object for next time)."""
    if isinstance(urdf, Robot):
        return urdf
    robot = getattr(urdf, _ATTR, None)
    if isinstance(robot, Robot):
        return robot
    robot = Robot(prebuilt=urdf)
    setattr(urdf, _ATTR, robot)
    return robot
