"""Self-collision report: sample the c-space, count collisions per frame pair, judge the mask.

:func:`self_collision_report` answers "is my sphere model and mask right?" pair by pair: how
often each pair of frames with spheres collides, its classification (the MoveIt Setup
Assistant's: adjacent, default, always, never, sometimes), optionally a proof for the "never"
pairs, and what the ``ignore`` mask should say. Findings come back as
:class:`~xrdf_tools.diagnostics.Diagnostic` objects; rendering lives in
:mod:`xrdf_tools.report.render`.

Modules:

* :mod:`.results`: the frozen values a report is made of (:class:`Report`, :class:`PairStat`, …);
* :mod:`.verdicts`: classification rules, the "never" bound, adjacency, findings and
  :data:`RULES` (the report's rule ids);
* :mod:`.build`: :func:`self_collision_report` itself (counting, certification, coverage);
* :mod:`.mask`: the recommended mask and :func:`recommended_xrdf`;
* :mod:`.job`: one report as ``xrdf report`` asks for it (:class:`ReportRequest`, the given
  configurations, :func:`run_report`, the XRDF with the recommended mask).

Every name is importable from ``xrdf_tools.report``.
"""

from __future__ import annotations

from .build import DEFAULT_CHUNK, ProgressFn, self_collision_report
from .job import ReportRequest, given_configurations, recommended_mask_yaml, run_report
from .mask import recommended_xrdf
from .results import (
    CertifyOptions,
    Classification,
    ConfigsError,
    MaskChange,
    PairStat,
    Recommendation,
    Report,
    Sampler,
    TrajectoryHit,
)
from .verdicts import ALWAYS_RATE, RULES, adjacent_frame_pairs, never_upper_bound

__all__ = [
    "ALWAYS_RATE",
    "DEFAULT_CHUNK",
    "RULES",
    "CertifyOptions",
    "Classification",
    "ConfigsError",
    "MaskChange",
    "PairStat",
    "ProgressFn",
    "Recommendation",
    "Report",
    "ReportRequest",
    "Sampler",
    "TrajectoryHit",
    "adjacent_frame_pairs",
    "given_configurations",
    "never_upper_bound",
    "recommended_mask_yaml",
    "recommended_xrdf",
    "run_report",
    "self_collision_report",
]
