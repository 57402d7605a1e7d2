"""Whole configurations of a :class:`KinematicModel`: the default one, MoveIt's default, and
c-space values expanded with defaults for the joints a c-space leaves out."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import numpy.typing as npt

from ...util.arrays import FloatArray
from .model import KinematicModel


def default_configuration(
    model: KinematicModel, defaults: Mapping[str, float] | None = None
) -> FloatArray:
    """Default value [n] of every actuated joint.

    ``defaults`` (XRDF ``default_joint_positions``) wins; other joints get zero clamped to
    their position limits. Entries for joints that are not actuated (mimic, fixed, unknown)
    are ignored here; the linter reports them.
    """
    q = np.clip(np.zeros(model.n_actuated), model.lower, model.upper)
    for name, value in (defaults or {}).items():
        k = model._joint_idx.get(name)
        if k is not None:
            q[k] = float(value)
    return q


def unset_defaults(model: KinematicModel) -> dict[str, float]:
    """The default each actuated joint has when ``default_joint_positions`` does not name it:
    zero clamped to its position limits (:func:`default_configuration` without defaults)."""
    q = default_configuration(model)
    return {name: float(v) for name, v in zip(model.actuated_joints, q, strict=True)}


def moveit_default_configuration(model: KinematicModel) -> FloatArray:
    """The default state as MoveIt's Setup Assistant computes it: each joint at 0 when 0 is
    within its limits, else the middle of its limits."""
    zero_ok = (model.lower <= 0.0) & (model.upper >= 0.0)
    mid = np.where(
        np.isfinite(model.lower) & np.isfinite(model.upper), (model.lower + model.upper) / 2, 0.0
    )
    return np.where(zero_ok, 0.0, mid)


def full_configuration(
    model: KinematicModel,
    cspace_joint_names: Sequence[str],
    q_cspace: npt.ArrayLike,
    defaults: Mapping[str, float] | None = None,
) -> FloatArray:
    """Expand c-space values [B, n_c] (or [n_c]) into full configurations [B, n] (or [n]).

    Joints not in ``cspace_joint_names`` (auxiliary coordinates) are held at their default
    (see :func:`default_configuration`). Raises :class:`UrdfError` for a c-space name that is
    not an actuated joint (saying whether it is a mimic, fixed or pruned joint) and
    ``ValueError`` for a repeated name or a wrongly shaped ``q_cspace``.
    """
    names = list(cspace_joint_names)
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ValueError(f"c-space joint names repeat: {', '.join(dup)}")
    idx = np.array([model.actuated_index(n) for n in names], dtype=np.intp)
    qc = np.asarray(q_cspace, dtype=np.float64)
    single = qc.ndim == 1
    if qc.ndim not in (1, 2) or qc.shape[-1] != len(names):
        raise ValueError(
            f"q_cspace must have shape [{len(names)}] or [B, {len(names)}], got {list(qc.shape)}"
        )
    qc2 = qc[None, :] if single else qc
    out = np.repeat(default_configuration(model, defaults)[None, :], qc2.shape[0], axis=0)
    out[:, idx] = qc2
    return out[0] if single else out
