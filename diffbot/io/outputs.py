"""Where outputs may go, and writing them whole or not at all.

Outputs never touch an input (compared resolved, links followed; a bag given as one of its files
is its whole directory), never replace an existing file unless asked (``force``), and appear
whole: they are written to a temporary file beside the target, then renamed over it.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Sequence
from pathlib import Path

from diffbot.errors import OutputError, OutputExistsError

__all__ = [
    "BAG_FILES",
    "check_bag_output",
    "input_clash",
    "output_target",
    "replace_bag",
    "write_text_atomic",
]

#: Storage files of a rosbag2 recording: given one of them, the recording is its directory.
BAG_FILES = (".db3", ".mcap")


def _occupied(path: Path) -> Path:
    """The resolved path an input occupies: a bag given as one of its files is its directory."""
    resolved = path.resolve()
    if (
        resolved.is_file()
        and resolved.suffix.lower() in BAG_FILES
        and (resolved.parent / "metadata.yaml").is_file()
    ):
        return resolved.parent
    return resolved


def input_clash(target: Path, inputs: Sequence[Path]) -> tuple[str, Path] | None:
    """How an output path would touch an input: ("is" | "inside" | "contains", that input).

    Paths are compared resolved, links followed; a bag given as one of its files is its whole
    directory. None when the output touches no input.
    """
    resolved = target.resolve()
    for given in inputs:
        occupied = _occupied(given)
        if resolved == occupied:
            return "is", given
        if occupied in resolved.parents:
            return "inside", given
        if resolved in occupied.parents:
            return "contains", given
    return None


def output_target(path: Path, *, force: bool, inputs: Sequence[Path] = ()) -> Path:
    """Check where an output may go; return the real path to replace (links followed).

    Raises:
        OutputExistsError: the path exists and ``force`` is not given.
        OutputError: it is not a regular file (a directory, a device), lies in a missing
            directory, or is (or is inside) one of the ``inputs``.
    """
    target = path.resolve() if path.is_symlink() else path
    if path.exists() or path.is_symlink():
        if not force:
            raise OutputExistsError(f"{path} exists: use {{force}} to overwrite it", path=str(path))
        if target.exists() and not target.is_file():
            raise OutputError(
                f"{path} is not a regular file: refusing to replace it", path=str(path)
            )
    if not target.parent.is_dir():
        raise OutputError(f"{path}: directory {target.parent} does not exist", path=str(path))
    clash = input_clash(target, inputs)
    if clash is not None:
        relation, given = clash
        what = {"is": "is an input", "inside": "lies inside the input", "contains": "contains"}
        detail = "" if relation == "is" else f" {given}"
        raise OutputError(
            f"{path} {what[relation]}{detail}: refusing to overwrite it", path=str(path)
        )
    return target


def write_text_atomic(
    path: Path,
    text: str,
    *,
    force: bool,
    inputs: Sequence[Path] = (),
    executable: bool = False,
) -> None:
    """Write a whole file or nothing: a temporary file beside it, then a rename.

    The file gets the permissions of the file it replaces, or the usual ones (umask applied;
    executable ones for scripts).
    """
    target = output_target(path, force=force, inputs=inputs)
    if target.exists():
        mode = stat.S_IMODE(target.stat().st_mode)
    else:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    if executable:
        mode |= (mode & 0o444) >> 2  # x wherever r
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def check_bag_output(path: Path, force: bool) -> None:
    """Check that a bag may be written at ``path`` (before any work is done).

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that
            holds something other than a rosbag2 recording.
        OutputError: its directory does not exist.
    """
    if (path.exists() or path.is_symlink()) and not force:
        raise OutputExistsError(f"{path} exists: use {{force}} to overwrite it", path=str(path))
    if path.is_dir() and any(path.iterdir()) and not (path / "metadata.yaml").exists():
        # force replaces files and earlier bags, never a directory of something else.
        raise OutputExistsError(
            f"{path} is a directory that is not a rosbag2 recording", path=str(path)
        )
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"{path}: directory {parent} does not exist", path=str(path))


def replace_bag(new: Path, path: Path, force: bool) -> None:
    """Move a finished bag directory ``new`` to ``path``, replacing what is there if ``force``."""
    if not (path.exists() or path.is_symlink()):
        os.replace(new, path)
        return
    if not force:
        raise OutputExistsError(f"{path} exists: use {{force}} to overwrite it", path=str(path))
    old = Path(tempfile.mkdtemp(dir=new.parent, prefix="old."))
    os.replace(path, old / path.name)
    try:
        os.replace(new, path)
    except BaseException:
        os.replace(old / path.name, path)
        raise
