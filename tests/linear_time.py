"""CPU time of a reader against the size of its input.

A reader fed an input eight times larger must not take much more than eight times as long: a
backtracking pattern or a quadratic loop fails, and so does a hang. Each measured run is a
forked copy of the test process (modules already loaded, warmed on the small input), killed
after :data:`TIMEOUT` seconds, and timed by its own CPU time, so that other work on a loaded
machine does not count; the least of a few runs is kept.
"""

from __future__ import annotations

import contextlib
import gc
import os
import resource
import select
import signal
import time
from collections.abc import Callable
from dataclasses import dataclass

from diffbot.errors import DiffbotError

#: How much larger the large input is than the small one.
FACTOR = 8
#: Allowed growth of the time per byte from the small input to the large one (generous: a
#: linear reader measures about 1, a quadratic one :data:`FACTOR`).
GROWTH = 4.0
#: CPU seconds allowed on top, for noise on small inputs.
SLACK = 0.05
#: Wall seconds a measured run may take before it counts as a hang.
TIMEOUT = 20.0


@dataclass(frozen=True)
class Timing:
    """CPU seconds of the least run on each input, and the inputs' sizes (bytes)."""

    small: float
    large: float
    small_size: int
    large_size: int

    def __str__(self) -> str:
        return (
            f"{self.small_size} B in {self.small * 1e3:.1f} ms, "
            f"{self.large_size} B in {self.large * 1e3:.1f} ms"
        )


def _cpu() -> float:
    """CPU seconds of this process (read to the nanosecond) and of its finished children."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def _run(work: Callable[[], object]) -> None:
    """Run one read; the errors a reader gives for bad input are a result, not a failure."""
    with contextlib.suppress(DiffbotError):
        work()


def cpu_seconds(work: Callable[[], object], timeout: float = TIMEOUT) -> float:
    """CPU seconds ``work`` takes in a forked copy of this process.

    Raises:
        AssertionError: it took more than ``timeout`` wall seconds (it is killed) or raised
            anything but a :class:`DiffbotError`.
    """
    readable, writable = os.pipe()
    gc.freeze()  # the copy's collections then leave the test process's objects (and pages) be
    pid = os.fork()
    if pid == 0:  # the copy: report CPU time or the exception, then leave at once
        os.close(readable)
        try:
            start = _cpu()
            _run(work)
            message = repr(_cpu() - start)
        except BaseException as err:  # reported to the parent, which fails the test
            message = f"!{type(err).__name__}: {err}"
        os.write(writable, message.encode(errors="replace")[:4000])
        os._exit(0)
    gc.unfreeze()
    os.close(writable)
    try:
        ready, _, _ = select.select([readable], [], [], timeout)
        if not ready:
            os.kill(pid, signal.SIGKILL)
            raise AssertionError(f"no result in {timeout:.0f} s")
        message = os.read(readable, 8192).decode()
    finally:
        os.close(readable)
        os.waitpid(pid, 0)
    if not message or message.startswith("!"):
        raise AssertionError(f"the reader failed: {message[1:] or 'no result'}")
    return float(message)


def measure(
    read: Callable[[bytes], object],
    small: bytes,
    large: bytes,
    runs: int = 3,
    *,
    accepts: bool = False,
) -> Timing:
    """The least CPU time of ``runs`` reads of each input (the large one twice at most).

    Raises:
        DiffbotError: the reader refuses the small input although it ``accepts`` it (a time
            measured up to an early error would prove nothing about the reading).
    """
    cpu_seconds(lambda: read(small))  # a hang on the small input fails here, in a copy
    if accepts:
        read(small)  # also loads what the reader loads lazily, in this process
    else:
        _run(lambda: read(small))
    small_time = min(cpu_seconds(lambda: read(small)) for _ in range(runs))
    large_time = min(cpu_seconds(lambda: read(large)) for _ in range(min(runs, 2)))
    return Timing(small_time, large_time, len(small), len(large))


def assert_linear(
    read: Callable[[bytes], object],
    make: Callable[[int], bytes],
    count: int,
    *,
    accepts: bool,
    slack: float = SLACK,
) -> Timing:
    """Fail unless reading ``make(FACTOR * count)`` takes at most :data:`GROWTH` times as long
    per byte as reading ``make(count)`` (plus ``slack`` seconds).

    Args:
        read: reads one input (bytes, often written to a file first); a :class:`DiffbotError`
            is a result like any other.
        make: the input made of ``count`` repetitions of its adversarial part.
        count: repetitions in the small input.
        accepts: whether the reader reads the input without an error (checked on the small one).
        slack: CPU seconds allowed on top.
    """
    small, large = make(count), make(FACTOR * count)
    timing = measure(read, small, large, accepts=accepts)
    budget = GROWTH * timing.small * len(large) / len(small) + slack
    assert timing.large <= budget, f"time grows faster than the input: {timing}"
    return timing
