"""Optional parts of the install: which extra provides what, and the one check before use.

The default install reads and writes XRDF, URDF, xacro and SRDF, lints, diffs, converts and
reports. Reading link geometry (meshes), fitting spheres and geometry-based lint checks need
the ``fit`` extra (yourdfpy, trimesh, scipy, manifold3d, rtree); pictures and recordings need
``viz`` (matplotlib, rerun-sdk, mcap; it includes ``fit``); ``all`` is everything.
"""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Sequence

from .errors import MissingDependencyError

__all__ = ["FIT", "VIZ", "install_hint", "require"]

#: Modules of each extra, checked before use.
FIT: tuple[str, ...] = ("yourdfpy", "trimesh", "scipy")
VIZ: tuple[str, ...] = ("matplotlib",)


def install_hint(extra: str) -> str:
    return f'pip install "xrdf-tools[{extra}]"'


def require(modules: Sequence[str], extra: str, what: str) -> None:
    """Raise a one-line :class:`MissingDependencyError` naming the extra when one of
    ``modules`` is not installed (``what``: the work that needs them)."""
    missing = [m for m in modules if not _installed(m)]
    if missing:
        raise MissingDependencyError(
            f"{what} needs the '{extra}' extra ({', '.join(missing)} not installed): "
            f"{install_hint(extra)}"
        )


def _installed(module: str) -> bool:
    if module in sys.modules:
        return sys.modules[module] is not None
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False
