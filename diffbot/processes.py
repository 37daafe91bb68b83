"""Child Python processes that never import code from the current folder.

A command is often run inside a robot description's repository, and that folder is untrusted:
a ``json.py``, ``numpy.py`` or ``diffbot/`` there must not run. A plain ``python -c`` child
puts the current folder first on ``sys.path``, so every child this package starts goes through
here instead:

- :func:`python_command` starts an isolated interpreter (``python -I``: no current folder, no
  ``PYTHON*`` variables, no user site) whose ``sys.path`` is this process's own minus the current
  folder, and which loads this very ``diffbot`` package from where this process loaded it (an
  editable install or a checkout included), never by a search of the path;
- :func:`safe_starts` covers the interpreters a process pool starts itself (the ``spawn`` and
  ``forkserver`` methods): they are told, through ``PYTHONSAFEPATH``, not to put the current
  folder on their path before the pool hands them this process's own.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from pathlib import Path

__all__ = ["clean_path", "python_command", "safe_starts"]

#: What a child runs first: the path it is given, then this package loaded from its own folder.
_PRELUDE = """\
import sys
sys.path[:] = {path!r}
import importlib.util
spec = importlib.util.spec_from_file_location(
    "diffbot", {init!r}, submodule_search_locations=[{package!r}]
)
module = importlib.util.module_from_spec(spec)
sys.modules["diffbot"] = module
spec.loader.exec_module(module)
"""


def _same_place(a: str, b: str) -> bool:
    with contextlib.suppress(OSError):
        return os.path.samefile(a, b)
    return False


def clean_path(path: list[str] | None = None) -> list[str]:
    """``path`` (default ``sys.path``) without the current folder and without relative entries.

    A relative entry (``''`` above all) is looked up from the current folder, wherever that is
    when the import happens, so it goes too.
    """
    here = os.getcwd()
    return [
        entry
        for entry in (sys.path if path is None else path)
        if os.path.isabs(entry) and not _same_place(entry, here)
    ]


def python_command(code: str) -> list[str]:
    """The command line of an isolated interpreter that runs ``code`` with this diffbot loaded.

    ``code`` may import any ``diffbot`` module; the standard library and installed packages come
    from this process's own path (without the current folder).
    """
    package = Path(__file__).resolve().parent
    prelude = _PRELUDE.format(
        path=clean_path(), init=str(package / "__init__.py"), package=str(package)
    )
    return [sys.executable, "-I", "-c", prelude + code]


@contextlib.contextmanager
def safe_starts() -> Iterator[None]:
    """Interpreters started inside this block keep the current folder off their path.

    Sets ``PYTHONSAFEPATH`` (Python 3.11 and later) for the block only; start every process of a
    pool inside it (a pool started with ``fork`` starts no new interpreter and needs nothing).
    """
    before = os.environ.get("PYTHONSAFEPATH")
    os.environ["PYTHONSAFEPATH"] = "1"
    try:
        yield
    finally:
        if before is None:
            os.environ.pop("PYTHONSAFEPATH", None)
        else:
            os.environ["PYTHONSAFEPATH"] = before
