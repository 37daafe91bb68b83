"""Where a description's ROS packages are, without a ROS install.

``$(find PKG)`` and ``model://NAME`` are resolved, in this order, from the folders the caller
gives, the description's own source tree, the bundled packages, then the folders of
``AMENT_PREFIX_PATH`` (``<prefix>/share/PKG``) and ``ROS_PACKAGE_PATH`` (searched below each
entry). A package is a folder holding a ``package.xml``, named by its ``<name>``.

The source tree is what a workspace or a clone holds: from the description's own package (the
nearest folder above it holding a ``package.xml``, at any depth below the filesystem's root and
the home folder; at most :data:`PACKAGE_LEVELS` folders are looked at), the workspace's
``src`` folder above it, else the repository it lies in (the nearest folder holding ``.git``),
at most :data:`TREE_LEVELS` up; else the package's parent folder, which holds its siblings. The
search is bounded (:data:`MAX_FOLDERS` folders, :data:`MAX_DEPTH` deep), follows no symbolic link
out of the tree, skips hidden, build and ignored folders, and is cached per tree.

A name is looked up only when it is a plain package name (letters, digits, ``_``, ``-`` and
``.``, not starting with a dot; :func:`folder_below`): a description asking for ``$(find /)`` or
``$(find ../..)`` reaches nothing outside.

A folder given for a package (:func:`given_package`) may be the folder holding its
``package.xml``, an install prefix (``install/NAME``, holding ``share/NAME``) or a share folder
(holding ``NAME``). A relative entry of ``AMENT_PREFIX_PATH`` or ``ROS_PACKAGE_PATH`` is taken
from the current folder, as ROS takes it.
"""

from __future__ import annotations

import contextlib
import functools
import os
import re
from collections import deque
from collections.abc import Mapping
from pathlib import Path
from typing import Final
from xml.etree import ElementTree

from diffbot.errors import DescriptionError, PackageNotFoundError
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import read_text

__all__ = [
    "MAX_DEPTH",
    "MAX_FOLDERS",
    "PACKAGE_LEVELS",
    "TREE_LEVELS",
    "PackageFinder",
    "folder_below",
    "given_package",
    "own_package",
    "package_name",
    "packages_under",
    "plain_name",
    "source_tree",
]

#: Most folders above a description searched for its own ``package.xml`` (the description's
#: folder counts as the first): deeper than any real layout (``batch/<name>/urdf/`` puts the
#: package four up), and each is one look-up of a name, nothing read.
PACKAGE_LEVELS: Final = 64
#: Folders above a description's package searched for the root of its source tree.
TREE_LEVELS: Final = 4
#: Most folders one search of a tree visits.
MAX_FOLDERS: Final = 20_000
#: Deepest folder below a tree's root a search visits.
MAX_DEPTH: Final = 8
#: Largest ``package.xml`` read (bytes): real ones are a few kB.
MAX_MANIFEST: Final = 1 << 20

_PLAIN_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\-]*")
_SKIPPED = frozenset({"build", "install", "log", "node_modules", "__pycache__", "site-packages"})
_IGNORE_MARKERS = ("COLCON_IGNORE", "CATKIN_IGNORE", "AMENT_IGNORE")


def plain_name(name: str) -> bool:
    """Whether ``name`` can name a package: no path separator, not ``.`` or ``..``, not empty."""
    return _PLAIN_NAME.fullmatch(name) is not None


def folder_below(base: Path, name: str, *, links: bool = False) -> Path | None:
    """``base / name`` when ``name`` is a plain name and that folder exists; None otherwise.

    Args:
        base: the folder searched.
        name: the package's or model's name.
        links: whether the folder may be a link to elsewhere: yes in a folder the user's
            environment names (an install may link its packages), no in a description's tree,
            whose links are the description's own.
    """
    if not plain_name(name):
        return None
    candidate = base / name
    with contextlib.suppress(OSError, RuntimeError):  # RuntimeError: a link loop (Python < 3.13)
        if candidate.is_dir() and (links or candidate.resolve().parent == base.resolve()):
            return candidate
    return None


def package_name(folder: Path) -> str:
    """A package's name: the ``<name>`` of its ``package.xml``, else the folder's name."""
    manifest = folder / "package.xml"
    with contextlib.suppress(OSError, ElementTree.ParseError, ValueError, DescriptionError):
        if manifest.is_file():
            text = read_text(manifest, DescriptionError, "a package.xml", max_chars=MAX_MANIFEST)
            name = ElementTree.fromstring(text).findtext("name")
            if name and name.strip():
                return name.strip()
    return folder.name


def given_package(name: str, folder: Path) -> Path:
    """The folder of package ``name`` a user means by ``folder``: the folder itself when it
    holds a ``package.xml`` (a source package), else its ``share/NAME`` (an install prefix), else
    its ``NAME`` holding a ``package.xml`` (a share folder); else the folder as given."""
    if (folder / "package.xml").is_file() or not name or name in (".", "..") or "/" in name:
        return folder
    if (folder / "share" / name).is_dir():
        return folder / "share" / name
    if (folder / name / "package.xml").is_file():
        return folder / name
    return folder


def own_package(description: Path) -> Path | None:
    """The folder of the package a description lies in, or None when it lies in none."""
    folder = resolved(description, DescriptionError).parent
    for candidate in [folder, *folder.parents][:PACKAGE_LEVELS]:
        # the root and the home folder are no package: a stray manifest there takes in everything
        if candidate == Path(candidate.anchor) or candidate == Path.home():
            break
        if (candidate / "package.xml").is_file():
            return candidate
    return None


def source_tree(description: Path) -> Path | None:
    """The root of the source tree a description's package lies in, or None outside a package."""
    package = own_package(description)
    if package is None:
        return None
    above = []
    for candidate in [package, *package.parents][: TREE_LEVELS + 1]:
        if candidate == Path(candidate.anchor) or candidate == Path.home():
            break
        above.append(candidate)
    # a workspace's src holds the repositories cloned side by side: it wins over the one repository
    for candidate in above[1:]:
        if candidate.name == "src":
            return candidate
    for candidate in above:
        if (candidate / ".git").exists():
            return candidate
    parent = package.parent
    if parent == Path(parent.anchor) or parent == Path.home():
        return package
    return parent


def _searched(folder: Path) -> bool:
    if folder.name.startswith(".") or folder.name in _SKIPPED or folder.is_symlink():
        return False
    return not any((folder / marker).exists() for marker in _IGNORE_MARKERS)


@functools.lru_cache(maxsize=64)
def packages_under(root: Path) -> Mapping[str, Path]:
    """Every package below ``root`` (itself included), by name; the shallowest wins a name.

    Bounded and cached: see the module's description.
    """
    found: dict[str, Path] = {}
    queue: deque[tuple[Path, int]] = deque([(root, 0)])
    visited = 0
    while queue and visited < MAX_FOLDERS:
        folder, depth = queue.popleft()
        visited += 1
        if (folder / "package.xml").is_file():
            found.setdefault(package_name(folder), folder)
            continue  # packages do not nest
        if depth >= MAX_DEPTH:
            continue
        try:
            children = sorted(entry for entry in folder.iterdir() if entry.is_dir())
        except OSError:
            continue
        queue.extend((child, depth + 1) for child in children if _searched(child))
    return found


class PackageFinder:
    """Resolves package names to folders for one description.

    Args:
        description: the description file, whose source tree is searched; None for none.
        given: packages the caller names (a relative folder is taken from the current folder):
            each a package's folder, an install prefix or a share folder (:func:`given_package`).
        bundled: packages that are always known (searched after the source tree).
    """

    def __init__(
        self,
        description: Path | None,
        given: Mapping[str, str | os.PathLike[str]],
        bundled: Mapping[str, str | os.PathLike[str]] | None = None,
    ) -> None:
        self.given = {
            name: given_package(name, Path(folder).absolute()) for name, folder in given.items()
        }
        #: How the caller wrote each given package's folder, by the folder it stands for.
        self.spelled = {
            Path(os.path.abspath(self.given[name])): os.path.normpath(
                os.path.join(folder, os.path.relpath(self.given[name], Path(folder).absolute()))
            )
            for name, folder in given.items()
        }
        self.relative = description is not None and not description.is_absolute()
        self.bundled = {name: Path(folder) for name, folder in (bundled or {}).items()}
        self.tree = source_tree(description) if description is not None else None

    def locate(self, name: str) -> Path | None:
        """The package's folder, or None when no place knows it."""
        if name in self.given:
            return self.given[name]
        if not plain_name(name):
            return None
        if self.tree is not None:
            found = packages_under(self.tree).get(name)
            if found is not None:
                return found
        if name in self.bundled:
            return self.bundled[name]
        # a relative entry is from the current folder: $(find) must not give a relative folder,
        # which xacro would take from the including file's
        for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
            candidate = (
                folder_below(Path(prefix).absolute() / "share", name, links=True)
                if prefix
                else None
            )
            if candidate is not None:
                return candidate
        for entry in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
            if entry and Path(entry).is_dir():
                found = packages_under(resolved(entry, PackageNotFoundError)).get(name)
                if found is not None:
                    return found
        return None

    def shown(self, path: str | os.PathLike[str]) -> str:
        """A path as the user would write it: in a given package, from the folder as given;
        else from the current folder when the description was given so and it lies below;
        else as it is."""
        absolute = Path(os.path.abspath(path))
        for folder, spelled in self.spelled.items():
            if absolute == folder or folder in absolute.parents:
                return os.path.join(spelled, os.path.relpath(absolute, folder)).removesuffix("/.")
        if self.relative and Path.cwd() in absolute.parents:
            return os.path.relpath(absolute)
        return os.fspath(path)
