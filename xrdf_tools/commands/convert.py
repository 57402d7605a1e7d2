"""``xrdf convert``: URDF/xacro + MoveIt SRDF or cuRobo config → canonical XRDF.

Exit codes: 0 written (diagnostics are only notes), 1 the result fails lint, ``--strict`` found
a fallback, or ``--check`` found a difference; 2 usage or input error.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from ..diagnostics import Diagnostic, Severity
from ..errors import XrdfToolsError
from .common import (
    EXIT_FINDINGS,
    OutputFormat,
    fail,
    has_failures,
    refuse_input_overwrite,
    render_diagnostics,
)

if TYPE_CHECKING:
    from ..model import Xrdf


def _pairs(values: list[str] | None, parse: Any) -> dict[str, str]:
    out: dict[str, str] = {}
    for v in values or []:
        k, val = parse(v)
        out[k] = val
    return out


def command(
    robot: Annotated[
        Path,
        typer.Argument(
            help="The robot: ROBOT.urdf, ROBOT.urdf.xacro or ROBOT.xacro (xacro is expanded "
            "without ROS; it evaluates Python, so only convert files you trust).",
            show_default=False,
        ),
    ],
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
    group: Annotated[
        str | None, typer.Option("--group", help="SRDF planning group (default: see docs).")
    ] = None,
    state: Annotated[
        str | None, typer.Option("--state", help="SRDF group_state for default positions.")
    ] = None,
    tool_frame: Annotated[
        list[str] | None,
        typer.Option(
            "--tool-frame", help="Tool frame (repeatable; the first is the end effector)."
        ),
    ] = None,
    acceleration: Annotated[
        float | None,
        typer.Option("--acceleration", help="Acceleration limit for joints the inputs lack."),
    ] = None,
    jerk: Annotated[
        float | None, typer.Option("--jerk", help="Jerk limit for joints the inputs lack.")
    ] = None,
    xacro_arg: Annotated[
        list[str] | None,
        typer.Option("--xacro-arg", help="xacro argument NAME:=VALUE (repeatable)."),
    ] = None,
    package_path: Annotated[
        list[str] | None,
        typer.Option("--package-path", help="ROS package location NAME=DIR (repeatable)."),
    ] = None,
    format_version: Annotated[
        str | None,
        typer.Option(
            "--format-version",
            help="XRDF version to write: 1.0 or 2.0. Default: 1.0, the version every reader "
            "loads (2.0 only when the robot needs it; the message says which readers drop it).",
            show_default=False,
        ),
    ] = None,
    target: Annotated[
        str | None,
        typer.Option(
            "--target",
            help="The program that will load the XRDF: curobo (cuRobo, Isaac ROS cuMotion; "
            "1.0 only), cumotion (cuMotion library) or isaac-sim (Robot Description Editor). "
            "Chooses the version and lints the result for that reader.",
            show_default=False,
        ),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option("-o", "--output", help="Write here (atomically) instead of stdout."),
    ] = None,
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
    no_lint: Annotated[
        bool, typer.Option("--no-lint", help="Skip linting the result against the URDF.")
    ] = False,
    fmt: Annotated[
        OutputFormat, typer.Option("--format", help="Diagnostics format (on stderr).")
    ] = OutputFormat.text,
) -> None:
    """Convert a URDF/xacro plus an SRDF or cuRobo config to XRDF; report every guess."""
    from ..convert import ConvertOptions, convert
    from ..packages import parse_package_path
    from ..sources.xacro_source import load_robot, parse_xacro_arg
    from ..xrdf_io import dump_xrdf

    if format_version not in (None, "1.0", "2.0"):
        fail(f"--format-version must be 1.0 or 2.0, not '{format_version}'")
    if check and output is None:
        fail("--check needs -o FILE (the file to compare with)")
    inputs = [robot, srdf, joint_limits, curobo]
    if output is not None and not check:
        refuse_input_overwrite(output, inputs)
    try:
        pkgs = _pairs(package_path, parse_package_path)
        xargs = _pairs(xacro_arg, parse_xacro_arg)
        options = ConvertOptions(
            srdf=srdf,
            joint_limits=joint_limits,
            curobo=curobo,
            group=group,
            state=state,
            tool_frames=tuple(tool_frame or ()),
            acceleration=acceleration,
            jerk=jerk,
            format_version=format_version,
            target=target,
        )
        urdf, urdf_text = load_robot(robot, xacro_args=xargs, package_paths=pkgs)
        x, diags = convert(urdf, options)
        if fit_spheres:
            x, more = _fit(x, robot, urdf, pkgs, xargs)
            diags = [d for d in diags if d.rule != "convert-no-spheres"] + more
        text = dump_xrdf(x)
        label = str(output) if output is not None else "<stdout>"
        lint_diags = [] if no_lint else _lint(text, robot, urdf_text, label, target)
    except XrdfToolsError as e:
        fail(e)
    if any(d.rule == "convert-no-spheres" for d in diags):
        # One loud "no spheres at all" says it; a per-link lint line for every link is noise.
        lint_diags = [d for d in lint_diags if d.rule != "mesh-without-spheres"]
    all_diags = [*diags, *lint_diags]
    if all_diags:
        typer.echo(render_diagnostics(all_diags, fmt), nl=False, err=True)
    errors = [d for d in lint_diags if d.severity is Severity.ERROR]
    if errors:
        fail(
            f"the converted XRDF has {len(errors)} lint error(s) against the URDF (listed "
            "above); fix the inputs or pass the missing values on the command line",
            EXIT_FINDINGS,
        )
    if strict and has_failures(diags, strict=True):
        n = sum(1 for d in diags if d.severity is not Severity.INFO)
        fail(f"--strict: {n} value(s) were guessed or dropped (listed above)", EXIT_FINDINGS)

    if check:
        assert output is not None
        from ..urdf_source import root_link

        _check(output, x, root_link(urdf))
        return
    if output is None:
        typer.echo(text, nl=False)
        return
    from ..yaml_io import write_atomic

    try:
        write_atomic(output, text)
    except OSError as e:
        fail(f"{output}: cannot write: {e.strerror or e}")


def _check(output: Path, x: Xrdf, root_frame: str) -> None:
    from ..diff import diff_xrdf
    from ..xrdf_io import load_xrdf

    if not output.exists():
        fail(f"{output}: does not exist; run without --check to create it", EXIT_FINDINGS)
    try:
        existing = load_xrdf(output)
    except XrdfToolsError as e:
        fail(e, EXIT_FINDINGS)
    result = diff_xrdf(existing, x, root_frame=root_frame)
    if result.is_equal:
        typer.echo(f"{output}: up to date", err=True)
        return
    typer.echo(_render_diff(result), nl=False)
    fail(
        f"{output}: out of date ({len(result.changes)} semantic difference(s) listed above); "
        "re-run without --check to update it",
        EXIT_FINDINGS,
    )


def _render_diff(result: Any) -> str:
    from ..diff_render import render_text

    return render_text(result)


def _lint(
    text: str, robot: Path, urdf_text: str | None, label: str, target: str | None
) -> list[Diagnostic]:
    """Lint the written XRDF ``text`` against the URDF (the expanded one for xacro input).

    ``label`` names the output in the diagnostics (the -o path, or ``<stdout>``).
    """
    import tempfile

    from ..lint import lint_text

    if urdf_text is None:
        return lint_text(text, label, urdf=robot, target=target)
    with tempfile.TemporaryDirectory(prefix="xrdf-convert-") as tmp:
        expanded = Path(tmp) / (robot.name.removesuffix(".xacro") + ".urdf")
        expanded.write_text(urdf_text, encoding="utf-8")
        return lint_text(text, label, urdf=expanded, target=target)


def _fit(
    x: Xrdf, robot: Path, urdf: Any, pkgs: dict[str, str], xargs: dict[str, str]
) -> tuple[Xrdf, list[Diagnostic]]:
    """Fit spheres to the links that have none (lazy import; exit 2 when unavailable)."""
    try:
        from ..spheres import fit_link_spheres
    except ImportError:
        fail("--fit-spheres: sphere fitting is not available in this installation")
    if xargs:
        fail("--fit-spheres does not support --xacro-arg yet; expand the xacro to a URDF first")
    from ..convert import with_spheres
    from ..sources import RobotTree

    have = dict(x.world_collision_spheres())
    links = None
    if have:
        links = [link for link in RobotTree.from_urdf(urdf).links if link not in have]
    fitted, diags = fit_link_spheres(os.fspath(robot), links=links, package_paths=pkgs)
    merged: dict[str, Any] = {k: list(v) for k, v in have.items()}
    for link, spheres in fitted.items():
        merged.setdefault(link, []).extend(spheres)
    return with_spheres(x, merged), list(diags)
