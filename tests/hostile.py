"""A folder of modules that must never run: each one, imported, writes its name to a marker."""

from __future__ import annotations

from pathlib import Path

#: Module files that shadow what a child process of diffbot imports first.
SHADOWS = (
    "json.py",
    "numpy.py",
    "diffbot.py",
    "diffbot/__init__.py",
    "multiprocessing/__init__.py",
)


def hostile_folder(folder: Path, marker: Path) -> Path:
    """``folder`` filled with :data:`SHADOWS`, each appending its own name to ``marker``."""
    for name in SHADOWS:
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(
            f"with open({str(marker)!r}, 'a') as _out:\n    _out.write({name!r} + '\\n')\n",
            encoding="utf-8",
        )
    return folder


#: Runs the diffbot CLI from the current folder without putting that folder on this process's
#: own path (as the installed ``diffbot`` script does), so only children can be caught.
CLI = (
    "import sys\n"
    "sys.path[:] = [p for p in sys.path if p]\n"
    "from diffbot.cli import main\n"
    "main(sys.argv[1:], prog_name='diffbot')\n"
)
