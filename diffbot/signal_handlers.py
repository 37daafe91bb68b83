"""Taking signals for the length of a run, and giving them back.

A signal ignored when a process starts stays ignored: ``nohup`` starts a command with SIGHUP
ignored so that it outlives its terminal, and a handler set over that would end it on the
hang-up after all. A handler installed outside Python (``signal.getsignal`` gives None) is left
alone too: Python could not put it back.
"""

from __future__ import annotations

import signal
from collections.abc import Callable, Iterable, Mapping
from typing import Any

__all__ = ["install", "restore"]


def install(signums: Iterable[int], handler: Callable[[int, Any], None]) -> dict[int, Any]:
    """Set ``handler`` for each of ``signums`` that is neither ignored nor set outside Python.

    Returns:
        The handlers replaced, by signal, for :func:`restore`.
    """
    saved: dict[int, Any] = {}
    for signum in signums:
        previous = signal.getsignal(signum)
        if previous is signal.SIG_IGN or previous is None:
            continue
        saved[signum] = signal.signal(signum, handler)
    return saved


def restore(saved: Mapping[int, Any]) -> None:
    """Put back the handlers :func:`install` replaced."""
    for signum, previous in saved.items():
        signal.signal(signum, previous)
