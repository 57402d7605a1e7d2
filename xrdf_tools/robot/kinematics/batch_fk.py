"""Batched forward kinematics of a :class:`KinematicModel`, looping only over frames.

Internally the batch is the last axis (``[F, 3, 3, B]``): every elementwise operation then
runs on contiguous rows of length B. :func:`fk_batch_last` returns that layout;
:func:`fk_rt` and :func:`fk` return batch-first views of it (no transposing copy).
"""

from __future__ import annotations

import threading
from collections.abc import Iterable

import numpy as np
import numpy.typing as npt

from ...util.arrays import FloatArray, IntArray
from .base import FrameSelection
from .model import KinematicModel
from .plan import KIND_PRISM, KIND_ROT


def _as_batch(model: KinematicModel, q: npt.ArrayLike) -> tuple[FloatArray, bool]:
    arr = np.asarray(q, dtype=np.float64)
    n = model.n_actuated
    if arr.ndim == 1 and arr.shape[0] == n:
        return arr[None, :], True
    if arr.ndim == 2 and arr.shape[1] == n:
        return arr, False
    raise ValueError(
        f"q must have shape [{n}] or [B, {n}] (one value per actuated joint: "
        f"{', '.join(model.actuated_joints) or 'none'}), got {list(arr.shape)}"
    )


def _needed(model: KinematicModel, sel: IntArray) -> list[int]:
    mark = np.zeros(model.n_frames, dtype=bool)
    parent = model._plan.parents
    for i in sel.tolist():
        while i >= 0 and not mark[i]:
            mark[i] = True
            i = parent[i]
    return [int(i) for i in np.flatnonzero(mark)]


_WORK = threading.local()
_WORK_MAX_BATCH = 1 << 16  # larger batches get fresh scratch buffers each call


def _scratch(B: int) -> dict[int, FloatArray]:
    """Per-thread scratch buffers [3, |c|, B] (c = ±3, ±4, ±5, ±10: the negative ones hold a
    product term), reused across calls."""
    cached: tuple[int, dict[int, FloatArray]] | None = getattr(_WORK, "buffers", None)
    if cached is not None and cached[0] == B:
        return cached[1]
    bufs: dict[int, FloatArray] = {}
    for c in (3, 4, 5, 10, -3, -4, -5, -10):
        bufs[c] = np.empty((3, abs(c), B))
    if B <= _WORK_MAX_BATCH:
        _WORK.buffers = (B, bufs)
    return bufs


def _times(M: FloatArray, A: FloatArray, work: dict[int, FloatArray], c: int) -> FloatArray:
    """``M @ A`` [3, c, B] for ``M`` (c, 3) and ``A`` [3, 3, B], summed term by term: unlike a
    BLAS product, each configuration's result does not depend on the batch around it (so an
    exact value is the same whichever configurations are computed together)."""
    out, term = work[c], work[-c]
    np.multiply(M[None, :, 0, None], A[:, None, 0, :], out=out)
    for k in (1, 2):
        np.multiply(M[None, :, k, None], A[:, None, k, :], out=term)
        out += term
    return out


def _fk_batch_last(
    model: KinematicModel,
    q2: FloatArray,
    needed: Iterable[int],
    R: FloatArray,
    t: FloatArray,
) -> None:
    """Fill rotations ``R`` [F, 3, 3, B] and translations ``t`` [F, 3, B] of ``needed``.

    Batch-last keeps every elementwise operation on contiguous rows of length B, and the
    parent rotation times the frame constants is one stacked matmul ``(c, 3) @ (3, 3, B)``.
    """
    plan = model._plan
    B = q2.shape[0]
    R[0] = np.eye(3)[:, :, None]
    t[0] = 0.0
    vals: FloatArray = np.empty((0, B))
    sin = omc = vals
    if len(plan.row_q):
        vals = q2.T[plan.row_q]  # [rows, B], a copy
        vals *= plan.row_mult[:, None]
        vals += plan.row_off[:, None]
        angles = vals[plan.rot_rows]
        sin = np.sin(angles)
        omc = np.cos(angles)
        np.subtract(1.0, omc, out=omc)
    work = _scratch(B)
    tmp = work[3]
    for f in needed:
        if f == 0:
            continue
        p = plan.parents[f]
        M = plan.consts_t[f]
        # X = parent rotation times the constants: (c, 3) @ (3, 3, B) -> [3, c, B]; when the
        # parent is the root (identity) it is the constants themselves, [3, c, 1]
        X = plan.consts_root[f] if p == 0 else _times(M, R[p], work, M.shape[0])
        kind = plan.kinds[f]
        Rf, tf = R[f], t[f]
        if kind == KIND_ROT:
            r = plan.rows[f]
            np.multiply(X[:, 3:6], sin[r], out=Rf)
            Rf += X[:, 0:3]
            np.multiply(X[:, 6:9], omc[r], out=tmp)
            Rf += tmp
            tcol = 9
        else:
            Rf[...] = X[:, 0:3]
            tcol = 3
        if p == 0:
            tf[...] = X[:, tcol]
        else:
            np.add(t[p], X[:, tcol], out=tf)
        if kind == KIND_PRISM:
            tf += vals[plan.rows[f]] * X[:, 4]


def fk_batch_last(
    model: KinematicModel,
    q: npt.ArrayLike,
    frames: FrameSelection = None,
    *,
    out: tuple[FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Forward kinematics in the fast batch-last layout.

    ``q``: [B, n] (or [n], treated as B = 1). Returns rotations [F', 3, 3, B] and
    translations [F', 3, B] (``R[f, :, :, b]`` is the 3x3 rotation of frame ``f`` for
    configuration ``b``). Sphere centres of frame ``f`` are then
    ``einsum("ikb,k->ib", R[f], c) + t[f]``, every operation on contiguous rows.

    ``out``: optional ``(R, t)`` arrays of those shapes to write into, so that a loop over
    chunks of a large sample does not allocate (and page-fault) new result arrays each time.
    """
    q2, _ = _as_batch(model, q)
    sel = model.frame_indices(frames)
    B = q2.shape[0]
    shape_r, shape_t = (len(sel), 3, 3, B), (len(sel), 3, B)
    if out is not None and (out[0].shape != shape_r or out[1].shape != shape_t):
        raise ValueError(
            f"out must be arrays of shapes {list(shape_r)} and {list(shape_t)}, got "
            f"{list(out[0].shape)} and {list(out[1].shape)}"
        )
    if frames is None:
        R, t = out if out is not None else (np.empty(shape_r), np.empty(shape_t))
        _fk_batch_last(model, q2, range(model.n_frames), R, t)
        return R, t
    F = model.n_frames
    R_all, t_all = np.empty((F, 3, 3, B)), np.empty((F, 3, B))
    _fk_batch_last(model, q2, _needed(model, sel), R_all, t_all)
    if out is None:
        return R_all[sel], t_all[sel]
    np.take(R_all, sel, axis=0, out=out[0])
    np.take(t_all, sel, axis=0, out=out[1])
    return out


def fk_rt(
    model: KinematicModel, q: npt.ArrayLike, frames: FrameSelection = None
) -> tuple[FloatArray, FloatArray]:
    """Batched forward kinematics as rotation and translation.

    ``q``: [B, n] (or [n]) actuated joint values. ``frames``: names or indices of the frames
    wanted (default all); only these and their ancestors are computed.

    Returns ``(R, t)``: base-frame rotations [B, F', 3, 3] and translations [B, F', 3] (or
    [F', 3, 3] and [F', 3] for a single configuration). They are strided views of the
    batch-last result of :func:`fk_batch_last` (no copy); use ``np.ascontiguousarray`` if a
    caller needs contiguous memory.
    """
    q2, single = _as_batch(model, q)
    R, t = fk_batch_last(model, q2, frames)
    Rb, tb = R.transpose(3, 0, 1, 2), t.transpose(2, 0, 1)
    return (Rb[0], tb[0]) if single else (Rb, tb)


def fk(model: KinematicModel, q: npt.ArrayLike, frames: FrameSelection = None) -> FloatArray:
    """Batched forward kinematics: homogeneous transforms [B, F', 4, 4] of the frames.

    ``q``: [B, n] (or [n], giving [F', 4, 4]) actuated joint values in
    :attr:`KinematicModel.actuated_joints` order. ``frames``: names or indices (default all
    frames, in model order); only these and their ancestors are computed. Each transform maps
    frame coordinates to base-frame coordinates. The result is a strided view of a batch-last
    buffer (no transposing copy).

    Raises ``ValueError`` for a wrongly shaped ``q`` or an out-of-range index, and
    :class:`UrdfError` for an unknown frame name.
    """
    q2, single = _as_batch(model, q)
    sel = model.frame_indices(frames)
    B = q2.shape[0]
    out = np.empty((len(sel), 4, 4, B))
    if frames is None:  # write straight into the output
        _fk_batch_last(model, q2, range(model.n_frames), out[:, :3, :3], out[:, :3, 3])
    else:
        fk_batch_last(model, q2, sel, out=(out[:, :3, :3], out[:, :3, 3]))
    out[:, 3, :3] = 0.0
    out[:, 3, 3] = 1.0
    view: FloatArray = out.transpose(3, 0, 1, 2)
    return view[0] if single else view
