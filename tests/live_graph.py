"""What the live tests share: this process's DDS domain, how long to wait for the graph, a
waiting loop, a history deep enough to read after the fact, and diffbot commands as processes."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from diffbot.live.transport import Node, QosProfile

#: This test process's domain (1..232); another process's tests take another one.
DOMAIN = 1 + os.getpid() % 232
#: How long a test waits for discovery or a message before it fails (s).
PATIENCE = 20.0


def deep() -> QosProfile:
    """A subscription profile that keeps every message until the test reads them."""
    from diffbot.live.transport import QosProfile as Profile

    return Profile(reliable=False, depth=100_000)


def until(node: Node, condition: Callable[[], bool]) -> None:
    """Spin ``node`` until ``condition()`` holds; fail after :data:`PATIENCE` seconds."""
    import time

    end = time.monotonic() + PATIENCE
    while not condition() and time.monotonic() < end:
        node.spin_once(0.02)
    assert condition(), "the graph did not get there in time"


@contextmanager
def live_process(*args: str) -> Iterator[subprocess.Popen[str]]:
    """``diffbot ARGS --quiet`` running in this test's domain, ended (SIGTERM) on the way out."""
    process = subprocess.Popen(
        [sys.executable, "-m", "diffbot", *args, "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )
    try:
        yield process
    finally:
        process.terminate()
        try:
            process.communicate(timeout=PATIENCE)
        finally:
            process.kill()
