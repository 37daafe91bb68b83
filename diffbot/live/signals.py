"""Signals that end a live node (SIGINT, SIGTERM, SIGHUP), taken where they cannot hurt.

Python runs a signal's handler in the main thread between two bytecodes, wherever it is. A
handler that raises (the KeyboardInterrupt of Ctrl-C, the SystemExit the command line raises for
SIGTERM and SIGHUP) can land inside cyclonedds' ``take``, in the Python code its C part calls
for each sample's info; that call then returns NULL to C, and the process dies of a
segmentation fault (about once in 65 signals to a node fed at 1 kHz).

So, as rclpy does, while a node runs the handlers only record the signal and wake the nodes'
wait sets (:func:`deferred`); the loops check :func:`caught` between their steps and end
cleanly. When the outermost :func:`deferred` block ends, the signal goes to the handler that was
there before (raising its KeyboardInterrupt or SystemExit at that safe point), or, with
``deliver=False``, is taken as the normal end of the run (how ``diffbot node`` ends: exit code
0, the status line printed).

Only the main thread handles signals: elsewhere :func:`deferred` does nothing and
:func:`caught` is None.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from diffbot import signal_handlers

__all__ = ["ENDING_SIGNALS", "caught", "deferred"]

#: The signals that ask a node to end.
ENDING_SIGNALS = signal_handlers.ENDING_SIGNALS


class _State:
    """What the active :func:`deferred` blocks share (main thread only)."""

    def __init__(self) -> None:
        self.depth = 0
        self.signum: int | None = None
        self.saved: dict[int, Any] = {}
        self.wakers: list[Callable[[], None]] = []


_STATE = _State()


def _handler(signum: int, frame: object) -> None:
    # Records and wakes, nothing else: no exception may start here.
    if _STATE.signum is None:
        _STATE.signum = signum
    for wake in tuple(_STATE.wakers):
        wake()


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def caught() -> int | None:
    """The signal a :func:`deferred` block of the main thread has caught and not yet handed on
    (None: none, or not called from the main thread)."""
    return _STATE.signum if _in_main_thread() else None


@contextmanager
def deferred(
    wake: Callable[[], None] | None = None, *, deliver: bool = True, ends_run: bool = False
) -> Iterator[None]:
    """Within the block, an ending signal is only recorded (:func:`caught`) and ``wake()``
    called (from the handler: it must only wake, as a guard condition's ``set`` does).

    Blocks nest: the outermost installs the handlers (not over a signal that is ignored, as
    under ``nohup``), and on leaving restores them and, when a signal came, hands it to the
    handler that was there before (``deliver``), or drops it (``deliver=False``). A block left
    by an exception restores the handlers and hands nothing on. With ``ends_run`` the block
    decides the run's outcome (``diffbot node``: exit code 0), and the outermost one settles the
    signals it took (:func:`diffbot.signal_handlers.settle`): in a process that ends with its
    run they stay ignored, so that a second Ctrl-C while it exits cannot change that outcome.
    """
    if not _in_main_thread():
        yield
        return
    outermost = _STATE.depth == 0
    if outermost:
        # One held since the command line loaded or set up ends the run as one during its
        # setup does, before the block does anything.
        signal_handlers.act_on_held()
        _STATE.signum = None
        _STATE.saved = signal_handlers.install(ENDING_SIGNALS, _handler)
    _STATE.depth += 1
    if wake is not None:
        _STATE.wakers.append(wake)
    try:
        yield
    finally:
        _STATE.depth -= 1
        if wake is not None:
            _STATE.wakers.remove(wake)
        if outermost:
            saved, _STATE.saved = _STATE.saved, {}
            if ends_run:
                signal_handlers.settle(saved)
            else:
                signal_handlers.restore(saved)
            received, _STATE.signum = _STATE.signum, None
    if outermost and deliver and received is not None:
        signal_handlers.hand_on(received, saved.get(received, signal.SIG_DFL))
