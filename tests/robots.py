"""Real robot descriptions from the ``example-robot-data`` package (a dev dependency).

The package is a cmeel wheel: its URDFs live under ``<site-packages>/cmeel.prefix/share/
example-robot-data/robots``. Tests that need them call :func:`robot_urdf`, which skips the
test cleanly when the package is not installed.
"""

from __future__ import annotations

import importlib.metadata
import sys
import sysconfig
from functools import lru_cache
from pathlib import Path

import pytest

REL = Path("cmeel.prefix", "share", "example-robot-data", "robots")

#: short name -> path below ``robots/``
ROBOTS: dict[str, str] = {
    "panda": "panda_description/urdf/panda.urdf",  # prismatic fingers, one mimic
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "kinova": "kinova_description/robots/kinova.urdf",  # continuous joints
    "xarm7": "xarm_description/urdf/xarm7.urdf",
    "z1": "z1_description/urdf/z1.urdf",
    "pr2": "pr2_description/urdf/pr2.urdf",  # 82 links, prismatic torso, continuous, mimics
    "baxter": "baxter_description/urdf/baxter.urdf",  # prismatic grippers with mimics
    "romeo": "romeo_description/urdf/romeo.urdf",  # 44 mimic joints, multiplier -1
    "talos": "talos_data/robots/talos_full_v2.urdf",  # gripper mimics, multiplier -1
    "anymal": "anymal_b_simple_description/robots/anymal.urdf",  # legged; SRDF in `<a />` style
}


@lru_cache(maxsize=1)
def robots_dir() -> Path | None:
    """``…/share/example-robot-data/robots`` or None when the package is absent."""
    candidates: list[Path] = []
    try:
        dist = importlib.metadata.distribution("example-robot-data")
        candidates.append(Path(str(dist.locate_file(REL))))
    except importlib.metadata.PackageNotFoundError:
        pass
    for key in ("purelib", "platlib"):
        candidates.append(Path(sysconfig.get_paths()[key]) / REL)
    candidates.extend(Path(p) / REL for p in sys.path if p)
    for c in candidates:
        if c.is_dir():
            return c
    return None


def robot_urdf(name: str) -> Path:
    """Path of robot ``name`` (a key of :data:`ROBOTS`); skips when unavailable."""
    root = robots_dir()
    if root is None:
        pytest.skip("example-robot-data is not installed")
    path = root / ROBOTS[name]
    if not path.is_file():
        pytest.skip(f"{path} not found in example-robot-data")
    return path


def panda_copy_with_mesh(tmp_path: Path, mesh: str) -> tuple[Path, Path]:
    """The example-robot-data Panda URDF copied under ``tmp_path`` (its package found with
    ``--package-path example-robot-data=tmp_path``) with one of its meshes, ``mesh`` (e.g.
    ``"visual/link0.dae"``), beside it: ``(urdf, mesh file)``; the other meshes are absent."""
    panda = robot_urdf("panda")
    desc = tmp_path / "robots" / "panda_description"
    copied = desc / "meshes" / mesh
    copied.parent.mkdir(parents=True)
    copied.write_bytes((panda.parents[1] / "meshes" / mesh).read_bytes())
    urdf = desc / "urdf" / "panda.urdf"
    urdf.parent.mkdir()
    urdf.write_bytes(panda.read_bytes())
    return urdf, copied


#: A link name that matplotlib's math text would stop at (an unknown command between ``$``).
DOLLAR_LINK = "arm$\\undefinedcommand{$"


def dollar_robot(tmp_path: Path) -> tuple[Path, str]:
    """A two-link URDF ``r.urdf`` named ``r$x`` whose moving link is :data:`DOLLAR_LINK`
    (collision boxes, one revolute joint); returns its path and that link name."""
    urdf = tmp_path / "r.urdf"
    urdf.write_text(
        '<robot name="r$x"><link name="base"><collision><geometry><box size=".2 .2 .1"/>'
        f'</geometry></collision></link><link name="{DOLLAR_LINK}"><collision>'
        '<origin xyz="0 0 .2"/><geometry><box size=".06 .06 .3"/></geometry></collision></link>'
        f'<joint name="j1" type="revolute"><parent link="base"/><child link="{DOLLAR_LINK}"/>'
        '<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>'
    )
    return urdf, DOLLAR_LINK
