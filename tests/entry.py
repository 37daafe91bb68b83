"""The command line started through its entry point with a signal that comes while its modules
load: the first import of click waits, in the middle of the import, until a signal has come."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

from live_graph import PATIENCE

#: A signal, and how a run ends on it before it does anything: exit code, stderr (stripped).
Ending = tuple[int, int, str]
ENDINGS: list[Ending] = [(signal.SIGINT, 130, "error: aborted"), (signal.SIGTERM, 143, "")]

_GATED = """
import importlib.abc, sys, time
from diffbot import __main__ as entry, signal_handlers

patience, linger = float(sys.argv[1]), float(sys.argv[2])

class Gate(importlib.abc.MetaPathFinder):
    opened = False

    def find_spec(self, name, path, target=None):
        if name == "click" and not Gate.opened:
            Gate.opened = True
            print("loading", flush=True)
            end = time.monotonic() + patience
            while signal_handlers._Held.signum is None and time.monotonic() < end:
                time.sleep(0.001)  # where an unheld signal raises, inside the import
            if linger:
                print("held", flush=True)
                time.sleep(linger)
        return None

sys.meta_path.insert(0, Gate())
sys.argv[:] = ["diffbot", *sys.argv[3:]]
entry.run()
"""


def started_gated(*args: str, linger: float = 0.0) -> subprocess.Popen[str]:
    """``diffbot ARGS`` through the entry point, its import of click held up until a signal
    came (at most :data:`PATIENCE` seconds), then ``linger`` seconds more; its first line on
    stdout says it is loading, the next (with ``linger``) that a signal is held."""
    process = subprocess.Popen(
        [sys.executable, "-c", _GATED, str(PATIENCE), str(linger), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )
    assert process.stdout is not None
    assert process.stdout.readline() == "loading\n", process.communicate(timeout=PATIENCE)
    return process


def signalled(signum: int, *args: str) -> tuple[int, str, str]:
    """``diffbot ARGS`` sent ``signum`` in the middle of its import of click: its exit code,
    stdout and stderr."""
    process = started_gated(*args)
    try:
        process.send_signal(signum)
        out, err = process.communicate(timeout=PATIENCE)
    finally:
        process.kill()
    return process.returncode, out, err
