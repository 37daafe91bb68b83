"""Where outputs may go, and writing them whole or not at all.

Outputs never touch an input (compared resolved, links followed; a bag given as one of its files
is its whole directory), never replace an existing file unless asked (``force``), and appear
whole: they are written to a temporary file beside the target, then moved into place. Unless
``force`` is given, the move itself refuses to replace anything (a hard link, or a rename
without replace), so of two runs writing the same new output one wins and the other fails
cleanly, with nothing lost. ``force`` replaces a directory only when it holds a rosbag2
recording this tool could have written (``metadata.yaml`` and storage files, nothing else),
and never anything but a regular file or such a directory (a device, a FIFO, a socket).

Every file a run reads is noted (:func:`note_input`) while a run is guarded (:func:`guarded_run`,
which the command line opens around every command): the paths of the command line as click
parses them (options and arguments of the path types of :mod:`diffbot.commands.paths`), before
the command starts, and each file as its reader opens it (descriptions and what they include,
controllers files, plans, recordings, truth files). Every output check here compares the output
with all of them, so a command cannot forget one.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import sys
import tempfile
import threading
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import TextIO

from diffbot.errors import OutputError, OutputExistsError
from diffbot.io.pathnames import resolved
from diffbot.numbers import flag

__all__ = [
    "BAG_FILES",
    "atomic_text",
    "check_bag_output",
    "check_not_input",
    "check_output_name",
    "check_replaceable",
    "guarded_run",
    "input_clash",
    "move_new",
    "note_input",
    "note_stdin",
    "noted_inputs",
    "output_target",
    "replace_bag",
    "write_text_atomic",
]

#: Storage files of a rosbag2 recording: given one of them, the recording is its directory.
BAG_FILES = (".db3", ".mcap")

# The inputs of the guarded run, in the order noted; None when no run is guarded (library use).
_noted: dict[Path, None] | None = None
#: The device and inode of a regular file redirected into standard input, when read.
_noted_stdin: list[tuple[int, int]] = []
_noted_lock = threading.Lock()


@contextlib.contextmanager
def guarded_run(inputs: Iterable[str | os.PathLike[str]] = ()) -> Iterator[None]:
    """Guard one run: the inputs noted inside it are kept off every output checked inside it.

    Args:
        inputs: inputs known from the start.
    """
    global _noted
    with _noted_lock:
        saved, _noted = _noted, {}
        saved_stdin = _noted_stdin[:]
        _noted_stdin.clear()
    try:
        for path in inputs:
            note_input(path)
        yield
    finally:
        with _noted_lock:
            _noted = saved
            _noted_stdin[:] = saved_stdin


def note_input(path: str | os.PathLike[str]) -> None:
    """Note a file (or a recording's directory) the run reads, before it is read; outputs
    checked afterwards may not be, lie inside or contain it. Does nothing outside a guarded run."""
    with _noted_lock:
        if _noted is not None:
            _noted[Path(os.path.abspath(path))] = None


def note_stdin() -> None:
    """Note standard input as an input of the run: a file redirected into it (``< a.csv``) is
    then kept off every output, as the file named would be."""
    try:
        info = os.fstat(0)
    except OSError:
        return
    with _noted_lock:
        if _noted is not None and stat.S_ISREG(info.st_mode):
            _noted_stdin.append((info.st_dev, info.st_ino))


def noted_inputs() -> tuple[Path, ...]:
    """The inputs noted so far in the guarded run (absolute paths); empty outside one."""
    with _noted_lock:
        return () if _noted is None else tuple(_noted)


def check_output_name(
    path: str, *, folder: bool = False, source: bool = False, holder: bool = False
) -> None:
    """Refuse an output name that names no output of its own: an empty name, the root, or a last
    part ``.`` or ``..`` (``.``, ``/``, ``x.csv/.``, ``out/..``); for a file (``folder`` false),
    also a name ending in a slash. Such a name stands for a folder that already exists (the
    current one, the root, the one holding ``x.csv``), so the output would appear under another
    name than the one asked for, or replace that folder. A folder output (a bag) may end in a
    slash (``run_bag/``). With ``source``, ``path`` is the file read whose changed copy is
    written beside it, under a name made from its own: the same names are refused. With
    ``holder``, ``path`` is a folder that receives outputs (one per input) and may be any
    folder, ``.`` and ``..`` too: only an empty name is refused. ``-`` is refused everywhere:
    it stands for standard output, not for a file of that name.

    Raises:
        OutputError: the name is one of those.
    """
    if not path.strip():
        raise OutputError(f"{path!r}: an empty name, not a file or folder name", path=path)
    if path == "-":  # what reads standard input where a recording is named
        raise OutputError(
            "-: standard output, not a file: without the output option the output goes there; "
            "write ./- for a file named '-'",
            path=path,
        )
    if holder:
        return
    separators = "/" + os.sep
    trimmed = path.rstrip(separators)
    if folder:
        refused = "a folder that exists: give the output a name of its own"
    else:
        refused = f"a folder, but a file is {'read' if source else 'written'} there"
    if not trimmed:
        raise OutputError(f"{path}: the root, {refused}", path=path)
    if trimmed != path and not folder:
        raise OutputError(f"{path}: ends with a slash, {refused}", path=path)
    last = trimmed
    for separator in separators:
        last = last.rpartition(separator)[2]
    if last in (".", ".."):
        raise OutputError(f"{path}: ends with {last!r}, {refused}", path=path)


def check_replaceable(path: Path) -> None:
    """Refuse to replace what ``path`` names unless it is a regular file or a directory (whose
    content the caller judges): never a device, a FIFO or a socket, even with ``force``.

    Raises:
        OutputError: it names a device, a FIFO or a socket (links followed).
    """
    try:
        mode = os.stat(path).st_mode
    except OSError:  # nothing there, or a dangling link: nothing to lose
        return
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise OutputError(
            f"{path} is not a regular file (a device, FIFO or socket): refusing to replace it, "
            "even with {force}",
            path=str(path),
        )


def _occupied(path: Path) -> Path:
    """The resolved path an input occupies: a bag given as one of its files is its directory."""
    real = resolved(path)
    if (
        real.is_file()
        and real.suffix.lower() in BAG_FILES
        and (real.parent / "metadata.yaml").is_file()
    ):
        return real.parent
    return real


def _identity(path: Path) -> tuple[int, int] | None:
    """The device and inode of an existing file (one file under several hard links has one),
    or None."""
    try:
        info = path.stat()
    except OSError:
        return None
    return info.st_dev, info.st_ino


def input_clash(target: Path, inputs: Sequence[Path] = ()) -> tuple[str, Path] | None:
    """How an output path would touch an input: ("is" | "inside" | "contains", that input).

    The inputs are ``inputs`` and every input noted in the guarded run (:func:`note_input`).
    Paths are compared resolved, links followed, and an existing output by its device and inode
    (a hard link to an input is that input); a bag given as one of its files is its whole
    directory. None when the output touches no input.

    Raises:
        OutputError: the output is a loop of symbolic links, or cannot be resolved.
        PathError: an input cannot be resolved.
    """
    real = resolved(target, OutputError)
    identity = _identity(real)
    if identity is not None:
        with _noted_lock:
            if identity in _noted_stdin:
                return "is", Path("-")
    for given in dict.fromkeys([*inputs, *noted_inputs()]):
        occupied = _occupied(given)
        if real == occupied or (identity is not None and identity == _identity(occupied)):
            return "is", given
        if occupied in real.parents:
            return "inside", given
        if real in occupied.parents:
            return "contains", given
    return None


def output_target(path: Path, *, force: bool, inputs: Sequence[Path] = ()) -> Path:
    """Check where an output may go; return the real path to replace (links followed).

    Raises:
        OutputExistsError: the path exists and ``force`` is not given.
        OutputError: it is not a regular file (a directory, a device), lies in a missing
            directory, is (or is inside) one of the ``inputs``, or is a loop of symbolic links.
    """
    force = flag(force, "force", OutputError)
    target = resolved(path, OutputError) if path.is_symlink() else path
    # An input is never written, force or not: say so rather than offer force.
    check_not_input(path, target, inputs)
    if path.exists() or path.is_symlink():
        if not force:
            raise OutputExistsError(f"{path} exists: use {{force}} to overwrite it", path=str(path))
        check_replaceable(target)
        if target.exists() and not target.is_file():
            raise OutputError(
                f"{path} is not a regular file: refusing to replace it", path=str(path)
            )
    if not target.parent.is_dir():
        raise OutputError(f"{path}: directory {target.parent} does not exist", path=str(path))
    return target


def check_not_input(path: Path, target: Path | None = None, inputs: Sequence[Path] = ()) -> None:
    """Refuse an output that is, lies inside or contains an input (given or noted).

    Args:
        path: the output, as given.
        target: where it really goes (links followed), if known; else ``path``.
        inputs: inputs besides those noted in the guarded run.

    Raises:
        OutputError: it is, lies inside or contains an input.
    """
    clash = input_clash(path if target is None else target, inputs)
    if clash is not None:
        relation, given = clash
        what = {"is": "is an input", "inside": "lies inside the input", "contains": "contains"}
        detail = "" if relation == "is" else f" {given}"
        raise OutputError(
            f"{path} {what[relation]}{detail}: refusing to overwrite it", path=str(path)
        )


@contextlib.contextmanager
def atomic_text(
    path: Path,
    *,
    force: bool,
    inputs: Sequence[Path] = (),
    executable: bool = False,
) -> Iterator[TextIO]:
    """A text file to write as it comes that appears whole or not at all: a temporary file
    beside it, renamed over it when the block ends without an error (removed otherwise).

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
            yield out
            try:
                out.flush()
            except OSError as err:  # a full disk, a quota
                raise OutputError(
                    f"{path}: cannot write ({err.strerror})", path=str(path)
                ) from None
        os.chmod(tmp, mode)
        if force:
            os.replace(tmp, target)
        else:
            move_new(Path(tmp), target, shown=path)
    finally:
        Path(tmp).unlink(missing_ok=True)


def _lost_race(path: Path) -> OutputExistsError:
    return OutputExistsError(
        f"{path} was created by another program while this output was written: left as it "
        "is; use {force} to overwrite it",
        path=str(path),
    )


def _rename_noreplace(source: Path, target: Path) -> bool:
    """Rename without replacing (Linux ``renameat2(RENAME_NOREPLACE)``); False if unavailable.

    Raises:
        FileExistsError: ``target`` exists.
    """
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except AttributeError:  # a C library without it
        return False
    at_fdcwd, rename_noreplace = -100, 1
    result = renameat2(
        at_fdcwd, os.fsencode(source), at_fdcwd, os.fsencode(target), rename_noreplace
    )
    if result == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP):  # kernel or file system lacks it
        return False
    raise OSError(code, os.strerror(code), str(target))


def move_new(source: Path, target: Path, *, shown: Path | None = None) -> None:
    """Move a finished file or directory to ``target``, which must not exist, atomically.

    A file is hard-linked to its new name (which fails if the name exists) and then unlinked;
    a directory is renamed without replace. Between a check and a rename, another program
    could create ``target``; this way it cannot be lost.

    Raises:
        OutputExistsError: ``target`` exists (another program won the race).
    """
    try:
        if source.is_file() and _link(source, target):
            source.unlink()
            return
        if _rename_noreplace(source, target):
            return
        if target.exists() or target.is_symlink():  # no atomic way here: the best check
            raise FileExistsError
        os.rename(source, target)
    except FileExistsError:
        raise _lost_race(shown or target) from None


def _link(source: Path, target: Path) -> bool:
    """Hard-link ``source`` as ``target``; False where the file system has no hard links."""
    try:
        os.link(source, target)
    except FileExistsError:
        raise
    except OSError as err:
        if err.errno in (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.EMLINK):
            return False
        raise
    return True


def write_text_atomic(
    path: Path,
    text: str,
    *,
    force: bool,
    inputs: Sequence[Path] = (),
    executable: bool = False,
) -> None:
    """Write a whole file or nothing (see :func:`atomic_text`)."""
    with atomic_text(path, force=force, inputs=inputs, executable=executable) as out:
        try:
            out.write(text)
        except OSError as err:  # a full disk, a quota
            raise OutputError(f"{path}: cannot write ({err.strerror})", path=str(path)) from None


def check_bag_output(path: Path, force: bool) -> None:
    """Check that a bag may be written at ``path`` (before any work is done).

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that
            holds anything but a rosbag2 recording (``metadata.yaml`` and storage files).
        OutputError: its directory does not exist, it is a device, FIFO or socket, or it is,
            lies inside or contains an input.
    """
    force = flag(force, "force", OutputError)
    check_not_input(path, path)
    if (path.exists() or path.is_symlink()) and not force:
        raise OutputExistsError(f"{path} exists: use {{force}} to overwrite it", path=str(path))
    check_replaceable(path)
    _check_replaceable_bag(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"{path}: directory {parent} does not exist", path=str(path))


def _check_replaceable_bag(path: Path) -> None:
    """Refuse a directory at ``path`` unless it is empty or a bag this tool could have written:
    ``force`` replaces files and such bags, never a directory of anything else."""
    if not path.is_dir() or path.is_symlink():
        return
    others = sorted(
        entry.name
        for entry in path.iterdir()
        if not entry.is_file()
        or entry.is_symlink()
        or (entry.name != "metadata.yaml" and entry.suffix.lower() not in BAG_FILES)
    )
    if others or (any(path.iterdir()) and not (path / "metadata.yaml").is_file()):
        shown = f" (it holds {', '.join(others[:3])}{', ...' if len(others) > 3 else ''})"
        raise OutputExistsError(
            f"{path} is a directory that is not a rosbag2 recording"
            f"{shown if others else ''}: refusing to replace it",
            path=str(path),
        )


def replace_bag(new: Path, path: Path, force: bool) -> None:
    """Move a finished bag directory ``new`` to ``path``, replacing what is there if ``force``
    and it is a file or a bag (checked again now, not only before the work)."""
    check_not_input(path, path)
    if not force:
        move_new(new, path)
        return
    if not (path.exists() or path.is_symlink()):
        os.replace(new, path)
        return
    check_replaceable(path)
    _check_replaceable_bag(path)
    old = Path(tempfile.mkdtemp(dir=new.parent, prefix="old."))
    os.replace(path, old / path.name)
    try:
        os.replace(new, path)
    except BaseException:
        os.replace(old / path.name, path)
        raise
