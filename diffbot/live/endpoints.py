"""What a node makes: publishers, subscriptions and timers, shaped like rclpy's.

Received payloads are decoded one by one: a malformed one is counted in
:attr:`Subscription.malformed` and dropped, never raised.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

from diffbot.live.cyclone import (
    DataReader,
    DataWriter,
    DDSException,
    IdlStruct,
    InstanceState,
    SampleState,
    ViewState,
    ddspy_take,
    ddspy_write,
)
from diffbot.live.errors import LiveError

__all__ = ["Publisher", "Subscription", "Timer", "wait_for"]

M = TypeVar("M", bound=IdlStruct)


class Publisher(Generic[M]):
    """A ROS publisher: :meth:`publish` writes one message."""

    def __init__(self, writer: DataWriter[M], topic: str) -> None:
        self._writer = writer
        #: The ROS topic name.
        self.topic = topic

    def publish(self, message: M) -> None:
        """Send ``message`` to every matched subscription."""
        self._writer.write(message)

    def publish_serialized(self, data: bytes | bytearray) -> None:
        """Send a message already serialized (encapsulation header and CDR body), as
        :mod:`diffbot.live.cdr` writes the ones a node sends per sample."""
        padding = -len(data) % 4  # as cyclonedds pads its own payloads
        ret = ddspy_write(self._writer._ref, data + b"\0" * padding if padding else data)
        if ret < 0:
            raise LiveError(f"writing {self.topic} failed (DDS error {ret})")

    @property
    def subscription_count(self) -> int:
        """How many subscriptions match this publisher now."""
        return int(self._writer.get_publication_matched_status().current_count)  # type: ignore[no-untyped-call]

    def wait_for_subscribers(self, timeout: float, count: int = 1) -> bool:
        """Wait until ``count`` subscriptions have matched, at most ``timeout`` seconds."""
        return wait_for(lambda: self.subscription_count >= count, timeout)

    def flush(self, timeout: float) -> bool:
        """Wait until reliable subscriptions acknowledged everything sent, at most ``timeout``
        seconds (before the node goes away, so its last message is not lost)."""
        try:
            return bool(self._writer.wait_for_acks(int(timeout * 1e9)))
        except DDSException:
            return False


@dataclass
class Subscription(Generic[M]):
    """A ROS subscription: ``callback(message)`` for each message a spin takes.

    Attributes:
        topic: the ROS topic name.
        received: messages decoded and handed to the callback.
        malformed: payloads that could not be decoded (truncated, bad lengths), dropped.
    """

    reader: DataReader[M]
    decode: Callable[[bytes], M]
    callback: Callable[[M], None]
    topic: str
    received: int = 0
    malformed: int = 0
    #: The DDS type name this subscription reads.
    type_name: str = ""
    #: :attr:`dropped` when last read.
    last_dropped: int = 0

    @property
    def publisher_count(self) -> int:
        """How many publishers match this subscription now."""
        return int(self.reader.get_subscription_matched_status().current_count)  # type: ignore[no-untyped-call]

    @property
    def dropped(self) -> int:
        """Messages that arrived while the reader's queue was full (a ``drop_newest`` profile)
        or that the network lost, as DDS counts them: never handed to the callback."""
        reader = self.reader
        try:
            rejected = reader.get_sample_rejected_status().total_count  # type: ignore[no-untyped-call]
            lost = reader.get_sample_lost_status().total_count  # type: ignore[no-untyped-call]
        except DDSException:  # the node is gone: the count when it went
            return self.last_dropped
        self.last_dropped = int(rejected) + int(lost)
        return self.last_dropped

    def wait_for_publishers(self, timeout: float, count: int = 1) -> bool:
        """Wait until ``count`` publishers have matched, at most ``timeout`` seconds."""
        return wait_for(lambda: self.publisher_count >= count, timeout)

    def deliver(self, payloads: Iterable[bytes]) -> None:
        """Decode serialized messages (with their encapsulation header) and hand each to the
        callback; a payload that does not decode is counted in :attr:`malformed`."""
        decode = self.decode
        callback = self.callback
        for data in payloads:
            try:
                message = decode(data)
            except Exception:  # any decoding failure (struct.error, ...) is a malformed payload
                self.malformed += 1
                continue
            self.received += 1
            callback(message)

    def take(self, limit: int = 256) -> int:
        """Decode up to ``limit`` waiting messages and hand each to the callback; the count."""
        mask = SampleState.Any | ViewState.Any | InstanceState.Any
        taken = ddspy_take(self.reader._ref, mask, limit)
        if isinstance(taken, int):
            raise LiveError(f"reading {self.topic} failed (DDS error {taken})")
        self.deliver(data for data, info in taken if info.valid_data)
        return len(taken)


@dataclass
class Timer:
    """Calls ``callback()`` every ``period`` seconds of the monotonic clock while spinning."""

    period: float
    callback: Callable[[], None]
    due: float = field(default=0.0)

    def fire_if_due(self, now: float) -> None:
        if now >= self.due:
            # The next tick stays on the schedule; after a stall it skips missed ticks.
            self.due += self.period * max(1, math.floor((now - self.due) / self.period) + 1)
            self.callback()


def wait_for(condition: Callable[[], bool], timeout: float) -> bool:
    """Poll ``condition`` until it holds or ``timeout`` seconds pass; whether it held."""
    end = time.monotonic() + timeout
    while True:
        if condition():
            return True
        if time.monotonic() >= end:
            return False
        time.sleep(0.005)
