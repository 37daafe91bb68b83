"""Driving a plan live: its commands published on a monotonic-clock schedule, then zero.

The commands are a :class:`diffbot.ramps.CommandStream` (a plan sampled at a rate, each command
held for its period): the k-th goes out at ``start + times[k]`` of the monotonic clock, never
``previous + period``, so sleeping late once does not shift the rest. Each is a
geometry_msgs/Twist (or TwistStamped) on ``cmd_vel``, or one Float64MultiArray per side. However
the drive ends (the last command, Ctrl-C, SIGTERM, SIGHUP, an error) the robot is commanded to
stop.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from diffbot.live import types
from diffbot.live.messages import commands, now_ns, time_of, twist_command
from diffbot.live.transport import Node, Publisher

if TYPE_CHECKING:
    from diffbot.ramps import CommandStream

__all__ = ["DriveReport", "DriveSettings", "Driver"]

#: How long before a command's time the schedule stops sleeping and polls the clock (s): sleep
#: wakes up late by up to a scheduler tick; the last stretch is waited out exactly.
_SPIN_AHEAD = 0.002


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
    left_topic: str = "left_wheel_velocity_controller/commands"
    right_topic: str = "right_wheel_velocity_controller/commands"
    joints: tuple[int, int] = (1, 1)


@dataclass(frozen=True)
class DriveReport:
    """How a drive went: commands sent, whether it ran to its end, and its timing.

    Attributes:
        sent: commands published (the final zero included).
        total: commands in the plan.
        completed: every command went out (not cut short by a signal).
        lateness: each command's publication time minus its scheduled time (s).
        duration_error: when the last command went out minus when it was due (s).
    """

    sent: int
    total: int
    completed: bool
    lateness: tuple[float, ...]
    duration_error: float

    def percentile(self, q: float) -> float:
        """The ``q`` quantile (0..1) of the lateness (s), nearest rank; 0 with no command."""
        if not self.lateness:
            return 0.0
        ordered = sorted(self.lateness)
        return ordered[min(len(ordered) - 1, max(0, math.ceil(q * len(ordered)) - 1))]


class Driver(Node):
    """Publishes a command stream live.

    Example::

        with Driver(stream, DriveSettings(stamped=True)) as driver:
            driver.wait_for_subscriber(5.0)
            report = driver.drive()

    Args:
        stream: the commands and their times.
        settings: topics and message kinds.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        stream: CommandStream,
        settings: DriveSettings = DriveSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_drive",
    ) -> None:
        self.stream = stream
        self.settings = settings
        #: Commands published so far by :meth:`drive`.
        self.sent = 0
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
        """Whether every command topic has a subscriber within ``timeout`` seconds."""
        end = time.monotonic() + timeout
        return all(
            p.wait_for_subscribers(max(end - time.monotonic(), 0.0)) for p in self._publishers()
        )

    def other_publishers(self) -> int:
        """How many publishers besides this one command the same topics (another drive, a
        teleop): their commands would mix with these."""
        return sum(max(len(self.publications(topic)) - 1, 0) for topic in self.topics)

    def send(self, k: int) -> None:
        """Publish command ``k`` of the stream."""
        s = self.stream
        if self._sides:
            left, right = self.settings.joints
            self._sides[0].publish(commands([float(s.left[k])] * left))
            self._sides[1].publish(commands([float(s.right[k])] * right))
        else:
            self._send_twist(float(s.linear[k]), float(s.angular[k]))

    def _send_twist(self, linear: float, angular: float) -> None:
        twist = twist_command(linear, angular)
        if self._stamped is not None:
            header = types.Header(time_of(now_ns()), self.settings.frame_id)
            self._stamped.publish(types.TwistStamped(header, twist))
        elif self._twist is not None:
            self._twist.publish(twist)

    def stop(self) -> None:
        """Command zero on every topic."""
        if self._sides:
            left, right = self.settings.joints
            self._sides[0].publish(commands([0.0] * left))
            self._sides[1].publish(commands([0.0] * right))
        else:
            self._send_twist(0.0, 0.0)

    def drive(self, progress: Callable[[int], None] | None = None) -> DriveReport:
        """Publish every command on schedule, then zero; zero also when interrupted (the
        interruption is raised again after the stop). ``progress(1)`` after each command."""
        times = self.stream.times
        total = int(times.size)
        lateness: list[float] = []
        self.sent = sent = 0
        start = time.monotonic()
        try:
            for k in range(total):
                due = start + float(times[k])
                _wait_until(due)
                lateness.append(time.monotonic() - due)  # when the publication starts
                self.send(k)
                self.sent = sent = sent + 1
                if progress is not None:
                    progress(1)
        finally:
            self.stop()
            for publisher in self._publishers():
                publisher.flush(1.0)
        error = lateness[-1] if sent == total and total else 0.0
        return DriveReport(sent, total, sent == total, tuple(lateness), error)


def _wait_until(due: float) -> None:
    """Sleep until the monotonic clock reaches ``due``: coarse sleep, then a short poll."""
    left = due - time.monotonic()
    if left > _SPIN_AHEAD:
        time.sleep(left - _SPIN_AHEAD)
    while time.monotonic() < due:
        pass
