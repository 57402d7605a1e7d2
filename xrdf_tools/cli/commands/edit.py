"""`xrdf edit`: edit spheres, the self-collision mask and default positions in a browser."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ...util.errors import XrdfToolsError
from ...util.extras import FIT, require
from ...util.numbers import REPORT_SAMPLES
from .options import ROBOT_URDF
from .options import configs as configs_option
from .options import seed as seed_option
from .plain import (
    OutputFormat,
    check_robot_overwrite,
    detail,
    echo,
    is_stdio,
    load_robot_option,
    timed,
)
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    echo_diagnostics,
    fail,
    load_xrdf_input,
    note,
    refuse_input_overwrite,
    typer_option,
)

if TYPE_CHECKING:
    from ...robot.core import Robot
    from ...xrdf.model import Xrdf

LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1")

#: The draft's diagnostics that say the c-space or the tool frame was guessed (their messages
#: name ``xrdf convert``'s options, which ``xrdf edit`` does not have).
GUESSED = frozenset({"convert-chosen-group", "convert-chosen-tool-frame"})


def _draft(robot: Robot, srdf: Path | None, seed: int, samples: int) -> Xrdf:
    """The one-command draft: ``xrdf convert URDF [--srdf S] --fit-spheres``."""
    from ...convert.core import ConvertOptions
    from ...convert.pipeline import FitOptions, MaskOptions, convert_robot

    result = convert_robot(
        robot,
        ConvertOptions(srdf=srdf),
        fit=FitOptions(seed=seed),
        mask=MaskOptions(samples=samples, seed=seed),
        lint=False,
    )
    echo_diagnostics(
        [d for d in result.diagnostics if d.severity.name != "INFO"], OutputFormat.text
    )
    if {d.rule for d in result.diagnostics} & GUESSED:
        note(
            "the draft's c-space and tool frames were guessed: change them in the page's "
            "C-space panel (--group, --chain, --joints and --tool-frame are `xrdf convert`'s: "
            "draft with it and edit that file to use them)"
        )
    return result.xrdf


def _warn_refused(why: str) -> None:
    """A request the page refused (another web page, a rebinding name) or a malformed one it
    dropped: said even with -q, once per kind."""
    echo(f"warning: {why}", err=True)


def _checked_target(
    xrdf_file: Path | None,
    urdf: Path | None,
    output: Path | None,
    srdf: Path | None,
    configs: Path | None,
    host: str,
) -> tuple[Path, Path]:
    """The file Save writes and the URDF, once the options, the extra and the address are
    checked (each refusal one line, exit 2), before the robot is read and a draft fitted."""
    try:
        require(("viser", *FIT), "edit", "xrdf edit")
    except XrdfToolsError as e:
        fail(e)
    if urdf is None:
        fail("--urdf is required: the URDF (or xacro) of the robot")
    if xrdf_file is None and output is None:
        fail("give ROBOT.xrdf to edit, or -o NEW.xrdf to start from a draft of the URDF")
    if xrdf_file is not None and srdf is not None:
        fail("--srdf is read only for a draft (-o without ROBOT.xrdf); the XRDF has its mask")
    if is_stdio(xrdf_file) or is_stdio(output):
        fail("xrdf edit needs files (not '-'): Save writes the XRDF back")
    target = output if output is not None else xrdf_file
    assert target is not None
    if output is not None:
        refuse_input_overwrite(output, [urdf, srdf, configs])
        if xrdf_file is None and output.exists():
            fail(f"{output} exists; edit it with: xrdf edit {output} --urdf {urdf}")
    try:
        from ...edit.guard import check_address  # numpy: only for this command

        check_address(host)
    except XrdfToolsError as e:
        fail(e)
    return target, urdf


def command(
    xrdf_file: Annotated[
        Path | None,
        typer.Argument(
            metavar="ROBOT.xrdf",
            help="XRDF to edit (omit it with -o to start from a draft of the URDF).",
            show_default=False,
        ),
    ] = None,
    urdf: Annotated[Path | None, typer_option(ROBOT_URDF)] = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output",
            "-o",
            help="Where Save writes (default: ROBOT.xrdf itself). Without ROBOT.xrdf: start "
            "from the draft `xrdf convert URDF --fit-spheres` makes.",
        ),
    ] = None,
    srdf: Annotated[
        Path | None,
        typer.Option("--srdf", help="MoveIt SRDF for the draft (with -o and no ROBOT.xrdf)."),
    ] = None,
    configs: Annotated[
        Path | None,
        typer_option(
            configs_option("Configurations to pose the robot in, picked by number on the page.")
        ),
    ] = None,
    port: Annotated[
        int,
        typer.Option(
            "--port", min=0, max=65535, help="TCP port; when it is taken, the next free one."
        ),
    ] = 8080,
    host: Annotated[
        str,
        typer.Option("--host", help="Address to listen on. Anyone who can reach it can edit."),
    ] = "127.0.0.1",
    no_browser: Annotated[
        bool, typer.Option("--no-browser", help="Do not open a browser; print the address.")
    ] = False,
    readonly: Annotated[
        bool, typer.Option("--readonly", help="Look and try edits; saving is disabled.")
    ] = False,
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            "-n",
            min=1,
            help="Configurations sampled for the draft's mask (-o without XRDF) and, to start "
            "with, by the page's report (as `xrdf report --samples`).",
        ),
    ] = REPORT_SAMPLES,
    seed: Annotated[int, typer_option(seed_option("the draft's fit and samples"))] = 0,
    package_path: PackagePathOption = None,
    xacro_arg: XacroArgOption = None,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Edit an XRDF in the browser: move, resize, add, delete, connect, scale and refit
    spheres; pose the robot and see its self-collisions live; toggle mask pairs, run a report
    and apply its mask; set buffers and default positions; choose the c-space joints, their
    acceleration and jerk limits, and the tool frames. Undo/redo; Save shows the `xrdf diff`
    first.

    Nothing is written until you press Save, and only to ROBOT.xrdf (or -o). Stop with Ctrl-C.
    Needs the edit extra: pip install "xrdf-tools[edit]".

    \b
    Examples:
      xrdf edit robot.xrdf --urdf robot.urdf
      xrdf edit --urdf robot.urdf --srdf robot.srdf -o robot.xrdf
    """
    target, urdf = _checked_target(xrdf_file, urdf, output, srdf, configs, host)
    if host not in LOCAL_HOSTS:
        typer.echo(
            f"warning: listening on {host}: anyone who can reach port {port} can edit and save "
            f"{target}",
            err=True,
        )
    try:
        from ...edit.state import EditState
        from ...robot.packages import parse_package_paths
        from ...xrdf.model import Xrdf

        robot = load_robot_option(urdf, xacro_arg, package_path, srdf)
        check_robot_overwrite(output, robot)
        if xrdf_file is None:
            with timed("draft"):
                note(f"drafting {output} from {urdf} (fitting spheres, sampling the mask)")
                doc = _draft(robot, srdf, seed, samples)
            state = EditState.start(doc, saved=Xrdf())
        else:
            state = EditState.start(load_xrdf_input(xrdf_file))
        from ...edit.page import EditorPage

        with timed("page"):
            page = EditorPage(
                robot,
                state,
                target=target,
                host=host,
                port=port,
                readonly=readonly,
                configs=configs,
                package_paths=parse_package_paths(package_path),
                report_samples=samples,
                on_refused=_warn_refused,
            )
    except XrdfToolsError as e:
        fail(e)
    except OSError as e:
        fail(f"cannot serve on {host}:{port}: {e.strerror or e}")
    try:  # from here on, Ctrl-C is the way to stop: exit 0 wherever it lands
        echo_diagnostics(page.diagnostics, OutputFormat.text)
        url = page.url
        note(f"editing {target} at {url} (Ctrl-C stops{'; read-only' if readonly else ''})")
        if not no_browser:
            import webbrowser

            detail("opening a browser")
            webbrowser.open(url)
        page.serve_forever()
    except KeyboardInterrupt:
        page.close()
    if page.state.dirty:
        note(f"stopped; unsaved changes to {target} were discarded")
