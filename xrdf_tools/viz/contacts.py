"""The sphere pairs in self-collision at each configuration a scene draws."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..diagnostics import Diagnostic
from ..util.arrays import FloatArray
from ..xrdf.model import Xrdf

if TYPE_CHECKING:
    from ..robot.kinematics import KinematicModel
    from ..selfcollision.collision import Contact

Progress = Callable[[int, int], None]

__all__ = ["SpherePair", "sphere_contacts"]


@dataclass(frozen=True)
class SpherePair:
    """Two spheres in self-collision; ``clearance`` < 0 is the penetration depth (m)."""

    frame_a: str
    sphere_a: int
    frame_b: str
    sphere_b: int
    clearance: float

    def describe(self) -> str:
        return (
            f"{self.frame_a}[{self.sphere_a}] <-> {self.frame_b}[{self.sphere_b}] "
            f"(clearance {self.clearance * 1000:.1f} mm)"
        )


def sphere_contacts(
    kin: KinematicModel,
    xrdf: Xrdf,
    Q: FloatArray,
    progress: Progress | None,
    diags: list[Diagnostic],
    chunk: int = 256,
) -> tuple[list[tuple[tuple[SpherePair, ...], tuple[Contact, ...]]], int, int]:
    """Per configuration of ``Q`` [B, n]: every colliding sphere pair, and the colliding
    frame pairs (worst sphere pair first), by :mod:`xrdf_tools.selfcollision.collision`; and the
    numbers of frame pairs checked and ignored by the mask. Memory is linear in the spheres
    (sphere pairs are visited per frame pair in bounded blocks)."""
    from ..selfcollision.collision import (
        build_sphere_set,
        colliding_sphere_pairs,
        contacts_of_pairs,
        sphere_world_centers,
    )

    every, sdiags = build_sphere_set(kin, xrdf, include_masked=True)
    diags.extend(sdiags)
    spheres = every.select_frame_pairs(~every.frame_pair_masked)
    checked, ignored = spheres.n_frame_pairs, every.n_frame_pairs - spheres.n_frame_pairs
    out: list[tuple[tuple[SpherePair, ...], tuple[Contact, ...]]] = []
    total = len(Q)
    if spheres.n_pairs == 0:
        if progress is not None:
            progress(total, total)
        return [((), ())] * total, checked, ignored
    label_frame = [spheres.frame_names[f] for f in spheres.frame_of_sphere.tolist()]
    label_index = spheres.sphere_index.tolist()
    for start in range(0, total, chunk):
        centers = sphere_world_centers(kin, spheres, Q[start : start + chunk])
        for b in range(centers.shape[0]):
            found = colliding_sphere_pairs(spheres, centers[b])
            if not found:
                out.append(((), ()))
                continue
            pairs = [
                SpherePair(label_frame[i], label_index[i], label_frame[j], label_index[j], clr)
                for _, i, j, clr in found
            ]
            pairs.sort(key=lambda sp: sp.clearance)
            out.append((tuple(pairs), tuple(contacts_of_pairs(spheres, found))))
        if progress is not None:
            progress(min(start + chunk, total), total)
    return out, checked, ignored
