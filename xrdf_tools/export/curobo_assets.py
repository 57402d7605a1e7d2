"""``asset_root_path`` of an exported cuRobo config: the directory cuRobo's mesh loader needs.

cuRobo reads a URDF's mesh file names through its own handler: it strips ``package://`` and
joins what is left to ``asset_root_path`` (an absolute name is kept). So a mesh
``package://ur_description/meshes/base.stl`` is found only when ``asset_root_path`` is the
directory that holds ``ur_description``, and a relative mesh ``meshes/base.stl`` only when it
is the directory the URDF named it from. :func:`mesh_root` finds the one directory that serves
every mesh of the robot, or says which meshes no directory serves with the others (kinematics
and the sphere model do not need the meshes; cuRobo features that load them do).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import unquote

from ..util.errors import SourceError
from ..util.text import name_list

if TYPE_CHECKING:
    from ..robot.core import Robot
    from ..robot.packages import PackageResolver

__all__ = [
    "MeshRoot",
    "curobo_paths",
    "expanded_urdf_path",
    "mesh_root",
    "plain_file_path",
    "unserved_note",
    "with_plain_file_names",
]


@dataclass(frozen=True)
class MeshRoot:
    """The directory for ``asset_root_path`` (None: no mesh decides it) and, when no one
    directory serves every mesh, the meshes that cuRobo will not find from it."""

    directory: Path | None
    unserved: tuple[str, ...] = ()
    #: ``(package, folder)`` of each package found in a folder of another name (a clone of
    #: ``Universal_Robots_ROS2_Description`` holds ``ur_description``): cuRobo finds none of its
    #: meshes, whatever ``asset_root_path`` is.
    misnamed: tuple[tuple[str, str], ...] = ()
    #: ``(package, folder)`` of every package with meshes when they are in different
    #: directories (two workspaces): no one ``asset_root_path`` serves them all.
    scattered: tuple[tuple[str, str], ...] = ()
    #: Each package whose meshes were found in several folders (``--package-path`` given
    #: once per folder): ``(package, ((folder, entries), ...))``, ``entries`` the names
    #: directly in that folder that its meshes are below. cuRobo joins every name to one
    #: directory, so it finds the meshes of one folder at most.
    split: tuple[tuple[str, tuple[tuple[str, tuple[str, ...]], ...]], ...] = ()


def mesh_root(robot: Robot, *, plain_file_names: bool = False) -> MeshRoot:
    """The directory that serves the most mesh file names of ``robot`` as cuRobo joins them
    (ties: the URDF's own directory first, then the name), and the names it does not serve.
    With ``plain_file_names`` the URDF cuRobo reads is the one :func:`with_plain_file_names`
    writes, whose ``file://`` names are absolute paths, which any directory serves.

    A package that cannot be found is left to the mesh checks of the other commands."""

    resolver = robot.mesh_resolver()
    own = Path(robot.path).resolve().parent
    serves: dict[Path | None, list[str]] = {}
    misnamed: dict[str, str] = {}
    parts: dict[str, dict[Path, list[str]]] = {}  # package → folder → entries its meshes use
    for uri in dict.fromkeys(_mesh_names(robot)):
        if Path(uri).is_absolute():  # cuRobo keeps an absolute name: any directory serves it
            continue
        if plain_file_names and plain_file_path(uri) is not None:
            continue
        try:
            root = _root_for(uri, resolver, own, misnamed, parts)
        except SourceError:
            continue
        serves.setdefault(root, []).append(uri)
    split = tuple(
        (name, tuple((str(f), tuple(dict.fromkeys(e))) for f, e in folders.items()))
        for name, folders in parts.items()
        if len(folders) > 1
    )
    for name, _ in split:
        misnamed.pop(name, None)
    roots = [r for r in serves if r is not None]
    if not roots:
        return MeshRoot(None, tuple(serves.get(None, ())), tuple(misnamed.items()), split=split)
    best = min(roots, key=lambda r: (-len(serves[r]), r != own, str(r)))
    unserved = [u for r, uris in serves.items() if r != best for u in uris]
    packages = {
        name: str(root / name)
        for root, uris in serves.items()
        if root is not None
        for u in uris
        if (name := _package_of(u)) and len(parts.get(name, ())) < 2
    }
    homes = {str(Path(folder).parent) for folder in packages.values()}
    scattered = tuple(sorted(packages.items())) if len(homes) > 1 else ()
    return MeshRoot(best, tuple(unserved), tuple(misnamed.items()), scattered, split)


def _package_of(uri: str) -> str:
    """The package a ``package://`` mesh name is in, '' for another name."""
    if not uri.startswith("package://"):
        return ""
    return uri[len("package://") :].partition("/")[0]


_FILE_URI = re.compile(r"""(\bfilename\s*=\s*)(?:"(file://[^"]*)"|'(file://[^']*)')""")
#: Characters XML 1.0 cannot hold, even as a character reference.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def with_plain_file_names(urdf_text: str) -> tuple[str, int]:
    """``urdf_text`` with each ``file://`` mesh name written as its plain, decoded path (which
    cuRobo keeps as written, where it joins a ``file://`` name to ``asset_root_path`` and never
    finds it), and how many were rewritten. The attribute is read as the XML parser reads it
    (entities and character references, line breaks as spaces) and written so that it reads
    back as exactly that path; a name :func:`plain_file_path` cannot give is left as it was."""

    rewritten = 0

    def plain(m: re.Match[str]) -> str:
        nonlocal rewritten
        quote = '"' if m.group(2) is not None else "'"
        uri = _attribute_value(m.group(2) if m.group(2) is not None else m.group(3), quote)
        path = None if uri is None else plain_file_path(uri)
        if path is None:
            return m.group(0)
        rewritten += 1
        return f"{m.group(1)}{quote}{_attribute_text(path, quote)}{quote}"

    return _FILE_URI.sub(plain, urdf_text), rewritten


def plain_file_path(uri: str) -> str | None:
    """The plain path a ``file://`` mesh name ``uri`` is read from (decoded as the robot
    loader decodes it), or None when it is not a ``file://`` name or its path cannot be
    written in XML (a ``%00``)."""
    from ..robot.packages import file_uri_path

    if not uri.startswith("file://"):
        return None
    path = file_uri_path(uri)
    return None if _NOT_XML.search(path) else path


def _attribute_value(raw: str, quote: str) -> str | None:
    """The value the XML parser reads from the attribute text ``raw`` (None: not well-formed,
    such as an entity the document does not define)."""
    from ..util.safe_xml import XmlSyntaxError, parse_xml

    try:
        element = parse_xml(f"<a v={quote}{raw}{quote}/>".encode())
    except XmlSyntaxError:
        return None
    value: str = element.get("v")
    return value


def _attribute_text(value: str, quote: str) -> str:
    """``value`` as attribute text between ``quote`` characters that reads back as it is."""
    refs = {"&": "&amp;", "<": "&lt;", quote: "&quot;" if quote == '"' else "&apos;"}
    refs |= {"\t": "&#9;", "\n": "&#10;", "\r": "&#13;"}
    return "".join(refs.get(c, c) for c in value)


def unserved_note(root: MeshRoot) -> str:
    """One line on the meshes cuRobo will not find from ``root.directory``."""
    note = (
        f"{len(root.unserved)} mesh file name(s) cannot be found from asset_root_path "
        f"({name_list(root.unserved, 3)}): cuRobo joins each to that one directory "
        "(package:// stripped); its kinematics and spheres do not need them, loading the "
        "robot's meshes does"
    )
    if any(u.startswith("file://") for u in root.unserved):
        note += (
            ". cuRobo keeps a file:// name as written, so it never finds one: name those meshes "
            "by their plain paths or package:// URIs in the URDF"
        )
    if root.scattered:
        note += (
            ". The packages are in different folders ("
            + ", ".join(f"{p} in {Path(f).parent}" for p, f in root.scattered)
            + "): link them side by side (mkdir DIR; ln -s "
            + " ".join(f for _, f in root.scattered)
            + " DIR/) and export again with "
            + " ".join(f"--package-path {p}=DIR/{p}" for p, _ in root.scattered)
        )
    for package, folders in root.split:
        note += _split_note(package, folders)
    for package, folder in root.misnamed:
        note += (
            f". Package '{package}' is the folder {folder}, which is not named after it, so no "
            f"directory serves its meshes: make a link named '{package}' to it (ln -s "
            f"{folder} DIR/{package}) and export again with --package-path {package}=DIR/"
            f"{package}"
        )
    return note


def _split_note(package: str, folders: tuple[tuple[str, tuple[str, ...]], ...]) -> str:
    """What to do about a package whose meshes are in several folders: one folder named after
    it that links what the meshes use of each (when no two folders use an entry of one
    name), named by ``--package-path`` in the export."""
    listed = ", ".join(folder for folder, _ in folders)
    note = (
        f". Package '{package}' is split over {len(folders)} folders ({listed}); cuRobo finds "
        "every mesh below one folder named after the package"
    )
    entries = [e for _, used in folders for e in used]
    if len(set(entries)) < len(entries):  # two folders use e.g. meshes/: their files must merge
        return note + (
            f": copy the meshes of each into one folder named '{package}' and export again "
            f"with --package-path {package}=DIR/{package}"
        )
    links = " ".join(f"{Path(folder) / e}" for folder, used in folders for e in used)
    return note + (
        f": make one (mkdir -p DIR/{package}; ln -s {links} DIR/{package}/) and export again "
        f"with --package-path {package}=DIR/{package}"
    )


def _root_for(
    uri: str,
    resolver: PackageResolver,
    own: Path,
    misnamed: dict[str, str],
    parts: dict[str, dict[Path, list[str]]],
) -> Path | None:
    """The directory cuRobo must join ``uri`` to, or None when no directory can serve it (a
    ``file://`` or Gazebo ``model://`` name, which cuRobo keeps as written; a package in a
    folder not named after it: recorded in ``misnamed``). The package folder is the one the
    file was found in (a package split over several: each folder and the entry of it the
    name is below recorded in ``parts``)."""
    if uri.startswith("package://"):
        name, _, sub = uri[len("package://") :].partition("/")
        if not name:
            return None
        folder = resolver.package_folder(name, unquote(sub))
        entry = Path(unquote(sub)).parts[:1] or ("",)
        parts.setdefault(name, {}).setdefault(folder, []).append(entry[0])
        if folder.name != name:
            misnamed.setdefault(name, str(folder))
            return None
        return folder.parent
    if uri.startswith(("file://", "model://")):
        return None
    return _folder_of_relative(uri, resolver, own)


def _folder_of_relative(uri: str, resolver: PackageResolver, own: Path) -> Path:
    """The directory a relative mesh name was found below: the URDF's own, or the parent of
    it that holds the name (as the robot reader finds it, see ``robot.packages``), which
    cuRobo needs as asset_root_path as it joins the name to it as written. ``own`` when the
    file is nowhere (the mesh checks of the other commands say so)."""
    found = resolver.resolve_uri(uri)
    try:
        if not found.is_file():
            return own
    except OSError:  # a name too long for the file system
        return own
    root = found
    for _ in Path(uri).parts:  # lexical: "../meshes/a.stl" below own is own
        root = root.parent
    return root.resolve()


def _mesh_names(robot: Robot) -> Iterator[str]:
    """Every mesh file name of the robot's visual and collision elements, in URDF order."""
    for link in robot.urdf.link_map.values():
        for part in (*link.visuals, *link.collisions):
            mesh = part.geometry.mesh if part.geometry is not None else None
            if mesh is not None and mesh.filename:
                yield str(mesh.filename)


def curobo_paths(
    urdf: str | os.PathLike[str],
    relative_to: str | os.PathLike[str] | None,
    assets: MeshRoot | None = None,
) -> tuple[str, str]:
    """``urdf_path`` and ``asset_root_path`` as a cuRobo config holds them: relative to the
    directory ``relative_to`` with ``/`` separators, or absolute when it is None or no
    relative path exists (another drive). ``asset_root_path`` is ``assets.directory`` when
    the meshes decide it (:func:`mesh_root`), else the URDF's directory. Symbolic links are
    kept as given."""
    upath = Path(os.path.abspath(urdf))
    found = assets.directory if assets is not None else None
    root = Path(os.path.abspath(found)) if found is not None else upath.parent
    if relative_to is not None:
        base = os.path.abspath(relative_to)
        try:
            rel, rel_root = os.path.relpath(upath, base), os.path.relpath(root, base)
        except ValueError:  # another drive: only an absolute path reaches it
            pass
        else:
            return Path(rel).as_posix(), Path(rel_root).as_posix()
    return str(upath), str(root)


def expanded_urdf_path(output: str | os.PathLike[str]) -> Path:
    """Where the expanded URDF of a xacro goes beside ``output``: named after it
    (``cfg/px150.yml`` → ``cfg/px150.urdf``), so that each exported config has its own; two
    exports of one xacro with different ``--xacro-arg`` values (``ur_type:=ur3e``,
    ``ur_type:=ur5e``) to one folder never share, and so never replace, each other's URDF."""
    return Path(output).with_suffix(".urdf")
