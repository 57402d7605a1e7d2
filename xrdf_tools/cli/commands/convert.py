"""``xrdf convert``: URDF/xacro + MoveIt SRDF or cuRobo config → canonical XRDF.

Exit codes: 0 written (diagnostics are only notes), 1 the result fails lint, ``--strict`` found
a fallback, or ``--check`` found a difference; 2 usage or input error.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...util.errors import XrdfToolsError
from ...util.numbers import MAX_SAMPLES, REPORT_SAMPLES
from .options import format_version as format_version_option
from .options import output as output_option
from .options import seed as seed_option
from .options import split_names
from .options import target as target_option
from .plain import (
    OutputFormat,
    Verbosity,
    detail,
    is_stdio,
    note,
    pairs,
    progress_lines,
    timed,
    verbosity,
)
from .spheres import (
    FitMethod,
    GeometryFrom,
    VisualCheck,
    fit_method_help,
    geometry_from_option,
    visual_check_option,
)
from .typer_common import (
    AllowMissingMeshesOption,
    ChainOption,
    DiagnosticsFormatOption,
    GroupOption,
    JointsOption,
    PackagePathOption,
    QuietOption,
    StateOption,
    ToolFrameOption,
    VerboseOption,
    XacroArgOption,
    fail,
    finite,
    progress_bar,
    refuse_input_overwrite,
    stderr_is_terminal,
    typer_option,
)

if TYPE_CHECKING:
    from ...convert.pipeline import FitOptions, Progress
    from ...spheres.fit import Plane
    from .typer_common import ProgressUpdate

#: Progress bar label of each stage of :func:`xrdf_tools.convert.pipeline.convert_robot`.
_STAGES = {
    "reading": "reading link geometry",
    "fitting": "fitting spheres (2 steps a link)",
    "sampling": "sampling the mask",
}


def command(
    robot: Annotated[
        Path | None,
        typer.Argument(
            metavar="ROBOT.urdf|xacro",
            help="The robot: ROBOT.urdf, ROBOT.urdf.xacro or ROBOT.xacro (xacro is expanded "
            "without ROS; it evaluates Python, so only convert files you trust). With --curobo "
            "it may be left out: the config's urdf_path, beside the config, is taken.",
            show_default=False,
        ),
    ] = None,
    srdf: Annotated[
        Path | None, typer.Option("--srdf", help="MoveIt SRDF (groups, states, ignore pairs).")
    ] = None,
    joint_limits: Annotated[
        Path | None,
        typer.Option("--joint-limits", help="MoveIt joint_limits.yaml (acceleration, jerk)."),
    ] = None,
    curobo: Annotated[
        Path | None,
        typer.Option("--curobo", help="cuRobo robot YAML (classic or 2.0 layout) or Lula YAML."),
    ] = None,
    group: GroupOption = None,
    state: StateOption = None,
    tool_frame: ToolFrameOption = None,
    acceleration: Annotated[
        float | None,
        typer.Option(
            "--acceleration",
            callback=finite,
            help="Acceleration limit (rad/s² or m/s²) for joints the inputs lack. Default: 10, "
            "with a warning.",
        ),
    ] = None,
    jerk: Annotated[
        float | None,
        typer.Option(
            "--jerk",
            callback=finite,
            help="Jerk limit (rad/s³ or m/s³) for joints the inputs lack. Default: 1000, with "
            "a warning.",
        ),
    ] = None,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    format_version: Annotated[
        str | None,
        typer_option(
            format_version_option(
                "1.0, the version every reader loads (2.0 only when the robot needs it; the "
                "message says which readers drop it)."
            )
        ),
    ] = None,
    target: Annotated[
        str | None,
        typer_option(
            target_option(
                "Chooses the version and lints the result for that reader (its checks become "
                "errors). Default: none (XRDF 1.0, the readers' checks as warnings)."
            )
        ),
    ] = None,
    output: Annotated[Path | None, typer_option(output_option("the XRDF"))] = None,
    check: Annotated[
        bool,
        typer.Option(
            "--check",
            help="Do not write: compare with the existing -o file and exit 1 on any "
            "semantic difference.",
        ),
    ] = False,
    strict: Annotated[
        bool,
        typer.Option("--strict", help="Fail (exit 1) when any value had to be guessed."),
    ] = False,
    fit_spheres: Annotated[
        bool,
        typer.Option("--fit-spheres", help="Fit spheres to the link meshes when none are given."),
    ] = False,
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            "-n",
            min=1,
            max=MAX_SAMPLES,
            help="With --fit-spheres or a Lula --curobo file (it has no mask): configurations "
            "sampled for the self-collision mask "
            "(as `xrdf report --samples`; at most 10,000,000,000).",
        ),
    ] = REPORT_SAMPLES,
    seed: Annotated[
        int,
        typer_option(seed_option("the fit and of the mask's samples (--fit-spheres, a Lula file)")),
    ] = 0,
    geometry_from: Annotated[
        GeometryFrom, geometry_from_option("With --fit-spheres")
    ] = GeometryFrom.collision,
    per_link: Annotated[
        int | None,
        typer.Option(
            "--per-link",
            min=1,
            max=64,
            help="With --fit-spheres: spheres per link (default: the fewest, up to 16, that "
            "cover 90 % of the link).",
        ),
    ] = None,
    sphere_budget: Annotated[
        int | None,
        typer.Option(
            "--sphere-budget",
            min=1,
            help="With --fit-spheres: this many spheres in total, one per link and the rest "
            "where they add the most covered volume (instead of --per-link).",
        ),
    ] = None,
    clip: Annotated[
        list[str] | None,
        typer.Option(
            "--clip",
            help="With --fit-spheres: LINK:nx,ny,nz,d keeps LINK's spheres on the side of the "
            "plane n.x = d that n points to (link frame, metres; as `xrdf spheres --clip`).",
        ),
    ] = None,
    method: Annotated[
        FitMethod,
        typer.Option(
            "--method",
            case_sensitive=False,
            help=fit_method_help(
                "--per-link, --sphere-budget", "90 %", "--clip is enforced", "With --fit-spheres"
            ),
        ),
    ] = FitMethod.ours,
    visual_check: Annotated[
        VisualCheck, visual_check_option("With --fit-spheres")
    ] = VisualCheck.fast,
    joints: JointsOption = None,
    chain: ChainOption = None,
    allow_missing_meshes: AllowMissingMeshesOption = False,
    no_lint: Annotated[
        bool, typer.Option("--no-lint", help="Skip linting the result against the URDF.")
    ] = False,
    fmt: DiagnosticsFormatOption = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Convert a URDF/xacro plus an SRDF or cuRobo config to XRDF; report every guess.

    With --fit-spheres: fit spheres to the links' collision geometry and compute the
    self-collision mask like `xrdf report --write-mask`, so the result is planning-ready.
    Every link with that geometry gets spheres or the command fails (exit 1, naming each
    link and why); a mesh file that cannot be found is an input error (exit 2) unless
    --allow-missing-meshes.

    \b
    Examples:
      xrdf convert robot.urdf --srdf robot.srdf --fit-spheres -o robot.xrdf
      xrdf convert robot.urdf --srdf robot.srdf --group left_arm --group right_arm \\
          --fit-spheres --target curobo -o robot.xrdf
      xrdf convert robot.urdf --chain base_link:tool0 --fit-spheres -o robot.xrdf
      xrdf convert robot.urdf.xacro --srdf robot.srdf --joint-limits joint_limits.yaml \\
          --package-path my_robot_description=../my_robot_description -o robot.xrdf
      xrdf convert robot.urdf --srdf robot.srdf --fit-spheres -o robot.xrdf --check
    """
    from ...convert.core import ConvertOptions
    from ...convert.pipeline import MaskOptions, convert_robot
    from ...convert.sources.cspace import parse_chain
    from ...robot.packages import parse_package_paths
    from ...robot.xacro_source import parse_xacro_arg
    from .convert_outcome import check_against, report_findings, write_result

    _check_usage(format_version, check, output)
    robot = _robot_or_config_urdf(robot, curobo)
    inputs = _input_files(robot, srdf, joint_limits, curobo)
    if output is not None and not check:
        refuse_input_overwrite(output, inputs)
    try:
        pkgs = parse_package_paths(package_path)
        xargs = pairs(xacro_arg, parse_xacro_arg)
        options = ConvertOptions(
            srdf=srdf,
            joint_limits=joint_limits,
            curobo=curobo,
            state=state,
            tool_frames=tuple(tool_frame or ()),
            acceleration=acceleration,
            jerk=jerk,
            format_version=format_version,
            target=target,
            groups=tuple(group or ()),
            joints=tuple(split_names(joints, "--joints", "JOINT[,JOINT...]")),
            chains=tuple(
                parse_chain(c) for c in split_names(chain, "--chain", "BASE_LINK:TIP_LINK[,...]")
            ),
        )
        fit = _fit_options(
            fit_spheres,
            method,
            per_link=per_link,
            sphere_budget=sphere_budget,
            geometry_from=geometry_from,
            seed=seed,
            allow_missing_meshes=allow_missing_meshes,
            clip=clip,
            visual_check=visual_check,
        )
        mask = MaskOptions(samples=samples, seed=seed) if fit_spheres else None
        label = "<stdout>" if output is None or is_stdio(output) else str(output)
        with progress_bar(fit_spheres) as bar, timed("convert"):
            result = convert_robot(
                robot,
                options,
                xacro_args=xargs,
                package_paths=pkgs,
                fit=fit,
                mask=mask,
                lint=not no_lint,
                label=label,
                progress=_staged(bar),
                allow_missing_meshes=allow_missing_meshes,
                missing_mask=MaskOptions(samples=samples, seed=seed),
            )
    except XrdfToolsError as e:
        fail(e)
    report_findings(result, fmt, fit_spheres, strict)
    if check:
        assert output is not None
        check_against(output, result.xrdf, result.robot.root_link())
        return
    write_result(result, output)


def _robot_or_config_urdf(robot: Path | None, curobo: Path | None) -> Path:
    """The robot given, else the one the --curobo config names (said); exit 2 without both."""
    from ...convert.sources.curobo_config import config_urdf

    if robot is not None:
        return robot
    if curobo is None:
        fail("give the robot to convert: ROBOT.urdf|xacro (see xrdf convert --help)")
    try:
        urdf = config_urdf(curobo)
    except XrdfToolsError as e:
        fail(e)
    note(f"robot: {urdf} (the config's urdf_path)")
    return urdf


def _check_usage(format_version: str | None, check: bool, output: Path | None) -> None:
    """Exit 2 on a --format-version that is no XRDF version, or --check without a file."""
    if format_version not in (None, "1.0", "2.0"):
        fail(f"--format-version must be 1.0 or 2.0, not '{format_version}'")
    if check and (output is None or is_stdio(output)):
        fail("--check needs -o FILE (the file to compare with)")


def _input_files(
    robot: Path, srdf: Path | None, joint_limits: Path | None, curobo: Path | None
) -> list[Path | None]:
    """The files convert reads (the output may overwrite none of them): the robot, the SRDF,
    the joint limits, the cuRobo config and the spheres file it reads."""
    inputs: list[Path | None] = [robot, srdf, joint_limits, curobo]
    if curobo is not None:
        from ...convert.sources.curobo_config import referenced_files

        inputs += referenced_files(curobo)  # the spheres file the config reads
    return inputs


def _fit_options(
    fit_spheres: bool,
    method: FitMethod,
    *,
    per_link: int | None,
    sphere_budget: int | None,
    geometry_from: GeometryFrom,
    seed: int,
    allow_missing_meshes: bool,
    clip: list[str] | None,
    visual_check: VisualCheck = VisualCheck.fast,
) -> FitOptions | None:
    """What --fit-spheres and its options ask for (None without it); exit 2 on options
    that contradict each other. Raises :class:`XrdfToolsError` for an unusable --method or
    --clip."""
    from ...convert.pipeline import FitOptions

    if per_link is not None and sphere_budget is not None:
        fail("give --per-link or --sphere-budget, not both")
    if method is not FitMethod.ours and not fit_spheres:
        fail(f"--method {method.value} fits spheres: give --fit-spheres as well")
    if not fit_spheres:
        return None
    from ...spheres.morphit import check_method

    check_method(method.value)
    return FitOptions(
        source=geometry_from.value,
        seed=seed,
        per_link=per_link,
        allow_missing_meshes=allow_missing_meshes,
        sphere_budget=sphere_budget,
        clips=_clips(clip),
        method=method.value,
        visual_check=visual_check.value,
    )


def _clips(values: list[str] | None) -> dict[str, list[Plane]]:
    """``--clip LINK:nx,ny,nz,d`` values by link."""
    from ...spheres.fit import parse_clip

    out: dict[str, list[Plane]] = {}
    for text in values or []:
        link, plane = parse_clip(text)
        out.setdefault(link, []).append(plane)
    return out


def _staged(bar: ProgressUpdate | None) -> Progress | None:
    """The assistant's ``progress(stage, done, total, item)`` drawn on the common bar; with
    ``-v`` and no terminal (CI logs), one line per step of the fit, naming its link, and per
    tenth of the sampling."""
    if bar is not None:
        return lambda stage, done, total, _item: bar(_STAGES.get(stage, stage), done, total)
    if stderr_is_terminal() or verbosity() < Verbosity.VERBOSE:
        return None
    sampling = progress_lines(_STAGES["sampling"])

    def line(stage: str, done: int, total: int, item: str) -> None:
        if stage in ("reading", "fitting"):
            detail(f"{_STAGES[stage]}: {done + 1}/{total} {item}".rstrip())
        elif sampling is not None:
            sampling(done, total)

    return line
