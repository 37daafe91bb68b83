"""What a path given as the robot is, when it is no description: a ROS package folder (its
descriptions are listed), a controllers YAML (it goes to ``--controllers``), a launch file.

Only names are looked at, and the head of a YAML file: nothing is run, nothing is read past
:data:`HEAD_BYTES`, and the walk of a folder is bounded (:data:`MAX_ENTRIES`, :data:`MAX_DEPTH`).
"""

from __future__ import annotations

import contextlib
import os
import stat
from pathlib import Path
from typing import Final

from diffbot.errors import DescriptionError
from diffbot.io.textfile import open_regular

__all__ = [
    "HEAD_BYTES",
    "LAUNCH_SUFFIXES",
    "MAX_DEPTH",
    "MAX_ENTRIES",
    "MAX_LISTED",
    "descriptions_in",
    "is_controllers_file",
    "is_launch_file",
    "is_package_folder",
    "not_a_description",
]

#: Endings of ROS launch files (Python, XML, YAML; ``.launch`` is ROS 1's XML).
LAUNCH_SUFFIXES: Final = (".launch.py", ".launch.xml", ".launch.yaml", ".launch")
#: Endings of the descriptions a package folder is searched for.
_DESCRIPTION_SUFFIXES: Final = (".urdf", ".urdf.xacro", ".sdf")
#: Most entries of a folder's tree looked at when listing its descriptions.
MAX_ENTRIES: Final = 5000
#: Deepest folder below a package searched for descriptions (``urdf/`` is 1, ``models/x/`` 2,
#: ``description/batch/<robot>/urdf/`` 4); the walk is bounded by :data:`MAX_ENTRIES` too.
MAX_DEPTH: Final = 8
#: Most descriptions named in a message; the rest are counted.
MAX_LISTED: Final = 12
#: Most bytes of a YAML file read to tell a controllers file.
HEAD_BYTES: Final = 65536

_SKIPPED: Final = frozenset({"build", "install", "log", "node_modules", "__pycache__"})
#: Words only a ros2_control (or ROS 1 controller) parameters file holds.
_CONTROLLER_WORDS: Final = ("ros__parameters", "controller_manager", "diff_drive_controller")


def is_package_folder(path: Path) -> bool:
    """Whether ``path`` is a folder holding a ``package.xml``."""
    with contextlib.suppress(OSError, ValueError):
        return path.is_dir() and (path / "package.xml").is_file()
    return False


def is_launch_file(path: Path) -> bool:
    """Whether ``path``'s name is a ROS launch file's."""
    return path.name.lower().endswith(LAUNCH_SUFFIXES)


def descriptions_in(folder: Path) -> tuple[list[Path], int]:
    """The robot descriptions below ``folder`` (``.urdf``, ``.urdf.xacro``, ``.sdf``), those in
    a ``urdf`` folder first (a robot's top-level description lives there, its pieces often
    beside it in other folders), then the shallower, then by path; at most
    :data:`MAX_LISTED`, and how many there are in all.

    The walk skips hidden, build and install folders and follows no symbolic link.
    """
    found: list[Path] = []
    pending: list[tuple[Path, int]] = [(folder, 0)]
    seen = 0
    while pending and seen < MAX_ENTRIES:
        current, depth = pending.pop()
        try:
            with os.scandir(current) as listing:
                entries = sorted(listing, key=lambda entry: entry.name)
        except OSError:
            continue
        for entry in entries:
            seen += 1
            if seen > MAX_ENTRIES:
                break
            with contextlib.suppress(OSError):
                mode = entry.stat(follow_symlinks=False).st_mode
                name = entry.name
                if stat.S_ISDIR(mode):
                    if depth < MAX_DEPTH and not name.startswith(".") and name not in _SKIPPED:
                        pending.append((Path(entry.path), depth + 1))
                elif stat.S_ISREG(mode) and name.lower().endswith(_DESCRIPTION_SUFFIXES):
                    found.append(Path(entry.path).relative_to(folder))
    found.sort(key=lambda p: ("urdf" not in p.parts[:-1], len(p.parts), p.as_posix()))
    return found[:MAX_LISTED], len(found)


def is_controllers_file(path: Path) -> bool:
    """Whether ``path`` is a YAML file whose head holds a word only controller parameters do
    (``ros__parameters``, ``controller_manager``, ``diff_drive_controller``)."""
    if not path.name.lower().endswith((".yaml", ".yml")):
        return False
    try:
        fd = open_regular(path, DescriptionError, "a controllers file")
    except (OSError, DescriptionError):
        return False
    try:
        head = os.read(fd, HEAD_BYTES).decode("utf-8", "replace")
    except OSError:
        return False
    finally:
        os.close(fd)
    return any(word in head for word in _CONTROLLER_WORDS)


def not_a_description(robot: str) -> str | None:
    """Why the path ``robot``, given as the robot, is no description, as one line telling what
    to give instead; None when it may be one (left to the description readers to judge).

    A folder that is neither an SDF model nor a bag lists the descriptions inside it; a
    controllers YAML is told to go to ``--controllers``; a launch file to be replaced by the
    description it loads.
    """
    path = Path(robot)
    if path.is_dir():
        if any((path / name).exists() for name in ("model.config", "model.sdf", "metadata.yaml")):
            return None
        kind = "a ROS package folder" if is_package_folder(path) else "a directory"
        listed, total = descriptions_in(path)
        if not listed:
            return (
                f"{robot}: is {kind}, not a robot description, and holds none (no .urdf, "
                ".urdf.xacro or .sdf file): give the description file"
            )
        names = ", ".join(os.path.join(robot, p) for p in listed)
        more = f" and {total - len(listed)} more" if total > len(listed) else ""
        return f"{robot}: is {kind}, not a robot description: give one of its descriptions: " + (
            names + more
        )
    if is_launch_file(path):
        return (
            f"{robot}: is a launch file, which diffbot does not run: give the description it loads "
            "(its .urdf.xacro, with the arguments it passes as NAME:=VALUE), and the controllers "
            "YAML it starts with --controllers FILE"
        )
    if is_controllers_file(path):
        return (
            f"{robot}: is a controllers file, not a robot description: give it with "
            f"--controllers {robot}, beside the description (.urdf, .urdf.xacro or .sdf)"
        )
    return None
