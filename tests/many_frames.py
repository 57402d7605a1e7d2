"""Synthetic robots with many sphere-carrying frames, written here (URDF and XRDF text).

* :func:`chain_robot`: a serial chain of ``n`` revolute joints (axes turning through y, x,
  z), every link one sphere: ``(n + 1) n / 2`` frame pairs, the shape at the frame ceiling;
* :func:`tree_robot`: a seeded tree of ``links`` links with branches, revolute, continuous,
  prismatic, fixed and mimic joints (a mimic on the same branch as its master and one on
  another branch), one to three spheres per link.

Used by the engine and report tests and by ``benchmarks/bench_scale.py``.
"""

from __future__ import annotations

import numpy as np

from tests.sphere_xrdf import sphere_xrdf

_AXES = ("0 1 0", "1 0 0", "0 0 1")


def _joint(name: str, kind: str, parent: str, child: str, xyz: str, extra: str = "") -> str:
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}"/>{extra}</joint>'
    )


def _limit(lo: float, hi: float) -> str:
    return f'<limit lower="{lo}" upper="{hi}" effort="1" velocity="1"/>'


def _urdf(links: list[str], joints: list[str]) -> str:
    body = "".join(f'<link name="{n}"/>' for n in links) + "".join(joints)
    return f'<?xml version="1.0"?><robot name="many">{body}</robot>\n'


def chain_robot(n: int) -> tuple[str, str]:
    """(URDF, XRDF) of a serial chain of ``n`` revolute joints 5 cm apart, each link one
    sphere of 2 cm radius, every joint in the c-space."""
    links = [f"l{i}" for i in range(n + 1)]
    joints = [
        _joint(
            f"j{i}",
            "revolute",
            links[i - 1],
            links[i],
            "0 0 0.05",
            f'<axis xyz="{_AXES[i % 3]}"/>{_limit(-1.0, 1.0)}',
        )
        for i in range(1, n + 1)
    ]
    spheres = {name: [(0.0, 0.0, 0.025, 0.02)] for name in links}
    return _urdf(links, joints), sphere_xrdf([f"j{i}" for i in range(1, n + 1)], spheres)


def tree_robot(links: int, seed: int = 0) -> tuple[str, str]:
    """(URDF, XRDF) of a seeded tree of ``links`` links: each link hangs from one of the six
    links before it (branches), by a revolute joint, or every 7th by a prismatic one, every
    11th by a fixed one, every 13th by a continuous one; link 9's joint mimics link 3's
    (the same branch or not, as the tree falls) and the last link's mimics the first
    joint's. Every movable joint that is not a mimic is in the c-space."""
    rng = np.random.default_rng(seed)
    names = [f"t{i}" for i in range(links)]
    joints: list[str] = []
    cspace: list[str] = []
    spheres: dict[str, list[tuple[float, float, float, float]]] = {}
    for i in range(1, links):
        parent = names[int(rng.integers(max(0, i - 6), i))]
        x, y = (round(float(v), 3) for v in rng.uniform(-0.04, 0.04, 2))
        xyz = f"{x} {y} 0.06"
        axis = f'<axis xyz="{_AXES[int(rng.integers(3))]}"/>'
        if i in (9, links - 1):
            master = "jt3" if i == 9 else "jt1"
            mimic = f'<mimic joint="{master}" multiplier="-1.0" offset="0.1"/>'
            joints.append(
                _joint(f"jt{i}", "revolute", parent, names[i], xyz, axis + _limit(-2, 2) + mimic)
            )
            continue
        if i % 11 == 0:
            joints.append(_joint(f"jt{i}", "fixed", parent, names[i], xyz))
            continue
        if i % 7 == 0:
            kind, lim = "prismatic", _limit(-0.03, 0.05)
        elif i % 13 == 0:
            kind, lim = "continuous", '<limit effort="1" velocity="1"/>'
        else:
            kind, lim = "revolute", _limit(-1.5, 1.5)
        joints.append(_joint(f"jt{i}", kind, parent, names[i], xyz, axis + lim))
        cspace.append(f"jt{i}")
    for name in names:
        count = int(rng.integers(1, 4))
        spheres[name] = [
            (*(round(float(v), 3) for v in rng.uniform(-0.02, 0.02, 2)), 0.03, 0.02)
            for _ in range(count)
        ]
    return _urdf(names, joints), sphere_xrdf(cspace, spheres)
