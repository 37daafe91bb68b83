"""A node that leaves says so in a way Fast DDS reads at once: its discovery disposals (the
participant's and its endpoints') carry a key hash, as Cyclone sends them with
``GenerateKeyhash`` in diffbot's configuration. Without one, Fast DDS 2.9 (ROS 2's default
middleware) kept a diffbot node on its graph until the lease ran out, 10 s later.

The second test watches the wire itself: every UDP datagram on the loopback interface, captured
raw (root only) while a node in another process leaves, its RTPS DATA submessages read for the
status info of a disposal and for a key hash beside it. The process ends at once after the node
is destroyed (``os._exit``, no interpreter clean-up): the disposals must be out by then.
"""

from __future__ import annotations

import os
import socket
import struct
import subprocess
import sys
import threading
import time

import pytest
from live_graph import PATIENCE

from diffbot.live import types
from diffbot.live.discovery import INTERNAL, cyclone_config
from diffbot.live.transport import Node, QosProfile

#: RTPS submessage and parameter ids (DDSI-RTPS 2.5, 9.4.5 and 9.6.3).
_DATA = 0x15
_PID_SENTINEL = 0x0001
_PID_KEY_HASH = 0x0070
_PID_STATUS_INFO = 0x0071
#: The status info flags of a disposal and an unregistration.
_GONE = 0x3
#: The writers of discovery whose disposals say a participant left (DDSI-RTPS 2.5, 9.3.2): the
#: participant's own (SPDP) and that of its subscriptions (SEDP).
_PARTICIPANTS = bytes.fromhex("000100c2")
_SUBSCRIPTIONS = bytes.fromhex("000004c2")
_LEFT = {_PARTICIPANTS, _SUBSCRIPTIONS}


@pytest.mark.parametrize("reach", ["SUBNET", "LOCALHOST", "OFF"])
def test_every_discovery_range_sends_key_hashes(reach: str) -> None:
    config = cyclone_config(reach)
    assert "<GenerateKeyhash>true</GenerateKeyhash>" in config
    assert INTERNAL in config
    # After the user's own configuration, so that this setting wins.
    assert cyclone_config(reach, "file:///etc/dds.xml").endswith(config)


def _disposals(datagrams: list[bytes], prefix: bytes) -> list[tuple[bytes, bool]]:
    """For each DATA submessage from participant ``prefix`` whose inline QoS says its instance
    is disposed or unregistered: the writer's entity id, and whether a key hash came with it."""
    found: list[tuple[bytes, bool]] = []
    for payload in datagrams:
        if payload[:4] != b"RTPS" or payload[8:20] != prefix:
            continue
        at = 20
        while at + 4 <= len(payload):
            kind, flags = payload[at], payload[at + 1]
            order = "<" if flags & 1 else ">"
            (length,) = struct.unpack_from(order + "H", payload, at + 2)
            body = at + 4
            end = body + length if length else len(payload)
            if kind == _DATA and flags & 0x02:  # inline QoS present
                (to_qos,) = struct.unpack_from(order + "H", payload, body + 2)
                params = _parameters(payload, body + 4 + to_qos, end, order)
                status = params.get(_PID_STATUS_INFO)
                if status is not None and status[3] & _GONE:
                    found.append((payload[body + 8 : body + 12], _PID_KEY_HASH in params))
            at = end
    return found


def _writers(disposals: list[tuple[bytes, bool]]) -> set[bytes]:
    return {writer for writer, _ in disposals}


def _parameters(data: bytes, at: int, end: int, order: str) -> dict[int, bytes]:
    params: dict[int, bytes] = {}
    while at + 4 <= end:
        pid, length = struct.unpack_from(order + "HH", data, at)
        if pid == _PID_SENTINEL:
            break
        params[pid] = data[at + 4 : at + 4 + length]
        at += 4 + length
    return params


#: A classic BPF program (Linux socket filter) that keeps what the test reads and nothing else:
#: incoming IPv4 UDP datagrams whose payload starts with "RTPS". The kernel drops the rest
#: before it is queued, so that the loopback traffic of other processes on a busy machine does
#: not fill the socket's buffer and crowd out the datagrams looked for.
_RTPS_ONLY = [
    (0x20, 0, 0, 0xFFFFF004),  # ld pkttype (SKF_AD_OFF + SKF_AD_PKTTYPE)
    (0x15, 8, 0, 4),  # PACKET_OUTGOING: each datagram once, as it comes in
    (0x28, 0, 0, 12),  # ldh ethertype
    (0x15, 0, 6, 0x0800),  # IPv4
    (0x30, 0, 0, 23),  # ldb protocol
    (0x15, 0, 4, 17),  # UDP
    (0xB1, 0, 0, 14),  # ldx 4 * (header length)
    (0x40, 0, 0, 22),  # ld [x + 14 + 8]: the payload's first four bytes
    (0x15, 0, 1, int.from_bytes(b"RTPS", "big")),
    (0x06, 0, 0, 0x40000),  # keep the whole datagram
    (0x06, 0, 0, 0),  # drop
]
_SO_ATTACH_FILTER = 26
_SO_RCVBUFFORCE = 33
_PACKET_STATISTICS = 6


class _Capture:
    """Every RTPS datagram that comes in on the loopback interface, read raw in a thread until
    stopped; :attr:`dropped` says how many the kernel could not queue."""

    def __init__(self) -> None:
        import ctypes

        self.sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.ntohs(0x0003))
        program = b"".join(struct.pack("HBBI", *op) for op in _RTPS_ONLY)
        code = ctypes.create_string_buffer(program)
        fprog = struct.pack("HL", len(_RTPS_ONLY), ctypes.addressof(code))
        self.sock.setsockopt(socket.SOL_SOCKET, _SO_ATTACH_FILTER, fprog)
        self.sock.setsockopt(socket.SOL_SOCKET, _SO_RCVBUFFORCE, 64 << 20)
        self.sock.bind(("lo", 0))
        self.sock.settimeout(0.1)
        self.dropped = 0
        self.payloads: list[bytes] = []
        self.stopped = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        while not self.stopped.is_set():
            try:
                frame, address = self.sock.recvfrom(65_536)
            except TimeoutError:
                continue
            if address[2] == socket.PACKET_OUTGOING:  # each datagram once, as it comes in
                continue
            ip = frame[14:]
            if len(ip) < 28 or ip[0] >> 4 != 4 or ip[9] != 17:  # IPv4, UDP
                continue
            self.payloads.append(ip[(ip[0] & 0x0F) * 4 + 8 :])

    def stop(self) -> list[bytes]:
        self.stopped.set()
        self.thread.join(5.0)
        _, self.dropped = struct.unpack("II", self.sock.getsockopt(263, _PACKET_STATISTICS, 8))
        self.sock.close()
        return self.payloads


_LEAVER = """
import os
import sys
from diffbot.live import types
from diffbot.live.transport import Node
node = Node("leaver")
subscription = node.create_subscription(types.String, "keyhash_probe", lambda m: None)
assert subscription.wait_for_publishers(float(sys.argv[1]))
print(node.participant.guid.bytes[:12].hex(), flush=True)
sys.stdin.readline()
node.destroy_node()
os._exit(0)
"""


@pytest.mark.skipif(
    not hasattr(socket, "AF_PACKET") or os.geteuid() != 0, reason="a raw capture needs root"
)
def test_a_leaving_node_sends_its_disposals_with_a_key_hash() -> None:
    capture = _Capture()
    try:
        with Node("peer") as peer:
            probe = peer.create_publisher(types.String, "keyhash_probe", QosProfile())
            leaver = subprocess.Popen(
                [sys.executable, "-c", _LEAVER, str(PATIENCE)],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                env=os.environ.copy(),
            )
            try:
                assert leaver.stdout is not None
                prefix = bytes.fromhex(leaver.stdout.readline().strip())
                _, err = leaver.communicate("\n", timeout=PATIENCE)
            finally:
                leaver.kill()
            assert leaver.returncode == 0, err
            assert probe.topic == "keyhash_probe"  # kept alive until the leaver has gone
            end = time.monotonic() + PATIENCE
            while time.monotonic() < end:  # until the participant's own disposal came
                peer.spin_once(0.05)
                if _writers(_disposals(list(capture.payloads), prefix)) >= _LEFT:
                    break
    finally:
        payloads = capture.stop()
    gone = _disposals(payloads, prefix)
    # The participant and its reader are disposed, each disposal with its key hash.
    assert _writers(gone) >= _LEFT, (
        f"{len(payloads)} datagrams ({capture.dropped} dropped), disposals from "
        f"{prefix.hex()} by {sorted(w.hex() for w in _writers(gone))}"
    )
    assert all(hashed for _, hashed in gone), gone
