"""One report as ``xrdf report`` asks for it: its settings, the configurations it is given, the
report itself and the XRDF with the recommended mask.

:class:`ReportRequest` holds what the command line chose; :func:`given_configurations` reads a
file of configurations in c-space order (through the robot's kinematic model);
:func:`run_report` builds the :class:`~xrdf_tools.report.Report`;
:func:`recommended_mask_yaml` is the XRDF text with the recommended ``ignore`` list.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..util.numbers import REPORT_SAMPLES
from .build import ProgressFn, self_collision_report
from .mask import recommended_xrdf
from .results import CertifyOptions, Report, Sampler

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..util.arrays import FloatArray
    from ..xrdf.model import Xrdf


@dataclass(frozen=True)
class ReportRequest:
    """What to report on: ``samples`` configurations drawn with ``sampler`` and ``seed`` (or
    the given ones), sphere ``coverage``, exact clearances below ``clearance_margin`` metres,
    ``jobs`` worker processes, ``certify`` the "never" pairs, and the default pose as MoveIt
    takes it (``moveit``); see :func:`~xrdf_tools.report.self_collision_report`."""

    samples: int = REPORT_SAMPLES
    seed: int = 0
    sampler: Sampler = "uniform"
    coverage: bool = False
    clearance_margin: float = 0.01
    jobs: int = 1
    certify: CertifyOptions | None = None
    moveit: bool = False


def given_configurations(
    robot: Robot, xrdf: Xrdf, path: str | os.PathLike[str], *, urdf_path: str
) -> FloatArray:
    """The configurations [N, n_c] of the file ``path`` (.npy or .csv) in c-space order, read
    against the robot's kinematic model. Raises :class:`~xrdf_tools.util.errors.XrdfToolsError`."""
    from ..robot.kinematics import build_kinematic_model
    from ..selfcollision.configurations import load_cspace_configurations

    kin, _ = build_kinematic_model(robot, xrdf, path=urdf_path)
    return load_cspace_configurations(path, kin, xrdf)


def run_report(
    robot: Robot,
    xrdf: Xrdf,
    request: ReportRequest,
    *,
    urdf_path: str,
    configs: FloatArray | None = None,
    progress: ProgressFn | None = None,
    certify_progress: ProgressFn | None = None,
) -> Report:
    """The self-collision report of ``request`` (of ``configs`` when given, else sampled);
    ``progress`` follows the configurations, ``certify_progress`` the pairs certified."""
    return self_collision_report(
        robot,
        xrdf,
        samples=request.samples,
        seed=request.seed,
        sampler=request.sampler,
        configs=configs,
        progress=progress,
        urdf_path=urdf_path,
        coverage=request.coverage,
        clearance_margin=request.clearance_margin,
        jobs=request.jobs,
        certify=request.certify,
        moveit=request.moveit,
        certify_progress=certify_progress,
    )


def recommended_mask_yaml(xrdf: Xrdf, report: Report) -> str:
    """The XRDF text of ``xrdf`` with the report's recommended ``ignore`` list."""
    from ..xrdf.io import dump_xrdf

    return dump_xrdf(recommended_xrdf(xrdf, report))
