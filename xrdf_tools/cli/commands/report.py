"""``xrdf report``: self-collision report over sampled (or given) configurations.

Exit codes: 0 no finding; 1 a finding of severity error (an unmasked pair always colliding or
colliding at the default pose, a given configuration in collision) or, with ``--strict``, a
warning (mask hides collisions, unknown mask frame); 2 usage or input error.

The options come from :data:`xrdf_tools.cli.commands.report_core.REPORT_OPTIONS` and what the
command does is :func:`xrdf_tools.cli.commands.report_core.run`: the fast start-up path of
``xrdf report`` reads the same table and runs the same function (without typer).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ...util.errors import XrdfToolsError
from ...util.numbers import CERTIFY_BOXES, REPORT_SAMPLES
from .report_core import (
    REPORT_OPTIONS,
    MaskPolicy,
    ReportArgs,
    ReportFormat,
    ReportPart,
    SamplerChoice,
    run,
)
from .typer_common import (
    PackagePathOption,
    QuietOption,
    VerboseOption,
    XacroArgOption,
    fail,
    progress_bar,
    typer_option,
)


def _option(name: str, **typer_only: Any) -> Any:
    return typer_option(REPORT_OPTIONS[name], **typer_only)


def command(
    xrdf_file: Annotated[
        Path,
        typer.Argument(
            metavar="ROBOT.xrdf", help="The XRDF to check ('-': stdin).", show_default=False
        ),
    ],
    urdf: Annotated[Path, _option("urdf", show_default=False)],
    samples: Annotated[int, _option("samples")] = REPORT_SAMPLES,
    seed: Annotated[int, _option("seed")] = 0,
    sampler: Annotated[SamplerChoice, _option("sampler")] = SamplerChoice.uniform,
    configs: Annotated[Path | None, _option("configs")] = None,
    output_format: Annotated[ReportFormat, _option("output_format")] = ReportFormat.text,
    output: Annotated[Path | None, _option("output")] = None,
    plot: Annotated[Path | None, _option("plot")] = None,
    write_mask: Annotated[Path | None, _option("write_mask")] = None,
    clearance_margin: Annotated[float, _option("clearance_margin")] = 0.01,
    coverage: Annotated[bool, _option("coverage")] = False,
    jobs: Annotated[int | None, _option("jobs")] = None,
    certify: Annotated[bool, _option("certify")] = False,
    certify_boxes: Annotated[int, _option("certify_boxes")] = CERTIFY_BOXES,
    certify_budget: Annotated[float | None, _option("certify_budget")] = None,
    mask_policy: Annotated[MaskPolicy, _option("mask_policy")] = MaskPolicy.sampled,
    moveit: Annotated[bool, _option("moveit")] = False,
    only: Annotated[ReportPart, _option("only")] = ReportPart.all,
    min_rate: Annotated[float, _option("min_rate")] = 0.0,
    strict: Annotated[bool, _option("strict")] = False,
    timings: Annotated[bool, _option("timings")] = False,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Sample the c-space and report, per frame pair, how often it self-collides, how the
    ignore mask treats it and what to do about it.

    Exit codes: 0 no error finding, 1 an error finding (or a warning with --strict), 2 usage
    or input error.

    \b
    Examples:
      xrdf report robot.xrdf --urdf robot.urdf
      xrdf report robot.xrdf --urdf robot.urdf -n 1000000 --plot matrix.png \\
          --write-mask robot.masked.xrdf
      xrdf report robot.xrdf --urdf robot.urdf --certify --mask-policy proven -f json -o report.json
      xrdf report robot.xrdf --urdf robot.urdf --configs trajectory.csv
    """
    args = ReportArgs(
        xrdf_file,
        urdf,
        samples,
        seed,
        sampler,
        configs,
        output_format,
        output,
        plot,
        write_mask,
        clearance_margin,
        coverage,
        jobs,
        certify,
        certify_boxes,
        certify_budget,
        mask_policy,
        moveit,
        only,
        min_rate,
        strict,
        timings,
        xacro_arg,
        package_path,
    )
    try:
        code = run(args, progress_bar)
    except XrdfToolsError as exc:
        fail(exc)
    if code:
        raise typer.Exit(code)
