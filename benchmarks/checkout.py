"""Run ``python -m diffbot`` from a given source tree: this checkout, or a git revision of it.

Start-up comparisons against an earlier revision need that revision's package on the import
path, not the installed one. :func:`revision_tree` exports the revision into a temporary folder
(``git archive``: the repository's worktree list and index are left alone, even when the run is
interrupted) and removes it afterwards; :func:`diffbot_command` builds the command line and
environment that import the package of a given tree, and checks once that they do.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tarfile
import tempfile
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from interleave import Side, command

#: The repository this script belongs to (its working tree, uncommitted changes included).
REPOSITORY = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Tree:
    """A source tree holding a ``diffbot`` package.

    Attributes:
        root: the folder holding ``diffbot/``.
        label: how reports name it (a short commit hash, with ``+changes`` when uncommitted work
            is included).
    """

    root: Path
    label: str


def git(*args: str) -> str:
    """Standard output of a git command run in :data:`REPOSITORY`, stripped."""
    done = subprocess.run(
        ["git", "-C", str(REPOSITORY), *args], capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        raise SystemExit(f"git {' '.join(args)} failed: {done.stderr.strip()}")
    return done.stdout.strip()


def working_tree() -> Tree:
    """This checkout as it is on disk."""
    head = git("rev-parse", "--short", "HEAD")
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "diffbot")
    return Tree(REPOSITORY, f"{head}+changes" if dirty else head)


@contextlib.contextmanager
def revision_tree(revision: str) -> Iterator[Tree]:
    """The files of ``revision`` in a temporary folder, removed on exit.

    Raises:
        SystemExit: ``revision`` names no commit of the repository.
    """
    try:
        commit = git("rev-parse", "--verify", "--quiet", f"{revision}^{{commit}}")
    except SystemExit:
        raise SystemExit(f"--baseline {revision}: no such commit in {REPOSITORY}") from None
    with tempfile.TemporaryDirectory(prefix="diffbot-baseline-") as tmp:
        archive = Path(tmp) / "tree.tar"
        git("archive", "--format=tar", f"--output={archive}", commit)
        root = Path(tmp) / "tree"
        with tarfile.open(archive) as tar:
            if hasattr(tarfile, "data_filter"):
                tar.extractall(root, filter="data")
            else:  # Python releases before the extraction filters; the archive is git's own
                tar.extractall(root)
        archive.unlink()
        yield Tree(root, f"{revision} ({commit[:9]})")


def diffbot_side(
    tree: Tree, args: Sequence[str], env: Mapping[str, str], *, cpu: bool = False
) -> Side:
    """A timed side running ``python -m diffbot ARGS`` with ``tree``'s package.

    ``PYTHONPATH`` puts the tree ahead of site-packages (and of an editable install, whose
    finder comes after the path entries); the command runs with the tree as its working
    folder, which ``-m`` puts first on the path.

    Raises:
        SystemExit: the package imported from there is not the tree's.
    """
    environment = dict(env)
    environment["PYTHONPATH"] = os.pathsep.join(
        [str(tree.root), *filter(None, [env.get("PYTHONPATH")])]
    )
    probe = subprocess.run(
        [sys.executable, "-c", "import diffbot; print(diffbot.__file__)"],
        cwd=tree.root,
        env=environment,
        capture_output=True,
        text=True,
        check=False,
    )
    imported = Path(probe.stdout.strip()).resolve() if probe.returncode == 0 else None
    expected = (tree.root / "diffbot" / "__init__.py").resolve()
    if imported != expected:
        raise SystemExit(
            f"python -m diffbot in {tree.root} would import {imported or probe.stderr.strip()}, "
            f"not {expected}"
        )
    argv = [sys.executable, "-m", "diffbot", *args]
    return command(argv, env=environment, cwd=tree.root, cpu=cpu)
