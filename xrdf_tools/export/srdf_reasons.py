"""SRDF ``reason`` per frame pair from an ``xrdf report --format json`` document: the reasons
``xrdf export srdf --report`` gives the pairs it adds (:func:`xrdf_tools.export.srdf.sync_srdf`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..util.errors import SourceError

__all__ = ["REPORT_REASONS", "USER", "Pair", "load_report_reasons", "reasons_from_report"]

USER = "User"
#: ``xrdf report`` pair classification → SRDF ``reason`` (MoveIt Setup Assistant names).
REPORT_REASONS: Mapping[str, str] = {
    "adjacent": "Adjacent",
    "default": "Default",
    "always": "Always",
    "never": "Never",
}
_ALWAYS_RATE = 0.95  # same threshold as xrdf_tools.report.ALWAYS_RATE (not imported: numpy)

Pair = frozenset[str]


def _reason_of(p: Mapping[str, Any]) -> str:
    """``classification`` when present, else derived from the same fields the report uses."""
    cls = p.get("classification")
    if isinstance(cls, str):
        return REPORT_REASONS.get(cls, USER)
    rate, hits = p.get("rate"), p.get("hits")
    clearance = p.get("default_clearance")
    if p.get("adjacent") is True:
        return "Adjacent"
    if isinstance(clearance, (int, float)) and clearance < 0:
        return "Default"
    if isinstance(rate, (int, float)) and rate > _ALWAYS_RATE:
        return "Always"
    if hits == 0:
        return "Never"
    return USER


def reasons_from_report(data: Any, path: str = "<report>") -> dict[Pair, str]:
    """SRDF reasons per frame pair from ``xrdf report --format json`` data.

    ``classification`` adjacent/default/always/never → ``Adjacent``/``Default``/``Always``/
    ``Never``; ``sometimes`` (ignored although seen colliding: a user decision) → ``User``.
    Without ``classification`` the reason is derived in the report's own order: ``adjacent``
    true, ``default_clearance`` < 0, ``rate`` > 0.95, ``hits`` == 0, else ``User``. Pairs the
    report does not list (frames without spheres) get ``User`` from :func:`sync_srdf`.
    """
    pairs = data.get("pairs") if isinstance(data, Mapping) else None
    if not isinstance(pairs, list):
        raise SourceError(
            "not an 'xrdf report --format json' document (no 'pairs' list)", path=path
        )
    out: dict[Pair, str] = {}
    for p in pairs:
        a = p.get("frame_a") if isinstance(p, Mapping) else None
        b = p.get("frame_b") if isinstance(p, Mapping) else None
        if not (isinstance(a, str) and isinstance(b, str)):
            raise SourceError("a report pair lacks 'frame_a'/'frame_b'", path=path)
        out[frozenset((a, b))] = _reason_of(p)
    return out


def load_report_reasons(path: str | os.PathLike[str]) -> dict[Pair, str]:
    """:func:`reasons_from_report` of a JSON file; one-line :class:`SourceError` on failure."""
    p = os.fspath(path)
    try:
        data = json.loads(Path(p).read_bytes())
    except OSError as e:
        raise SourceError(f"cannot read report: {e.strerror or e}", path=p) from None
    except ValueError as e:
        raise SourceError(f"the report is not JSON: {e}", path=p) from None
    return reasons_from_report(data, p)
