"""A symmetric solid's oriented box in the same frame whichever of its equal candidates the
box search picks (another machine's BLAS can tip the choice): a plate's sheet spheres and a
flat part's bounding box do not change."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh

from xrdf_tools.spheres.mesh_solids import bounding_box
from xrdf_tools.spheres.obb import oriented_box
from xrdf_tools.spheres.robot_fit import fit_robot
from xrdf_tools.util.fixed_order import quantized

TURN = trimesh.transformations.euler_matrix(0.3, -0.7, 1.1)


def _plate(extents: tuple[float, float, float]) -> trimesh.Trimesh:
    plate = trimesh.creation.box(extents=extents)
    plate.apply_transform(TURN)
    return plate


def _urdf(
    tmp_path: Path, mesh: trimesh.Trimesh, box: tuple[float, float, float] | None = None
) -> Path:
    """A one-link URDF: the plate as an STL file, or as a ``<box>`` of ``box`` turned alike."""
    mesh.export(tmp_path / "plate.stl")
    shape = '<mesh filename="plate.stl"/>'
    origin = '<origin xyz="0.1 0 0.2"/>'
    if box is not None:
        shape = '<box size="{} {} {}"/>'.format(*box)
        rpy = trimesh.transformations.euler_from_matrix(TURN)
        origin = '<origin xyz="0.1 0 0.2" rpy="{} {} {}"/>'.format(*rpy)
    urdf = tmp_path / "plate.urdf"
    urdf.write_text(
        f'<robot name="plate"><link name="plate"><collision>{origin}'
        f"<geometry>{shape}</geometry></collision></link></robot>"
    )
    return urdf


def _turns() -> list[np.ndarray]:
    """Turns of a box's frame that describe the same box (its extents permuted alike): half
    turns about each axis, and quarter turns (which swap two axes: two equal candidates on a
    square plate)."""
    out = [np.diag([*signs, 1.0]) for signs in ((-1, -1, 1), (-1, 1, -1), (1, -1, -1))]
    for i, j in ((0, 1), (1, 2), (0, 2)):
        quarter = np.eye(4)
        quarter[[i, j], [i, j]] = 0.0
        quarter[i, j], quarter[j, i] = -1.0, 1.0
        out.append(quarter)
    return out


def _picking(turn: np.ndarray) -> Any:
    """``oriented_bounds`` returning its box described in the frame turned by ``turn``."""
    found = trimesh.bounds.oriented_bounds

    def picked(*args: Any, **kwargs: Any) -> tuple[np.ndarray, np.ndarray]:
        to_box, extents = found(*args, **kwargs)
        return turn @ to_box, np.abs(turn[:3, :3]) @ np.asarray(extents)

    return picked


@pytest.mark.parametrize("size", [(0.05, 0.03, 0.0003), (0.04, 0.04, 0.0005)])
def test_a_plates_sheet_spheres_do_not_follow_which_equal_box_is_picked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, size: tuple[float, float, float]
) -> None:
    """A plate from an STL file, and a square one as a URDF <box> (its sides exactly equal)."""
    urdf = _urdf(tmp_path, _plate(size), box=size if size[0] == size[1] else None)
    first = fit_robot(urdf).spheres["plate"]
    assert len(first) > 1
    for turn in _turns():
        monkeypatch.setattr(trimesh.bounds, "oriented_bounds", _picking(turn))
        assert fit_robot(urdf).spheres["plate"] == first


def test_a_flat_parts_bounding_box_does_not_follow_which_equal_box_is_picked(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    square = trimesh.Trimesh(
        vertices=[[0, 0, 0], [0.02, 0, 0], [0.02, 0.02, 0], [0, 0.02, 0]], faces=[[0, 1, 2]]
    )
    square.faces = np.array([[0, 1, 2], [0, 2, 3]])
    square.apply_transform(TURN)
    box = bounding_box(square)
    assert box is not None
    for turn in _turns():
        monkeypatch.setattr(trimesh.bounds, "oriented_bounds", _picking(turn))
        turned = bounding_box(square)
        assert turned is not None
        assert np.array_equal(quantized(turned.vertices), quantized(box.vertices))
        assert np.array_equal(turned.faces, box.faces)


def test_the_box_frame_is_canonical_and_holds_the_points() -> None:
    plate = _plate((0.05, 0.03, 0.0003))
    to_link, extents = oriented_box(plate.vertices)
    rotation = to_link[:3, :3]
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) > 0.0
    assert list(extents) == sorted(extents)
    np.testing.assert_allclose(extents, [0.0003, 0.03, 0.05], rtol=1e-9)
    for axis in rotation.T[:2]:  # the first clearly non-zero component is positive
        assert next(c for c in axis if abs(c) > 1e-9) > 0.0
    for p in plate.vertices:  # every vertex within the box (a plain loop)
        local = [sum((p[r] - to_link[r, 3]) * to_link[r, k] for r in range(3)) for k in range(3)]
        assert all(abs(x) <= e / 2.0 + 1e-12 for x, e in zip(local, extents, strict=True))
