"""The vertices of a binary glTF (``.glb``) file as trimesh reads them, without a mesh.

:func:`glb_vertices` gives the points of every triangle primitive the file's scene draws, each
with the transform of the node that instances it (``matrix``, or ``translation``, ``rotation``
and ``scale``, composed from the scene's root nodes down), in the file's own frame and units,
as trimesh's glTF loader places them (no axis change). They are read from the file's binary
chunk with numpy in milliseconds instead of trimesh's tens to hundreds.

Where the file holds something this reader does not follow exactly (a compressed primitive:
Draco or meshopt; a sparse or quantized position accessor; a buffer outside the file; a
primitive that draws lines or points; a node cycle), it raises :class:`GltfNotRead` naming it:
a wrong box is worse than none, and the caller then counts the file as not read. What the
scene expands to is bounded as it is walked, each node once per instance: nodes nested
:data:`MAX_DEPTH` deep, :data:`MAX_NODES` node instances, :data:`MAX_INSTANCES` mesh instances
and :data:`MAX_POINTS` instanced vertices at most, counted before any is copied; past one it
raises :class:`GltfTooBig` (a node shared twice at each of 60 levels is a 2 kB file of 2^60
nodes, and 5,000 instances of a 3 MB mesh would be 36 GB of vertices). Transforms that
overflow give non-finite vertices without a numpy warning (the caller checks them). Nothing is
read outside the bytes given.
"""

from __future__ import annotations

import json
import struct
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from ..util.arrays import AnyArray, FloatArray

__all__ = ["GltfNotRead", "GltfTooBig", "glb_vertices"]

#: Nodes nested at most this deep.
MAX_DEPTH = 64
#: Mesh instances of one scene at most.
MAX_INSTANCES = 10_000
#: Node instances of one scene at most, every shared child counted each time it is reached.
MAX_NODES = 100_000
#: Vertices handed back at most, every instance counted (as the COLLADA reader's bound).
MAX_POINTS = 20_000_000
#: The largest ``byteStride`` glTF allows.
_MAX_STRIDE = 252
_MAGIC = b"glTF"
_JSON_CHUNK = 0x4E4F534A
_BIN_CHUNK = 0x004E4942
_FLOAT = 5126
#: Triangles, triangle strip, triangle fan (the modes trimesh reads as faces).
_TRIANGLE_MODES = (4, 5, 6)


class GltfNotRead(Exception):
    """The file holds something :func:`glb_vertices` does not read exactly (the message)."""


class GltfTooBig(GltfNotRead):
    """The scene expands past a bound (see the module): no reader should walk or copy it."""


def glb_vertices(data: bytes) -> FloatArray:
    """The vertices [N, 3] of the triangle primitives of the ``.glb`` file ``data``, placed by
    the scene's node transforms. Raises :class:`GltfNotRead`."""
    doc, binary = _chunks(data)
    with np.errstate(all="ignore"):  # overflow: inf or NaN, which the caller checks
        instances = [
            (primitive, transform)
            for mesh, transform in _instances(doc)
            for primitive in _primitives(doc, mesh)
        ]
        read: dict[int, FloatArray] = {}  # each primitive read once, however often drawn
        for primitive, _ in instances:
            if id(primitive) not in read:
                read[id(primitive)] = _used(doc, binary, primitive)
        if sum(len(read[id(p)]) for p, _ in instances) > MAX_POINTS:
            raise GltfTooBig(f"over {MAX_POINTS} vertices, every mesh instance counted")
        pieces = [_placed(read[id(p)], transform) for p, transform in instances]
    return np.concatenate(pieces) if pieces else np.zeros((0, 3))


def _chunks(data: bytes) -> tuple[Mapping[str, Any], bytes]:
    """The JSON document and the binary chunk of a GLB file."""
    if len(data) < 20 or data[:4] != _MAGIC:
        raise GltfNotRead("not a binary glTF file")
    version, length = struct.unpack_from("<II", data, 4)
    if version != 2 or length > len(data):
        raise GltfNotRead(f"glTF version {version} or a length past the file")
    chunks: dict[int, bytes] = {}
    at = 12
    while at + 8 <= length:
        size, kind = struct.unpack_from("<II", data, at)
        if at + 8 + size > length:
            raise GltfNotRead("a chunk past the end of the file")
        chunks.setdefault(kind, data[at + 8 : at + 8 + size])
        at += 8 + size
    if _JSON_CHUNK not in chunks:
        raise GltfNotRead("no JSON chunk")
    try:
        doc = json.loads(chunks[_JSON_CHUNK].decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        raise GltfNotRead("a JSON chunk that does not parse") from None
    if not isinstance(doc, dict):
        raise GltfNotRead("a JSON chunk that is not an object")
    if doc.get("extensionsRequired"):
        raise GltfNotRead(f"required extensions {doc['extensionsRequired']}")
    return doc, chunks.get(_BIN_CHUNK, b"")


def _instances(doc: Mapping[str, Any]) -> Iterator[tuple[int, FloatArray]]:
    """Each mesh the scene draws and the transform placing it."""
    nodes = _list(doc, "nodes")
    scenes = _list(doc, "scenes")
    chosen = doc.get("scene", 0)
    if scenes:
        roots = _indices(_item(scenes, chosen, "scene"), "nodes")
    else:  # no scene: every node no other node holds, as trimesh takes them
        held = {c for n in nodes for c in _indices(n, "children")}
        roots = [i for i in range(len(nodes)) if i not in held]
    count = visited = 0
    stack = [(i, np.eye(4), 1) for i in reversed(roots)]
    while stack:
        index, above, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise GltfTooBig(f"nodes nested deeper than {MAX_DEPTH} (or a node cycle)")
        visited += 1
        if visited > MAX_NODES:
            raise GltfTooBig(f"a scene of more than {MAX_NODES} nodes, shared ones counted")
        node = _item(nodes, index, "node")
        transform = above @ _local(node)
        if "mesh" in node:
            count += 1
            if count > MAX_INSTANCES:
                raise GltfTooBig(f"over {MAX_INSTANCES} mesh instances")
            yield _index(node["mesh"]), transform
        stack.extend((c, transform, depth + 1) for c in reversed(_indices(node, "children")))


def _local(node: Mapping[str, Any]) -> FloatArray:
    """A node's own transform: its ``matrix`` (column-major), else T · R · S."""
    if "matrix" in node:
        given: FloatArray = _numbers(node["matrix"], 16, "matrix").reshape(4, 4).T
        return given
    m = np.eye(4)
    x, y, z, w = _numbers(node.get("rotation", [0, 0, 0, 1]), 4, "rotation")
    m[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    m[:3, :3] *= _numbers(node.get("scale", [1, 1, 1]), 3, "scale")
    m[:3, 3] = _numbers(node.get("translation", [0, 0, 0]), 3, "translation")
    return m


def _primitives(doc: Mapping[str, Any], mesh: int) -> Iterator[Mapping[str, Any]]:
    for primitive in _list(_item(_list(doc, "meshes"), mesh, "mesh"), "primitives"):
        if not isinstance(primitive, dict):
            raise GltfNotRead("a primitive that is not an object")
        if primitive.get("extensions"):
            raise GltfNotRead(f"a primitive with extensions {sorted(primitive['extensions'])}")
        if primitive.get("mode", 4) in _TRIANGLE_MODES:
            yield primitive


def _used(doc: Mapping[str, Any], binary: bytes, primitive: Mapping[str, Any]) -> FloatArray:
    """The ``POSITION`` values of ``primitive`` that its ``indices`` use (all without
    indices), from the GLB's binary chunk: the vertices trimesh keeps."""
    attributes = primitive.get("attributes")
    if not isinstance(attributes, dict) or "POSITION" not in attributes:
        raise GltfNotRead("a primitive without POSITION")
    positions = _accessor(doc, binary, attributes["POSITION"], "VEC3", (_FLOAT,))
    if "indices" not in primitive:
        return positions
    used = _accessor(doc, binary, primitive["indices"], "SCALAR", tuple(_INDEX_TYPES))
    if used.size and int(used.max()) >= len(positions):
        raise GltfNotRead("an index past the POSITION accessor")
    referenced = np.zeros(len(positions), dtype=bool)
    referenced[used.astype(np.intp)] = True
    kept: FloatArray = positions[referenced]
    return kept


#: glTF component types of indices: unsigned byte, short and int.
_INDEX_TYPES = {5121: "<u1", 5123: "<u2", 5125: "<u4"}
_WIDTH = {"VEC3": 3, "SCALAR": 1}


def _accessor(
    doc: Mapping[str, Any], binary: bytes, index: Any, kind: str, types: tuple[int, ...]
) -> FloatArray:
    """The values of accessor ``index`` ([count, 3] for VEC3, [count] for SCALAR), which must
    be of ``kind`` and one of the component ``types``, in the GLB's binary chunk."""
    accessor = _item(_list(doc, "accessors"), index, "accessor")
    component = accessor.get("componentType")
    if "sparse" in accessor or component not in types or accessor.get("normalized"):
        raise GltfNotRead(f"a sparse, normalized or {component} {kind} accessor")
    if accessor.get("type") != kind or "bufferView" not in accessor:
        raise GltfNotRead(f"an accessor that is not {kind} data")
    view = _item(_list(doc, "bufferViews"), accessor["bufferView"], "bufferView")
    buffer = _item(_list(doc, "buffers"), view.get("buffer"), "buffer")
    if buffer.get("uri") is not None or _index(view.get("buffer")) != 0:
        raise GltfNotRead("a buffer outside the GLB file")
    dtype = np.dtype("<f4" if component == _FLOAT else _INDEX_TYPES[component])
    width = _WIDTH[kind] * dtype.itemsize
    count = _index(accessor.get("count"))
    stride = _index(view.get("byteStride", width)) or width
    start = _index(view.get("byteOffset", 0)) + _index(accessor.get("byteOffset", 0))
    end = _index(view.get("byteOffset", 0)) + _index(view.get("byteLength"))
    if (
        stride < width
        or stride > max(width, _MAX_STRIDE)
        or end > len(binary)
        or (count and start + stride * (count - 1) + width > end)
    ):
        raise GltfNotRead(f"a {kind} accessor past its buffer")
    shape = (count, 3) if kind == "VEC3" else (count,)
    strides = (stride, dtype.itemsize) if kind == "VEC3" else (stride,)
    if not count:
        return np.zeros(shape)
    values: AnyArray = np.ndarray(shape, dtype=dtype, buffer=binary, offset=start, strides=strides)
    return np.asarray(values, dtype=np.float64)


def _placed(points: FloatArray, transform: FloatArray) -> FloatArray:
    return np.asarray(points @ transform[:3, :3].T + transform[:3, 3], dtype=np.float64)


def _list(owner: Mapping[str, Any], key: str) -> list[Any]:
    value = owner.get(key, [])
    if not isinstance(value, list):
        raise GltfNotRead(f"'{key}' is not a list")
    return value


def _item(items: list[Any], index: Any, what: str) -> Mapping[str, Any]:
    i = _index(index)
    if i >= len(items) or not isinstance(items[i], dict):
        raise GltfNotRead(f"{what} {i} is not in the file")
    return items[i]  # type: ignore[no-any-return]


def _indices(owner: Mapping[str, Any], key: str) -> list[int]:
    return [_index(v) for v in _list(owner, key)]


def _index(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise GltfNotRead(f"{value!r} is not an index or a size")
    return value


def _numbers(value: Any, n: int, what: str) -> FloatArray:
    if not isinstance(value, list) or len(value) != n:
        raise GltfNotRead(f"a node {what} that is not {n} numbers")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        raise GltfNotRead(f"a node {what} that is not {n} numbers")
    try:
        return np.asarray(value, dtype=np.float64)
    except OverflowError:  # an integer past float range (JSON integers have no bound)
        raise GltfNotRead(f"a node {what} with a number past float range") from None
