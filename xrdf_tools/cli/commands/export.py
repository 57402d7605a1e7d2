"""``xrdf export curobo|srdf|xrdf``: XRDF → cuRobo robot YAML; XRDF ignore pairs synced into a
MoveIt SRDF; an XRDF rewritten for the reader that will load it."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...diagnostics import Diagnostic, Severity
from ...util.errors import XrdfToolsError
from .options import format_version as format_version_option
from .options import output as output_option
from .options import target as target_option
from .plain import EXIT_FINDINGS, OutputFormat, is_stdio, pairs
from .typer_common import (
    DiagnosticsFormatOption,
    PackagePathOption,
    QuietOption,
    RobotUrdfOption,
    VerboseOption,
    XacroArgOption,
    echo_diagnostics,
    fail,
    load_xrdf_input,
    read_xrdf_input,
    refuse_input_overwrite,
    refuse_output_clash,
    refuse_two_stdin,
    typer_option,
    write_output,
)

if TYPE_CHECKING:
    from ...export.curobo_axes import AxisRewrite
    from ...robot.core import Robot
    from ...xrdf.model import Xrdf

app = typer.Typer(
    help="Export an XRDF to a cuRobo robot YAML, sync its ignore pairs into a MoveIt SRDF, or "
    "rewrite it for a reader (--target).",
    no_args_is_help=True,
    rich_markup_mode=None,
)


def _load_robot(urdf: Path, package_path: list[str] | None, xacro_arg: list[str] | None) -> Robot:
    """The URDF (or expanded xacro), as every command loads ``--urdf``; its warnings (defects
    in parts no command uses, xacro's own) go with the command's diagnostics, in its
    ``--format``. Raises :class:`XrdfToolsError`."""
    from ...robot.packages import parse_package_paths
    from ...robot.xacro_source import load_robot, parse_xacro_arg

    return load_robot(
        urdf,
        xacro_args=pairs(xacro_arg, parse_xacro_arg),
        package_paths=parse_package_paths(package_path),
    )


XrdfArgument = Annotated[
    Path,
    typer.Argument(metavar="ROBOT.xrdf", help="The XRDF file ('-': stdin).", show_default=False),
]
OutputOption = Annotated[Path | None, typer_option(output_option("the result"))]
FormatOption = DiagnosticsFormatOption


@app.command("curobo", short_help="XRDF + URDF → cuRobo robot YAML (robot_cfg).")
def curobo(
    xrdf: XrdfArgument,
    urdf: RobotUrdfOption,
    layout: Annotated[
        str,
        typer.Option(
            "--layout",
            metavar="<2.0|classic>",
            help=(
                "cuRobo config layout: 2.0 (tool_frames; cuRobo main) or classic "
                "(ee_link; cuRobo 0.7.x, which main does not load)."
            ),
        ),
    ] = "2.0",
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    absolute_paths: Annotated[
        bool,
        typer.Option(
            "--absolute-paths",
            help="Write urdf_path and asset_root_path absolute (as cuRobo finds them without "
            "setup) instead of relative to the output file (a file you can commit).",
        ),
    ] = False,
    expanded_urdf: Annotated[
        Path | None,
        typer.Option(
            "--expanded-urdf",
            help="Where to write the URDF that urdf_path names when the export writes one (a "
            "xacro --urdf, joint axes rewritten; default: beside the output, named after it: "
            "cfg/ur3e.yml → cfg/ur3e.urdf).",
            show_default=False,
        ),
    ] = None,
    keep_axes: Annotated[
        bool,
        typer.Option(
            "--keep-axes",
            help="Write no URDF with the joint axes cuRobo cannot take (not exactly x, y or z) "
            "rewritten: such an axis on a chain cuRobo builds then stops the export.",
        ),
    ] = False,
    output: OutputOption = None,
    fmt: FormatOption = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Write a cuRobo robot YAML (floats, FIXED, lists in c-space order by joint name).

    urdf_path and asset_root_path are relative to the output file's directory (to the current
    directory when writing to stdout), so the pair can be committed and moved together;
    cuRobo joins a relative path to its own asset directory, so set
    robot_cfg.kinematics.external_asset_path to that directory when loading, or pass
    --absolute-paths. cuRobo cannot load a xacro, nor turn a joint about an axis other than
    x, y or z: with a xacro --urdf, or joint axes tilted (or a rounding error off x, y or z),
    a URDF is written beside the output (or to --expanded-urdf) and urdf_path names it; its
    axes are rewritten so that every link frame stays where it was (--keep-axes: not).

    \b
    Examples:
      xrdf export curobo ur5.xrdf --urdf ur5.urdf -o ur5.yml
      xrdf export curobo px150.xrdf --urdf px150.urdf.xacro --xacro-arg robot_name:=px150 \\
          --package-path trossen_descriptions=DIR -o cfg/px150.yml   # + cfg/px150.urdf
    """
    from ...export.curobo import CUROBO_LAYOUTS, to_curobo
    from ...export.curobo_assets import with_plain_file_names
    from ...export.curobo_axes import axes_to_rewrite
    from ...export.curobo_loader import loader_errors
    from ...xrdf.io import parse_xrdf

    if layout not in CUROBO_LAYOUTS:
        fail(f"--layout must be one of {', '.join(CUROBO_LAYOUTS)}, not '{layout}'")
    if output is not None:
        refuse_input_overwrite(output, [xrdf, urdf])
    try:
        source, label = read_xrdf_input(xrdf)
        x = parse_xrdf(source, label)
        robot = _load_robot(urdf, package_path, xacro_arg)
        rewrites = [] if keep_axes else axes_to_rewrite(robot)
        written = _urdf_target(robot, rewrites, urdf, output, expanded_urdf, xrdf)
        to_dir = None if absolute_paths else _output_dir(output)
        text, diags = to_curobo(
            x,
            robot,
            layout=layout,
            urdf_path=written or urdf,
            relative_to=to_dir,
            plain_file_names=written is not None,
        )
        errors = loader_errors(source, label, robot, axes_written=not keep_axes)
        diags = [*robot.warnings, *errors, *diags]
        urdf_text = _urdf_text(robot, rewrites, x) if written is not None else ""
    except XrdfToolsError as e:
        fail(e)
    if any(d.severity is Severity.ERROR for d in diags):
        echo_diagnostics(diags, fmt)
        n = sum(d.severity is Severity.ERROR for d in diags)
        fail(
            f"cuRobo's loader would raise on the exported config ({n} error(s) above, in the "
            "XRDF or the URDF): nothing written",
            EXIT_FINDINGS,
        )
    if written is not None:
        urdf_text, plain = with_plain_file_names(urdf_text)
        write_output(urdf_text, written)
        if robot.expanded:
            diags.append(_expanded_note(urdf, written, plain))
        if rewrites:
            diags.append(_axes_note(urdf, rewrites, written))
    echo_diagnostics(diags, fmt)
    write_output(text, output)


def _urdf_text(robot: Robot, rewrites: list[AxisRewrite], x: Xrdf) -> str:
    """The URDF text the export writes for cuRobo: the robot's (a xacro's expansion), with
    the joint axes of ``rewrites`` rewritten by links and joints named unlike the frames and
    joints the XRDF ``x`` adds (cuRobo adds them to the URDF's)."""
    from ...export.curobo_axes import straighten_axes

    text = robot.text or ""
    if not rewrites:
        return text
    added = [name for m in x.added_frames() for name in (m.frame_name, m.joint_name)]
    return straighten_axes(text, robot.path, rewrites, added)


def _output_dir(output: Path | None) -> Path:
    """The directory paths are written relative to: the output's, or the current one."""
    if output is None or is_stdio(output):
        return Path.cwd()
    return output.parent


def _urdf_target(
    robot: Robot,
    rewrites: list[AxisRewrite],
    urdf: Path,
    output: Path | None,
    explicit: Path | None,
    xrdf: Path,
) -> Path | None:
    """Where the URDF the export writes goes (None: cuRobo reads ``urdf`` as it is): the
    expansion of a xacro ``--urdf`` or a URDF with the joint axes of ``rewrites`` rewritten."""
    from ...export.curobo import expanded_urdf_path

    if not robot.expanded and not rewrites:
        if explicit is not None:
            fail(
                f"--expanded-urdf: {urdf} is not a xacro file and every joint axis is x, y or z "
                "(no URDF to write)"
            )
        return None
    if explicit is not None and is_stdio(explicit):
        fail(
            "--expanded-urdf -: urdf_path must name the URDF written for cuRobo, a file; "
            "give a file path"
        )
    if explicit is not None:
        target = explicit
    elif output is None or is_stdio(output):
        why = (
            f"{urdf} is {_a_xacro(urdf)}, which cuRobo cannot load"
            if robot.expanded
            else f"{urdf} has {len(rewrites)} joint axis(es) cuRobo cannot take (not exactly "
            "x, y or z), rewritten in a URDF written for it (--keep-axes: not)"
        )
        fail(
            f"{why}: pass -o FILE (the URDF is written beside it, named after it) or "
            "--expanded-urdf PATH"
        )
    else:
        target = expanded_urdf_path(output)
        if target == output:
            fail(
                f"-o {output}: the URDF written for cuRobo is named after the output "
                f"({target.name}); name the output .yml or pass --expanded-urdf PATH"
            )
    refuse_output_clash({"-o": output, "--expanded-urdf": target})
    refuse_input_overwrite(target, [xrdf, urdf])
    return target


def _a_xacro(urdf: Path) -> str:
    """What ``urdf`` is: a xacro file, or a ``.urdf`` that a user would not call one."""
    if urdf.suffix == ".xacro":
        return "a xacro"
    return f"a xacro (the {urdf.suffix or 'file'} uses xacro: macros, includes or $(...))"


def _axes_note(urdf: Path, rewrites: list[AxisRewrite], written: Path) -> Diagnostic:
    """The note on the joint axes rewritten in the URDF written."""
    from ...export.curobo_axes import axes_note

    message = axes_note(rewrites, str(written))
    return Diagnostic(str(urdf), None, None, "export-joint-axes", Severity.INFO, message, "")


def _expanded_note(urdf: Path, written: Path, plain: int) -> Diagnostic:
    """The note on the expanded URDF written, with the ``plain`` ``file://`` mesh names it
    holds as plain paths."""
    rewritten = (
        f"; its {plain} file:// mesh name(s) written as plain paths (cuRobo joins a file:// "
        "name to asset_root_path and never finds it)"
        if plain
        else ""
    )
    return Diagnostic(
        str(urdf),
        None,
        None,
        "export-expanded-urdf",
        Severity.INFO,
        f"{urdf.name} is {_a_xacro(urdf)}, which cuRobo cannot load: wrote the expanded URDF "
        f"to {written}; urdf_path names it{rewritten}",
        "",
    )


@app.command("srdf", short_help="Sync the ignore pairs into a MoveIt SRDF.")
def srdf(
    xrdf: XrdfArgument,
    merge: Annotated[
        Path | None,
        typer.Option(
            "--merge",
            help="Existing SRDF to sync: its disable_collisions become the XRDF's ignore pairs "
            "(pairs no longer ignored are removed); everything else is kept. An SRDF xacro is "
            "refused: merge into its expansion (xrdf expand).",
        ),
    ] = None,
    urdf: Annotated[
        Path | None,
        typer.Option(
            "--urdf", help="The robot's URDF (or xacro): gives <robot name> and checks link names."
        ),
    ] = None,
    report: Annotated[
        Path | None,
        typer.Option(
            "--report",
            help="'xrdf report --format json' output: reasons (Adjacent/Default/Always/Never) "
            "of added pairs; default User.",
        ),
    ] = None,
    robot_name: Annotated[
        str | None,
        typer.Option("--robot-name", help="<robot name> of a new SRDF without --urdf."),
    ] = None,
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    output: OutputOption = None,
    fmt: FormatOption = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Sync the XRDF's ignore pairs into a MoveIt SRDF's disable_collisions.

    With --merge, the SRDF's disabled pairs become exactly the XRDF's ignore pairs: pairs
    still ignored are kept untouched, pairs no longer ignored are removed (a warning each),
    new ones are added (reasons from --report, else User); everything else in the file is
    kept byte for byte. Without --merge a new SRDF holds only the disable_collisions.

    \b
    Examples:
      xrdf report robot.xrdf --urdf robot.urdf -f json -o report.json --write-mask robot.masked.xrdf
      xrdf export srdf robot.masked.xrdf --merge robot.srdf --urdf robot.urdf \\
          --report report.json -o robot.synced.srdf
    """
    from ...export.srdf import load_report_reasons, sync_srdf

    inputs = [xrdf, merge, report, urdf]
    refuse_two_stdin({"XRDF": [xrdf], "--merge": [merge]})
    if output is not None:
        refuse_input_overwrite(output, inputs)
    try:
        x = load_xrdf_input(xrdf)
        robot = _load_robot(urdf, package_path, xacro_arg) if urdf is not None else None
        tree = None if robot is None else robot.tree
        reasons = load_report_reasons(report) if report is not None else None
        existing = _read_srdf(merge) if merge is not None else None
        result = sync_srdf(
            x,
            existing,
            urdf=tree,
            robot_name=robot_name if tree is not None else robot_name or _stem(xrdf),
            reasons=reasons,
            srdf_path=str(merge or output or "<srdf>"),
        )
    except XrdfToolsError as e:
        fail(e)
    echo_diagnostics([*(robot.warnings if robot is not None else ()), *result.diagnostics], fmt)
    write_output(result.data, output)


def _stem(xrdf: Path) -> str:
    """The default robot name: the XRDF's file name up to its first dot."""
    return "robot" if str(xrdf) == "-" else xrdf.stem.split(".")[0]


def _read_srdf(path: Path) -> bytes:
    from ...util.fileio import read_input_bytes

    try:
        return read_input_bytes(path, what="SRDF file", allow_stdin=True)
    except XrdfToolsError as e:
        fail(e)


@app.command("xrdf", short_help="Rewrite an XRDF for its reader (e.g. 2.0 → 1.0).")
def xrdf_for_target(
    xrdf: XrdfArgument,
    target: Annotated[
        str | None,
        typer_option(
            target_option(
                "Chooses the version and lints the result for that reader (nothing is written "
                "when it would refuse the file). Default: none (XRDF 1.0, not linted)."
            )
        ),
    ] = None,
    format_version: Annotated[
        str | None,
        typer_option(
            format_version_option(
                "what the target loads; without --target, 1.0 (every reader loads it)."
            )
        ),
    ] = None,
    output: OutputOption = None,
    fmt: FormatOption = OutputFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Rewrite an XRDF for the reader that will load it (e.g. a 2.0 file as 1.0 for cuRobo).

    Everything the version change cannot carry over is reported; the input is never
    overwritten. With --target the result is also linted for that reader (as `xrdf lint
    --target`, without a URDF): when the reader would refuse it or silently load something
    else (cuRobo: no tool_frames, no self_collision), its errors are listed, nothing is
    written and the exit code is 1.

    \b
    Examples:
      xrdf export xrdf robot_2_0.xrdf --target curobo -o robot.xrdf
      xrdf export xrdf robot.xrdf --format-version 2.0 -o robot_2_0.xrdf
    """
    from ...export.curobo import for_target
    from ...xrdf.io import dump_xrdf

    if output is not None:
        refuse_input_overwrite(output, [xrdf])
    try:
        x, diags = for_target(load_xrdf_input(xrdf), target, format_version)
    except XrdfToolsError as e:
        fail(e)
    text = dump_xrdf(x)
    refused = _reader_errors(text, target, output) if target is not None else []
    echo_diagnostics([*diags, *refused], fmt)
    if refused:
        fail(
            f"not written: {target} would not load it as it is ({len(refused)} error(s) listed "
            "above); fix the input, or rewrite it without --target",
            EXIT_FINDINGS,
        )
    write_output(text, output)


def _reader_errors(text: str, target: str, output: Path | None) -> list[Diagnostic]:
    """The errors of linting the rewritten ``text`` for ``target`` (no URDF)."""
    from ...lint import lint_text

    label = str(output) if output is not None and not is_stdio(output) else "<stdout>"
    found = lint_text(text, label, target=target)
    return [d for d in found if d.severity is Severity.ERROR]
