"""The conversions of :mod:`xrdf_tools.util.rotations` agree with one another and with trimesh's
(which yourdfpy reads URDF origins with)."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from xrdf_tools.util.rotations import (
    axis_angle_matrix,
    matrix_from_quat,
    matrix_from_rpy,
    quat_from_rpy,
    quat_xyzw_from_matrix,
    skew,
    unit_quat,
)

RPYS = [
    (0.0, 0.0, 0.0),
    (0.3, -0.2, 0.1),
    (math.pi / 2, 0.0, 0.0),
    (1.0, 1.5, -2.5),
    (3.0, -0.1, 2.9),
]


@pytest.mark.parametrize("rpy", RPYS)
def test_rpy_matrix_and_quaternion_agree(rpy: tuple[float, float, float]) -> None:
    tra = pytest.importorskip("trimesh.transformations")  # what yourdfpy reads rpy with

    rot = np.array(matrix_from_rpy(*rpy))
    q = unit_quat(*quat_from_rpy(*rpy))
    assert rot == pytest.approx(np.array(matrix_from_quat(q)), abs=1e-12)
    assert rot == pytest.approx(tra.euler_matrix(*rpy, "sxyz")[:3, :3], abs=1e-12)
    ref = tra.quaternion_from_euler(*rpy, "sxyz")
    assert q == pytest.approx(ref, abs=1e-12) or q == pytest.approx(-ref, abs=1e-12)
    x, y, z, w = quat_xyzw_from_matrix(rot)
    assert w >= 0
    back = np.array(matrix_from_quat((w, x, y, z)))
    assert back == pytest.approx(rot, abs=1e-12)


def test_axis_angle_is_a_rotation_about_the_axis() -> None:
    a = np.array([1.0, 2.0, 2.0]) / 3.0
    rot = axis_angle_matrix(a, 0.7)
    assert rot @ a == pytest.approx(a)
    assert rot @ rot.T == pytest.approx(np.eye(3), abs=1e-12)
    assert axis_angle_matrix(np.array([0.0, 0.0, 1.0]), 0.4) == pytest.approx(
        np.array(matrix_from_rpy(0.0, 0.0, 0.4)), abs=1e-12
    )
    v = np.array([0.3, -1.0, 2.0])
    assert skew(a) @ v == pytest.approx(np.cross(a, v))


def test_zero_quaternion_is_the_identity() -> None:
    assert unit_quat(0.0, 0.0, 0.0, 0.0) == (1.0, 0.0, 0.0, 0.0)
    assert unit_quat(2.0, 0.0, 0.0, 0.0) == (1.0, 0.0, 0.0, 0.0)


def test_importing_does_not_import_numpy() -> None:
    """The XRDF model uses it at lint start-up, which does not load numpy."""
    code = "import sys, xrdf_tools.util.rotations; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
