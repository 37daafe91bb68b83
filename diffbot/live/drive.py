"""Driving a plan live: its commands published on a monotonic-clock schedule, then zero.

The commands are a :class:`diffbot.ramps.CommandStream` (a plan sampled at a rate, each command
held for its period), whole or in consecutive pieces as
:meth:`diffbot.ramps.RampedPlan.command_chunks` makes them (millions of commands in constant
memory): the k-th goes out at ``start + times[k]`` of the monotonic clock, never
``previous + period``, so sleeping late once does not shift the rest. Each is a
geometry_msgs/Twist (or TwistStamped) on ``cmd_vel``, or one Float64MultiArray per side. However
the drive ends (the last command, Ctrl-C, SIGTERM, SIGHUP, an error) the robot is commanded to
stop; a signal only wakes the schedule (:mod:`diffbot.live.signals`), which stops between two
commands.
"""

from __future__ import annotations

import bisect
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from diffbot.live import types
from diffbot.live.cdr import encode_float64_array, encode_twist
from diffbot.live.messages import commands, now_ns, time_of, twist_command
from diffbot.live.names import check_distinct_topics, check_frame_id
from diffbot.live.signals import caught, deferred
from diffbot.live.transport import Node, Publisher
from diffbot.wheel_topics import LEFT_TOPIC, RIGHT_TOPIC

if TYPE_CHECKING:
    from diffbot.ramps import CommandStream

__all__ = ["DriveReport", "DriveSettings", "Driver", "Lateness"]

#: How long before a command's time the schedule stops sleeping and polls the clock (s): a wait
#: on the wait set usually ends within a few tens of µs of its time, and this last stretch is
#: waited out exactly. Kept short: on a busy machine a process that polls for longer uses up its
#: share of the processor and is put back in the queue, which makes it later, not earlier (a
#: margin of 2 ms doubled the median lateness and did not lower the 99th percentile).
_SPIN_AHEAD = 0.0003
#: The longest a wait between commands blocks before it looks for a signal again (s).
_WAIT_SLICE = 0.05
#: The edges of the lateness histogram (s): 1 µs wide up to 10 ms, then 1 % wider each, up to
#: an hour; percentiles are read to within a bin.
_EDGES: tuple[float, ...] = tuple(
    [k * 1e-6 for k in range(10_001)]
    + [0.01 * 1.01**k for k in range(1, math.ceil(math.log(360_000) / math.log(1.01)) + 1)]
)


@dataclass
class Lateness:
    """How late commands went out (s), in constant memory: a count per bin (1 µs wide below
    10 ms, 1 % wide above), the earliest and the latest.

    Attributes:
        count: commands measured.
        earliest: the smallest lateness (s; inf with none).
        latest: the largest (s; -inf with none).
        last: the last command's (s; 0 with none).
    """

    count: int = 0
    earliest: float = math.inf
    latest: float = -math.inf
    last: float = 0.0
    _bins: dict[int, int] = field(default_factory=dict, repr=False)

    def add(self, seconds: float) -> None:
        """Count one command ``seconds`` late."""
        self.count += 1
        self.earliest = min(self.earliest, seconds)
        self.latest = max(self.latest, seconds)
        self.last = seconds
        index = bisect.bisect_left(_EDGES, seconds)
        self._bins[index] = self._bins.get(index, 0) + 1

    def percentile(self, q: float) -> float:
        """The ``q`` quantile (0..1), nearest rank, as its bin's upper edge (within 1 µs below
        10 ms, 1 % above; never past :attr:`latest`); 0 with no command."""
        if not self.count:
            return 0.0
        rank = min(self.count, max(1, math.ceil(q * self.count)))
        seen = 0
        for index in sorted(self._bins):
            seen += self._bins[index]
            if seen >= rank:
                edge = _EDGES[index] if index < len(_EDGES) else math.inf
                return min(edge, self.latest)
        return self.latest  # pragma: no cover - the counts add up to count


@dataclass(frozen=True)
class DriveSettings:
    """Where and how the commands go.

    Attributes:
        cmd_vel: the velocity command topic.
        stamped: send geometry_msgs/TwistStamped (stamped now, in ``frame_id``).
        frame_id: the frame of stamped commands.
        wheels: send per-side Float64MultiArray commands instead of twists.
        left_topic: the left side's command topic.
        right_topic: the right side's.
        joints: how many joints each side commands (left, right).
    """

    cmd_vel: str = "cmd_vel"
    stamped: bool = False
    frame_id: str = "base_link"
    wheels: bool = False
    left_topic: str = LEFT_TOPIC
    right_topic: str = RIGHT_TOPIC
    joints: tuple[int, int] = (1, 1)


@dataclass(frozen=True)
class DriveReport:
    """How a drive went: commands sent, whether it ran to its end, and its timing.

    Attributes:
        sent: commands published (the final zero after them not counted).
        total: commands in the plan (those known when the drive was cut short).
        completed: every command went out (not cut short by a signal).
        lateness: how late each command's publication started after its scheduled time.
        duration_error: when the last command went out minus when it was due (s).
    """

    sent: int
    total: int
    completed: bool
    lateness: Lateness
    duration_error: float

    def percentile(self, q: float) -> float:
        """The ``q`` quantile (0..1) of the lateness (s); 0 with no command."""
        return self.lateness.percentile(q)


class Driver(Node):
    """Publishes a command stream live.

    Example::

        with Driver(stream, DriveSettings(stamped=True)) as driver:
            driver.wait_for_subscriber(5.0)
            report = driver.drive()

    Args:
        stream: the commands and their times: one stream, or its consecutive pieces (an
            iterable of streams, driven once: :meth:`~diffbot.ramps.RampedPlan.command_chunks`).
        settings: topics and message kinds.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        stream: CommandStream | Iterable[CommandStream],
        settings: DriveSettings = DriveSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_drive",
    ) -> None:
        check_frame_id(settings.frame_id, "frame_id")
        self.stream = stream
        self.settings = settings
        #: Commands in the plan, when known before the drive (one stream: its size).
        self.total: int | None = None if isinstance(stream, Iterable) else int(stream.times.size)
        #: Commands published so far by :meth:`drive`.
        self.sent = 0
        if settings.wheels:
            sides = [("{left_topic}", settings.left_topic), ("{right_topic}", settings.right_topic)]
            check_distinct_topics(sides, name)
        super().__init__(name, domain=domain)
        self._twist: Publisher[types.Twist] | None = None
        self._stamped: Publisher[types.TwistStamped] | None = None
        self._sides: tuple[Publisher[types.Float64MultiArray], ...] = ()
        if settings.wheels:
            self._sides = (
                self.create_publisher(types.Float64MultiArray, settings.left_topic),
                self.create_publisher(types.Float64MultiArray, settings.right_topic),
            )
        elif settings.stamped:
            self._stamped = self.create_publisher(types.TwistStamped, settings.cmd_vel)
        else:
            self._twist = self.create_publisher(types.Twist, settings.cmd_vel)

    @property
    def topics(self) -> tuple[str, ...]:
        """The topics the commands go to."""
        s = self.settings
        return (s.left_topic, s.right_topic) if s.wheels else (s.cmd_vel,)

    def _publishers(
        self,
    ) -> list[
        Publisher[types.Twist] | Publisher[types.TwistStamped] | Publisher[types.Float64MultiArray]
    ]:
        if self._sides:
            return list(self._sides)
        return [p for p in (self._twist, self._stamped) if p is not None]

    def wait_for_subscriber(self, timeout: float) -> bool:
        """Whether every command topic has a subscriber within ``timeout`` seconds (False at
        once when a signal came: :func:`~diffbot.live.signals.caught`)."""
        end = time.monotonic() + timeout
        while True:
            if all(p.subscription_count > 0 for p in self._publishers()):
                return True
            if time.monotonic() >= end or caught() is not None:
                return False
            self._pause(min(time.monotonic() + 0.005, end))

    def other_publishers(self) -> int:
        """How many publishers besides this one command the same topics (another drive, a
        teleop): their commands would mix with these."""
        return sum(max(len(self.publications(topic)) - 1, 0) for topic in self.topics)

    def send(self, stream: CommandStream, k: int) -> None:
        """Publish command ``k`` of ``stream``."""
        if self._sides:
            left, right = self.settings.joints
            self._sides[0].publish_serialized(encode_float64_array([float(stream.left[k])] * left))
            self._sides[1].publish_serialized(
                encode_float64_array([float(stream.right[k])] * right)
            )
        else:
            self._send_twist(float(stream.linear[k]), float(stream.angular[k]))

    def _send_twist(self, linear: float, angular: float) -> None:
        if self._stamped is not None:
            header = types.Header(time_of(now_ns()), self.settings.frame_id)
            self._stamped.publish(types.TwistStamped(header, twist_command(linear, angular)))
        elif self._twist is not None:
            # Serialized here in one struct call, not field by field by the type's serializer.
            self._twist.publish_serialized(encode_twist(linear, angular))

    def stop(self) -> None:
        """Command zero on every topic."""
        if self._sides:
            left, right = self.settings.joints
            self._sides[0].publish(commands([0.0] * left))
            self._sides[1].publish(commands([0.0] * right))
        else:
            self._send_twist(0.0, 0.0)

    def drive(self, progress: Callable[[int], None] | None = None) -> DriveReport:
        """Publish every command on schedule, then zero; zero also when a signal comes (the
        signal is handed on after the stop, unless an enclosing
        :func:`~diffbot.live.signals.deferred` block takes it). ``progress(1)`` after each
        command."""
        stream = self.stream
        pieces: Iterable[CommandStream] = stream if isinstance(stream, Iterable) else (stream,)
        lateness = Lateness()
        self.sent = 0
        self._wake.set(False)
        start = time.monotonic()
        with deferred(self.wake):
            try:
                for piece in pieces:
                    if not self._drive_piece(piece, start, lateness, progress):
                        break
            finally:
                self.stop()
                for publisher in self._publishers():
                    publisher.flush(1.0)
            total = self.sent if self.total is None else self.total
            completed = caught() is None and self.sent == total
        error = lateness.last if completed and total else 0.0
        return DriveReport(self.sent, total, completed, lateness, error)

    def _drive_piece(
        self,
        piece: CommandStream,
        start: float,
        lateness: Lateness,
        progress: Callable[[int], None] | None,
    ) -> bool:
        """Publish one piece's commands at their times; False when a signal stopped it."""
        times = piece.times
        for k in range(int(times.size)):
            due = start + float(times[k])
            if not self._pause(due):
                return False
            lateness.add(time.monotonic() - due)  # when the publication starts
            self.send(piece, k)
            self.sent += 1
            if progress is not None:
                progress(1)
        return True

    def _pause(self, due: float) -> bool:
        """Wait until the monotonic clock reaches ``due``: on the wait set (a signal wakes it),
        then a short poll; False, at once, when a signal came."""
        while caught() is None:
            left = due - time.monotonic()
            if left <= _SPIN_AHEAD:
                while time.monotonic() < due:
                    pass
                return caught() is None
            self._waitset.wait(int(min(left - _SPIN_AHEAD, _WAIT_SLICE) * 1e9))
        return False
