"""Progress on stderr while a long command works: click's progress bar, shown only when stderr
is a terminal and --quiet is not given."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import click

__all__ = ["progress"]


def _wanted(quiet: bool) -> bool:
    return not quiet and sys.stderr.isatty()


@contextmanager
def progress(
    total: int | None, label: str, unit: str, *, quiet: bool
) -> Iterator[Callable[[int], None]]:
    """A function to call with each amount done: it advances a bar of ``total`` ``unit`` on
    stderr (done, rate, time left), or does nothing when the bar is not wanted."""
    if total is None or total <= 0 or not _wanted(quiet):
        yield lambda done: None
        return
    start = time.monotonic()
    count = 0
    with click.progressbar(
        length=total,
        label=label,
        file=sys.stderr,
        show_pos=True,
        show_percent=True,
        show_eta=True,
        item_show_func=lambda rate: rate,
    ) as bar:

        def advance(done: int) -> None:
            nonlocal count
            count += done
            elapsed = time.monotonic() - start
            rate = f"{count / elapsed:,.0f} {unit}/s" if elapsed > 0 else None
            bar.update(done, rate)

        yield advance
        if count < total:  # what the reader did not count (a CSV header line)
            bar.update(total - count)
