"""Configurations for `xrdf viz` and `xrdf report`: sampled in c-space, or read from a file.

Both return full actuated configurations [B, n] (:attr:`KinematicModel.actuated_joints`
order); joints outside the c-space stay at their default
(:func:`xrdf_tools.robot.kinematics.full_configuration`).

Configuration files (``--configs FILE``), one configuration per row:

* ``.npy``: a [B, k] (or [k]) array;
* ``.json`` / ``.yaml`` / ``.yml``: a list of rows, each a list of numbers or a mapping
  ``{joint_name: value}`` (joints left out keep their default);
* anything else: text, numbers separated by commas or whitespace, ``#`` comments, and an
  optional header row of joint names.

Rows without names have k = the c-space size (c-space order) or k = the number of actuated
joints (actuated order).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..robot.binding import cspace_indices
from ..util.arrays import FloatArray
from ..util.errors import SourceError, XrdfToolsError
from ..util.fileio import max_input_bytes, read_input_bytes, read_input_text
from ..util.numbers import bound_problem
from ..util.text import name_list
from ..xrdf.model import Xrdf
from ..yaml.io import YMap, YSeq, parse_yaml, to_python

if TYPE_CHECKING:
    from ..robot.kinematics import KinematicModel


MAX_SAMPLES = 100_000


def load_cspace_configurations(
    path: str | os.PathLike[str], kin: KinematicModel, xrdf: Xrdf
) -> FloatArray:
    """Configurations [B, n_c] in c-space order (:func:`~xrdf_tools.robot.binding.cspace_joints`)
    from a file.

    Same formats as :func:`load_configurations`, no row cap; values given for joints outside
    the c-space are not kept (those joints stay at their defaults).
    """
    q = load_configurations(path, kin, xrdf, max_rows=None)
    _, idx = cspace_indices(kin, xrdf)
    return np.ascontiguousarray(q[:, idx])


def sample_configurations(
    kin: KinematicModel, xrdf: Xrdf, n: int, seed: int | None = 0
) -> FloatArray:
    """``n`` configurations [n, n_actuated] drawn uniformly within the c-space joint limits."""
    from ..robot.kinematics import full_configuration
    from .sampling import sample_uniform

    if n < 0 or n > MAX_SAMPLES:
        raise SourceError(f"--samples must be between 0 and {MAX_SAMPLES}, got {n}")
    names, idx = cspace_indices(kin, xrdf)
    for j, k in zip(names, idx, strict=True):
        if not kin.lower[k] <= kin.upper[k]:
            raise SourceError(
                f"joint '{j}' cannot be sampled: lower limit {kin.lower[k]} > upper limit "
                f"{kin.upper[k]}",
                path=kin.source_path,
            )
    qc = sample_uniform(kin.lower[idx], kin.upper[idx], n, seed)
    return full_configuration(kin, names, qc, xrdf.default_joint_positions).reshape(
        n, kin.n_actuated
    )


def load_configurations(
    path: str | os.PathLike[str],
    kin: KinematicModel,
    xrdf: Xrdf,
    *,
    max_rows: int | None = MAX_SAMPLES,
) -> FloatArray:
    """Configurations [B, n_actuated] from a file (formats in the module docstring).

    ``max_rows`` caps the number of rows (None: no cap). Raises :class:`SourceError` naming the
    file (and line) for anything unreadable.
    """
    p = Path(path)
    spath = os.fspath(path)
    limit = 4 * max_input_bytes()  # tables of many configurations are larger than robot files
    if p.suffix.lower() == ".npy":
        raw = read_input_bytes(p, what="configurations file", error=SourceError, max_bytes=limit)
        return _assemble(_npy_rows(raw, spath), None, kin, xrdf, spath, max_rows=max_rows)
    text = read_input_text(p, what="configurations file", error=SourceError, max_bytes=limit)
    if p.suffix.lower() in (".json", ".yaml", ".yml"):
        data, rows_line, row_lines = _load_structured(text, p.suffix.lower(), spath)
        if not isinstance(data, list):
            empty = not text.strip()
            raise SourceError(
                "expected a list of configurations (lists of numbers or {joint: value} maps)"
                + ("; the file is empty" if empty else ""),
                path=spath,
                line=rows_line if rows_line is not None else _first_content_line(text),
            )
        return _assemble(data, None, kin, xrdf, spath, row_lines, max_rows=max_rows)
    header, header_line, rows, lines = _parse_text(text, spath)
    return _assemble(rows, header, kin, xrdf, spath, lines, header_line, max_rows=max_rows)


def _npy_rows(data: bytes, spath: str) -> list[Any]:
    """Rows of a ``.npy`` array (no pickles; a damaged file is a :class:`SourceError`)."""
    import io

    try:
        arr = np.atleast_2d(np.asarray(np.load(io.BytesIO(data), allow_pickle=False), float))
    except (ValueError, TypeError, OSError, EOFError) as e:
        detail = " ".join(str(e).split()) or type(e).__name__
        raise SourceError(f"not a numeric .npy array: {detail}", path=spath) from None
    if arr.ndim != 2:
        raise SourceError(
            f"a .npy array of configurations must be [B, k] or [k], not {list(arr.shape)}",
            path=spath,
        )
    rows: list[Any] = arr.tolist()
    return rows


def _load_structured(text: str, suffix: str, spath: str) -> tuple[Any, int | None, list[int]]:
    """The configurations of a JSON or YAML file (the list itself, or the ``configurations``
    entry of a mapping), the line of that list and the line of each row (YAML only: JSON
    keeps no positions)."""
    if suffix == ".json":
        try:
            data = json.loads(text)
        except json.JSONDecodeError as e:
            raise SourceError(
                f"invalid JSON: {e.msg}", path=spath, line=e.lineno, col=e.colno
            ) from None
        except RecursionError:
            raise SourceError("invalid JSON: nested too deeply", path=spath) from None
        if isinstance(data, Mapping) and "configurations" in data:
            data = data["configurations"]
        return data, None, []
    try:
        node = parse_yaml(text, spath).root
    except XrdfToolsError as e:
        raise SourceError(e.message, path=spath, line=e.line, col=e.col) from None
    if isinstance(node, YMap) and node.get("configurations") is not None:
        node = node.get("configurations")
    rows = node.items if isinstance(node, YSeq) else ()
    return to_python(node), (node.line if node is not None else None), [r.line for r in rows]


_SPLIT = re.compile(r"[,\s;]+")


def _parse_text(
    text: str, spath: str
) -> tuple[list[str] | None, int | None, list[list[float]], list[int]]:
    header: list[str] | None = None
    header_line: int | None = None
    rows: list[list[float]] = []
    lines: list[int] = []
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        tokens = [t for t in _SPLIT.split(line) if t]
        try:
            rows.append([float(t) for t in tokens])
            lines.append(lineno)
        except ValueError:
            if header is None and not rows:
                header, header_line = tokens, lineno
                continue
            bad = next(t for t in tokens if not _is_float(t))
            raise SourceError(f"'{bad}' is not a number", path=spath, line=lineno) from None
    return header, header_line, rows, lines


def _is_float(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _assemble(
    rows: Sequence[Any],
    header: Sequence[str] | None,
    kin: KinematicModel,
    xrdf: Xrdf,
    spath: str,
    lines: Sequence[int] | None = None,
    header_line: int | None = None,
    *,
    max_rows: int | None = MAX_SAMPLES,
) -> FloatArray:
    from ..robot.kinematics import default_configuration

    if max_rows is not None and len(rows) > max_rows:
        raise SourceError(f"too many configurations ({len(rows)} > {max_rows})", path=spath)
    if not rows:  # nothing checked would read as "never colliding" for every pair
        raise SourceError(
            "the file holds no configuration (one per row"
            + (", below the header of joint names)" if header is not None else ")"),
            path=spath,
            line=header_line if header_line is not None else 1 if lines is not None else None,
        )
    q0 = default_configuration(kin, xrdf.default_joint_positions)
    cspace, _ = cspace_indices(kin, xrdf)
    out = np.repeat(q0[None, :], len(rows), axis=0)

    def line_of(k: int) -> int | None:
        return lines[k] if lines is not None and k < len(lines) else None

    def columns(names: Sequence[str], line: int | None) -> list[int]:
        try:
            return [kin.actuated_index(str(n)) for n in names]
        except XrdfToolsError as e:
            raise SourceError(e.message, path=spath, line=line) from None

    header_idx = columns(header, header_line) if header is not None else None
    for k, row in enumerate(rows):
        if isinstance(row, Mapping):
            idx = columns(list(row), line_of(k))
            values: list[Any] = list(row.values())
        elif isinstance(row, (list, tuple)):
            values = list(row)
            if header_idx is not None:
                idx = header_idx
            elif len(values) == len(cspace):
                idx = columns(cspace, line_of(k))
            elif len(values) == kin.n_actuated:
                idx = list(range(kin.n_actuated))
            else:
                raise SourceError(
                    f"configuration {k} has {len(values)} values; expected {len(cspace)} "
                    f"(c-space: {name_list(cspace, 12)}) or {kin.n_actuated} (all actuated joints)",
                    path=spath,
                    line=line_of(k),
                )
        else:
            raise SourceError(
                f"configuration {k} must be a list of numbers or a {{joint: value}} map",
                path=spath,
                line=line_of(k),
            )
        if len(values) != len(idx):
            raise SourceError(
                f"configuration {k} has {len(values)} values for {len(idx)} named joints",
                path=spath,
                line=line_of(k),
            )
        out[k, idx] = _row_values(values, k, spath, line_of(k))
    return out


def _row_values(values: Sequence[Any], k: int, path: str, line: int | None) -> FloatArray:
    """Configuration ``k``'s values as floats, each a number within the bounds every number
    read keeps (:mod:`xrdf_tools.util.numbers`; ``float()`` of a 400-digit integer raises)."""
    for v in values:
        problem = bound_problem(v) if isinstance(v, (int, float)) else None
        if problem is not None:
            raise SourceError(f"configuration {k}: a value {problem}", path=path, line=line)
    try:
        vals = np.array([float(v) for v in values], dtype=np.float64)
    except (TypeError, ValueError):
        raise SourceError(
            f"configuration {k} holds a value that is not a number", path=path, line=line
        ) from None
    if not np.all(np.isfinite(vals)):
        raise SourceError(f"configuration {k} holds a non-finite value", path=path, line=line)
    return vals


def _first_content_line(text: str) -> int:
    """The line of the first character that is not white space (1 for an empty text)."""
    stripped = text.lstrip()
    return text.count("\n", 0, len(text) - len(stripped)) + 1 if stripped else 1
