"""The report's build steps as they were before they walked the tree once per body, frozen
here as the baseline of ``bench_scale.py``'s ``many_frames`` case:

* the layout (``body_pairs``): per body pair, the two bodies' ancestors listed by walking up
  to the root, each reach ball's radius summed by walking from the body up to the joint below
  the common ancestor (one ``numpy.linalg.norm`` per joint and pair), the bodies between the
  two by another walk, and each part's side (augmented matrices, bounding sphere) made anew
  for every body pair;
* the report's joints on each frame pair's path: ``KinematicModel.joints_on_path`` per pair,
  a walk from each frame up to the root.

Same layout and the same counts as the tool (the benchmark checks both).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from xrdf_tools.robot.kinematics import KinematicModel
from xrdf_tools.selfcollision.collision import SphereSet
from xrdf_tools.selfcollision.engine.bodies import EPS32, PRISM, Bodies, chain_error
from xrdf_tools.selfcollision.engine.bounds import energy_error
from xrdf_tools.selfcollision.engine.layout import (
    _LOCAL_JOINTS,
    Layout,
    _both_parts,
    _bound,
    _fix,
    _part_index,
    _side_rows,
)
from xrdf_tools.selfcollision.engine.pairs import BodyPair
from xrdf_tools.selfcollision.engine.reach import Reach, SidePrune, _extent
from xrdf_tools.selfcollision.engine.reach import _side as _prune_side
from xrdf_tools.util.arrays import FloatArray, IntArray


def body_pairs(
    spheres: SphereSet,
    frame_body: IntArray,
    local: FloatArray,
    err: float,
    skip: set[int],
    reach: Reach,
    limit: float,
) -> Layout:
    s = spheres
    groups: dict[tuple[int, int], list[int]] = {}
    for k in range(s.n_frame_pairs):
        if k in skip:
            continue
        ba, bb = int(frame_body[s.frame_pair_a[k]]), int(frame_body[s.frame_pair_b[k]])
        groups.setdefault((min(ba, bb), max(ba, bb)), []).append(k)
    out = Layout()
    for key, ks in groups.items():
        out.pairs.extend(_split_pair(s, frame_body, local, err, reach, limit, key, ks, out))
    return out


def _split_pair(
    s: SphereSet,
    frame_body: IntArray,
    local: FloatArray,
    err: float,
    reach: Reach,
    limit: float,
    key: tuple[int, int],
    ks: list[int],
    layout: Layout,
) -> list[BodyPair]:
    a, b = key
    side: dict[int, list[int]] = {a: [], b: []}
    for k in ks:
        for f in (int(s.frame_pair_a[k]), int(s.frame_pair_b[k])):
            if f not in side[int(frame_body[f])]:
                side[int(frame_body[f])].append(f)
    ia, wa = _side_rows(s, side[a])
    ib, wb = _side_rows(s, side[b])
    r = s.self_radii
    pa, pb = _prune(reach, a, b, local[ia], r[ia], local[ib], r[ib], limit)
    fixed_a, fixed_b = reach.on_axis(a, b, local[ia], local[ib])
    sampled_a, sampled_b = pa.keep & ~fixed_a, pb.keep & ~fixed_b
    fix_a, fix_b = pa.keep & fixed_a, pb.keep & fixed_b
    any_fixed = bool(fix_a.any() or fix_b.any())
    gap_a = {f: float(pa.gap[sl].min()) for f, sl in wa.items()}
    gap_b = {f: float(pb.gap[sl].min()) for f, sl in wb.items()}
    any_a = {f: bool(sampled_a[sl].any()) for f, sl in wa.items()}
    any_b = {f: bool(sampled_b[sl].any()) for f, sl in wb.items()}
    kept: list[tuple[int, int, int]] = []
    for k in ks:
        fa, fb = int(s.frame_pair_a[k]), int(s.frame_pair_b[k])
        if fa not in wa:
            fa, fb = fb, fa
        low = min(gap_a[fa], gap_b[fb])
        if low < np.inf:
            layout.out_of_reach[k] = low
        if any_fixed:
            _fix(layout, k, ia[wa[fa]], ib[wb[fb]], fix_a[wa[fa]], pb.keep[wb[fb]])
            _fix(layout, k, ib[wb[fb]], ia[wa[fa]], fix_b[wb[fb]], sampled_a[wa[fa]])
        if any_a[fa] and any_b[fb]:
            kept.append((k, fa, fb))
    keep = set(ia[sampled_a].tolist()) | set(ib[sampled_b].tolist())
    parts_a, parts_b = _both_parts(s, (a, b), kept, keep, local)
    part_of_a, part_of_b = _part_index(parts_a), _part_index(parts_b)
    by_parts: dict[tuple[int, int], list[tuple[int, int, int]]] = {}
    for k, fa, fb in kept:
        for at_a in part_of_a[fa]:
            for at_b in part_of_b[fb]:
                by_parts.setdefault((at_a, at_b), []).append((k, fa, fb))
    return _assemble_parts(s, local, err, reach, (a, b), (parts_a, parts_b), by_parts)


def _assemble_parts(
    s: SphereSet,
    local: FloatArray,
    err: float,
    reach: Reach,
    key: tuple[int, int],
    parts: tuple[list[tuple[set[int], set[int]]], list[tuple[set[int], set[int]]]],
    by_parts: dict[tuple[int, int], list[tuple[int, int, int]]],
) -> list[BodyPair]:
    made: dict[tuple[int, int], _Side] = {}

    def side(which: int, at: int) -> _Side:
        if (which, at) not in made:
            frames, keep = parts[which][at]
            idx, where = _side_rows(s, sorted(frames), keep)
            centres, radii = local[idx], s.self_radii[idx]
            made[which, at] = _Side(idx, where, centres, radii, _bound(centres, radii))
        return made[which, at]

    out = []
    for at_a in range(len(parts[0])):
        for at_b in range(len(parts[1])):
            mine = by_parts.get((at_a, at_b))
            if mine:
                out.append(_assemble(err, reach, key, (side(0, at_a), side(1, at_b)), mine))
    return out


@dataclass(frozen=True, eq=False)
class _Side:
    idx: IntArray
    where: dict[int, slice]
    centres: FloatArray
    radii: FloatArray
    bound: FloatArray


def _assemble(
    err: float,
    reach: Reach,
    key: tuple[int, int],
    sides: tuple[_Side, _Side],
    kept: list[tuple[int, int, int]],
) -> BodyPair:
    a, b = key
    sa, sb = sides
    blocks = [(k, sa.where[fa], sb.where[fb]) for k, fa, fb in kept]
    if len(sb.idx) > len(sa.idx):
        sa, sb, a, b = sb, sa, b, a
        blocks = [(k, cols, rows) for k, rows, cols in blocks]
    p, ra = sa.centres, sa.radii
    q, rb = sb.centres, sb.radii
    p_aug = np.hstack(
        [
            -2.0 * p,
            np.ones((len(p), 1)),
            (np.sum(p * p, axis=1) - ra * ra)[:, None],
            -2.0 * ra[:, None],
        ]
    )
    path: tuple[tuple[int, ...], tuple[int, ...]] | None = body_chains(reach.bodies, a, b)
    tau = 2.0 * err + 8.0 * EPS32 * reach.bodies.lever
    if path is not None and len(path[0]) + len(path[1]) <= _LOCAL_JOINTS:
        reach_max = float(np.max(np.linalg.norm(np.vstack([p, q]), axis=1)))
        err_path, lever = chain_error(reach.bodies, path, reach.travel(), reach_max)
        tau_path = 2.0 * err_path + 8.0 * EPS32 * lever
        if tau_path < tau:
            err, tau = err_path, tau_path
        else:
            path = None
    else:
        path = None
    row_starts = np.array(sorted(sl.start for sl in sa.where.values()), dtype=np.intp)
    col_starts = np.array(sorted(sl.start for sl in sb.where.values()), dtype=np.intp)
    pmax = float(np.max(np.linalg.norm(p, axis=1))) if len(p) else 0.0
    return BodyPair(
        a=a,
        b=b,
        ia=sa.idx,
        ib=sb.idx,
        p_aug=p_aug.astype(np.float32),
        q_aug=np.hstack([q, np.ones((len(q), 1))]).astype(np.float32),
        ra64=ra,
        rb64=rb,
        r_b=rb[:, None].astype(np.float32),
        r2_b=(rb * rb)[:, None].astype(np.float32),
        blocks=tuple(blocks),
        row_starts=row_starts,
        col_starts=col_starts,
        seg_a=np.searchsorted(row_starts, [rw.start for _, rw, _ in blocks]).astype(np.intp),
        seg_b=np.searchsorted(col_starts, [cl.start for _, _, cl in blocks]).astype(np.intp),
        p32=p.astype(np.float32),
        delta=energy_error(pmax, float(ra.max() + rb.max()), err),
        bound_a=sa.bound,
        bound_b=sb.bound,
        path=path,
        tau=tau,
    )


def body_chains(bodies: Bodies, a: int, b: int) -> tuple[tuple[int, ...], tuple[int, ...]]:
    up_a = [a]
    while up_a[-1] != 0:
        up_a.append(bodies.parent[up_a[-1]])
    chain_b = [b]
    while chain_b[-1] not in up_a:
        chain_b.append(bodies.parent[chain_b[-1]])
    lca = chain_b.pop()
    return tuple(up_a[: up_a.index(lca)][::-1]), tuple(chain_b[::-1])


def _up(reach: Reach, b: int) -> list[int]:
    out = [b]
    while out[-1] != 0:
        out.append(reach.bodies.parent[out[-1]])
    return out


def _ball(reach: Reach, top: int, d: int) -> tuple[FloatArray, float]:
    b = reach.bodies
    ext = 0.0
    k = d
    while k != top:
        ext += float(np.linalg.norm(b.consts[k][:3, 3]))
        if b.kind[k] == PRISM:
            ext += max(abs(reach.lo[k]), abs(reach.hi[k]))
        k = b.parent[k]
    C = b.consts[top]
    centre = C[:3, 3].copy()
    if b.kind[top] == PRISM:
        centre += C[:3, 2] * (reach.lo[top] + reach.hi[top]) / 2.0
        ext += (reach.hi[top] - reach.lo[top]) / 2.0
    return centre, ext


def _prune(
    reach: Reach,
    a: int,
    b: int,
    xa: FloatArray,
    ra: FloatArray,
    xb: FloatArray,
    rb: FloatArray,
    limit: float,
) -> tuple[SidePrune, SidePrune]:
    up_a, up_b = _up(reach, a), _up(reach, b)
    common = set(up_a) & set(up_b)
    lca = next(x for x in up_a if x in common)
    with np.errstate(invalid="ignore", over="ignore"):
        if lca not in (a, b):
            ca, ea = _ball(reach, up_a[up_a.index(lca) - 1], a)
            cb, eb = _ball(reach, up_b[up_b.index(lca) - 1], b)
            far = float(np.linalg.norm(ca - cb)) - ea - eb
            ga = far - (np.linalg.norm(xa, axis=1) + ra) - float(np.max(_extent(xb, rb)))
            gb = far - (np.linalg.norm(xb, axis=1) + rb) - float(np.max(_extent(xa, ra)))
            return _prune_side(ga, limit), _prune_side(gb, limit)
        swap = lca == b
        if swap:
            a, b, xa, ra, xb, rb, up_b = b, a, xb, rb, xa, ra, up_a
        top = up_b[up_b.index(a) - 1]
        if top == b and reach.bodies.kind[b] != PRISM:
            g_anc, g_desc = reach._circles(b, xa, ra, xb, rb)
        else:
            centre, ext = _ball(reach, top, b)
            u = np.linalg.norm(xa - centre, axis=1) - ra
            v = _extent(xb, rb) + ext
            g_anc, g_desc = u - float(np.max(v)), float(np.min(u)) - v
    anc, desc = _prune_side(g_anc, limit), _prune_side(g_desc, limit)
    return (desc, anc) if swap else (anc, desc)


def cspace_joints_on_paths(
    kin: KinematicModel, spheres: SphereSet, cspace: frozenset[str]
) -> list[int]:
    """The report's per-pair count as it was: ``joints_on_path`` by walks, pair by pair."""
    return [
        len(cspace.intersection(_joints_on_path(kin, a, b))) for a, b in spheres.frame_pair_names()
    ]


def _joints_on_path(kin: KinematicModel, frame_a: str, frame_b: str) -> tuple[str, ...]:
    a, b = kin.frame_index(frame_a), kin.frame_index(frame_b)
    up_a = kin.ancestors(a)
    up_b = kin.ancestors(b)
    common = set(up_a) & set(up_b)
    moving = [f for f in (*up_a, *up_b) if f not in common]
    found = {int(kin.q_index[f]) for f in moving if int(kin.q_index[f]) >= 0}
    return tuple(kin.actuated_joints[i] for i in sorted(found))
