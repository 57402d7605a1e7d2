"""``xrdf inspect``: what a URDF/xacro (+ SRDF) holds and what ``xrdf convert`` would pick.

Exit codes: 0 shown; 2 usage or input error (unreadable URDF, xacro or SRDF).
"""

from __future__ import annotations

import json
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ...util.errors import XrdfToolsError
from .options import split_names
from .plain import echo, timed
from .typer_common import (
    ChainOption,
    GroupOption,
    JointsOption,
    PackagePathOption,
    QuietOption,
    StateOption,
    ToolFrameOption,
    VerboseOption,
    XacroArgOption,
    fail,
)


class InspectFormat(str, Enum):
    text = "text"
    json = "json"


def command(
    robot: Annotated[
        Path,
        typer.Argument(
            metavar="ROBOT.urdf|xacro",
            help="The robot: ROBOT.urdf, ROBOT.urdf.xacro or ROBOT.xacro (xacro is expanded "
            "without ROS; it evaluates Python, so only inspect files you trust).",
            show_default=False,
        ),
    ],
    srdf: Annotated[
        Path | None,
        typer.Option("--srdf", help="MoveIt SRDF: its groups, and the default choice with it."),
    ] = None,
    group: GroupOption = None,
    chain: ChainOption = None,
    joints: JointsOption = None,
    state: StateOption = None,
    tool_frame: ToolFrameOption = None,
    xacro_arg: XacroArgOption = None,
    package_path: PackagePathOption = None,
    fmt: Annotated[
        InspectFormat,
        typer.Option(
            "--format",
            "-f",
            help="text (a tree for people) or json (stable keys, docs/inspect.md).",
        ),
    ] = InspectFormat.text,
    quiet: QuietOption = False,
    verbose: VerboseOption = False,
) -> None:
    """Show a robot's links, joints, chains and SRDF groups, and the c-space and tool frame
    `xrdf convert` would pick — before converting.

    The tree lists every joint as `joint (type [lower, upper], …) → child link`: mimic
    joints name the joint they follow, joints of the default c-space are numbered
    (`c-space #3`), and wheels, grippers and head/sensor joints that the default leaves out
    say so; '·' marks a link without collision geometry (it gets no spheres). The chains
    section lists, per leaf, the actuated joints from the root (the value for `--chain
    ROOT:LEAF`); the last section is exactly what `xrdf convert ROBOT [--srdf S]` would choose,
    and why. Give convert's --group, --chain, --joints, --state or --tool-frame to see what
    it picks with them (the tree numbers that c-space). Only the URDF/SRDF XML is read: no
    mesh is loaded.

    \b
    Examples:
      xrdf inspect tiago.urdf
      xrdf inspect panda.urdf --srdf panda.srdf
      xrdf inspect talos.urdf --srdf talos.srdf --group l_arm --group r_arm
      xrdf inspect ur5_robot.urdf --format json | jq '.default.cspace'
    """
    from ...convert.core import ConvertOptions
    from ...convert.inspect import inspect_robot
    from ...convert.inspect_text import render_inspection
    from ...convert.sources.cspace import parse_chain
    from .plain import load_robot_option

    try:
        choice = ConvertOptions(
            groups=tuple(group or ()),
            chains=tuple(
                parse_chain(c) for c in split_names(chain, "--chain", "BASE_LINK:TIP_LINK[,...]")
            ),
            joints=tuple(split_names(joints, "--joints", "JOINT[,JOINT...]")),
            state=state,
            tool_frames=tuple(tool_frame or ()),
        )
        with timed("inspect"):
            loaded = load_robot_option(robot, xacro_arg, package_path, srdf)
            result = inspect_robot(loaded, srdf, choice)
    except XrdfToolsError as e:
        fail(e)
    if fmt is InspectFormat.json:
        echo(json.dumps(result.to_dict(), indent=2, ensure_ascii=False))
    else:
        echo(render_inspection(result), nl=False)
