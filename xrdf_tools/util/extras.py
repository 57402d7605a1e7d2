"""Optional parts of the install: which extra provides what, and the one check before use.

The default install reads and writes XRDF, URDF, xacro and SRDF, lints, diffs, converts and
reports. Reading link geometry (meshes), fitting spheres and geometry-based lint checks need
the ``fit`` extra (yourdfpy, trimesh, scipy, manifold3d, rtree); pictures and recordings need
``viz`` (matplotlib, rerun-sdk, mcap; it includes ``fit``); ``all`` is everything.

Inside a pre-commit hook (``PRE_COMMIT=1``, which pre-commit sets) ``pip install`` cannot
reach the hook's environment: the hint names the packages for the hook's
``additional_dependencies`` instead, read from the installed package's metadata.
"""

from __future__ import annotations

import importlib.util
import os
import re
import sys
from collections.abc import Sequence

from .errors import MissingDependencyError

__all__ = ["FIT", "VIZ", "extra_requirements", "install_hint", "require"]

#: Modules of each extra, checked before use.
FIT: tuple[str, ...] = ("yourdfpy", "trimesh", "scipy")
VIZ: tuple[str, ...] = ("matplotlib",)


#: ``extra == "fit"`` in a requirement's environment marker.
_EXTRA_MARKER = re.compile(r"""extra\s*==\s*["']([^"']+)["']""")


def install_hint(extra: str) -> str:
    """How to install ``extra``: with pip, or in a pre-commit hook its packages for the hook's
    ``additional_dependencies``."""
    if os.environ.get("PRE_COMMIT") == "1":
        packages = extra_requirements(extra)
        if packages:
            return (
                f"in a pre-commit hook, add its packages to the hook's additional_dependencies: "
                f"[{', '.join(packages)}]"
            )
    return f'pip install "xrdf-tools[{extra}]"'


def extra_requirements(extra: str) -> list[str]:
    """The requirements ``extra`` adds (``["trimesh>=4.0", ...]``), extras it includes
    expanded, from the installed distribution's metadata; [] when that is not available."""
    from importlib.metadata import PackageNotFoundError, requires

    try:
        listed = requires("xrdf-tools") or []
    except PackageNotFoundError:
        return []
    by_extra: dict[str, list[str]] = {}
    for req in listed:
        spec, _, marker = req.partition(";")
        if m := _EXTRA_MARKER.search(marker):
            by_extra.setdefault(m.group(1), []).append(spec.strip())
    out: list[str] = []
    todo, seen = [extra], set()
    while todo:
        name = todo.pop(0)
        if name in seen:
            continue
        seen.add(name)
        for spec in by_extra.get(name, []):
            if spec.startswith("xrdf-tools["):
                todo.extend(e.strip() for e in spec[len("xrdf-tools[") : -1].split(","))
            elif spec not in out:
                out.append(spec)
    return out


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
