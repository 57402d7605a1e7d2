"""Sphere-model visualizations: a pure :class:`Scene` and small back-ends that draw it.

The one interface: :func:`render` ``(scene, target, path, ...)`` where ``target`` is

* ``"rrd"``   — a rerun recording file (``rerun-sdk``, the ``viz`` extra);
* ``"spawn"`` — stream to a newly spawned rerun viewer (``rerun-sdk``);
* ``"mcap"``  — an MCAP file with Foxglove ``SceneUpdate``/``FrameTransform`` messages
  (``mcap``, the ``viz`` extra);
* ``"png"``   — a static matplotlib picture of the default pose (the ``viz`` extra), framed
  by a :class:`Picture` (camera, legend, size; the viewers of the others have their own).

Back-end modules are imported only when used, so neither rerun nor mcap is needed to import
:mod:`xrdf_tools` or to build a scene. Files are written atomically: to a temporary file in the
target directory, renamed over the target when complete.
"""

from __future__ import annotations

import contextlib
import importlib
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Protocol

from ..selfcollision.configurations import load_configurations, sample_configurations
from ..util.errors import XrdfToolsError
from ..util.extras import install_hint
from ..util.fileio import atomic_output
from .contacts import SpherePair
from .scene import (
    COLLISION_RGBA,
    LinkScene,
    Progress,
    Sample,
    Scene,
    build_scene,
    choose_group,
    link_color,
    scene_configurations,
    scene_diagnostics,
    sphere_counts,
)

Target = Literal["rrd", "spawn", "mcap", "png"]
TARGETS: tuple[Target, ...] = ("rrd", "spawn", "mcap", "png")

#: target -> (module, function); each function is a :class:`Backend`.
_BACKENDS: dict[str, tuple[str, str]] = {
    "rrd": ("xrdf_tools.viz.rerun_backend", "write_rrd"),
    "spawn": ("xrdf_tools.viz.rerun_backend", "spawn"),
    "mcap": ("xrdf_tools.viz.mcap_backend", "write_mcap"),
    "png": ("xrdf_tools.viz.png", "write_png"),
}

VIZ_EXTRA_HINT = install_hint("viz")


@dataclass(frozen=True)
class Picture:
    """How a static picture (``"png"``) is framed: the camera (elevation, azimuth in degrees;
    None: the three-quarter ``iso`` view of :data:`xrdf_tools.viz.png.VIEWS`), the legend of
    the links (``"auto"`` or ``"off"``) and the side of the square picture in pixels."""

    view: tuple[float, float] | None = None
    legend: Literal["auto", "off"] = "auto"
    size_px: int = 640


#: The picture drawn when none is asked for.
DEFAULT_PICTURE = Picture()


class Backend(Protocol):
    """What every back-end provides: draw ``scene`` into ``path`` (None for ``spawn``);
    ``picture`` frames a static picture (the interactive viewers ignore it)."""

    def __call__(
        self,
        scene: Scene,
        path: Path | None,
        *,
        buffered: bool = False,
        progress: Progress | None = None,
        picture: Picture = ...,
    ) -> None: ...


class VizError(XrdfToolsError):
    """A visualization cannot be written (e.g. the output directory does not exist)."""


def backend(target: Target) -> Backend:
    """The back-end function for ``target`` (imports its module now)."""
    if target not in _BACKENDS:
        raise VizError(f"unknown visualization target '{target}' (valid: {', '.join(TARGETS)})")
    module, name = _BACKENDS[target]
    fn: Backend = getattr(importlib.import_module(module), name)
    return fn


def render(
    scene: Scene,
    target: Target,
    path: str | os.PathLike[str] | None = None,
    *,
    buffered: bool = False,
    progress: Progress | None = None,
    picture: Picture = DEFAULT_PICTURE,
) -> None:
    """Draw ``scene`` with the ``target`` back-end into ``path``.

    ``buffered`` also draws each sphere's self-collision buffered radius; ``picture`` frames
    a ``"png"``. Raises :class:`MissingDependencyError` when the back-end's package is not
    installed and :class:`VizError` for an unusable output path.
    """
    if target != "spawn" and path is None:
        raise VizError(f"target '{target}' needs an output path")
    out = None if path is None else Path(path)
    backend(target)(scene, out, buffered=buffered, progress=progress, picture=picture)


def require(module: str, package: str) -> None:
    """Import check for a back-end's package: a one-line :class:`MissingDependencyError`
    naming the ``viz`` extra."""
    from ..util.extras import require as require_extra

    require_extra((module,), "viz", f"this output ({package})")


@contextlib.contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """A temporary path next to ``path``; renamed to ``path`` when the block succeeds, removed
    in any case (:func:`xrdf_tools.util.fileio.atomic_output`; the directory must exist)."""
    with atomic_output(path, create_parents=False) as tmp:
        yield tmp


__all__ = [
    "COLLISION_RGBA",
    "DEFAULT_PICTURE",
    "TARGETS",
    "VIZ_EXTRA_HINT",
    "Backend",
    "LinkScene",
    "Picture",
    "Progress",
    "Sample",
    "Scene",
    "SpherePair",
    "Target",
    "VizError",
    "atomic_path",
    "backend",
    "build_scene",
    "choose_group",
    "link_color",
    "load_configurations",
    "render",
    "require",
    "sample_configurations",
    "scene_configurations",
    "scene_diagnostics",
    "sphere_counts",
]
