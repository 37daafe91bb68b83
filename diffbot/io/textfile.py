"""Opening text inputs: regular files only, with one-line errors of the caller's kind."""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterator
from typing import TextIO

from diffbot.errors import DiffbotError
from diffbot.io.outputs import note_input

__all__ = ["check_regular", "open_regular", "open_text", "read_text"]


def check_regular(
    path: str | os.PathLike[str], error: type[DiffbotError], kind: str, *, name: str | None = None
) -> None:
    """Refuse, by its type and before it is opened, anything but an existing regular file.

    A FIFO would block its reader and a device (``/dev/zero``) feed it endless data. The file is
    noted as an input of the run (:func:`diffbot.io.outputs.note_input`): no output goes over it.

    Raises:
        error: the file is missing, a directory, a FIFO, socket or device, or cannot be examined.
    """
    name = os.fspath(path) if name is None else name
    note_input(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise error(f"{name}: no such file") from None
    except OSError as err:
        raise error(f"{name}: cannot read ({err.strerror})") from None
    if stat.S_ISDIR(mode):
        raise error(f"{name}: is a directory, not {kind}")
    if not stat.S_ISREG(mode):
        raise error(f"{name}: not a regular file (a FIFO, socket or device), not {kind}")


@contextlib.contextmanager
def open_text(
    path: str | os.PathLike[str],
    error: type[DiffbotError],
    kind: str,
    *,
    name: str | None = None,
    newline: str | None = None,
    keep_bom: bool = False,
) -> Iterator[TextIO]:
    """Open a UTF-8 text file for reading (a leading BOM dropped, unless ``keep_bom``).

    Only a regular file is opened: a FIFO, a device or a directory is refused by its type first,
    so that none can block or feed endless data.

    Args:
        path: the file.
        error: the error to raise, for example ``PlanError``.
        kind: what the file should be, for messages ("a plan file").
        name: the input's name in messages (default: the path).
        newline: as for :func:`open` (``""`` for CSV).
        keep_bom: read a leading BOM as the character U+FEFF, for a copy that must keep every
            byte it does not change.

    Raises:
        error: the file is missing, not a regular file, not UTF-8 text, or unreadable (also while
            the caller reads it).
    """
    name = os.fspath(path) if name is None else name
    check_regular(path, error, kind, name=name)
    try:
        fd = open_regular(path, error, kind, name=name)
        # a BOM is not part of the content
        encoding = "utf-8" if keep_bom else "utf-8-sig"
        with open(fd, encoding=encoding, newline=newline) as handle:
            yield handle
    except FileNotFoundError:
        raise error(f"{name}: no such file") from None
    except IsADirectoryError:
        raise error(f"{name}: is a directory, not {kind}") from None
    except UnicodeDecodeError as err:
        raise error(f"{name}: not a text file ({err.reason})") from None
    except OSError as err:
        raise error(f"{name}: cannot read ({err.strerror})") from None


def open_regular(
    path: str | os.PathLike[str], error: type[DiffbotError], kind: str, *, name: str | None = None
) -> int:
    """A descriptor for reading a file already checked by :func:`check_regular`: opened without
    blocking and checked again, in case the file was swapped for a FIFO in between.

    Raises:
        error: it is no longer a regular file.
        OSError: it cannot be opened.
    """
    name = os.fspath(path) if name is None else name
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise error(f"{name}: not a regular file (a FIFO, socket or device), not {kind}")
    return fd


def read_text(
    path: str | os.PathLike[str],
    error: type[DiffbotError],
    kind: str,
    *,
    max_chars: int | None = None,
) -> str:
    """The text of a UTF-8 file (a leading BOM dropped); see :func:`open_text`.

    Raises:
        error: as :func:`open_text`, or the file holds more than ``max_chars`` characters
            (found without reading past them).
    """
    with open_text(path, error, kind) as handle:
        if max_chars is None:
            return handle.read()
        text = handle.read(max_chars + 1)
    if len(text) > max_chars:
        raise error(f"{os.fspath(path)}: {kind} of more than {max_chars} characters")
    return text
