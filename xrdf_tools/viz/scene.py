"""The pure, back-end independent picture of a sphere model: what every back-end draws.

:func:`build_scene` evaluates everything once (forward kinematics of every sample, the
self-collision contacts, the link meshes) so that the rerun, MCAP and PNG writers only
translate a :class:`Scene` into their format.

* Per link (:class:`LinkScene`): its spheres in the link frame (true radii and self-collision
  buffered radii), one colour, its meshes.
* Per sample (:class:`Sample`): the actuated joint values, the pose of every frame (in
  :attr:`Scene.poses`), and the colliding sphere pairs found with the XRDF's self-collision
  semantics (:mod:`xrdf_tools.selfcollision.collision`). Sample 0 is always the default pose.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..diagnostics import Diagnostic, Severity
from ..selfcollision.collision.spheres import is_slot
from ..util.arrays import FloatArray
from ..util.errors import GeometryGroupError, SourceError
from ..util.fixed_order import matmul, rigid_inverse
from ..xrdf.model import Sphere, Xrdf
from .contacts import SpherePair, sphere_contacts
from .meshes import MeshKind, Rgba, load_link_meshes
from .scene_links import LinkScene, link_color, sphere_links, with_meshes

if TYPE_CHECKING:
    import yourdfpy

    from ..robot.core import Robot
    from ..robot.kinematics import KinematicModel
    from ..robot.packages import PackagePaths
    from ..selfcollision.collision import Contact

Progress = Callable[[int, int], None]

#: Colour of spheres in self-collision (and reserved: no link gets it).
COLLISION_RGBA: Rgba = (0.95, 0.05, 0.05, 1.0)


@dataclass(frozen=True, eq=False)
class Sample:
    """One step of the ``sample`` timeline.

    ``step`` is its position on the timeline (0: default pose); ``source`` is the row of the
    input configurations it came from (-1 for the default pose); ``q`` [n] the actuated joint
    values; ``contacts`` every sphere pair in self-collision (worst first);
    ``frame_contacts`` one :class:`~xrdf_tools.selfcollision.collision.Contact` per colliding frame
    pair.
    """

    step: int
    source: int
    q: FloatArray
    contacts: tuple[SpherePair, ...] = ()
    frame_contacts: tuple[Contact, ...] = ()

    @property
    def label(self) -> str:
        return "default pose" if self.source < 0 else f"configuration {self.source}"

    def colliding_pairs(self) -> list[tuple[str, str]]:
        """The colliding frame pairs, worst first."""
        return [(c.frame_a, c.frame_b) for c in self.frame_contacts]

    def describe_contacts(self) -> list[str]:
        """One line per colliding frame pair: worst sphere pair, clearance, count."""
        return [
            f"{c.frame_a}[{c.sphere_a}] <-> {c.frame_b}[{c.sphere_b}] "
            f"(clearance {c.clearance * 1000:.1f} mm, {c.n_sphere_pairs} sphere pair(s))"
            for c in self.frame_contacts
        ]

    def colliding_spheres(self) -> dict[str, set[int]]:
        """``{frame: {sphere index in the XRDF list}}`` of spheres in a colliding pair."""
        out: dict[str, set[int]] = {}
        for c in self.contacts:
            out.setdefault(c.frame_a, set()).add(c.sphere_a)
            out.setdefault(c.frame_b, set()).add(c.sphere_b)
        return out


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything a back-end draws. ``poses`` [N, F, 4, 4]: frame-to-base transforms of
    every frame (``frame_names`` order) for each of the N samples."""

    robot_name: str
    group: str
    frame_names: tuple[str, ...]
    parent: tuple[int, ...]
    joint_names: tuple[str, ...]
    links: tuple[LinkScene, ...]
    samples: tuple[Sample, ...]
    poses: FloatArray
    mesh_kind: MeshKind = "none"
    collisions_shown: bool = True
    diagnostics: tuple[Diagnostic, ...] = field(default=())
    #: Frame pairs with spheres on both sides that self-collision checks / its mask ignores
    #: (0 and 0 without a ``self_collision`` section).
    frame_pairs_checked: int = 0
    frame_pairs_ignored: int = 0

    @property
    def base_frame(self) -> str:
        return self.frame_names[0]

    @property
    def n_spheres(self) -> int:
        return sum(link.n_spheres for link in self.links)

    def sphere_counts(self) -> dict[str, int]:
        return {link.name: link.n_spheres for link in self.links}

    def link(self, name: str) -> LinkScene:
        for link in self.links:
            if link.name == name:
                return link
        raise KeyError(name)

    def relative_pose(self, step: int, frame: int) -> FloatArray:
        """Transform [4, 4] of ``frame`` in its parent frame at sample ``step``."""
        pose: FloatArray = self.relative_poses(step, step + 1)[0, frame]
        return pose

    def relative_poses(self, start: int, stop: int) -> FloatArray:
        """Transforms [stop - start, F, 4, 4] of every frame in its parent frame (a root: in
        the base frame) at samples ``start`` to ``stop``, composed term by term: the same
        bits as one pose at a time."""
        poses = self.poses[start:stop]
        parent = np.asarray(self.parent)
        rooted = parent < 0
        inverse = rigid_inverse(poses[:, np.where(rooted, 0, parent)])
        out = matmul(inverse, poses)
        out[:, rooted] = poses[:, rooted]
        return out

    def red_spheres(self, step: int) -> dict[str, set[int]]:
        """``{link: {sphere index in the XRDF list}}`` drawn red at sample ``step``: the
        spheres of its colliding pairs, none when collisions are not shown."""
        return self.samples[step].colliding_spheres() if self.collisions_shown else {}

    def colors(self, step: int) -> dict[str, list[Rgba]]:
        """Colour of every drawn sphere per link at sample ``step`` (red when colliding)."""
        hit = self.red_spheres(step)
        out: dict[str, list[Rgba]] = {}
        for link in self.links:
            ids = hit.get(link.name, set())
            out[link.name] = [COLLISION_RGBA if i in ids else link.color for i in link.sphere_ids]
        return out


def choose_group(xrdf: Xrdf, group: str | None = None) -> str:
    """The geometry group to draw: ``group``, else the self-collision group, else the world
    collision group, else the only group. Raises :class:`GeometryGroupError` listing the
    defined groups when there is no sensible choice."""
    defined = list(xrdf.geometry or {})
    if group is not None:
        if group not in defined:
            from ..util.errors import did_you_mean

            raise GeometryGroupError(
                f"geometry group '{group}' is not defined (defined: {', '.join(defined) or 'none'})"
                + did_you_mean(group, defined),
                path=xrdf.source.path or None,
            )
        return group
    if xrdf.self_collision is not None:
        return xrdf.self_collision.geometry
    if xrdf.world_collision is not None:
        return xrdf.world_collision.geometry
    if len(defined) == 1:
        return defined[0]
    if not defined:
        raise GeometryGroupError(
            "no collision section names a geometry group and none is defined: the XRDF has no "
            "spheres to draw; fit them with `xrdf spheres ROBOT.urdf --xrdf THIS.xrdf -o OUT` "
            "or `xrdf convert --fit-spheres`",
            **xrdf.source.locate(""),
        )
    raise GeometryGroupError(
        "no collision section names a geometry group; choose one with --group "
        f"(defined: {', '.join(defined)})",
        **xrdf.source.locate(""),
    )


def build_scene(
    urdf: Robot | yourdfpy.URDF,
    xrdf: Xrdf,
    configurations: npt.ArrayLike | None = None,
    *,
    kinematic_model: KinematicModel | None = None,
    group: str | None = None,
    meshes: MeshKind = "visual",
    colliding_only: bool = False,
    urdf_path: str | os.PathLike[str] | None = None,
    package_paths: PackagePaths | None = None,
    progress: Progress | None = None,
) -> Scene:
    """Evaluate the sphere model of ``xrdf`` on ``urdf`` for drawing.

    ``configurations`` [B, n] are full actuated configurations (see
    :func:`xrdf_tools.robot.kinematics.full_configuration`); the scene always starts with the
    default pose. ``colliding_only`` keeps, after the default pose, only configurations with
    a self-collision. ``meshes`` chooses the URDF elements drawn with each link.
    ``progress(done, total)`` is called while contacts are computed.

    Spheres on a frame the kinematic tree lacks are left out with a warning (the self-collision
    group's by :func:`xrdf_tools.selfcollision.collision.build_sphere_set`). Raises
    :class:`GeometryGroupError` for an unknown group.
    """
    from ..robot.binding import cspace_indices
    from ..robot.core import as_robot
    from ..robot.kinematics import fk

    robot = as_robot(urdf)
    diags: list[Diagnostic] = []
    kin = _kinematics(robot, xrdf, kinematic_model, diags)
    cspace_indices(kin, xrdf)  # the XRDF's c-space must match the URDF, samples or not
    chosen = choose_group(xrdf, group)
    spheres = xrdf.resolved_spheres(chosen)
    _require_a_robot_frame(kin, xrdf, chosen, spheres, urdf_path)
    Q = _default_pose_then(kin, xrdf, configurations)
    collisions = _self_collisions(kin, xrdf, Q, chosen, progress, diags)
    keep = [0] + [k for k in range(1, len(Q)) if not colliding_only or collisions.found[k][0]]
    samples = tuple(
        Sample(step, k - 1, np.array(Q[k]), *collisions.found[k]) for step, k in enumerate(keep)
    )
    poses = np.ascontiguousarray(fk(kin, Q[keep]))
    links = sphere_links(xrdf, kin, chosen, spheres, diags)
    # Meshes: every URDF link kept in the tree, whether or not it has spheres.
    mesh_map, mdiags = load_link_meshes(
        robot, kin.frame_names, meshes, urdf_path=urdf_path, package_paths=package_paths
    )
    diags.extend(mdiags)
    return Scene(
        robot_name=str(getattr(robot.urdf.robot, "name", "") or "robot"),
        group=chosen,
        frame_names=kin.frame_names,
        parent=tuple(int(p) for p in kin.parent),
        joint_names=kin.actuated_joints,
        links=with_meshes(links, mesh_map, kin),
        samples=samples,
        poses=poses,
        mesh_kind=meshes,
        collisions_shown=collisions.shown,
        diagnostics=tuple(sorted(diags)),
        frame_pairs_checked=collisions.checked,
        frame_pairs_ignored=collisions.ignored,
    )


def _kinematics(
    robot: Robot, xrdf: Xrdf, given: KinematicModel | None, diags: list[Diagnostic]
) -> KinematicModel:
    """``given``, else the kinematic model of ``robot`` under ``xrdf``'s modifiers (its
    diagnostics added to ``diags``)."""
    if given is not None:
        return given
    from ..robot.kinematics import build_kinematic_model

    kin, kdiags = build_kinematic_model(robot, xrdf)
    diags.extend(kdiags)
    return kin


def _require_a_robot_frame(
    kin: KinematicModel,
    xrdf: Xrdf,
    group: str,
    spheres: Mapping[str, tuple[Sphere, ...]],
    urdf_path: str | os.PathLike[str] | None,
) -> None:
    """Raise :class:`SourceError` when ``group`` has spheres but on no frame of the robot:
    the XRDF was most likely written for another URDF."""
    if not spheres or any(frame in kin.frame_names for frame in spheres):
        return
    upath = urdf_path if urdf_path is not None else kin.source_path
    raise SourceError(
        f"none of the {len(spheres)} sphere frames of group '{group}' "
        f"({', '.join(list(spheres)[:3])}{', …' if len(spheres) > 3 else ''}) is a frame of "
        f"{os.fspath(upath) if upath else 'the URDF'}: is this the URDF the XRDF was written "
        "for?",
        path=xrdf.source.path or "<xrdf>",
    )


def _default_pose_then(
    kin: KinematicModel, xrdf: Xrdf, configurations: npt.ArrayLike | None
) -> FloatArray:
    """The timeline's configurations [1 + B, n]: the default pose, then ``configurations``
    [B, n] (a ``ValueError`` when their shape is not that)."""
    from ..robot.kinematics import default_configuration

    q0 = default_configuration(kin, xrdf.default_joint_positions)
    if configurations is None:
        return q0[None, :]
    qc = np.asarray(configurations, dtype=np.float64)
    if qc.ndim != 2 or qc.shape[1] != kin.n_actuated:
        raise ValueError(
            f"configurations must have shape [B, {kin.n_actuated}], got {list(qc.shape)}"
        )
    return np.vstack([q0[None, :], qc])


@dataclass(frozen=True)
class _SelfCollisions:
    """Per configuration, its colliding sphere pairs and frame pairs; the frame pairs the
    mask checks and ignores; whether the drawn group is the self-collision one (so colliding
    spheres are coloured)."""

    found: list[tuple[tuple[SpherePair, ...], tuple[Contact, ...]]]
    checked: int
    ignored: int
    shown: bool


def _self_collisions(
    kin: KinematicModel,
    xrdf: Xrdf,
    Q: FloatArray,
    drawn: str,
    progress: Progress | None,
    diags: list[Diagnostic],
) -> _SelfCollisions:
    """The self-collisions of every configuration of ``Q`` (none without a self-collision
    section), with a note when the ``drawn`` group is not the one they are found with."""
    if xrdf.self_collision is None:
        return _SelfCollisions([((), ())] * len(Q), 0, 0, False)
    self_group = xrdf.self_collision.geometry
    found, checked, ignored = sphere_contacts(kin, xrdf, Q, progress, diags)
    if self_group != drawn:
        diags.append(
            Diagnostic(
                xrdf.source.path or "<xrdf>",
                None,
                None,
                "viz-collisions-not-drawn",
                Severity.INFO,
                f"drawing group '{drawn}', but self-collision uses '{self_group}': colliding "
                "pairs are logged, spheres are not coloured",
            )
        )
    return _SelfCollisions(found, checked, ignored, self_group == drawn)


def sphere_counts(xrdf: Xrdf, group: str) -> dict[str, int]:
    """Drawable spheres (all but attached-object slots) per frame of ``group``."""
    return {
        frame: sum(1 for s in spheres if not is_slot(s.radius))
        for frame, spheres in xrdf.resolved_spheres(group).items()
    }


__all__: Sequence[str] = (
    "COLLISION_RGBA",
    "LinkScene",
    "Sample",
    "Scene",
    "build_scene",
    "choose_group",
    "link_color",
    "sphere_counts",
)


def scene_configurations(
    kin: KinematicModel,
    xrdf: Xrdf,
    *,
    configs: str | os.PathLike[str] | None = None,
    samples: int = 0,
    seed: int | None = 0,
) -> FloatArray | None:
    """The configurations a scene draws after the default pose: those of the file
    ``configs`` (.npy or .csv), else ``samples`` drawn within the c-space limits, else None
    (the default pose alone). Raises :class:`~xrdf_tools.util.errors.XrdfToolsError`."""
    from ..selfcollision.configurations import load_configurations, sample_configurations

    if configs is not None:
        return load_configurations(configs, kin, xrdf)
    if samples:
        return sample_configurations(kin, xrdf, samples, seed)
    return None


def scene_diagnostics(scene: Scene, *earlier: Sequence[Diagnostic]) -> list[Diagnostic]:
    """The diagnostics of building ``scene`` and of the steps before it (``earlier``, e.g.
    the kinematic model's), each said once (same rule and message) and in order."""
    unique = {
        (d.rule, d.message): d for d in [*(d for ds in earlier for d in ds), *scene.diagnostics]
    }
    return sorted(unique.values())
