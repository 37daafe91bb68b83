"""Taking signals for the length of a run, and giving them back.

A signal ignored when a process starts stays ignored: ``nohup`` starts a command with SIGHUP
ignored so that it outlives its terminal, and a handler set over that would end it on the
hang-up after all. A handler installed outside Python (``signal.getsignal`` gives None) is left
alone too: Python could not put it back.

A process that ends with its run (the command line's) does not give its signals back: once
the outcome is decided it ignores them while it exits (:func:`settle`).
"""

from __future__ import annotations

import signal
from collections.abc import Callable, Iterable, Mapping
from typing import Any

__all__ = ["ends_with_run", "ignore", "install", "process_ends_with_run", "restore", "settle"]


class _Process:
    """Whether this process ends when its run does: the command line's entry point says so;
    a run inside another program (click's test runner, a notebook) gives its signals back."""

    ends_with_run = False


def process_ends_with_run() -> None:
    """Say that this process ends when its run does (the command line's entry point)."""
    _Process.ends_with_run = True


def ends_with_run() -> bool:
    """Whether :func:`process_ends_with_run` was called in this process."""
    return _Process.ends_with_run


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


def ignore(signums: Iterable[int]) -> None:
    """Ignore each of ``signums`` from now on, but one set outside Python (left alone).

    For a process whose outcome is decided and that ends with its run: while the interpreter
    shuts down it puts back the default action of every signal Python handles (the end of a
    process), and tearing down DDS participants and threads takes a few tenths of a second,
    so a second Ctrl-C in that time would turn a clean exit into a death by signal. An
    ignored signal stays ignored.
    """
    for signum in signums:
        if signal.getsignal(signum) is not None:
            signal.signal(signum, signal.SIG_IGN)


def settle(saved: Mapping[int, Any], also: Iterable[int] = ()) -> None:
    """Give back the signals a run took, once its outcome is decided: put back the handlers
    :func:`install` replaced, or, in a process that ends with its run
    (:func:`process_ends_with_run`), leave those signals and ``also`` ignored while it exits
    (:func:`ignore`)."""
    if _Process.ends_with_run:
        ignore([*saved, *also])
    else:
        restore(saved)
