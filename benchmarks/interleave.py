"""Interleaved timing: the compared sides take turns round by round.

Timing each side in its own block lets a slow spell of the machine fall on one side only, which
moves the ratios from run to run. Here round k runs every side once, in the given order on even
rounds and in the reverse order on odd ones, so a steady drift in machine speed cancels between
neighbours. Each round yields one ratio per pair of sides; the figure to quote is the median of
those per-round ratios, with their spread.

A side is a callable that runs the work once and returns the seconds it took:
:func:`timed` wraps an in-process callable, :func:`command` a subprocess, and a side may also
measure itself. Both time wall time by default, or CPU time with ``cpu=True``.
"""

from __future__ import annotations

import gc
import os
import resource
import statistics
import subprocess
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

#: Runs the compared work once and returns the time it took (s).
Side = Callable[[], float]

#: What ``--cpu`` means, for the scripts' help and headers.
CPU_HELP = (
    "time CPU time (user + system) instead of wall time: steadier when other processes compete "
    "for the cores, but blind to time spent waiting (disk, page cache misses); a command's CPU "
    "time adds up all its threads (NumPy's BLAS pool too), so it may exceed its wall time"
)


def timed(work: Callable[[], object], *, cpu: bool = False) -> Side:
    """A side that times one call of ``work``.

    A garbage collection runs before the timed call, so every side starts from the same heap
    state instead of paying for the garbage the side before it left.

    Args:
        work: the compared work; its result is dropped at once.
        cpu: time this thread's CPU time (``time.thread_time``) instead of the wall time
            (``time.perf_counter``).
    """
    clock = time.thread_time if cpu else time.perf_counter

    def run() -> float:
        gc.collect()
        start = clock()
        work()
        return clock() - start

    return run


def children_cpu_time() -> float:
    """User + system CPU time (s) of the child processes waited for so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def command(
    argv: Sequence[str],
    *,
    env: Mapping[str, str] | None = None,
    cwd: Path | None = None,
    cpu: bool = False,
) -> Side:
    """A side that runs ``argv`` as a fresh process and times it from start to exit.

    Standard output is discarded; a failing command raises with its standard error, so a broken
    side is never timed as a fast one.

    Args:
        argv: the command line.
        env: its environment (default: this process's).
        cwd: its working folder (default: this process's).
        cpu: time the process's CPU time (user + system, from ``getrusage``) instead of the
            wall time from launch to exit.
    """
    args = list(argv)
    environment = dict(env) if env is not None else dict(os.environ)
    clock = children_cpu_time if cpu else time.perf_counter

    def run() -> float:
        start = clock()
        done = subprocess.run(
            args, env=environment, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
        )
        seconds = clock() - start
        if done.returncode != 0:
            message = done.stderr.decode(errors="replace").strip()
            raise RuntimeError(f"{' '.join(args)} exited with {done.returncode}: {message}")
        return seconds

    return run


@dataclass(frozen=True)
class Ratio:
    """Per-round ratios of one side's time to another's.

    Attributes:
        numerator: name of the side divided.
        denominator: name of the side divided by.
        values: one ratio per round, in round order.
    """

    numerator: str
    denominator: str
    values: tuple[float, ...]

    @property
    def median(self) -> float:
        """The median of the per-round ratios."""
        return statistics.median(self.values)

    @property
    def quartiles(self) -> tuple[float, float]:
        """First and third quartile of the per-round ratios (both the value for one round)."""
        if len(self.values) < 2:
            return self.values[0], self.values[0]
        q1, _, q3 = statistics.quantiles(self.values, n=4, method="inclusive")
        return q1, q3

    def describe(self, digits: int = 2) -> str:
        """The median with its interquartile range and extremes.

        For example ``0.81 (IQR 0.79-0.84, range 0.75-0.90, 15 rounds)``.
        """
        q1, q3 = self.quartiles
        f = f".{digits}f"
        count = len(self.values)
        return (
            f"{self.median:{f}} (IQR {q1:{f}}-{q3:{f}}, "
            f"range {min(self.values):{f}}-{max(self.values):{f}}, "
            f"{count} round{'s' if count != 1 else ''})"
        )


@dataclass(frozen=True)
class Timings:
    """Per-round wall times (s) of every side, by side name, in round order."""

    seconds: Mapping[str, tuple[float, ...]]

    def median(self, side: str) -> float:
        """The median time (s) of one side."""
        return statistics.median(self.seconds[side])

    def ratio(self, numerator: str, denominator: str) -> Ratio:
        """Per-round ratios ``numerator / denominator``: each round's pair run side by side."""
        pairs = zip(self.seconds[numerator], self.seconds[denominator], strict=True)
        return Ratio(numerator, denominator, tuple(a / b for a, b in pairs))


def interleave(sides: Mapping[str, Side], rounds: int, *, warmup: int = 1) -> Timings:
    """Run the sides round by round and collect their times.

    Args:
        sides: the compared sides by name, in the order of the even rounds.
        rounds: timed rounds (>= 1).
        warmup: untimed rounds first, to fill caches (imports, the OS file cache, lazy set-up).

    Returns:
        Every side's time (s) in each timed round.

    Raises:
        ValueError: ``rounds`` below 1, ``warmup`` below 0 or no sides.
    """
    if rounds < 1:
        raise ValueError(f"rounds must be at least 1, got {rounds}")
    if warmup < 0:
        raise ValueError(f"warmup must be at least 0, got {warmup}")
    if not sides:
        raise ValueError("sides must name at least one side")
    order = list(sides)
    for _ in range(warmup):
        for name in order:
            sides[name]()
    seconds: dict[str, list[float]] = {name: [] for name in order}
    for k in range(rounds):
        for name in order if k % 2 == 0 else reversed(order):
            seconds[name].append(sides[name]())
    return Timings({name: tuple(times) for name, times in seconds.items()})
