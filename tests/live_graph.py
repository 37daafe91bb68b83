"""What the live tests share: this process's DDS domain, how long to wait for the graph, a
waiting loop, a history deep enough to read after the fact, and diffbot commands as processes."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from diffbot.live.transport import Node, QosProfile


#: Domains 1..101 only: their ports (7400 + 250 x domain and up) stay below Linux's ephemeral
#: range (32768 on), and a domain near 232 has room for few participants before its ports pass
#: 65535. Each test process takes a block of :data:`BLOCK` of them: its own, then spares for
#: the graphs it keeps apart (:func:`spare_domain`).
DOMAINS = 101
BLOCK = 5


def _slot() -> int:
    """The block this process tries first: from its id, or, for the workers of a run split
    over processes (pytest-xdist), from the run's controller and the worker's number, so that
    the workers of one run start apart."""
    blocks = DOMAINS // BLOCK
    worker = os.environ.get("PYTEST_XDIST_WORKER", "")
    if not worker.startswith("gw"):
        return os.getpid() % blocks
    count = max(int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")), 1)
    return (os.getppid() * count + int(worker[2:])) % blocks


#: The block each process holds, by process id.
_held: dict[int, int] = {}


def _claim() -> int:
    """A block no other process on this machine holds, from :func:`_slot` on: held by an
    exclusive lock on a file of its own, whose descriptor stays open until this process ends.
    Two test runs at once (a mutation run's forked children, which share what their parent
    imported; pytest-xdist's workers; two checkouts) never share a domain. Where every block is
    held, or there are no file locks, the first one tried."""
    first = _slot()
    try:
        import fcntl
    except ImportError:  # no flock (Windows)
        return first
    blocks = DOMAINS // BLOCK
    folder = tempfile.gettempdir()
    for k in range(blocks):
        block = (first + k) % blocks
        path = os.path.join(folder, f"diffbot-test-domains-{block}.lock")
        try:
            fd = os.open(path, os.O_RDONLY | os.O_CREAT, 0o644)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            continue
        return block
    return first


def domain() -> int:
    """This test process's domain; another process's tests take another one. A forked child
    takes its own, not its parent's."""
    pid = os.getpid()
    if pid not in _held:
        _held[pid] = _claim()
    return 1 + BLOCK * _held[pid]


#: How long a test waits for discovery or a message before it fails (s): DIFFBOT_TEST_PATIENCE
#: where set (a mutation run, where a broken node would make every wait run out).
PATIENCE = float(os.environ.get("DIFFBOT_TEST_PATIENCE", "20"))


def spare_domain(k: int) -> int:
    """The ``k``-th spare domain of this process's block (k from 1 to ``BLOCK - 1``). Nodes
    share 1 to 3; 4 is kept for the participant test that needs a domain no node started."""
    if not 1 <= k < BLOCK:
        raise ValueError(f"a block has {BLOCK - 1} spare domains, not {k}")
    return domain() + k


def timer_periods(node: Node, callback: Callable[[], None]) -> list[float]:
    """The periods (s) of ``node``'s timers that call ``callback``."""
    return [t.period for t in node._timers if t.callback == callback]


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


class ServiceClient:
    """A ROS 2 service client as rmw_cyclonedds makes one, written against cyclonedds alone:
    requests on ``rq/<name>Request``, replies read from ``rr/<name>Reply``, both led by the
    16-byte request header (the client's 64-bit id, the request's sequence number); replies
    for another client id are ignored, as rmw_cyclonedds does."""

    def __init__(self, name: str, request_type: type, response_type: type, guid: int) -> None:
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.pub import DataWriter
        from cyclonedds.qos import Policy, Qos
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        from diffbot.live.participant import participant

        qos = Qos(
            Policy.Reliability.Reliable(max_blocking_time=100_000_000),
            Policy.Durability.Volatile,
            Policy.History.KeepLast(depth=10),
            Policy.DataRepresentation(use_cdrv0_representation=True),
        )
        base = name.lstrip("/")
        self.participant: DomainParticipant = participant(None)
        self.writer = DataWriter(
            self.participant, Topic(self.participant, f"rq/{base}Request", request_type), qos
        )
        self.reader = DataReader(
            self.participant, Topic(self.participant, f"rr/{base}Reply", response_type), qos
        )
        self.guid = guid
        self.seq = 0

    def wait_for_service(self) -> None:
        """Wait for discovery: the server's request reader and reply writer matched."""
        import time

        end = time.monotonic() + PATIENCE
        while time.monotonic() < end:
            writer = self.writer.get_publication_matched_status().current_count
            reader = self.reader.get_subscription_matched_status().current_count
            if writer >= 1 and reader >= 1:
                return
            time.sleep(0.02)
        raise AssertionError("the service was not discovered in time")

    def call(self, request: object) -> object:
        """Send ``request`` under this client's id and the next sequence number; the reply."""
        import time

        self.seq += 1
        request.guid = self.guid  # type: ignore[attr-defined]
        request.seq = self.seq  # type: ignore[attr-defined]
        self.writer.write(request)
        end = time.monotonic() + PATIENCE
        while time.monotonic() < end:
            for reply in self.reader.take(N=10):
                if reply.guid == self.guid and reply.seq == self.seq:
                    return reply
            time.sleep(0.01)
        raise AssertionError("no reply in time")

    def close(self) -> None:
        from diffbot.live.participant import leave

        leave(self.participant)
