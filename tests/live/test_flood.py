"""A publisher flooding ``joint_states`` as fast as Python can send: ``node odom`` keeps up or
drops with a count (what it read and what it dropped add up to what was sent, less what the
network lost unseen), its memory stays flat, and it answers the next joint state at once."""

from __future__ import annotations

import re
import struct
import time
from pathlib import Path
from typing import Any

from live_graph import PATIENCE, deep, live_process, until

from diffbot.live import types
from diffbot.live.cdr import encode_joint_state
from diffbot.live.transport import Node, Publisher
from diffbot.urdf import load_params

#: An arbitrary wall-clock start (ns).
T0 = 1_700_000_000 * 10**9
#: How much a node's resident memory may grow over the flood (bytes): its queue of 100 joint
#: states and the odometry it sends are a few kB; a queue that grew with the flood would hold
#: the flood's tens of MB.
RSS_BOUND = 8 * 2**20
STAMP = struct.Struct("<iI")


def rss(pid: int) -> int:
    """A process's resident memory (bytes), from /proc."""
    status = Path(f"/proc/{pid}/status").read_text()
    match = re.search(r"^VmRSS:\s+(\d+) kB", status, re.MULTILINE)
    assert match is not None
    return int(match.group(1)) * 1024


def stamp_of(data: bytes) -> Any:
    """An Odometry's stamp (ns) from its serialized bytes."""
    sec, nanosec = STAMP.unpack_from(data, 4)
    return sec * 10**9 + nanosec


def flood(send: Publisher[Any], names: list[str], start: int, seconds: float) -> int:
    """Publish joint states back to back for ``seconds``, stamped 1 us apart from ``start``;
    how many."""
    publish = send.publish_serialized
    n = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        for _ in range(100):
            publish(encode_joint_state(start + n * 1000, "", names, [n * 1e-6, n * 1e-6]))
            n += 1
    return n


def test_a_flood_of_joint_states_is_kept_up_with_or_dropped_and_counted() -> None:
    params = load_params()
    names = [params.left_joint, params.right_joint]
    # Only the stamps of the odometry (sec, nanosec after the 4-byte encapsulation header):
    # decoding every message of the flood in full would make the probe the slow one.
    stamps: list[int] = []
    with live_process("node", "odom", "--no-tf") as process, Node("flood") as probe:
        states = probe.create_publisher(types.JointState, "joint_states")
        probe.create_subscription(
            types.Odometry,
            "odom",
            stamps.append,
            deep(),
            decode=stamp_of,
        )
        assert states.wait_for_subscribers(PATIENCE)
        until(probe, lambda: probe.publisher_types("odom") != set())
        sent = flood(states, names, T0, 0.5)  # warm-up: the node's buffers take their size
        time.sleep(1.0)
        before = rss(process.pid)
        sent += flood(states, names, T0 + sent * 1000, 2.0)
        time.sleep(1.0)
        after = rss(process.pid)
        # Still responsive: a joint state after the flood is answered within a second or two.
        last = T0 + (sent + 10**6) * 1000
        asked = time.monotonic()
        states.publish_serialized(encode_joint_state(last, "", names, [1.0, 1.0]))
        sent += 1
        until(probe, lambda: last in stamps)
        answered = time.monotonic() - asked
        process.terminate()
        _, stderr = process.communicate(timeout=PATIENCE)
    status = stderr.strip().splitlines()[-1]
    match = re.fullmatch(
        r"odom: (\d+) joint states, (\d+) used, (\d+) published(?:; skipped: (\d+) dropped "
        r"while behind)?",
        status,
    )
    assert match is not None, status
    received, used, published = (int(match.group(i)) for i in (1, 2, 3))
    dropped = int(match.group(4) or 0)
    print(
        f"sent {sent}, received {received}, dropped {dropped}, rss {before} -> {after}, "
        f"answered in {answered:.3f} s"
    )
    assert sent > 10_000  # a flood indeed
    # Every joint state is read or counted as dropped, but for those the kernel's socket buffer
    # lost between the processes, which a best-effort reader cannot see: a few percent here.
    unseen = sent - received - dropped
    assert 0 <= unseen <= 0.1 * sent
    assert used == published == received
    assert after - before < RSS_BOUND
    assert answered < 2.0
