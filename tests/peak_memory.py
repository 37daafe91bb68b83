"""The most memory Python allocates while some work runs: how the tests prove that a reader
streams in constant memory, or refuses an input before it holds it."""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def peak_bytes(run: Callable[[], T]) -> tuple[T, int]:
    """What ``run()`` returns, and the most memory Python allocated while it ran (bytes)."""
    tracemalloc.start()
    try:
        result = run()
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
