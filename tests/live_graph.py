"""What the live tests share: this process's DDS domain, how long to wait for the graph, a
waiting loop, a history deep enough to read after the fact, and diffbot commands as processes."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable, Iterator, Sequence
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


def until(nodes: Node | Sequence[Node], condition: Callable[[], bool]) -> None:
    """Spin ``nodes`` (one, or several in turn) in this thread until ``condition()`` holds; fail
    after :data:`PATIENCE` seconds.

    A node under test spun here rather than in a thread of its own (:meth:`Node.start`) makes
    the order of events the test's, however busy the machine: what a test publishes before a
    spin reaches the node within that spin (delivery in one process is immediate), and what the
    node publishes in its spin reaches the nodes after it in ``nodes`` before the condition is
    checked again.
    """
    import time

    spun = list(nodes) if isinstance(nodes, Sequence) else [nodes]
    wait = 0.02 / len(spun)
    end = time.monotonic() + PATIENCE
    while not condition() and time.monotonic() < end:
        for node in spun:
            node.spin_once(wait)
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
