"""Resolve ROS package references without ROS: ``package://pkg/…``, ``$(find pkg)``, ``file://``.

A Gazebo ``model://NAME/…`` URI is resolved as ``package://NAME/…`` (a folder named ``NAME``,
or ``--package-path NAME=DIR``), as yourdfpy's default handler strips the scheme and looks for
``NAME/…`` beside the URDF and in its parents (cuRobo's loader strips only ``package://``, so
``export curobo`` counts such meshes among those it cannot find). A relative or ``file://``
path with ``%20`` and other escapes is read decoded, as ROS's resource retriever reads a
``file://`` URI (a relative one that names a file as written is taken as written). An absolute
``file://`` path that does not exist but lies in a ROS install's ``share/PKG/`` (a URDF expanded
on another machine: ``/opt/ros/humble/share/PKG/…``) is read from package ``PKG`` as found here.

Where a package is looked for, in order:
1. explicit ``package_paths`` (``{"pkg": "/path/to/pkg"}``, from ``--package-path pkg=DIR``;
   ``{"pkg": ["/a", "/b"]}`` for a package split over several folders, from the option given
   once per folder): a file ``package://pkg/rel`` is the first ``DIR/rel`` that exists, in
   the order given, ``$(find pkg)`` the first ``DIR``, and a file in none of them is a
   :class:`SourceError` naming every ``DIR`` (the search below is not made for a package
   given so). A relative ``DIR`` is taken relative to the current directory (as every
   command-line path is), never to the file that names the package;
2. for a package not given: the input file's folder, then each of its parents (up to six
   folders, and never the home directory, the temporary directory or the file-system root
   unless the input sits right in it: they hold unrelated projects), nearest first: in each,
   a directory at most two levels below holding a ``package.xml`` whose ``<name>`` is
   ``pkg``, else a sub-directory named ``pkg``, else the folder itself if so named. The
   nearest folder that has the package wins, so a ``package.xml`` of the same name under a
   far parent never shadows the package the robot sits in; a file the nearest one lacks is
   looked for in the farther ones (a package split over two source folders that install
   into one).

An unresolved package is a :class:`SourceError` naming the package and the directories searched.
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeAlias
from urllib.parse import unquote

from ..util.errors import SourceError, XrdfToolsError
from ..util.fileio import is_file, read_input_bytes
from ..util.text import name_list

#: The folder of a package, or the folders of one split over several, looked in in order.
PackageDirs: TypeAlias = "str | os.PathLike[str] | Sequence[str | os.PathLike[str]]"
#: ``package_paths`` of every loader: package name → its folder(s) (``--package-path``).
PackagePaths: TypeAlias = "Mapping[str, PackageDirs]"

_NAME_RE = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")


def package_name(package_xml: Path) -> str | None:
    """The ``<name>`` of a ``package.xml`` (None if unreadable)."""
    try:
        m = _NAME_RE.search(read_input_bytes(package_xml, what="package.xml"))
    except XrdfToolsError:
        return None
    return m.group(1).decode("utf-8", "replace") if m else None


@dataclass
class PackageResolver:
    """Finds package directories for a given input file.

    ``start`` is the file (or directory) whose ancestors are searched; ``package_paths`` are
    explicit ``name → directory`` (or ``name → directories``, looked in in order) entries
    that win over anything found on disk.
    """

    start: Path
    package_paths: PackagePaths = field(default_factory=dict)
    max_depth: int = 2
    _cache: dict[str, Path] = field(default_factory=dict, init=False, repr=False)
    #: The ``package_paths`` folders, each absolute, by package (filled on creation).
    _given: dict[str, tuple[Path, ...]] = field(default_factory=dict, init=False, repr=False)
    #: The folders scanned so far, nearest first, each with the packages its package.xml
    #: files below name.
    _scanned: list[tuple[Path, dict[str, Path]]] = field(
        default_factory=list, init=False, repr=False
    )

    def __post_init__(self) -> None:
        self._given = package_folders(self.package_paths)

    def _roots(self) -> list[Path]:
        """The input's folder, then its parents up to (not into) a shared folder."""
        p = self.start.resolve()
        base = p if _is_dir(p) else p.parent
        shared = _shared_folders()
        roots = [base]
        for parent in base.parents:
            if parent in shared or parent == parent.parent:
                break
            roots.append(parent)
        return roots

    def _search_folders(self) -> Iterator[tuple[Path, dict[str, Path]]]:
        """The folders searched, nearest first, each scanned once on first need (never more
        than six: the whole file system is not crawled)."""
        yield from list(self._scanned)
        for root in self._roots()[len(self._scanned) : _MAX_FOLDERS]:
            index: dict[str, Path] = {}
            for xml in _package_xmls(root, self.max_depth):
                name = package_name(xml)
                if name and name not in index:
                    index[name] = xml.parent
            self._scanned.append((root, index))
            yield root, index

    def find_below_roots(self, sub: str) -> Path:
        """``sub`` below the first search directory that holds it: the ``--package-path``
        directories, then the input's folder and its parents (a ``package:///sub`` URI, as
        Pinocchio resolves it against its package directories)."""
        given = [d for folders in self._given.values() for d in folders]
        roots = [*given, *self._roots()]
        for root in roots:
            cand = root / sub
            if is_file(cand) or _is_dir(cand):
                return cand
        raise SourceError(
            f"cannot find '{sub}' of a package:/// URI below any search directory (the "
            f"--package-path directories, {roots[len(given)]} and its parents); pass "
            "--package-path NAME=DIR with the directory that holds it"
        )

    def find(self, name: str) -> Path:
        """Directory of package ``name``; raises :class:`SourceError` when not found."""
        if name in self._cache:
            return self._cache[name]
        if name in self._given:
            for d in self._given[name]:
                why = _not_a_directory(d)
                if why is not None:
                    raise SourceError(f"--package-path {name}={d}: {why}")
            self._cache[name] = self._given[name][0]
            return self._given[name][0]
        found: Path | None = None
        for root, index in self._search_folders():
            found = index.get(name)
            if found is None and _is_dir(root / name):
                found = root / name
            if found is None and root.name == name:
                found = root
            if found is not None:
                break
        if found is None:
            searched = ", ".join(str(p) for p, _ in self._scanned) or str(self.start)
            raise SourceError(
                f"cannot find ROS package '{name}' (searched for package.xml named '{name}' in "
                f"and below: {searched}); pass --package-path {name}=DIR"
            )
        self._cache[name] = found
        return found

    def package_folder(self, name: str, sub: str) -> Path:
        """The folder of package ``name`` that its file ``sub`` is in (``package://name/sub``).

        A package given in ``package_paths``: the first of its folders that holds ``sub`` as
        a file, else the first where something else is at ``sub`` (a directory, a FIFO: the
        reader says what it is); a :class:`SourceError` naming every folder when none holds
        anything there. A package found by the search: the nearest folder, or a farther one
        of the same package that holds the file the nearest lacks (the nearest when none
        does). Raises :class:`SourceError` when the package cannot be found."""
        nearest = self.find(name)
        if name in self._given:
            return self._given_folder(name, sub)
        if not sub or is_file(nearest / sub) or _is_dir(nearest / sub):
            return nearest
        return next((f for f in self._elsewhere(name) if is_file(f / sub)), nearest)

    def _given_folder(self, name: str, sub: str) -> Path:
        """The first ``package_paths`` folder of ``name`` holding the file ``sub`` (see
        :meth:`package_folder`)."""
        folders = self._given[name]
        found = next((d for d in folders if is_file(d / sub)), None)
        found = found or next((d for d in folders if _anything_at(d / sub)), None)
        if found is not None:
            return found
        tried = name_list((str(d / sub) for d in folders), _FOLDERS_SHOWN)
        if len(folders) == 1:
            where = f"the --package-path directory of '{name}' (looked for {tried})"
        else:
            where = f"any of the {len(folders)} --package-path directories of '{name}' "
            where += f"(looked for, in order: {tried})"
        raise SourceError(
            f"file not found in {where}; a package split over several folders takes "
            f"--package-path {name}=DIR once per folder (repeated, the first that holds a "
            "file wins)"
        )

    def _elsewhere(self, name: str) -> Iterator[Path]:
        """The farther folders that also hold package ``name``, nearest first: a package split
        over two source folders that install into one (iCub's manual models beside the
        generated ones, both package 'iCub')."""
        nearest = self.find(name)
        for root, index in self._search_folders():
            for folder in (index.get(name), root / name, root if root.name == name else None):
                if folder is not None and folder != nearest and _is_dir(folder):
                    yield folder

    def _holder_hint(self, name: str, sub: str) -> str:
        """A package of another name found in the search that holds ``sub`` (a package
        renamed after the export wrote its URIs: SolidWorks' ``moveo_urdf_4`` in a folder whose
        package.xml says ``moveo_urdf``), as the --package-path to give; else ""."""
        if not sub:
            return ""
        for _, index in self._scanned:
            for other, folder in sorted(index.items()):
                if other != name and is_file(folder / sub):
                    return (
                        f"; package '{other}' at {folder} holds {sub}: "
                        f"--package-path {name}={folder}"
                    )
        return ""

    def resolve_uri(self, uri: str, relative_to: Path | None = None) -> Path:
        """A mesh or include URI as a local path (``package://``, ``file://`` or relative).
        Raises :class:`SourceError` for a URI whose decoded path holds a NUL byte (``%00``),
        which no file name can (``os.stat`` raises ``ValueError`` on it)."""
        path = self._resolved(uri, relative_to)
        if "\0" in str(path):
            raise SourceError("a path with a NUL byte (%00), which no file name holds")
        return path

    def _resolved(self, uri: str, relative_to: Path | None) -> Path:
        scheme = package_scheme(uri)
        if scheme:
            rest = uri[len(scheme) :]
            name, _, sub = rest.partition("/")
            if not name:  # package:///a/b: a path below a package search directory
                return self.find_below_roots(unquote(sub))
            try:
                return self.package_folder(name, unquote(sub)) / unquote(sub)
            except SourceError as e:
                gazebo = _GAZEBO_NOTE if scheme == "model://" else ""
                hint = self._holder_hint(name, unquote(sub))
                raise SourceError(e.message + hint + gazebo) from None
        if uri.startswith("file://"):
            path = Path(file_uri_path(uri))
            return path if _anything_at(path) else self._installed(path)
        base = relative_to or (self.start if _is_dir(self.start) else self.start.parent)
        as_written = _local_path(base, uri)
        if unquote(uri) == uri or is_file(as_written):
            return as_written
        decoded = _local_path(base, unquote(uri))  # mesh%20dir/arm.stl: mesh dir/arm.stl
        return decoded if is_file(decoded) else as_written

    def _installed(self, path: Path) -> Path:
        """A ``file://`` path that does not exist, read from its package when it lies in a ROS
        install's ``share/PKG/`` (where ``$(find PKG)`` pointed on the machine that expanded
        the xacro: ``/opt/ros/humble/share/ur_description/…``,
        ``…/install/arm_description/share/arm_description/…``): the same file of package PKG
        as found here; ``path`` itself when it names no such folder. Raises
        :class:`SourceError` naming ``--package-path PKG=DIR`` when PKG cannot be found."""
        parts = _path_parts(str(path))
        share = next((i for i in range(len(parts) - 3, 0, -1) if parts[i] == "share"), None)
        if share is None:
            return path
        name, sub = parts[share + 1], "/".join(parts[share + 2 :])
        try:
            return self.package_folder(name, sub) / sub
        except SourceError as e:
            raise SourceError(
                f"mesh file not found, nor in package '{name}' here (the path is in its install "
                f"folder where the URDF was written): {e.message}"
            ) from None


def _path_parts(path: str) -> tuple[str, ...]:
    """The folders and file of ``path`` as the machine that wrote it meant them: ``..`` taken
    against the folder before it (``share/robo/../arm/x.stl`` is in package ``arm``, and
    ``share/robo/../../x`` in none: never a file above the package folder found here) and
    ``\\`` a separator (``C:\\ros\\share\\robo\\x.stl``, written on Windows)."""
    import posixpath

    return Path(posixpath.normpath(path.replace("\\", "/"))).parts


def file_uri_path(uri: str) -> str:
    """The path a ``file://`` URI names, decoded (``%20`` a space), as the mesh reader opens
    it."""
    return unquote(uri[len("file://") :])


def package_scheme(uri: str) -> str:
    """``package://`` or ``model://`` (a Gazebo model, found as a package of that name) when
    ``uri`` starts with it, else ''."""
    return next((s for s in ("package://", "model://") if uri.startswith(s)), "")


_GAZEBO_NOTE = (
    "; a model:// URI names a Gazebo model, looked for as a package of that name "
    "(GAZEBO_MODEL_PATH and GZ_SIM_RESOURCE_PATH are not read)"
)


def _local_path(base: Path, path: str) -> Path:
    """``path`` as a file: itself when absolute, else below ``base`` or one of its parents."""
    p = Path(path)
    return p if p.is_absolute() else _relative_to_a_parent(base, p)


#: The --package-path folders an error names (1,000 of them made a 52 kB line).
_FOLDERS_SHOWN = 8

#: Folders searched for a package: the input's and its parents (see the module doc).
_MAX_FOLDERS = 6


def _shared_folders() -> set[Path]:
    """Folders that hold unrelated work (the home and temporary directories): a parent search
    stops below them, so a package left in another project there is never picked up."""
    out = set()
    for folder in (Path.home(), Path(tempfile.gettempdir()), Path("/var/tmp")):
        try:
            out.add(folder.resolve())
        except (OSError, RuntimeError):
            continue
    return out


#: Directories above the URDF's that a relative mesh path is also looked for in.
_PARENT_LEVELS = 4


def _relative_to_a_parent(base: Path, rel: Path) -> Path:
    """``base / rel``, or when no such file exists the first of ``base``'s parents (up to
    :data:`_PARENT_LEVELS` above it) that holds ``rel``, as yourdfpy (and so cuRobo) finds a
    relative mesh path: a URDF in ``robot/urdf/`` naming ``meshes/arm.stl`` that lies in
    ``robot/meshes/`` (cuRobo's tm12). The path below ``base`` when none holds it (the one an
    error names)."""
    first = base / rel
    if is_file(first):
        return first
    for parent in list(base.parents)[:_PARENT_LEVELS]:
        if is_file(parent / rel):
            return parent / rel
    return first


def _is_dir(path: Path) -> bool:
    """``path`` is a directory; False also when it cannot be looked at (a name too long)."""
    try:
        return path.is_dir()
    except OSError:
        return False


def _anything_at(path: Path) -> bool:
    """Something is at ``path`` (a file, a directory, a FIFO, a dangling link) or it cannot be
    looked at (a name too long for the file system): the reader then says what is wrong.
    False only when nothing is there."""
    try:
        os.lstat(path)
    except (FileNotFoundError, NotADirectoryError):
        return False
    except (OSError, ValueError):
        return True
    return True


def _not_a_directory(path: Path) -> str | None:
    """Why ``path`` is not a directory to search, or None when it is one."""
    try:
        if path.is_dir():
            return None
        return "not a directory" if path.exists() else "no such directory"
    except OSError as e:
        return f"cannot be used: {e.strerror or e}"


def absolute(directory: str | os.PathLike[str]) -> Path:
    """``directory`` (``~`` expanded) as an absolute path, a relative one taken from the
    current directory; not resolved, so symbolic links stay as given."""
    return Path(os.path.abspath(Path(directory).expanduser()))


def _package_xmls(root: Path, depth: int) -> list[Path]:
    out: list[Path] = []
    frontier = [root]
    for level in range(depth + 1):
        nxt: list[Path] = []
        for d in frontier:
            xml = d / "package.xml"
            if is_file(xml):
                out.append(xml)
            if level < depth:
                try:
                    nxt.extend(
                        c for c in sorted(d.iterdir()) if _is_dir(c) and not c.name.startswith(".")
                    )
                except OSError:
                    continue
        frontier = nxt[:500]
    return out


def package_folders(paths: PackagePaths | None) -> dict[str, tuple[Path, ...]]:
    """``paths`` (``name → DIR`` or ``name → [DIR, ...]``) as each package's folders, absolute
    (:func:`absolute`), in the order given, each once."""
    out: dict[str, tuple[Path, ...]] = {}
    for name, dirs in (paths or {}).items():
        given = [dirs] if isinstance(dirs, (str, os.PathLike)) else list(dirs)
        out[name] = tuple(dict.fromkeys(absolute(d) for d in given))
    return out


def absolute_package_paths(paths: PackagePaths | None) -> dict[str, str | tuple[str, ...]]:
    """``paths`` with absolute folders, as a loaded robot keeps them: a package's one folder
    as a string (the form ``package_paths`` has always had), the folders of a package split
    over several as a tuple of strings."""
    out: dict[str, str | tuple[str, ...]] = {}
    for name, folders in package_folders(paths).items():
        out[name] = str(folders[0]) if len(folders) == 1 else tuple(str(f) for f in folders)
    return out


def parse_package_paths(specs: Iterable[str] | None) -> dict[str, tuple[str, ...]]:
    """Every ``--package-path NAME=DIR`` of a command: each package's folders in the order
    given (the option repeated for one ``NAME``: a package split over several folders)."""
    out: dict[str, tuple[str, ...]] = {}
    for spec in specs or ():
        name, directory = parse_package_path(spec)
        out[name] = (*out.get(name, ()), directory)
    return out


def parse_package_path(spec: str) -> tuple[str, str]:
    """``NAME=DIR`` from the command line; ``DIR`` must be a directory (a mistyped one is
    said at once, also when the robot turns out not to use the package)."""
    name, sep, directory = spec.partition("=")
    if not sep or not name or not directory:
        raise SourceError(f"--package-path expects NAME=DIR, got '{spec}'")
    if "/" in name:  # package://a/b names package 'a': 'a/b' would never be looked up
        raise SourceError(f"--package-path {spec}: a package name holds no '/'")
    why = _not_a_directory(absolute(directory))
    if why is not None:
        raise SourceError(f"--package-path {name}={directory}: {why}")
    return name, directory


def unfound_packages_note(failures: Iterable[tuple[str | None, str]]) -> str:
    """The packages that cannot be found among ``(uri, reason)`` failures, when there are
    several: each named once with its mesh count (a mobile base with arms and grippers from
    several packages), so that one run says every --package-path to give; else ""."""
    counts: dict[str, int] = {}
    for uri, reason in failures:
        scheme = package_scheme(uri or "")
        if uri and scheme and "cannot find ROS package" in reason:
            name = uri[len(scheme) :].split("/", 1)[0]
            counts[name] = counts.get(name, 0) + 1
    if len(counts) < 2:
        return ""
    named = ", ".join(f"{name} ({n} mesh(es))" for name, n in counts.items())
    return f"; packages not found: {named}: pass --package-path NAME=DIR for each"
