"""Taking signals for the length of a run, and giving them back.

A signal ignored when a process starts stays ignored: ``nohup`` starts a command with SIGHUP
ignored so that it outlives its terminal, and a handler set over that would end it on the
hang-up after all. A handler installed outside Python (``signal.getsignal`` gives None) is left
alone too: Python could not put it back.

A process that ends with its run (the command line's) does not give its signals back: once
the outcome is decided it ignores them while it exits (:func:`settle`).

The command line holds the ending signals from its first step (:func:`hold`), before the
modules it needs have loaded: a signal that comes meanwhile is only recorded, and acted on where
the run can take it as it takes one during the run (:func:`act_on_held`), rather
than raised in the middle of an import (a traceback, or a library left half set up).
"""

from __future__ import annotations

import os
import signal

# Imported before anything else by the command line's entry point: no module for types only.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable, Iterable, Mapping
    from typing import Any

__all__ = [
    "ENDING_SIGNALS",
    "act_on_held",
    "ends_with_run",
    "hand_on",
    "hold",
    "ignore",
    "install",
    "process_ends_with_run",
    "release",
    "restore",
    "settle",
]

#: The signals that end a run: Ctrl-C, ``kill``, a terminal that goes away.
ENDING_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


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


class _Held:
    """The signals :func:`hold` holds: the handler each takes once the hold ends (what
    :func:`install` and :func:`restore` set meanwhile), and the first one that came."""

    under: dict[int, Any] = {}  # noqa: RUF012 (one hold per process)
    signum: int | None = None


def _record(signum: int, frame: object) -> None:
    # Records, nothing else: no exception may start here.
    if _Held.signum is None:
        _Held.signum = signum
        return
    # A second one while the first waits for the run to act on it (a long setup): whoever sends
    # it insists, and the process ends at once. Nothing is written while signals are held.
    if signum == signal.SIGINT:
        os.write(2, b"\nerror: aborted\n")
    os._exit(128 + signum)


def hold(signums: Iterable[int] = ENDING_SIGNALS) -> None:
    """From now until :func:`release`, a signal of ``signums`` (but one ignored or set outside
    Python) is only recorded, and a second one ends the process at once (exit status 128 + its
    number); the handlers :func:`install` sets meanwhile take effect at :func:`release`. Main
    thread only."""
    _Held.signum = None
    _Held.under = install(signums, _record)


def release() -> int | None:
    """End the hold: put the handlers in place that were set during it.

    Returns:
        The first signal that came during the hold, for the caller to act on (with
        :func:`hand_on`); None when none came, or nothing was held.
    """
    under, _Held.under = _Held.under, {}
    for signum, handler in under.items():
        signal.signal(signum, handler)
    received, _Held.signum = _Held.signum, None
    return received


def act_on_held() -> None:
    """End the hold (:func:`release`), and act on a signal that came during it as the handler
    now in place takes it (:func:`hand_on`): where the run can take a signal."""
    early = release()
    if early is not None:
        hand_on(early, signal.getsignal(early))


def hand_on(signum: int, handler: Any) -> None:
    """Act on ``signum`` as ``handler`` would have: call it (it may raise), or, for the default
    action, raise the signal again; an ignored signal does nothing."""
    if callable(handler):
        handler(signum, None)
    elif handler == signal.SIG_DFL:
        signal.raise_signal(signum)


def install(signums: Iterable[int], handler: Callable[[int, Any], None]) -> dict[int, Any]:
    """Set ``handler`` for each of ``signums`` that is neither ignored nor set outside Python
    (during a :func:`hold`, as the handler the signal takes when the hold ends).

    Returns:
        The handlers replaced, by signal, for :func:`restore`.
    """
    saved: dict[int, Any] = {}
    for signum in signums:
        if signum in _Held.under:
            saved[signum], _Held.under[signum] = _Held.under[signum], handler
            continue
        previous = signal.getsignal(signum)
        if previous is signal.SIG_IGN or previous is None:
            continue
        saved[signum] = signal.signal(signum, handler)
    return saved


def restore(saved: Mapping[int, Any]) -> None:
    """Put back the handlers :func:`install` replaced."""
    for signum, previous in saved.items():
        if signum in _Held.under:
            _Held.under[signum] = previous
        else:
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
