"""The vertices of a COLLADA (``.dae``) file as the sphere fitter reads them, without a mesh.

:func:`collada_vertices` gives the points whose box is the box of the mesh that trimesh
(through pycollada, as :func:`~xrdf_tools.robot.mesh_files.load_mesh_scene` reads it) makes of
the file, in the same frame, read from the XML with numpy in milliseconds instead of trimesh's
tens to thousands:

* the ``<visual_scene>`` that ``<scene>`` names, walked from its ``<node>`` elements: each
  node's ``<matrix>``, ``<translate>``, ``<rotate>`` and ``<scale>`` composed in order (single
  precision, as pycollada composes them), nested nodes, ``<instance_node>`` of a node of
  ``<library_nodes>``, and each ``<instance_geometry>`` with the transform above it;
* of each instanced geometry the vertices its ``<triangles>``, ``<polylist>`` and
  ``<polygons>`` use (not the whole ``<float_array>``);
* ``<asset><unit meter>`` applied (the file in metres); ``<up_axis>`` not applied, as
  neither trimesh nor pycollada applies it.

Where the file holds something this reader does not handle exactly as pycollada does (a
``<lookat>`` or ``<skew>``, strips and fans, lines, a reference it cannot follow, a source
pycollada would drop, a number that does not parse), it raises :class:`ColladaNotRead`
naming it: a wrong box is worse than none. The XML is read by the project's guarded parser
(no entity substitution, no DTD, no network); a text node over libxml2's 10 MB (one large
``<float_array>``) is allowed, the file being size-capped when read.

What the scene expands to is bounded before it is walked (:func:`check_collada_bounds`, also
run before trimesh reads a COLLADA file): ``<node>`` nesting and ``<instance_node>`` chains
:data:`MAX_DEPTH` deep, :data:`MAX_NODES` nodes and :data:`MAX_INSTANCES` geometry instances
once every ``<instance_node>`` is expanded (a node instanced twice at each of 60 levels is
2^60 nodes), no ``<instance_node>`` cycle. A file past them raises :class:`ColladaTooBig`:
no reader should be handed it. The number of points is capped too. Numbers that overflow
once transformed are handed back as they come (inf, nan): the caller checks the vertices.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..util.arrays import AnyArray, FloatArray
from ..util.safe_xml import XmlSyntaxError, parse_xml
from .collada_materials import loadable_materials
from .collada_values import (
    TRANSFORMS,
    ColladaNotRead,
    ColladaTooBig,
    composed,
    fail,
    numbers,
    ref,
)

__all__ = ["ColladaNotRead", "ColladaTooBig", "check_collada_bounds", "collada_vertices"]

#: Nodes nested (``<node>`` in ``<node>``, ``<instance_node>``) at most this deep.
MAX_DEPTH = 64
#: Geometry instances in one file at most (an ``<instance_node>`` tree can multiply them).
MAX_INSTANCES = 10_000
#: Nodes of the scene at most, every ``<instance_node>`` expanded.
MAX_NODES = 100_000
#: Points handed back at most.
MAX_POINTS = 20_000_000
_IGNORED_IN_NODE = frozenset({"instance_camera", "instance_light", "extra", "asset"})
#: ``<lines>`` are read to check them (pycollada drops a geometry with bad lines) but add no
#: vertex: trimesh keeps triangles only.
_PRIMITIVES = frozenset({"triangles", "polylist", "polygons", "lines"})
_INPUT_SIZES = {"NORMAL": 3, "TEXCOORD": 2}
_INPUTS = frozenset({"VERTEX", "NORMAL", "TEXCOORD", "COLOR"})


def collada_vertices(data: bytes) -> FloatArray:
    """The vertices [N, 3] (metres) of the triangles the COLLADA document ``data`` instances
    in its scene, each in the scene frame (not checked finite: a transform or unit may
    overflow). Raises :class:`ColladaNotRead` (:class:`ColladaTooBig` past a bound)."""
    document = _Document(_parsed(data))
    with np.errstate(over="ignore", invalid="ignore"):
        points = document.scene_points()
        every = np.concatenate(points) if points else np.zeros((0, 3))
        unit = document.unit()
        if unit is not None:
            every = every * unit
    return np.asarray(every, dtype=np.float64)


def check_collada_bounds(data: bytes) -> None:
    """Raise :class:`ColladaTooBig` when the scene of the COLLADA document ``data`` expands
    past the bounds (see the module); anything else (not XML, not COLLADA, no scene, a
    reference not followed) is left to the reader to say."""
    try:
        document = _Document(_parsed(data))
        document.scene()
    except ColladaTooBig:
        raise
    except ColladaNotRead:
        return


def _parsed(data: bytes) -> Any:
    try:
        return parse_xml(data, keep_comments=False, huge_tree=True)
    except XmlSyntaxError as e:
        raise ColladaNotRead(f"not well-formed XML: {e.reason}", line=e.line, col=e.col) from None


@dataclass
class _Geometry:
    """One ``<geometry>``: the used vertices (float32, as pycollada keeps them)."""

    points: FloatArray


@dataclass
class _Document:
    root: Any
    ns: str = ""
    geometries: dict[str, Any] = field(default_factory=dict)
    library_nodes: dict[str, Any] = field(default_factory=dict)
    materials: set[str] = field(default_factory=set)
    read: dict[str, _Geometry] = field(default_factory=dict)
    point_count: int = 0

    def __post_init__(self) -> None:
        tag = self.root.tag if isinstance(self.root.tag, str) else ""
        self.ns = tag[: tag.index("}") + 1] if tag.startswith("{") else ""
        if tag[len(self.ns) :] != "COLLADA":
            raise fail("not a COLLADA document", self.root)
        self.geometries = self._library("library_geometries", "geometry")
        self.geometries = {
            k: g for k, g in self.geometries.items() if self._child(g, "mesh") is not None
        }
        self.library_nodes = self._library("library_nodes", "node")
        self.materials = loadable_materials(self.root, self.ns)

    def t(self, name: str) -> str:
        return self.ns + name

    def _child(self, element: Any, name: str) -> Any:
        return element.find(self.t(name))

    def _library(self, library: str, item: str) -> dict[str, Any]:
        found: dict[str, Any] = {}
        for lib in self.root.findall(self.t(library)):
            for element in lib.findall(self.t(item)):
                key = element.get("id")
                if key is None:
                    continue
                if key in found:
                    raise fail(f"two <{item}> elements with id '{key}'", element)
                found[key] = element
        return found

    def unit(self) -> float | None:
        """The scale to metres, None for metres (pycollada: a ``meter`` that does not parse
        is no unit; trimesh: within ``isclose`` of 1 is metres)."""
        asset = self._child(self.root, "asset")
        unit = None if asset is None else self._child(asset, "unit")
        if unit is None:
            return None
        try:
            meter = float(unit.get("meter"))
        except (TypeError, ValueError):
            return None
        if not np.isfinite(meter) or meter <= 0.0:
            raise fail(f"unit of {meter} m", unit)
        return None if np.isclose(meter, 1.0) else meter

    def scene(self) -> Any:
        """The ``<visual_scene>`` that ``<scene>`` names, its expansion checked bounded."""
        instance = self.root.find(f"{self.t('scene')}/{self.t('instance_visual_scene')}")
        scenes = self._library("library_visual_scenes", "visual_scene")
        scene = scenes.get(ref(instance, "url") or "")
        if scene is None:
            raise fail("no <scene> naming a <visual_scene> of the file", instance)
        top_ids = {n.get("id") for n in scene.findall(self.t("node"))}
        if top_ids & set(self.library_nodes):
            raise fail("a scene node and a library node share an id", scene)
        _Expansion(self).check(scene)
        return scene

    def scene_points(self) -> list[FloatArray]:
        out: list[FloatArray] = []
        for node in self.scene().findall(self.t("node")):
            self._walk(node, np.eye(4), out)
        return out

    def _walk(self, node: Any, parent: FloatArray, out: list[FloatArray]) -> None:
        transforms: list[AnyArray] = []
        children: list[Any] = []
        for sub in node:
            name = self._local(sub)
            if name in TRANSFORMS:
                transforms.append(TRANSFORMS[name](numbers(sub, np.float32), sub))
            elif name in ("node", "instance_node", "instance_geometry"):
                children.append(sub)
            elif name not in _IGNORED_IN_NODE:
                raise fail(f"<{name}> in a <node> not read", sub)
        here = parent @ composed(transforms)
        for child in children:
            name = self._local(child)
            if name == "node":
                self._walk(child, here, out)
            elif name == "instance_node":
                target = self.library_nodes.get(ref(child, "url") or "")
                if target is None:
                    raise fail(f"<instance_node url='{child.get('url')}'> not followed", child)
                self._walk(target, here, out)
            else:
                out.append(self._instance(child, here))

    def _local(self, element: Any) -> str:
        tag = element.tag
        if not isinstance(tag, str):
            raise fail("an entity reference or processing instruction in a <node>", element)
        if not tag.startswith(self.ns) or (not self.ns and tag.startswith("{")):
            raise fail(f"element {tag} of another namespace in a <node>", element)
        return str(tag[len(self.ns) :])

    def _instance(self, element: Any, matrix: FloatArray) -> FloatArray:
        key = ref(element, "url") or ""
        if key not in self.geometries:
            raise fail(f"<instance_geometry url='{element.get('url')}'> not followed", element)
        for binding in element.iter(self.t("instance_material")):
            if ref(binding, "target") not in self.materials:
                raise fail(f"material '{binding.get('target')}' not loaded", binding)
        if key not in self.read:
            self.read[key] = _Geometry(self._used_vertices(self.geometries[key]))
        points = self.read[key].points
        self.point_count += len(points)
        if self.point_count > MAX_POINTS:
            raise fail(f"more than {MAX_POINTS} vertices instanced", element, ColladaTooBig)
        if not np.allclose(matrix[3], (0.0, 0.0, 0.0, 1.0), rtol=0.0, atol=0.0):
            raise fail("a projective node transform", element)
        return np.asarray(points @ matrix[:3, :3].T + matrix[:3, 3], dtype=np.float64)

    def _used_vertices(self, geometry: Any) -> FloatArray:
        mesh = self._child(geometry, "mesh")
        sources: dict[str, FloatArray] = {}
        vertices_element = None
        primitives: list[Any] = []
        for sub in mesh:
            name = self._local(sub)
            if name == "source":
                sources[sub.get("id") or ""] = self._source(sub)
            elif name == "vertices":
                vertices_element = sub
            elif name in _PRIMITIVES:
                primitives.append(sub)
            elif name != "extra":
                raise fail(f"<{name}> in a <mesh> not read", sub)
        if vertices_element is None:
            if primitives:
                raise fail("a <mesh> without <vertices>", mesh)
            return np.zeros((0, 3), dtype=np.float32)
        vertices = self._vertices(vertices_element, sources)
        used = np.zeros(len(vertices.position), dtype=bool)
        for primitive in primitives:
            for index in _Primitive(self, primitive, vertices, sources).vertex_indices():
                used[index] = True
        points = vertices.position[used]
        if not np.all(np.isfinite(points)):
            raise fail("a vertex that is not a finite number", geometry)
        return np.asarray(points, dtype=np.float32)

    def _source(self, source: Any) -> FloatArray:
        """A ``<source>`` as pycollada shapes it: ``(-1, params)`` (a texture's S, T, P
        without P)."""
        array = self._child(source, "float_array")
        if array is None:
            if (
                self._child(source, "IDREF_array") is None
                and self._child(source, "Name_array") is None
            ):
                raise fail("a <source> without an array", source)
            return np.zeros((0, 0), dtype=np.float32)
        values = numbers(array, np.float32)
        params = source.findall(
            f"{self.t('technique_common')}/{self.t('accessor')}/{self.t('param')}"
        )
        names = [p.get("name") for p in params]
        if not names or values.size % len(names):
            raise fail("a <source> whose numbers do not fill its <accessor>", source)
        shaped = values.reshape(-1, len(names))
        return shaped[:, :2] if names == ["S", "T", "P"] else shaped

    def _vertices(self, element: Any, sources: dict[str, FloatArray]) -> _Vertices:
        inputs: dict[str, FloatArray] = {}
        for given in element.findall(self.t("input")):
            source = sources.get(ref(given, "source") or "\0")
            semantic = given.get("semantic") or ""
            if source is None or semantic in inputs:
                raise fail(f"<input source='{given.get('source')}'> not read", given)
            inputs[semantic] = source
        key = element.get("id")
        position = inputs.pop("POSITION", None)
        if not key or position is None or position.shape[1] != 3:
            raise fail("<vertices> without an id or an XYZ POSITION", element)
        if set(inputs) - _INPUTS:
            raise fail(f"<vertices> inputs {sorted(inputs)} not read", element)
        return _Vertices(key, position, inputs)


@dataclass
class _Expansion:
    """What a scene's nodes expand to, each node element counted once (memoised): nodes,
    geometry instances and depth, every ``<instance_node>`` followed; a cycle raises."""

    doc: _Document
    seen: dict[Any, tuple[int, int, int]] = field(default_factory=dict)
    path: set[Any] = field(default_factory=set)

    def check(self, scene: Any) -> None:
        nodes = instances = 0
        for node in scene.findall(self.doc.t("node")):
            n, i, _ = self._of(node, 1)
            nodes, instances = nodes + n, instances + i
            if nodes > MAX_NODES:
                raise fail(f"a scene of more than {MAX_NODES} nodes", node, ColladaTooBig)
            if instances > MAX_INSTANCES:
                message = f"more than {MAX_INSTANCES} geometry instances"
                raise fail(message, node, ColladaTooBig)

    def _of(self, node: Any, depth: int) -> tuple[int, int, int]:
        """(nodes, geometry instances, height) of ``node`` expanded; ``depth``: its own."""
        if node in self.path:
            raise fail("an <instance_node> cycle", node, ColladaTooBig)
        if depth > MAX_DEPTH:
            raise fail(f"nodes nested deeper than {MAX_DEPTH}", node, ColladaTooBig)
        known = self.seen.get(node)
        if known is not None:
            if depth + known[2] - 1 > MAX_DEPTH:
                raise fail(f"nodes nested deeper than {MAX_DEPTH}", node, ColladaTooBig)
            return known
        self.path.add(node)
        nodes, instances, height = 1, 0, 1
        for child in node:
            tag = child.tag if isinstance(child.tag, str) else ""
            name = tag[len(self.doc.ns) :] if tag.startswith(self.doc.ns) else ""
            if name == "instance_geometry":
                instances += 1
                continue
            target = child if name == "node" else None
            if name == "instance_node":
                target = self.doc.library_nodes.get(ref(child, "url") or "")
            if target is not None:
                n, i, h = self._of(target, depth + 1)
                nodes, instances, height = nodes + n, instances + i, max(height, h + 1)
        self.path.discard(node)
        self.seen[node] = (nodes, instances, height)
        return nodes, instances, height


@dataclass(frozen=True)
class _Vertices:
    """A ``<vertices>``: its id, POSITION and other inputs (indexed with the positions)."""

    id: str
    position: FloatArray
    others: dict[str, FloatArray]


@dataclass
class _Primitive:
    """One ``<triangles>``, ``<polylist>`` or ``<polygons>``: its vertex indices checked as
    pycollada checks them (a primitive it rejects loses trimesh the whole geometry)."""

    doc: _Document
    element: Any
    vertices: _Vertices
    sources: dict[str, FloatArray]

    def vertex_indices(self) -> list[AnyArray]:
        inputs = self._inputs()
        stride = max(offset for offset, _, _ in inputs) + 1
        rows = self._rows(stride)
        if not len(rows):
            return []
        for offset, semantic, source in inputs:
            column = rows[:, offset]
            size = _INPUT_SIZES.get(semantic)
            if column.min() < 0 or column.max() >= len(source):
                raise fail(f"a {semantic} index out of its source", self.element)
            if size is not None and source.shape[1] != size:
                raise fail(f"a {semantic} source of {source.shape[1]} values", self.element)
        if self.doc._local(self.element) == "lines":
            return []
        return [rows[:, offset] for offset, semantic, _ in inputs if semantic == "VERTEX"]

    def _inputs(self) -> list[tuple[int, str, FloatArray]]:
        out: list[tuple[int, str, FloatArray]] = []
        for given in self.element.findall(self.doc.t("input")):
            semantic, target = given.get("semantic"), ref(given, "source")
            try:
                offset = int(given.get("offset"))
            except (TypeError, ValueError):
                raise fail("an <input> without an integer offset", given) from None
            if semantic not in _INPUTS or offset < 0 or offset > 64:
                raise fail(f"<input semantic='{semantic}' offset='{offset}'> not read", given)
            if semantic == "VERTEX":
                if target != self.vertices.id:
                    raise fail("a VERTEX input not of the mesh's <vertices>", given)
                out.append((offset, semantic, self.vertices.position))
                out.extend((offset, name, src) for name, src in self.vertices.others.items())
            elif target in self.sources:
                out.append((offset, semantic, self.sources[target]))
            else:
                raise fail(f"<input source='{given.get('source')}'> not found", given)
        if [s for _, s, _ in out].count("VERTEX") != 1:
            raise fail("a primitive without exactly one VERTEX input", self.element)
        return out

    def _rows(self, stride: int) -> AnyArray:
        """The index array, one row a vertex of a polygon, columns the input offsets."""
        kind = self.doc._local(self.element)
        lists = self.element.findall(self.doc.t("p"))
        if kind == "polygons":
            if self.element.find(self.doc.t("ph")) is not None:
                raise fail("<polygons> with holes", self.element)
            counts = [len(numbers(p, np.int32)) for p in lists]
            if any(c == 0 or c % stride or c // stride < 3 for c in counts):
                raise fail("a <polygons> <p> that is not a polygon", self.element)
            flat = np.concatenate([numbers(p, np.int32) for p in lists] or [np.zeros(0, np.int32)])
        else:
            if len(lists) != 1:
                raise fail(f"a <{kind}> with {len(lists)} <p> elements", self.element)
            flat = numbers(lists[0], np.int32)
            corners = (2 if kind == "lines" else 3) * stride
            if kind == "polylist":
                vcount = self.element.find(self.doc.t("vcount"))
                counts_array = numbers(vcount, np.int32) if vcount is not None else None
                if counts_array is None or (len(counts_array) and counts_array.min() < 3):
                    raise fail("a <polylist> <vcount> missing or under 3", self.element)
                corners = stride
                if len(flat) and int(counts_array.sum()) * stride != len(flat):
                    raise fail("a <polylist> whose <p> does not match <vcount>", self.element)
            if len(flat) % corners:
                raise fail(f"a <{kind}> <p> of {len(flat)} numbers", self.element)
        rows: AnyArray = flat.reshape(-1, stride)
        return rows
