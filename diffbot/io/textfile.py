"""Reading a whole text input file, with one-line errors of the caller's kind."""

from __future__ import annotations

import os

from diffbot.errors import DiffbotError


def read_text(path: str | os.PathLike[str], error: type[DiffbotError], kind: str) -> str:
    """The text of a UTF-8 file (a leading BOM dropped).

    Args:
        path: the file.
        error: the error to raise, for example ``PlanError``.
        kind: what the file should be, for messages ("a plan file").

    Raises:
        error: the file is missing, a directory, not UTF-8 text, or unreadable.
    """
    name = os.fspath(path)
    try:
        with open(name, encoding="utf-8-sig") as handle:  # a BOM is not part of the content
            return handle.read()
    except FileNotFoundError:
        raise error(f"{name}: no such file") from None
    except IsADirectoryError:
        raise error(f"{name}: is a directory, not {kind}") from None
    except UnicodeDecodeError as err:
        raise error(f"{name}: not a text file ({err.reason})") from None
    except OSError as err:
        raise error(f"{name}: cannot read ({err.strerror})") from None
