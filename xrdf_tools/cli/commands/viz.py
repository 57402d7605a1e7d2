"""`xrdf viz`: draw the sphere model to rerun (.rrd or a spawned viewer), MCAP or PNG."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from ...util.errors import XrdfToolsError
from .options import configs as configs_option
from .options import seed as seed_option
from .plain import OutputFormat, check_robot_overwrite, detail, is_stdio, load_robot_option, timed
from .typer_common import (
    AllowMissingMeshesOption,
    DiagnosticsFormatOption,
    PackagePathOption,
    QuietOption,
    RobotUrdfOption,
    VerboseOption,
    XacroArgOption,
    echo_diagnostics,
    fail,
    load_xrdf_input,
    note,
    one_bar,
    progress_bar,
    refuse_input_overwrite,
    typer_option,
)

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ...robot.packages import PackagePaths
    from ...viz import Target

#: Show a progress bar from this many samples on (when stderr is a terminal).
PROGRESS_FROM = 200


class LegendChoice(str, Enum):
    auto = "auto"
    off = "off"


class MeshChoice(str, Enum):
    visual = "visual"
    collision = "collision"
    none = "none"


def command(
    xrdf_file: Annotated[
        Path,
        typer.Argument(metavar="ROBOT.xrdf", help="XRDF file ('-': stdin).", show_default=False),
    ],
    urdf: RobotUrdfOption,
    rrd: Annotated[
        Path | None, typer.Option("--rrd", help="Write a rerun recording (.rrd).")
    ] = None,
    mcap: Annotated[
        Path | None, typer.Option("--mcap", help="Write an MCAP file for Foxglove.")
    ] = None,
    spawn: Annotated[bool, typer.Option("--spawn", help="Stream to a new rerun viewer.")] = False,
    png: Annotated[
        Path | None,
        typer.Option("--png", help="Write a static PNG of the default pose (matplotlib)."),
    ] = None,
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            "-n",
            min=0,
            help="Configurations drawn uniformly within the c-space joint limits, added after "
            "the default pose (step 0).",
        ),
    ] = 0,
    configs: Annotated[
        Path | None, typer_option(configs_option("Configurations to add after the default pose."))
    ] = None,
    colliding_only: Annotated[
        bool,
        typer.Option("--colliding-only", help="Keep only configurations in self-collision."),
    ] = False,
    meshes: Annotated[
        MeshChoice,
        typer.Option(
            "--meshes", help="URDF geometry drawn with the spheres (not in a --png picture)."
        ),
    ] = MeshChoice.visual,
    group: Annotated[
        str | None,
        typer.Option(
            "--group",
            help="Geometry group to draw. Default: the self-collision one, else the "
            "world-collision one.",
        ),
    ] = None,
    buffered: Annotated[
        bool,
        typer.Option("--buffered", help="Also draw the self-collision buffered radii."),
    ] = False,
    seed: Annotated[int, typer_option(seed_option("--samples"))] = 0,
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    allow_missing_meshes: AllowMissingMeshesOption = False,
    view: Annotated[
        str,
        typer.Option(
            "--view",
            help="--png camera: iso, front, side, top, or ELEV,AZIM in degrees (e.g. 30,-60).",
        ),
    ] = "iso",
    legend: Annotated[
        LegendChoice,
        typer.Option(
            "--legend",
            help="--png legend of the links: auto (in small columns below the picture from "
            "21 links on) or off.",
        ),
    ] = LegendChoice.auto,
    fmt: DiagnosticsFormatOption = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Draw the collision spheres on the robot: default pose, sampled configurations,
    self-collisions in red.

    Exactly one of --rrd, --mcap, --spawn, --png (spheres only: --meshes does not apply).
    Step 0 is the default pose, then one step per configuration from --samples or --configs.
    Every output needs the viz extra: pip install "xrdf-tools[viz]". A mesh file that cannot
    be found is an input error (exit 2) unless --allow-missing-meshes; one that cannot be read
    is left out of the drawing with a warning.

    \b
    Examples:
      xrdf viz robot.xrdf --urdf robot.urdf --png robot.png --view front
      xrdf viz robot.xrdf --urdf robot.urdf --rrd robot.rrd --samples 500 --colliding-only
      xrdf viz robot.xrdf --urdf robot.urdf --mcap robot.mcap --configs trajectory.csv
    """
    target, out = _one_output(rrd, mcap, spawn, png)
    _require_viz_extra(target)
    if samples and configs is not None:
        fail("--samples and --configs cannot be combined; choose one")
    if is_stdio(out):
        fail(f"--{target} needs a file name (not written to stdout)")
    if out is not None:
        refuse_input_overwrite(out, [xrdf_file, urdf, configs])
    from ...viz.png import parse_view

    try:
        camera = parse_view(view)
    except XrdfToolsError as e:
        fail(e)

    try:
        from ...robot.kinematics import build_kinematic_model
        from ...robot.packages import parse_package_paths
        from ...viz import (
            Picture,
            build_scene,
            render,
            require,
            scene_configurations,
            scene_diagnostics,
        )

        # Check the optional back-end first: no point computing a scene it cannot draw.
        if target in ("rrd", "spawn"):
            require("rerun", "rerun-sdk")
        elif target == "mcap":
            require("mcap", "mcap")
        pkgs = parse_package_paths(package_path)
        x = load_xrdf_input(xrdf_file)
        u = load_robot_option(urdf, xacro_arg, package_path)
        check_robot_overwrite(out, u)
        kin, kdiags = build_kinematic_model(u, x)
        drawn = "none" if target == "png" else meshes.value
        _require_meshes(u, drawn, kin.frame_names, pkgs, allow_missing_meshes)
        Q = scene_configurations(kin, x, configs=configs, samples=samples, seed=seed)
        n = 0 if Q is None else len(Q)
        detail(f"checking {n + 1} configuration(s) for self-collision (the default pose first)")
        label = "checking self-collision"
        with progress_bar(n + 1 >= PROGRESS_FROM) as bar, timed(label):
            scene = build_scene(
                u,
                x,
                Q,
                kinematic_model=kin,
                group=group,
                meshes=drawn,  # type: ignore[arg-type]
                colliding_only=colliding_only,
                urdf_path=urdf,
                package_paths=pkgs,
                progress=one_bar(bar, label),
            )
        echo_diagnostics(scene_diagnostics(scene, kdiags), fmt)
        label = f"writing {target}"
        with progress_bar(len(scene.samples) >= PROGRESS_FROM) as bar, timed(label):
            picture = Picture(view=camera, legend=legend.value)
            progress = one_bar(bar, label)
            render(scene, target, out, buffered=buffered, progress=progress, picture=picture)
    except XrdfToolsError as e:
        fail(e)
    except OSError as e:
        fail(f"{out}: cannot write: {e.strerror or e}")

    hit = sum(1 for s in scene.samples if s.contacts)
    where = "rerun viewer" if out is None else str(out)
    unread = _PNG_NOTE.get(target, "")
    note(
        f"{where}: {len(scene.links)} links, {scene.n_spheres} spheres (group '{scene.group}'), "
        f"{len(scene.samples)} sample(s), {hit} in self-collision{unread}"
    )
    detail(
        f"frame pairs: {scene.frame_pairs_checked} checked "
        f"({len(scene.samples[0].frame_contacts)} colliding at the default pose), "
        f"{scene.frame_pairs_ignored} ignored"
    )


def _one_output(
    rrd: Path | None, mcap: Path | None, spawn: bool, png: Path | None
) -> tuple[Target, Path | None]:
    """The one output chosen among --rrd, --mcap, --spawn and --png (a usage error otherwise)."""
    offered: tuple[tuple[Target, Path | None, bool], ...] = (
        ("rrd", rrd, rrd is not None),
        ("mcap", mcap, mcap is not None),
        ("spawn", None, spawn),
        ("png", png, png is not None),
    )
    chosen = [(target, out) for target, out, given in offered if given]
    if len(chosen) != 1:
        fail("choose exactly one output: --rrd OUT.rrd, --mcap OUT.mcap, --spawn or --png OUT.png")
    return chosen[0]


def _require_viz_extra(target: Target) -> None:
    """Drawing reads link geometry (the fit extra, part of viz); a PNG also needs matplotlib."""
    from ...util.extras import FIT, VIZ, require

    require((*FIT, *VIZ) if target == "png" else FIT, "viz", "xrdf viz")


#: What the summary adds per output: a PNG draws no meshes.
_PNG_NOTE = {"png": "; the PNG draws spheres only (meshes not read)"}


def _require_meshes(
    robot: Any, drawn: str, links: Sequence[str], pkgs: PackagePaths, allow: bool
) -> None:
    """Stop (MissingMeshError) when a mesh to draw cannot be found, unless ``allow``."""
    if drawn == "none":
        return
    from ...robot.link_geometry import require_meshes

    require_meshes(
        robot,
        drawn,  # type: ignore[arg-type]
        links=links,
        package_paths=pkgs,
        allow_missing=allow,
    )
