"""Products summed in a fixed order, and the vertex grid: the same bits on every machine."""

from __future__ import annotations

import numpy as np

from xrdf_tools.util.fixed_order import (
    QUANTUM,
    matmul,
    norm,
    quantized,
    rigid_inverse,
    transform_points,
)
from xrdf_tools.util.rotations import axis_angle_matrix


def _loop_matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The plain triple loop, each sum from the first term on."""
    out = np.zeros((a.shape[0], b.shape[1]))
    for i in range(a.shape[0]):
        for j in range(b.shape[1]):
            acc = a[i, 0] * b[0, j]
            for k in range(1, a.shape[1]):
                acc = acc + a[i, k] * b[k, j]
            out[i, j] = acc
    return out


def _rigid(rng: np.random.Generator) -> np.ndarray:
    T = np.eye(4)
    axis = rng.standard_normal(3)
    T[:3, :3] = axis_angle_matrix(axis / np.sqrt(axis @ axis), float(rng.uniform(-3, 3)))
    T[:3, 3] = rng.uniform(-1, 1, 3)
    return T


def test_matmul_is_the_plain_loop_bit_for_bit_and_agrees_with_blas() -> None:
    rng = np.random.default_rng(0)
    for shape in [(4, 4, 4), (3, 3, 1), (7, 3, 5), (1, 4, 4)]:
        a = rng.standard_normal(shape[:2])
        b = rng.standard_normal(shape[1:])
        got = matmul(a, b)
        assert np.array_equal(got, _loop_matmul(a, b))
        np.testing.assert_allclose(got, a @ b, rtol=1e-13, atol=1e-15)
    # stacked matrices and a vector
    A, B = rng.standard_normal((5, 3, 3)), rng.standard_normal((5, 3, 3))
    for i in range(5):
        assert np.array_equal(matmul(A, B)[i], _loop_matmul(A[i], B[i]))
    v = rng.standard_normal(3)
    assert np.array_equal(matmul(A[0], v), _loop_matmul(A[0], v[:, None])[:, 0])


def test_points_and_inverses_of_rigid_transforms() -> None:
    rng = np.random.default_rng(1)
    T = _rigid(rng)
    points = rng.uniform(-1, 1, (50, 3))
    moved = transform_points(T, points)
    homogeneous = np.hstack([points, np.ones((50, 1))])
    assert np.array_equal(moved, _loop_matmul(homogeneous, T.T)[:, :3])
    back = transform_points(rigid_inverse(T), moved)
    np.testing.assert_allclose(back, points, atol=1e-14)
    stacked = np.stack([T, _rigid(rng)])
    inv = rigid_inverse(stacked)
    for k in range(2):
        np.testing.assert_allclose(matmul(inv[k], stacked[k]), np.eye(4), atol=1e-14)
        np.testing.assert_allclose(inv[k], np.linalg.inv(stacked[k]), atol=1e-14)


def test_norm_sums_the_squares_in_order() -> None:
    assert norm([3.0, 4.0]) == 5.0
    v = np.random.default_rng(2).standard_normal(4)
    assert abs(norm(v) - float(np.linalg.norm(v))) <= 1e-15


def test_the_grid_is_exact_within_half_a_step_and_has_no_negative_zero() -> None:
    rng = np.random.default_rng(3)
    v = rng.uniform(-2, 2, 100_000)
    q = quantized(v)
    assert np.max(np.abs(q - v)) <= QUANTUM / 2 * (1 + 1e-9)
    assert np.array_equal(quantized(q), q)  # on the grid already
    tiny = quantized(np.array([-1e-300, -0.0, 1e-300]))
    assert not np.signbit(tiny).any()


def test_a_last_bit_never_moves_a_file_coordinate_to_another_grid_point() -> None:
    """Coordinates as mesh files hold them: float32 values (an STL file) and decimals in 0.1 µm
    (a text file, millimetres with four decimals). On a power-of-two grid one float32 value
    in 64 lies exactly on a rounding midpoint, on a decimal one every tenth decimal does; then
    the last bit a loader's transform leaves decides where it goes."""
    rng = np.random.default_rng(4)
    from_float32 = rng.uniform(-1, 1, 200_000).astype(np.float32).astype(np.float64)
    decimals = np.round(rng.uniform(-1e4, 1e4, 200_000), 4) / 1000.0
    for v in (from_float32, decimals):
        up, down = np.nextafter(v, np.inf), np.nextafter(v, -np.inf)
        assert np.array_equal(quantized(up), quantized(v))
        assert np.array_equal(quantized(down), quantized(v))
