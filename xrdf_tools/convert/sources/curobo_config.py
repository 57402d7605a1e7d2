"""A cuRobo robot config as a file: parsed with its repeated keys said, its kinematics
section, the files it names (its ``collision_spheres`` file, so that no output overwrites it;
its ``urdf_path``, the robot a convert given none takes)."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ...util.errors import SourceError, XrdfToolsError
from ...util.fileio import is_file
from ...yaml.io import YamlDocument, parse_yaml, positions_of, read_text, to_python
from . import Reporter
from .curobo_keys import key_text
from .curobo_spheres import find_spheres_file

__all__ = ["config_urdf", "kinematics_of", "load_config", "referenced_files"]


def kinematics_of(data: Mapping[str, Any]) -> Mapping[str, Any] | None:
    rc = data.get("robot_cfg")
    if isinstance(rc, Mapping) and isinstance(rc.get("kinematics"), Mapping):
        return rc["kinematics"]  # type: ignore[no-any-return]
    if isinstance(data.get("kinematics"), Mapping):
        return data["kinematics"]  # type: ignore[no-any-return]
    return None


def load_config(path: str | os.PathLike[str]) -> tuple[YamlDocument, Reporter]:
    """Parse a cuRobo YAML file. A repeated key is a warning, not an error: cuRobo loads its
    configs with PyYAML, which keeps the last value (its own ``franka.yml`` repeats
    ``usd_flip_joints``), so the last value is used here too."""
    doc = parse_yaml(read_text(path), str(path))
    rep = Reporter(doc.path, positions_of(doc))
    for dup in doc.duplicates:
        rep.report(
            "convert-duplicate-key",
            f"key '{dup.key_path}' appears more than once (first on line {dup.first_line}); "
            "cuRobo's YAML loader keeps the last value, and so does this conversion",
            dup.key_path,
            line=dup.line,
        )
    return doc, rep


def referenced_files(path: str | os.PathLike[str]) -> list[Path]:
    """Files a cuRobo config reads besides itself (its ``collision_spheres`` file), so that no
    output overwrites them. Unreadable or odd configs name none (reading them reports why)."""
    try:
        doc, rep = load_config(path)
        kin = kinematics_of(to_python(doc.root) or {})
    except (XrdfToolsError, AttributeError, TypeError):
        return []
    value = kin.get("collision_spheres") if kin is not None else None
    if not isinstance(value, str):
        return []
    try:
        return [find_spheres_file(value, Path(doc.path), rep, "collision_spheres")]
    except SourceError:
        return []


def config_urdf(path: str | os.PathLike[str]) -> Path:
    """The robot a cuRobo config names in ``urdf_path``, relative to the config's folder (as
    ``export curobo`` writes it), for a convert given no robot; raises at the key saying what
    to give instead when it names no file there."""
    doc, rep = load_config(path)
    data = to_python(doc.root)
    kin = kinematics_of(data) if isinstance(data, Mapping) else None
    value = kin.get("urdf_path") if kin is not None else None
    urdf = Path(path).parent / value if isinstance(value, str) and value else None
    if urdf is not None and is_file(urdf):
        short = Path(os.path.normpath(urdf))  # without export's dir/.. when it is that file
        return short if is_file(short) and os.path.samefile(short, urdf) else urdf
    nested = isinstance(data, Mapping) and "robot_cfg" in data
    line, col = rep.position(f"{'robot_cfg.' if nested else ''}kinematics.urdf_path")
    raise SourceError(
        f"no robot given, and the config {_no_urdf(data, value, urdf)}: give ROBOT.urdf|xacro "
        "before --curobo",
        path=str(path),
        line=line,
        col=col,
    )


def _no_urdf(data: Any, value: Any, urdf: Path | None) -> str:
    """Why the config's ``urdf_path`` ``value`` (``urdf``: beside the config) is no robot."""
    if not isinstance(data, Mapping) or kinematics_of(data) is None:
        if isinstance(data, Mapping) and isinstance(data.get("cspace"), list):
            return "is a Lula robot description, which names no URDF"
        return "is no cuRobo robot configuration (no robot_cfg.kinematics to name the URDF)"
    if urdf is None:
        if value is None or value == "":
            return "names none (kinematics.urdf_path)"
        kind = "a list" if isinstance(value, list) else "a mapping"
        shown = key_text(value) if not isinstance(value, (list, Mapping)) else kind
        return f"has urdf_path {shown}, not a file name"
    there = "a directory" if os.path.isdir(urdf) else "no file"
    return f"names '{value}', {there} beside it (cuRobo's own configs name one in its assets)"
