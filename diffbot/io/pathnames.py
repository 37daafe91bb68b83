"""Resolving paths: the one place a path is made absolute with its links followed.

A loop of symbolic links makes :meth:`pathlib.Path.resolve` raise ``RuntimeError`` on Python
3.11 and ``OSError`` on others; a name too long, a NUL byte or a folder without permission raise
other errors. Each becomes one error of the caller's kind here, so no reader, output check or
package search ends in a traceback on a hostile path.
"""

from __future__ import annotations

import errno
import os
from pathlib import Path

from diffbot.errors import DiffbotError, PathError

__all__ = ["resolved"]


def resolved(
    path: str | os.PathLike[str],
    error: type[DiffbotError] = PathError,
    *,
    name: str | None = None,
) -> Path:
    """``path`` made absolute, its links followed (what does not exist is kept as written).

    Args:
        path: the path.
        error: the error to raise, for example ``DescriptionError``.
        name: the path's name in messages (default: the path as given).

    Raises:
        error: the path is a loop of symbolic links, or cannot be resolved (too long, a NUL
            byte, a folder that cannot be searched).
    """
    shown = os.fspath(path) if name is None else name
    try:
        return Path(path).resolve()
    except RuntimeError:  # Python 3.11: "Symlink loop from ..."
        raise error(f"{shown}: a loop of symbolic links", path=shown) from None
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise error(f"{shown}: a loop of symbolic links", path=shown) from None
        raise error(f"{shown}: cannot be resolved ({err.strerror or err})", path=shown) from None
    except ValueError as err:  # a NUL byte
        raise error(f"{shown}: cannot be resolved ({err})", path=shown) from None
