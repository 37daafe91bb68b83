"""xacro expansion without ROS: ``$(find)`` from given package folders, warnings collected.

Descriptions are untrusted unless the caller vouches for them (``trust``): they expand in the
sandbox of :mod:`diffbot.urdf.sandbox`, which also bounds the work and records the files read.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from diffbot.errors import DescriptionError, PackageNotFoundError
from diffbot.formats.text import one_line
from diffbot.io.textfile import read_text

__all__ = ["BUNDLED_DESCRIPTION", "BUNDLED_PACKAGES", "Expansion", "check_xml", "expand"]

_DESCRIPTION_DIR = Path(__file__).resolve().parent.parent / "description"

#: The bundled robot description (the course's diffbot).
BUNDLED_DESCRIPTION = _DESCRIPTION_DIR / "diffbot.urdf.xacro"

#: ROS packages the bundled description refers to with ``$(find ...)``.
BUNDLED_PACKAGES: Mapping[str, Path] = {
    "diffbot_description": _DESCRIPTION_DIR,
    "diffbot_control": _DESCRIPTION_DIR,
}


@dataclass(frozen=True)
class Expansion:
    """An expanded description.

    Attributes:
        urdf: the URDF XML text.
        warnings: what xacro warned about, and xacro arguments the description never declares.
        files: every file the description was read from: the file itself, then what it
            included and the YAML data it loaded.
        folders: the folders an untrusted description may read (its own, its package's, the
            packages given or found by ``$(find PKG)``): files its text names, such as a
            controllers file, are read only there.
    """

    urdf: str
    warnings: tuple[str, ...] = ()
    files: tuple[Path, ...] = ()
    folders: tuple[Path, ...] = ()


class _RecordingArgs(dict[str, str]):
    """xacro's argument table, remembering which names the description declares or reads."""

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.seen: set[str] = set()

    def __contains__(self, key: object) -> bool:
        if isinstance(key, str):
            self.seen.add(key)
        return super().__contains__(key)

    def __getitem__(self, key: str) -> str:
        self.seen.add(key)
        return super().__getitem__(key)


def _locate(pkg: str, packages: Mapping[str, str | os.PathLike[str]]) -> str | None:
    """A package's directory: given (a relative one is taken from the current directory, as a
    shell user means it), then under AMENT_PREFIX_PATH; None when unknown."""
    if pkg in packages:
        return str(Path(packages[pkg]).absolute())
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        candidate = Path(prefix) / "share" / pkg
        if prefix and candidate.is_dir():
            return str(candidate)
    return None


_FIND = re.compile(r"\$\(find\s+([A-Za-z0-9_\-]+)\s*\)")
#: Files of a description's folder scanned for the packages it needs, at most.
_SCANNED = 200


def _needed_packages(source: Path) -> list[str]:
    """Packages named in `$(find ...)` by the description and the xacro files beside it."""
    names: list[str] = []
    files = [source, *sorted(source.parent.rglob("*.xacro"))[:_SCANNED]]
    for path in files:
        if not path.is_file():  # a FIFO or device would block or never end
            continue
        with contextlib.suppress(OSError, UnicodeDecodeError):
            for name in _FIND.findall(path.read_text(encoding="utf-8")):
                if name not in names:
                    names.append(name)
    return names


def _package_resolver(source: Path, packages: Mapping[str, str | os.PathLike[str]]) -> Any:
    def find(pkg: str) -> str:
        found = _locate(pkg, packages)
        if found is not None:
            return found
        missing = [name for name in _needed_packages(source) if _locate(name, packages) is None]
        missing = [pkg, *(name for name in missing if name != pkg)]
        listed = " ".join(f"{{packages}} {name}=DIR" for name in missing)
        what = f"package {pkg!r}" if len(missing) == 1 else f"packages {missing}"
        which = "its directory" if len(missing) == 1 else "their directories"
        raise PackageNotFoundError(
            f"{what} not found: give {which} with {listed}",
            package=pkg,
            missing=missing,
        )

    return find


def _is_xacro(path: Path, text: str) -> bool:
    return path.suffix == ".xacro" or re.search(r"xmlns:xacro\s*=", text) is not None


def _check_file(path: Path) -> str:
    return read_text(path, DescriptionError, "a URDF or xacro file")


def expand(
    path: str | os.PathLike[str] | None = None,
    args: Mapping[str, object] | None = None,
    packages: Mapping[str, str | os.PathLike[str]] | None = None,
    *,
    trust: bool = False,
) -> Expansion:
    """Expand a xacro description (or read a plain URDF) into URDF text.

    Args:
        path: a .urdf or .urdf.xacro file; None for the bundled robot.
        args: xacro arguments (``NAME:=VALUE`` on a xacro command line).
        packages: directories of ROS packages, for ``$(find PKG)``; the bundled robot's packages
            are always known, and ``AMENT_PREFIX_PATH`` is searched last.
        trust: let the description run xacro's full Python and read any file. Otherwise its
            expressions are evaluated in a sandbox and it reads files only inside its own folder
            tree (and its ROS package's) and the packages given or found.

    Returns:
        The URDF text and any warnings.

    Raises:
        DescriptionError: the file cannot be read or is not well-formed XML.
        XacroError: xacro failed (bad macro, expression, include).
        PackageNotFoundError: a ``$(find PKG)`` names an unknown package.
        SandboxError: an untrusted description uses Python the sandbox refuses, reads a file
            outside its folders, or any description grows past the expansion limits.
    """
    source = Path(path) if path is not None else BUNDLED_DESCRIPTION
    text = _check_file(source)
    given = {str(k): str(v) for k, v in (args or {}).items()}
    known: dict[str, str | os.PathLike[str]] = dict(BUNDLED_PACKAGES)
    known.update(packages or {})
    if not _is_xacro(source, text):
        from diffbot.urdf.sandbox import description_roots

        check_xml(text, str(source))
        warnings = [f"{source} is plain URDF: xacro argument {name!r} ignored" for name in given]
        folders = (*description_roots(source), *(Path(p).resolve() for p in known.values()))
        return Expansion(text, tuple(warnings), (source,), folders)
    return _run_xacro(source, given, known, trust)


def _run_xacro(
    source: Path,
    given: dict[str, str],
    packages: Mapping[str, str | os.PathLike[str]],
    trust: bool,
) -> Expansion:
    from diffbot.urdf.sandbox import process

    mappings = _RecordingArgs(given)
    find = _package_resolver(source, packages)
    stderr = io.StringIO()
    files: list[Path] = []
    folders: list[Path] = []
    with contextlib.redirect_stderr(stderr):
        urdf = process(
            source,
            mappings,
            roots=packages.values(),
            find=find,
            trust=trust,
            files=files,
            folders=folders,
        )
    warnings = [one_line(line.removeprefix("warning: ")) for line in stderr.getvalue().splitlines()]
    warnings = [w for w in warnings if w]
    for name in given:
        if name not in mappings.seen:
            warnings.append(f"xacro argument {name!r} is not declared by {source.name}: ignored")
    return Expansion(urdf, tuple(warnings), tuple(dict.fromkeys([source, *files])), tuple(folders))


def check_xml(text: str, source: str) -> ET.Element:
    """The root of URDF text; rejects text that is not well-formed XML (yourdfpy would silently
    'recover' it) or whose root is not ``<robot>``."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as err:
        raise DescriptionError(f"{source}: malformed XML: {err}") from None
    if root.tag != "robot":
        raise DescriptionError(
            f"{source}: not a URDF: the root element is <{root.tag}>, not <robot>"
        )
    return root


# --------------------------------------------------------------------------------------------
# URDF structure -> parameters
