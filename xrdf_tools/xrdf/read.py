"""Read an XRDF document into the model (public names re-exported by :mod:`xrdf_tools.xrdf.io`).

Reading is strict about types (one :class:`SchemaError` with file:line:col for the first
problem) and lenient about what the linter judges (missing ``cspace``, a section spelled for the
other version, unknown keys). Which keys a section has, which are required, where null is
accepted, list lengths and which numbers are lengths in metres come from the one description of
the XRDF shape in :mod:`xrdf_tools.xrdf.shape`; the ``_read_*`` functions below build the model
and word the errors.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence

from ..util.errors import GeometryGroupError, SchemaError
from ..util.frozen import FrozenMap
from ..yaml.hints import XML_NOT_YAML, looks_like_xml
from ..yaml.io import (
    YamlDocument,
    YMap,
    YNode,
    YScalar,
    YSeq,
    load_yaml,
    parse_yaml,
    positions_of,
    raise_on_duplicates,
    to_python,
)
from .model import (
    AddFrame,
    CollisionSection,
    CSpace,
    GeometryGroup,
    Modifier,
    Orientation,
    OrientationForm,
    RemoveMimicAttributes,
    SelfCollisionSection,
    SetBaseFrame,
    SourceMap,
    Sphere,
    Vec3,
    Xrdf,
    clone_order,
    resolve_group,
)
from .nodes import NodeReader, describe, is_null, plain_number, plain_numbers
from .shape import (
    ADD_FRAME,
    BUFFERS,
    CSPACE,
    DOCUMENT,
    FIXED_TRANSFORM,
    GROUP,
    MAX_LENGTH,
    MODIFIERS,
    ORIENTATION,
    REMOVE_MIMIC,
    SELF,
    SPHERE,
    SUPPORTED_VERSIONS,
    WORLD,
    Shape,
    version_string,
)

#: The top-level keys in the order of the spec (and of the canonical writer).
TOP_LEVEL_ORDER = tuple(DOCUMENT.fields)


def parse_xrdf(text: str, path: str = "<string>") -> Xrdf:
    """Parse XRDF text into the model (see :func:`xrdf_from_document`)."""
    doc = parse_yaml(text, path)
    raise_on_duplicates(doc)
    return xrdf_from_document(doc)


def load_xrdf(path: str | os.PathLike[str]) -> Xrdf:
    """Read an XRDF file. Raises :class:`XrdfToolsError` subclasses with file:line:col."""
    return xrdf_from_document(load_yaml(path))


def _read_header(r: NodeReader, root: YNode | None) -> tuple[YMap, str]:
    """The top-level mapping and its normalised ``format_version``."""
    if root is None:
        raise SchemaError(
            "the file is empty; an XRDF needs at least 'format' and 'format_version'",
            path=r.path,
            line=1,
            col=1,
        )
    if isinstance(root, YScalar) and looks_like_xml(root.value):
        raise SchemaError(XML_NOT_YAML, path=r.path, line=1, col=1)
    if not isinstance(root, YMap):
        raise r.fail(root, f"the top level of an XRDF must be a mapping, not {describe(root)}")
    fmt = root.get("format")
    if fmt is None:
        raise r.fail(root, "missing required key 'format' (expected 'format: xrdf')")
    if not (isinstance(fmt, YScalar) and fmt.value == "xrdf"):
        raise r.fail(fmt, f"'format' must be 'xrdf', not {describe(fmt)}")
    vnode = root.get("format_version")
    if vnode is None:
        raise r.fail(root, "missing required key 'format_version' (1.0 or 2.0)")
    version = version_string(vnode)
    if version is None or version not in SUPPORTED_VERSIONS:
        raise r.fail(
            vnode,
            f"unsupported format_version {describe(vnode)}; supported: "
            f"{', '.join(SUPPORTED_VERSIONS)}",
        )
    return root, version


def xrdf_from_document(doc: YamlDocument, *, check_groups: bool = True) -> Xrdf:
    """The model of a parsed YAML document; :class:`SchemaError` at the first problem.

    ``check_groups``: the geometry groups the collision sections name, and the groups they
    clone, must be defined and clone no cycle (lint turns it off: it reports those as
    findings and still wants the model)."""
    r = NodeReader(doc.path)
    root, version = _read_header(r, doc.root)
    modifiers = _read_modifiers(r, root.get("modifiers"))
    defaults = _read_defaults(r, root) if "default_joint_positions" in root else None
    cspace = _read_cspace(r, root.get("cspace")) if "cspace" in root else None
    tool_frames = (
        r.strings(root.get("tool_frames"), "tool_frames") if "tool_frames" in root else None
    )
    geometry = _read_geometry(r, root.get("geometry")) if "geometry" in root else None

    if "collision" in root and "world_collision" in root:
        raise r.fail(
            root.key_node("world_collision"),
            "both 'collision' and 'world_collision' are present; use 'collision' in 1.0 and "
            "'world_collision' in 2.0",
        )
    wkey = "collision" if "collision" in root else "world_collision"
    world = _read_world(r, root.get(wkey), wkey, geometry) if wkey in root else None
    self_c = (
        _read_self(r, root.get("self_collision"), geometry) if "self_collision" in root else None
    )
    if check_groups:
        for key in (wkey, "self_collision"):
            _check_group_defined(r, root.get(key), key, geometry or {})
    extra = FrozenMap((str(k), to_python(v)) for k, v in root.items() if k not in TOP_LEVEL_ORDER)
    return Xrdf(
        format_version=version,
        cspace=cspace,
        modifiers=modifiers,
        default_joint_positions=defaults,
        tool_frames=tool_frames,
        world_collision=world,
        self_collision=self_c,
        geometry=geometry,
        extra=extra,
        source=SourceMap(doc.path, positions_of(doc)),
    )


def _read_defaults(r: NodeReader, root: YMap) -> FrozenMap[str, float]:
    """``default_joint_positions`` (present; null reads as an empty mapping)."""
    shape = DOCUMENT.fields["default_joint_positions"]
    value = shape.values
    assert value is not None
    return r.frame_map(
        root.get("default_joint_positions"),
        "default_joint_positions",
        lambda v, w: r.num(v, value, w),
    )


def _read_vec3(r: NodeReader, node: YNode | None, shape: Shape, what: str) -> Vec3:
    """A position (``shape``: a list of 3 lengths in metres)."""
    x, y, z = r.nums(node, shape, what)
    return (x, y, z)


def _read_orientation(r: NodeReader, node: YNode | None, what: str) -> Orientation:
    m = r.section(node, ORIENTATION, what)
    if m is None:
        return Orientation.identity()
    forms: tuple[OrientationForm, ...] = ("quaternion", "euler_rpy")
    for form in forms:
        if form in m:
            values = r.nums(m.get(form), ORIENTATION.fields[form], f"{what}.{form}")
            return Orientation(form, values)
    if "w" not in m or "xyz" not in m:
        raise r.fail(
            m,
            f"{what} needs 'w' and 'xyz' ({{w: 1.0, xyz: [0.0, 0.0, 0.0]}}), or 'quaternion' "
            "[w, x, y, z], or 'euler_rpy' [r, p, y]",
        )
    w = r.num(m.get("w"), ORIENTATION.fields["w"], f"{what}.w")
    xyz = r.nums(m.get("xyz"), ORIENTATION.fields["xyz"], f"{what}.xyz")
    return Orientation("w_xyz", (w, *xyz))


def _read_modifiers(r: NodeReader, node: YNode | None) -> tuple[Modifier, ...]:
    seq = r.sequence(node, "modifiers", nullable=DOCUMENT.fields["modifiers"].nullable)
    if seq is None:
        return ()
    out: list[Modifier] = []
    for i, item in enumerate(seq):
        what = f"modifiers[{i}]"
        m = r.mapping(item, what, nullable=False)
        assert m is not None
        if len(m.pairs) != 1:
            raise r.fail(
                m,
                f"{what} must have exactly one key (add_frame, set_base_frame or "
                f"remove_mimic_attributes), found {len(m.pairs)}",
            )
        key, value = m.items()[0]
        read = _MODIFIER_READERS.get(key) if isinstance(key, str) else None
        if read is None:
            raise r.fail(
                m.pairs[0][0],
                f"unknown modifier '{key}'; valid: {', '.join(MODIFIERS)}",
            )
        out.append(read(r, value, f"{what}.{key}"))
    return tuple(out)


def _read_set_base_frame(r: NodeReader, value: YNode, w: str) -> Modifier:
    return SetBaseFrame(r.string(value, w))


def _read_add_frame(r: NodeReader, value: YNode, w: str) -> Modifier:
    a = r.section(value, ADD_FRAME, w)
    assert a is not None
    ft_what = f"{w}.fixed_transform"
    ft = r.section(r.get(a, ADD_FRAME, "fixed_transform", w), FIXED_TRANSFORM, ft_what)
    assert ft is not None
    jt = a.get("joint_type")

    def name(key: str) -> str:
        return r.string(r.get(a, ADD_FRAME, key, w), f"{w}.{key}")

    return AddFrame(
        frame_name=name("frame_name"),
        parent_frame_name=name("parent_frame_name"),
        joint_name=name("joint_name"),
        joint_type=r.string(jt, f"{w}.joint_type") if jt is not None else "FIXED",
        position=_read_vec3(
            r,
            r.get(ft, FIXED_TRANSFORM, "position", ft_what),
            FIXED_TRANSFORM.fields["position"],
            f"{ft_what}.position",
        ),
        orientation=_read_orientation(r, ft.get("orientation"), f"{ft_what}.orientation"),
    )


def _read_remove_mimic(r: NodeReader, value: YNode, w: str) -> Modifier:
    a = r.section(value, REMOVE_MIMIC, w)
    assert a is not None
    pl = a.get("position_limits")
    limits = None
    if pl is not None and not is_null(pl):
        lo, hi = r.nums(pl, REMOVE_MIMIC.fields["position_limits"], f"{w}.position_limits")
        limits = (lo, hi)
    vl = a.get("velocity_limits") if "velocity_limits" in a else a.get("velocity_limit")
    velocity = None
    if vl is not None and not is_null(vl):
        velocity = r.num(vl, REMOVE_MIMIC.fields["velocity_limits"], f"{w}.velocity_limits")
    joint = r.string(r.get(a, REMOVE_MIMIC, "joint_name", w), f"{w}.joint_name")
    return RemoveMimicAttributes(joint, limits, velocity)


_MODIFIER_READERS: dict[str, Callable[[NodeReader, YNode, str], Modifier]] = {
    "add_frame": _read_add_frame,
    "set_base_frame": _read_set_base_frame,
    "remove_mimic_attributes": _read_remove_mimic,
}
assert set(_MODIFIER_READERS) == set(MODIFIERS), "a reader for every modifier of the shape"


def _read_cspace(r: NodeReader, node: YNode | None) -> CSpace:
    m = r.section(node, CSPACE, "cspace")
    assert m is not None
    names_node = r.get(m, CSPACE, "joint_names", "cspace")
    names = r.strings(names_node, "cspace.joint_names")
    _no_repeats(r, names_node, names)

    def limits(key: str) -> tuple[float, ...]:
        return r.nums(r.get(m, CSPACE, key, "cspace"), CSPACE.fields[key], f"cspace.{key}")

    return CSpace(names, limits("acceleration_limits"), limits("jerk_limits"))


def _no_repeats(r: NodeReader, node: YNode | None, names: tuple[str, ...]) -> None:
    """A c-space names each joint once (a repeat makes the configuration vector ambiguous)."""
    seen: set[str] = set()
    for i, n in enumerate(names):
        if n in seen:
            item = node.item(i) if isinstance(node, YSeq) else node
            raise r.fail(item, f"cspace.joint_names[{i}]: joint '{n}' is listed twice")
        seen.add(n)


def _read_spheres(r: NodeReader, node: YNode, what: str) -> tuple[Sphere, ...]:
    seq = r.sequence(node, what)
    if seq is None:
        return ()
    out = []
    for i, item in enumerate(seq):
        sphere = _plain_sphere(item)
        if sphere is not None:
            out.append(sphere)
            continue
        w = f"{what}[{i}]"
        m = r.section(item, SPHERE, w)
        assert m is not None
        center_node = r.get(m, SPHERE, "center", f"sphere {w}")
        center = _read_vec3(r, center_node, SPHERE.fields["center"], f"{w}.center")
        radius_node = r.get(m, SPHERE, "radius", f"sphere {w}")
        radius = r.num(radius_node, SPHERE.fields["radius"], f"{w}.radius")
        out.append(Sphere(center, radius))
    return tuple(out)


def _plain_sphere(item: YNode) -> Sphere | None:
    """``{center: [x, y, z], radius: r}`` of plain numbers within the length bound, read
    without the per-node checks (and their message strings) of the general path; None for
    anything else, which the general path reads or refuses with its message."""
    if type(item) is not YMap or len(item.pairs) != 2:
        return None
    (k1, v1), (k2, v2) = item.pairs
    if not (isinstance(k1, YScalar) and isinstance(k2, YScalar)):
        return None
    if k1.value == "center" and k2.value == "radius":
        center_node, radius_node = v1, v2
    elif k1.value == "radius" and k2.value == "center":
        center_node, radius_node = v2, v1
    else:
        return None
    center = plain_numbers(center_node, MAX_LENGTH)
    if center is None or len(center) != 3 or not isinstance(radius_node, YScalar):
        return None
    radius = plain_number(radius_node.value, MAX_LENGTH)
    if radius is None:
        return None
    return Sphere((center[0], center[1], center[2]), radius)


def _read_geometry(r: NodeReader, node: YNode | None) -> FrozenMap[str, GeometryGroup]:
    def group(n: YNode, what: str) -> GeometryGroup:
        m = r.section(n, GROUP, what)
        if m is None:
            return GeometryGroup()
        spheres = r.frame_map(
            m.get("spheres"), f"{what}.spheres", lambda v, w: _read_spheres(r, v, w)
        )
        clone_node = m.get("clone")
        if isinstance(clone_node, YScalar) and clone_node.value is not None:
            raise r.fail(
                clone_node,
                f"{what}.clone must be a list of group names, not {describe(clone_node)}",
            )
        clone = r.strings(clone_node, f"{what}.clone")
        return GeometryGroup(spheres, clone)

    return r.frame_map(node, "geometry", group)


def _group_name(r: NodeReader, m: YMap, shape: Shape, what: str) -> str:
    g = r.get(m, shape, "geometry", what)
    if isinstance(g, YSeq) and len(g) == 1:
        return r.string(g.items[0], f"{what}.geometry[0]")
    return r.string(g, f"{what}.geometry")


def _check_group_defined(
    r: NodeReader, section: YNode | None, key: str, geometry: Mapping[str, GeometryGroup]
) -> None:
    """The group ``key.geometry`` names resolves (defined, clones defined, no clone cycle);
    else a :class:`SchemaError` at that name."""
    if not isinstance(section, YMap):
        return
    node = section.get("geometry")
    if isinstance(node, YSeq) and len(node) == 1:
        node = node.items[0]
    if not isinstance(node, YScalar):
        return
    group = str(node.value)
    try:
        clone_order(geometry, group)
    except GeometryGroupError as e:
        raise r.fail(node, f"{key}.geometry: {e.message}") from None


def _read_buffers(
    r: NodeReader,
    node: YNode | None,
    what: str,
    geometry: Mapping[str, GeometryGroup] | None,
    group: str,
) -> FrozenMap[str, float]:
    value = BUFFERS.values
    assert value is not None
    if isinstance(node, YScalar) and node.value is not None:
        # cuRobo accepts a single number for every frame: expand it over the group's frames.
        single = r.num(node, value, what)
        frames: Sequence[str] = ()
        if geometry and group in geometry:
            try:
                frames = list(resolve_group(geometry, group))
            except SchemaError:
                frames = []
        return FrozenMap((f, single) for f in frames)
    return r.frame_map(node, what, lambda v, w: r.num(v, value, w))


def _read_world(
    r: NodeReader, node: YNode | None, key: str, geometry: Mapping[str, GeometryGroup] | None
) -> CollisionSection:
    m = r.section(node, WORLD, key)
    assert m is not None
    group = _group_name(r, m, WORLD, key)
    return CollisionSection(
        group, _read_buffers(r, m.get("buffer_distance"), f"{key}.buffer_distance", geometry, group)
    )


def _read_self(
    r: NodeReader, node: YNode | None, geometry: Mapping[str, GeometryGroup] | None
) -> SelfCollisionSection:
    m = r.section(node, SELF, "self_collision")
    assert m is not None
    group = _group_name(r, m, SELF, "self_collision")
    ignore_node = m.get("ignore")
    if isinstance(ignore_node, YSeq) and len(ignore_node) == 0:
        ignore_node = None  # `ignore: []` as cuRobo's writer emits it means "nothing masked"

    def frames(v: YNode, w: str) -> tuple[str, ...]:
        if isinstance(v, YScalar) and v.value is not None:
            raise r.fail(v, f"{w} must be a list of frame names, not {describe(v)}")
        return r.strings(v, w)

    return SelfCollisionSection(
        group,
        _read_buffers(
            r, m.get("buffer_distance"), "self_collision.buffer_distance", geometry, group
        ),
        r.frame_map(ignore_node, "self_collision.ignore", frames),
    )
