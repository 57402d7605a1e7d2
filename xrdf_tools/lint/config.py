"""Lint configuration: ``.xrdf-lint.yaml`` or ``[tool.xrdf.lint]`` in ``pyproject.toml``.

::

    target: curobo              # the reader the files are for: curobo | cumotion | isaac-sim
    rules:                      # rule id (or prefix ending in '-') -> level
      curobo-: off              # error | warning | info | off
      unknown-key: error
    urdf:                       # glob (relative to the config file) -> URDF for those files
      "robots/ur10e/*.xrdf": robots/ur10e/ur10e.urdf

The shipped ``default.yaml`` holds the defaults; a user file is merged over it. Discovery looks
for ``.xrdf-lint.yaml`` and then a ``pyproject.toml`` with ``[tool.xrdf.lint]``, from the current
directory up to the file system root (the first hit wins).
"""

from __future__ import annotations

import fnmatch
import os
import sys
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..diagnostics import Severity
from ..util.errors import XrdfToolsError, did_you_mean
from ..util.fileio import read_input_text
from ..yaml.io import load_yaml, node_positions, parse_yaml, to_python
from ..yaml.shape import BOOL, NAME, check_shape, map_of, one_of

CONFIG_NAME = ".xrdf-lint.yaml"
LEVELS = ("error", "warning", "info", "off")
_LEVEL = one_of(NAME, BOOL, what="a level (error, warning, info or off)")
#: The structure of a ``.xrdf-lint.yaml`` (names and levels are checked by ``_parse``).
CONFIG_SHAPE = map_of(
    None,
    fields={
        "rules": map_of(
            one_of(_LEVEL, map_of(None, fields={"level": _LEVEL, "enabled": BOOL}), what="")
        ),
        "urdf": map_of(NAME, what="a mapping of XRDF path globs to URDF paths"),
        "target": NAME,
    },
    nullable=True,
    what="a mapping",
)


class ConfigError(XrdfToolsError):
    """The lint configuration cannot be used."""


@dataclass(frozen=True)
class LintConfig:
    """Severity overrides per rule (None = off), URDF globs, the target reader."""

    levels: Mapping[str, Severity | None] = field(default_factory=dict)
    urdf_map: tuple[tuple[str, str], ...] = ()
    base_dir: str = "."
    source: str | None = None
    #: The reader the files are for (a target id), or None.
    target: str | None = None
    #: ``(line, col)`` of each ``urdf_map`` value in :attr:`source` (None where unknown).
    urdf_positions: tuple[tuple[int, int] | None, ...] = ()

    def _level(self, rule: str) -> tuple[bool, Severity | None]:
        if rule in self.levels:
            return True, self.levels[rule]
        best: tuple[int, Severity | None] | None = None
        for pat, lvl in self.levels.items():
            if pat.endswith("-") and rule.startswith(pat) and (best is None or len(pat) > best[0]):
                best = (len(pat), lvl)
        return (True, best[1]) if best is not None else (False, None)

    def overrides(self, rule: str) -> bool:
        return self._level(rule)[0]

    def severity(self, rule: str, default: Severity) -> Severity | None:
        """The configured level of ``rule`` (None when turned off), else ``default``."""
        found, lvl = self._level(rule)
        return lvl if found else default

    def urdf_for(self, xrdf: Path) -> str | None:
        """The URDF mapped to ``xrdf`` by the first matching glob, or None."""
        i = self._match(xrdf)
        return None if i is None else str(Path(self.base_dir).resolve() / self.urdf_map[i][1])

    def urdf_where(self, xrdf: Path) -> tuple[str | None, int | None, int | None]:
        """Where the configuration names the URDF of ``xrdf``: ``(file, line, col)``."""
        i = self._match(xrdf)
        pos = self.urdf_positions[i] if i is not None and i < len(self.urdf_positions) else None
        return (self.source, *pos) if pos is not None else (self.source, None, None)

    def _match(self, xrdf: Path) -> int | None:
        """Index of the first ``urdf`` glob that matches ``xrdf`` (relative to the config)."""
        base = Path(self.base_dir).resolve()
        try:
            rel: str | None = xrdf.resolve().relative_to(base).as_posix()
        except ValueError:
            rel = None
        for i, (pattern, _) in enumerate(self.urdf_map):
            if (rel is not None and fnmatch.fnmatch(rel, pattern)) or fnmatch.fnmatch(
                xrdf.as_posix(), pattern
            ):
                return i
        return None


#: ``key_path -> (line, col)`` of a configuration file (empty for ``pyproject.toml``).
Positions = Mapping[str, tuple[int, int]]


def _error(message: str, source: str, positions: Positions, *key_paths: str) -> ConfigError:
    """A :class:`ConfigError` at the first of ``key_paths`` the file has a position for."""
    for kp in key_paths:
        if kp in positions:
            line, col = positions[kp]
            return ConfigError(message, path=source, line=line, col=col)
    return ConfigError(message, path=source)


def _parse(data: Any, source: str, base_dir: str, positions: Positions | None = None) -> LintConfig:
    from . import RULES  # the registry; imported late to avoid a cycle

    pos: Positions = positions or {}
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise _error("the lint configuration must be a mapping", source, pos, "")
    keys = ["rules", "urdf", "target"]
    unknown = sorted({str(k) for k in data} - set(keys))
    if unknown:
        key = unknown[0]
        raise _error(
            f"unknown configuration key {key!r}" + did_you_mean(key, keys),
            source,
            pos,
            f"{key}#key",
        )
    target = data.get("target")
    if target is not None:
        from ..xrdf.readers import parse_target

        try:
            target = getattr(parse_target(str(target)), "id", None)
        except XrdfToolsError as exc:
            raise _error(f"target: {exc.message}", source, pos, "target") from None
    urdf_map = _urdf_map(data.get("urdf") or {}, source, pos)
    return LintConfig(
        _levels(data.get("rules") or {}, [r.id for r in RULES], source, pos),
        urdf_map,
        base_dir,
        source,
        target,
        tuple(pos.get(f"urdf.{glob}") for glob, _ in urdf_map),
    )


def _levels(rules: Any, ids: list[str], source: str, pos: Positions) -> dict[str, Severity | None]:
    """``rules:`` as rule id (or prefix) -> level (None = off)."""
    if not isinstance(rules, dict):
        raise _error("'rules' must map rule ids to levels", source, pos, "rules")
    levels: dict[str, Severity | None] = {}
    for rid, lvl in rules.items():
        rid = str(rid)
        if not (rid in ids or (rid.endswith("-") and any(i.startswith(rid) for i in ids))):
            raise _error(
                f"unknown rule {rid!r}" + did_you_mean(rid, ids), source, pos, f"rules.{rid}#key"
            )
        if isinstance(lvl, dict):
            lvl = lvl.get("level", "off" if lvl.get("enabled") is False else None)
        if lvl is False:
            lvl = "off"
        if lvl not in LEVELS:
            raise _error(
                f"rule {rid!r}: level must be one of {', '.join(LEVELS)}, not {lvl!r}",
                source,
                pos,
                f"rules.{rid}.level",
                f"rules.{rid}",
            )
        levels[rid] = None if lvl == "off" else Severity(lvl)
    return levels


def _urdf_map(urdf: Any, source: str, pos: Positions) -> tuple[tuple[str, str], ...]:
    if not isinstance(urdf, dict):
        raise _error("'urdf' must map XRDF path globs to URDF paths", source, pos, "urdf")
    return tuple((str(k), str(v)) for k, v in urdf.items())


def _merge(base: LintConfig, over: LintConfig) -> LintConfig:
    return LintConfig(
        {**base.levels, **over.levels},
        over.urdf_map + base.urdf_map,
        over.base_dir,
        over.source,
        over.target if over.target is not None else base.target,
        over.urdf_positions + (None,) * len(base.urdf_map),
    )


def default_config() -> LintConfig:
    """The shipped ``default.yaml``."""
    here = Path(__file__).with_name("default.yaml")
    if here.is_file():  # installed as files: no importlib.resources (it imports zipfile)
        text = here.read_text(encoding="utf-8")
    else:  # pragma: no cover - a zipped install
        from importlib import resources

        text = resources.files(__package__).joinpath("default.yaml").read_text(encoding="utf-8")
    return _parse(to_python(parse_yaml(text, "default.yaml").root), "default.yaml", ".")


def load_config(path: str | os.PathLike[str]) -> LintConfig:
    """Read a ``.xrdf-lint.yaml`` or a ``pyproject.toml`` (its ``[tool.xrdf.lint]`` table)."""
    p = Path(path)
    if p.name == "pyproject.toml":
        table = _pyproject_table(p)
        data: Any = table if table is not None else {}
    else:
        try:
            doc = load_yaml(p)
        except XrdfToolsError as exc:
            raise ConfigError(exc.message, path=str(p), line=exc.line, col=exc.col) from None
        check_shape(doc.root, CONFIG_SHAPE, path=str(p), error=ConfigError)
        data = to_python(doc.root)
        return _merge(
            default_config(), _parse(data, str(p), str(p.parent), node_positions(doc.root))
        )
    return _merge(default_config(), _parse(data, str(p), str(p.parent)))


def _pyproject_table(p: Path) -> dict[str, Any] | None:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10: tomli is a dependency there
        import tomli as tomllib  # type: ignore[import-not-found, unused-ignore]
    text = read_input_text(p, what="pyproject.toml", error=ConfigError)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"invalid TOML: {' '.join(str(exc).split())}", path=str(p)) from None
    table = doc.get("tool", {}).get("xrdf", {}).get("lint")
    return table if isinstance(table, dict) else None


def discover_config(start: str | os.PathLike[str] = ".") -> LintConfig:
    """The first ``.xrdf-lint.yaml`` or ``[tool.xrdf.lint]`` from ``start`` upwards, merged
    over the defaults; the defaults alone when there is none."""
    d = Path(start).resolve()
    for folder in (d, *d.parents):
        cand = folder / CONFIG_NAME
        if cand.is_file():
            return load_config(cand)
        py = folder / "pyproject.toml"
        if py.is_file() and _pyproject_table(py) is not None:
            return load_config(py)
    return default_config()
