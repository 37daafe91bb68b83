"""xacro expansion without ROS: ``$(find)`` from given package folders, warnings collected.

Descriptions are untrusted unless the caller vouches for them (``trust``): they expand in the
sandbox of :mod:`diffbot.urdf.sandbox`, which also bounds the work and records the files read.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from diffbot.errors import DescriptionError, PackageNotFoundError
from diffbot.formats.text import one_line
from diffbot.io.pathnames import resolved
from diffbot.io.textfile import read_text
from diffbot.io.xmlhead import prolog_end
from diffbot.numbers import flag
from diffbot.urdf.packages import PackageFinder

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
        named_from: for each ``<parameters>`` text an included file wrote, that file's folder:
            a relative name in it starts there (elsewhere, from the description's folder).
        arguments: the xacro arguments the description declares or reads, sorted.
    """

    urdf: str
    warnings: tuple[str, ...] = ()
    files: tuple[Path, ...] = ()
    folders: tuple[Path, ...] = ()
    named_from: tuple[tuple[str, Path], ...] = ()
    arguments: tuple[str, ...] = ()


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


def _asked_by(source: Path) -> str:
    """The include chain being expanded (innermost first), for a message."""
    import xacro

    files = [Path(str(f)).name for f in (xacro.filestack or ()) if f]
    if not files:
        return source.name
    return " <- ".join(reversed(files))


def _package_resolver(source: Path, finder: PackageFinder) -> Any:
    from diffbot.urdf.packages import package_name

    checked: set[str] = set()

    def find(pkg: str) -> str:
        found = finder.locate(pkg)
        if found is not None:
            if pkg in finder.given and pkg not in checked:
                checked.add(pkg)
                held = package_name(found)
                if held != pkg and (found / "package.xml").is_file():
                    # stderr is the expansion's warnings (see _run_xacro)
                    print(
                        f"warning: the folder given for package {pkg!r} "
                        f"({finder.shown(found)}) holds package {held!r}: $(find {pkg}) "
                        "reads it all the same",
                        file=sys.stderr,
                    )
            return str(found)
        raise PackageNotFoundError(
            f"package {pkg!r} not found (needed by {_asked_by(source)}): give its directory "
            f"with {{packages}} {pkg}=DIR",
            package=pkg,
            missing=[pkg],
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
        path: a .urdf or .urdf.xacro file, an SDF model (``.sdf``, or a model folder with its
            ``model.config``, read by :mod:`diffbot.urdf.sdf`), a rosbag2 recording (its
            ``/robot_description``); None for the bundled robot.
        args: xacro arguments (``NAME:=VALUE`` on a xacro command line).
        packages: directories of ROS packages, for ``$(find PKG)``. Packages not given are
            looked for in the description's source tree, among the bundled ones, then under
            ``AMENT_PREFIX_PATH`` and ``ROS_PACKAGE_PATH`` (:mod:`diffbot.urdf.packages`).
        trust: let the description run xacro's full Python and read any file. Otherwise its
            expressions are evaluated in a sandbox and it reads files only inside its own folder
            tree (and its ROS package's) and the packages given or found.

    Returns:
        The URDF text and any warnings.

    Raises:
        DescriptionError: the file cannot be read or is not well-formed XML.
        XacroError: xacro failed (bad macro, expression, include).
        PackageNotFoundError: a ``$(find PKG)`` the expansion reaches names an unknown package
            (the message names the include chain that asked for it).
        SandboxError: an untrusted description uses Python the sandbox refuses, reads a file
            outside its folders, or any description grows past the expansion limits.
    """
    trust = flag(trust, "trust")
    source = Path(path) if path is not None else BUNDLED_DESCRIPTION
    given = {str(k): str(v) for k, v in (args or {}).items()}
    finder = PackageFinder(None if path is None else source, packages or {}, BUNDLED_PACKAGES)
    from diffbot.io.bag_description import is_description_bag

    if path is not None and is_description_bag(source):
        return _read_bag(source, given)
    if source.is_dir() or source.suffix == ".sdf":
        return _read_sdf(source, given, finder, trust)
    text = _check_file(source)
    if _is_sdf_text(text):
        return _read_sdf(source, given, finder, trust)
    if not _is_xacro(source, text):
        from diffbot.urdf.sandbox import description_roots

        check_xml(text, str(source))
        warnings = [f"{source} is plain URDF: xacro argument {name!r} ignored" for name in given]
        known = [*finder.given.values(), *finder.bundled.values()]
        folders = (*description_roots(source), *(resolved(p, DescriptionError) for p in known))
        return Expansion(text, tuple(warnings), (source,), folders)
    return _run_xacro(source, given, finder, trust)


def _is_sdf_text(text: str) -> bool:
    """Whether the root element, past the prolog, is ``<sdf>`` (read in time linear in the text,
    however many comments come before it)."""
    start = prolog_end(text)
    if start is None or not text.startswith("<sdf", start) or len(text) == start + 4:
        return False
    after = text[start + 4]
    return after == ">" or after.isspace()


def _read_bag(source: Path, given: Mapping[str, str]) -> Expansion:
    from diffbot.io.bag_description import DESCRIPTION_TOPIC, read_description

    text = read_description(source)
    check_xml(text, f"{source} {DESCRIPTION_TOPIC}")
    warnings = [f"{source} holds a URDF: xacro argument {name!r} ignored" for name in given]
    return Expansion(text, tuple(warnings), (source,))


def _read_sdf(
    source: Path, given: Mapping[str, str], finder: PackageFinder, trust: bool
) -> Expansion:
    from diffbot.urdf.sandbox import description_roots
    from diffbot.urdf.sdf import expand_sdf

    roots = description_roots(source)
    urdf, files = expand_sdf(source, finder, roots, trust=trust)
    warnings = [f"{source} is SDF: xacro argument {name!r} ignored" for name in given]
    # the folders of the models it included count as its own, as a xacro's packages do
    folders = tuple(dict.fromkeys([*roots, *(resolved(f, DescriptionError).parent for f in files)]))
    return Expansion(urdf, tuple(warnings), files, folders)


def _run_xacro(
    source: Path,
    given: dict[str, str],
    finder: PackageFinder,
    trust: bool,
) -> Expansion:
    from diffbot.urdf.sandbox import Reads, process

    mappings = _RecordingArgs(given)
    find = _package_resolver(source, finder)
    stderr = io.StringIO()
    reads = Reads()
    roots = [*finder.given.values(), *finder.bundled.values()]
    with contextlib.redirect_stderr(stderr):
        urdf = process(
            source, mappings, roots=roots, find=find, trust=trust, shown=finder.shown, reads=reads
        )
    warnings = [one_line(line.removeprefix("warning: ")) for line in stderr.getvalue().splitlines()]
    warnings = [w for w in warnings if w]
    for name in given:
        if name not in mappings.seen:
            warnings.append(f"xacro argument {name!r} is not declared by {source.name}: ignored")
    files = tuple(dict.fromkeys([source, *reads.files]))
    return Expansion(
        urdf,
        tuple(warnings),
        files,
        tuple(reads.folders),
        tuple(reads.named_from.items()),
        tuple(sorted(mappings.seen)),
    )


def check_xml(text: str, source: str) -> ET.Element:
    """The root of URDF text (the tree :func:`diffbot.urdf.urdf_model.read_robot` reads);
    rejects text that is not well-formed XML (never 'recovered', as some URDF parsers do) or
    whose root is not ``<robot>``."""
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
