"""Warnings said once: ``-q/--quiet`` on every command silences them, and a description's
warnings, once shown in full, come back on later commands as one line saying how many there are
and how to see them (``diffbot params`` and ``diffbot check`` always show them all).

Which warnings were shown is remembered in the parameter cache's folder
(:func:`diffbot.urdf.cache.cache_dir`), one empty file per description and set of warnings,
named by a digest of both: nothing is read back but whether the file exists. Without a cache
(``DIFFBOT_NO_CACHE=1``, or a folder that cannot be written), every warning is shown every time.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shlex
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Final

import click

__all__ = ["QUIET_KEY", "SHOWN_FOLDER", "quieted", "say_warnings", "shown_before", "with_quiet"]

#: Where the context remembers a ``--quiet`` given to a command that declares none itself.
QUIET_KEY: Final = "diffbot.quiet"
#: The folder of the parameter cache holding the marks of warnings already shown.
SHOWN_FOLDER: Final = "warned"


def _remember(ctx: click.Context, param: click.Parameter, value: Any) -> None:
    if value:
        ctx.meta[QUIET_KEY] = True


def with_quiet(command: click.Command) -> click.Command:
    """Give ``command`` (each command of a group) a ``-q/--quiet`` flag when it has none.

    A command's own ``--quiet`` (no progress bar) silences warnings too (:func:`quieted`).
    """
    if isinstance(command, click.Group):
        for sub in command.commands.values():
            with_quiet(sub)
        return command
    if not any("--quiet" in param.opts for param in command.params):
        command.params.append(
            click.Option(
                ["--quiet", "-q"],
                is_flag=True,
                expose_value=False,
                callback=_remember,
                help="No warnings on stderr.",
            )
        )
    return command


def quieted() -> bool:
    """Whether the running command was given ``-q/--quiet``."""
    ctx = click.get_current_context(silent=True)
    if ctx is not None and ctx.meta.get(QUIET_KEY):
        return True
    while ctx is not None:
        if ctx.params.get("quiet") is True:
            return True
        ctx = ctx.parent
    return False


def _mark(source: str, warnings: Sequence[str]) -> Path | None:
    from diffbot.urdf.cache import cache_dir

    folder = cache_dir()
    if folder is None:
        return None
    with contextlib.suppress(OSError, ValueError):
        if os.path.exists(source):  # the same file, however it was named
            source = os.path.realpath(source)
    digest = hashlib.sha256("\0".join([source, *warnings]).encode("utf-8", "replace"))
    return folder / SHOWN_FOLDER / digest.hexdigest()


def shown_before(source: str, warnings: Sequence[str]) -> bool:
    """Whether these warnings of the description ``source`` were shown in full before; marks
    them as shown when not (a mark that cannot be written leaves them unshown, to show again).
    """
    mark = _mark(source, warnings)
    if mark is None:
        return False
    if os.path.lexists(mark):
        return True
    with contextlib.suppress(OSError):
        mark.parent.mkdir(parents=True, exist_ok=True)
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
        os.close(os.open(mark, flags, 0o600))
    return False


def say_warnings(
    warnings: Sequence[str],
    source: str,
    robot: str | None,
    again: Sequence[str],
) -> None:
    """Show a description's warnings on stderr: in full the first time, as one line saying how
    many and how to see them when the same ones were shown before; nothing with ``--quiet``.

    Args:
        warnings: the messages.
        source: the description they are about, as the parameters name it.
        robot: the description as the user gave it (None: the bundled robot).
        again: the words of the command that shows the warnings again.
    """
    from diffbot.commands.options import warn

    if not warnings or quieted():
        return
    if not shown_before(source, warnings):
        for message in warnings:
            warn(message)
        return
    count = len(warnings)
    plural = "warning" if count == 1 else "warnings"
    warn(
        f"{count} {plural} about {robot or 'the bundled robot'}, shown before: "
        f"{shlex.join(again)} shows {'it' if count == 1 else 'them'}; -q silences warnings"
    )
