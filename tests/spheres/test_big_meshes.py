"""CAD-sized meshes (:mod:`xrdf_tools.spheres.inside`, :mod:`xrdf_tools.robot.mesh_files`):
the inside test's triangle grid is built once per mesh and gives the exact answer however it
is made; a mesh past the triangle limit, or a binary STL whose header lies, is refused with one
line naming the file. The limit is lowered here so that small meshes stand in for big ones
(what big ones cost: ``benchmarks/bench_big_mesh.py``)."""

from __future__ import annotations

import struct
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import trimesh
from typer.testing import CliRunner

from tests.odd_meshes import fan_capped_cylinder, fan_cone
from xrdf_tools.cli import app
from xrdf_tools.robot import link_geometry as lg
from xrdf_tools.spheres import inside
from xrdf_tools.spheres.inside import points_inside

ROBOT = """<robot name="r">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="arm"><collision><geometry><mesh filename="{}"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _every_pair(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """The parity test with every (point, triangle) pair: the answer any grid must give."""
    faces = np.asarray(mesh.faces, dtype=np.int64)
    table = inside._TriangleTable(np.asarray(mesh.vertices, dtype=np.float64), faces)
    tri = np.tile(np.arange(len(faces)), len(points))
    pnt = np.repeat(np.arange(len(points)), len(faces))
    hit, z = table.crossings(tri, pnt, points)
    crossed = np.bincount(hit[z > points[hit, 2]], minlength=len(points))
    out: np.ndarray = crossed % 2 == 1
    return out


def _slivered_cylinder() -> trimesh.Trimesh:
    """A closed tube of long slivers (8 sides, a 45-degree twist): many triangles whose xy
    boxes cross many grid cells, as a CAD part's long thin triangles do."""
    mesh = trimesh.creation.cylinder(radius=0.05, height=0.4, sections=8)
    mesh.vertices[:, :2] += 0.5 * mesh.vertices[:, 2:3] * mesh.vertices[:, [1, 0]] * [-1, 1]
    return mesh.subdivide().subdivide()


@pytest.mark.parametrize(
    "pairs_per_face, wide_cells, max_wide", [(8, 256, 64), (1, 2, 4), (8, 1, 10**9)]
)
def test_the_inside_test_is_exact_whatever_the_grid(
    monkeypatch: pytest.MonkeyPatch, pairs_per_face: int, wide_cells: int, max_wide: int
) -> None:
    """The default grid, one made coarser for slivers, and one holding every triangle in its
    list of wide ones all give the answer of testing every pair."""
    monkeypatch.setattr(inside, "MIN_PAIRS", 0)
    monkeypatch.setattr(inside, "PAIRS_PER_FACE", pairs_per_face)
    monkeypatch.setattr(inside, "WIDE_CELLS", wide_cells)
    monkeypatch.setattr(inside, "MAX_WIDE", max_wide)
    mesh = _slivered_cylinder()
    rng = np.random.default_rng(3)
    points = rng.uniform(mesh.bounds[0] - 0.01, mesh.bounds[1] + 0.01, size=(400, 3))
    points[:40, :2] = mesh.vertices[:40, :2]  # rays through vertices: the tie rules
    expected = _every_pair(mesh, points)
    assert 0.1 < expected.mean() < 0.9
    assert np.array_equal(points_inside(mesh, points), expected)


def _random_slivers(count: int) -> trimesh.Trimesh:
    """Long thin triangles in every direction (not a closed mesh: the parity of each point's
    crossings is compared all the same)."""
    rng = np.random.default_rng(11)
    a = rng.uniform(-1.0, 1.0, size=(count, 3))
    b = rng.uniform(-1.0, 1.0, size=(count, 3))
    c = a + (b - a) * rng.uniform(0.0, 1.0, size=(count, 1))
    c[:, :2] += rng.normal(scale=1e-3, size=(count, 2))  # a sliver along a -> b
    c[: count // 8, 1] = a[: count // 8, 1]  # some with a horizontal edge
    vertices = np.stack([a, b, c], 1).reshape(-1, 3)
    return trimesh.Trimesh(vertices, np.arange(3 * count).reshape(-1, 3), process=False)


def _testing_points(mesh: trimesh.Trimesh, grid: inside.FaceGrid) -> np.ndarray:
    """Random points, and points exactly on the grid's cell boundaries, on the triangles'
    edges and on their vertices, at random heights."""
    rng = np.random.default_rng(5)
    lo, hi = mesh.bounds
    v = np.asarray(mesh.vertices)[np.asarray(mesh.faces)]
    edge = v[:, 0] + (v[:, 1] - v[:, 0]) * rng.uniform(0.0, 1.0, size=(len(v), 1))
    columns = grid.lo[0] + grid.size[0] * rng.integers(0, grid.shape[0] + 1, size=400)
    rows = grid.lo[1] + grid.size[1] * rng.integers(0, grid.shape[1] + 1, size=400)
    xy = [
        rng.uniform(lo[:2], hi[:2], size=(800, 2)),
        np.stack([columns, rng.uniform(lo[1], hi[1], size=400)], 1),
        np.stack([rng.uniform(lo[0], hi[0], size=400), rows], 1),
        np.stack([columns, rows], 1),
        edge[rng.choice(len(v), size=600), :2],
        v[rng.choice(len(v), size=300), rng.integers(0, 3, size=300), :2],
    ]
    points = np.concatenate(xy)
    return np.column_stack([points, rng.uniform(lo[2], hi[2], size=len(points))])


@pytest.mark.parametrize(
    "make",
    [
        lambda: fan_cone(2000),
        lambda: fan_capped_cylinder(400, slant=(0.003, 0.002)),
        lambda: _random_slivers(600),
    ],
)
def test_slivers_and_fans_get_the_answer_of_testing_every_pair(
    make: Callable[[], trimesh.Trimesh],
) -> None:
    """Each long triangle is listed only in the cells its projection touches: points on cell
    boundaries, on edges and on vertices still meet every triangle that may count them (and
    none twice), so the answer is that of testing every pair, bit for bit."""
    mesh = make()
    grid = inside.face_grid(mesh)
    assert grid.shape.min() >= 10  # the grid is not made coarse for the slivers
    cell = np.repeat(np.arange(len(grid.start) - 1), np.diff(grid.start))
    listed = cell * len(mesh.faces) + grid.tri_of_cell
    assert len(np.unique(listed)) == len(listed)
    points = _testing_points(mesh, grid)
    expected = _every_pair(mesh, points)
    assert 0.05 < expected.mean() < 0.95
    assert np.array_equal(points_inside(mesh, points), expected)


def test_a_fan_is_tested_against_tens_of_triangles_a_point_not_thousands() -> None:
    """A 10,000-triangle fan cone: a point of its box meets about 70 triangles of the grid
    (1,700 when each was listed in every cell of its xy box)."""
    mesh = fan_cone(10_000)
    grid = inside.face_grid(mesh)
    rng = np.random.default_rng(0)
    points = rng.uniform(mesh.bounds[0], mesh.bounds[1], size=(2000, 3))
    cell = grid._cell_of(points[:, :2])
    key = cell[:, 0] * grid.shape[1] + cell[:, 1]
    met = grid.start[key + 1] - grid.start[key] + len(grid.wide)
    assert met.mean() < 150


def test_the_grid_is_built_once_per_mesh_and_again_when_it_changes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A fit asks about one solid a dozen times: its grid is built once; a mesh moved after
    its grid was built gets a new one (and the right answer)."""
    built = []
    real = inside.FaceGrid.__init__

    def counting(self: inside.FaceGrid, vertices: np.ndarray, faces: np.ndarray) -> None:
        built.append(len(faces))
        real(self, vertices, faces)

    monkeypatch.setattr(inside.FaceGrid, "__init__", counting)
    mesh = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    centre = np.zeros((1, 3))
    for _ in range(3):
        assert points_inside(mesh, centre).all()
    assert len(built) == 1
    mesh.vertices = np.asarray(mesh.vertices) + np.array([2.0, 0.0, 0.0])
    assert not points_inside(mesh, centre).any()
    assert len(built) == 2


def _robot(tmp_path: Path, mesh: Path) -> Path:
    urdf = tmp_path / "r.urdf"
    urdf.write_text(ROBOT.format(mesh.name))
    return urdf


def _spheres_refused(tmp_path: Path, urdf: Path) -> str:
    """`xrdf spheres` fails (exit 1, nothing written): the line that says why."""
    out = tmp_path / "r.xrdf"
    r = CliRunner().invoke(app, ["spheres", str(urdf), "--per-link", "2", "-o", str(out)])
    assert r.exit_code == 1, r.output
    assert not out.exists() and "Traceback" not in r.output
    (line,) = [t for t in r.output.splitlines() if "spheres-link-not-covered" in t]
    return line


@pytest.mark.parametrize("suffix", ["stl", "obj"])
def test_a_mesh_past_the_triangle_limit_is_refused_in_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, suffix: str
) -> None:
    """Past the limit (lowered to 100 here; by default what a binary STL at the mesh size
    limit holds, 5.4 million), a mesh is refused with its count and what to do; a binary STL
    before it is parsed at all."""
    monkeypatch.setattr(lg, "mesh_triangle_limit", lambda: 100)
    mesh = tmp_path / f"part.{suffix}"
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(mesh)  # 320 triangles
    if suffix == "stl":
        monkeypatch.setattr(lg, "load_mesh_parts", lambda path: pytest.fail("parsed"))
    line = _spheres_refused(tmp_path, _robot(tmp_path, mesh))
    assert f"part.{suffix}: 320 triangles, more than the 100 a mesh may have" in line
    assert "XRDF_TOOLS_MAX_INPUT_MB" in line


def test_a_mesh_within_the_limit_is_fitted(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(lg, "mesh_triangle_limit", lambda: 320)
    mesh = tmp_path / "part.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(mesh)
    out = tmp_path / "r.xrdf"
    args = ["spheres", str(_robot(tmp_path, mesh)), "--per-link", "2", "-o", str(out)]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    assert out.exists()


def test_a_binary_stl_whose_header_lies_is_said_so(tmp_path: Path) -> None:
    """A header claiming a billion triangles over a file that holds 320 reads as nothing:
    the message says which count is wrong, not just "no triangles"."""
    mesh = tmp_path / "part.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(mesh)
    data = mesh.read_bytes()
    mesh.write_bytes(data[:80] + struct.pack("<I", 10**9) + data[84:])
    line = _spheres_refused(tmp_path, _robot(tmp_path, mesh))
    assert "a binary STL whose header counts 1,000,000,000 triangles" in line
    assert f"whose {len(data):,} bytes hold 320" in line


def test_reading_each_link_is_said_with_v_on_a_non_terminal(tmp_path: Path) -> None:
    """Reading a CAD mesh and making it a solid takes seconds (18 s for 1.2 M triangles):
    with -v in a CI log, a line per link says it is under way, before the fit's own."""
    mesh = tmp_path / "part.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).export(mesh)
    out = tmp_path / "r.xrdf"
    args = ["spheres", str(_robot(tmp_path, mesh)), "--per-link", "2", "-o", str(out), "-v"]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    lines = r.stderr.splitlines()
    reading = [ln for ln in lines if ln.startswith("reading link geometry: ")]
    assert reading == ["reading link geometry: 1/2 base", "reading link geometry: 2/2 arm"]
    first_fit = next(i for i, ln in enumerate(lines) if ln.startswith("fitting spheres"))
    assert lines.index(reading[-1]) < first_fit


def test_a_mesh_of_one_body_is_not_copied_to_find_its_bodies() -> None:
    from xrdf_tools.spheres.mesh_solids import connected_bodies

    ball = trimesh.creation.icosphere(subdivisions=2)
    assert connected_bodies(ball)[0] is ball
    two = trimesh.util.concatenate([ball, ball.copy().apply_translation([3.0, 0.0, 0.0])])
    assert [len(b.faces) for b in connected_bodies(two)] == [320, 320]
