"""The open-loop odometry node: velocity commands in, nav_msgs/Odometry and odom -> base_link out.

What diff_drive_controller publishes with ``open_loop: true``: the pose the robot reaches by
doing exactly what it is commanded, each command held until the next or until it is ``timeout``
seconds old (:class:`~diffbot.live.held_commands.HeldCommands`). Commands are read as the
inverse-kinematics node reads them (geometry_msgs/Twist or TwistStamped, timed by their arrival
on this machine's clock); the odometry is published at the publish rate, stamped with that
clock. A command that is not finite or out of range (:mod:`diffbot.live.wire`) is refused and
counted, and the robot is taken to stop, as the inverse-kinematics node stops the wheels.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

from diffbot.kinematics import DiffDriveParams
from diffbot.live.held_commands import HeldCommands
from diffbot.live.messages import twist_mismatch
from diffbot.live.odometry import OdometryNode, OdometrySettings
from diffbot.live.transport import LiveError, Subscription
from diffbot.live.twist_subscriptions import subscribe_twists
from diffbot.live.wire import Refusals, twist_problem
from diffbot.numbers import MAX_PLAN_DURATION, MAX_TIMER_RATE, finite_in_range

__all__ = ["DEFAULT_PUBLISH_RATE", "CommandSettings", "OpenLoopOdometryNode"]

#: Odometry messages a second when no publish rate is given (Hz): diff_drive_controller's
#: default ``publish_rate``.
DEFAULT_PUBLISH_RATE = 50.0


@dataclass(frozen=True)
class CommandSettings:
    """Where the commands come from, and how long one holds.

    Attributes:
        cmd_vel: the velocity command topic.
        stamped: geometry_msgs/TwistStamped (True), Twist (False) or either, whichever the
            publisher sends (None).
        timeout: seconds after its arrival when a command stops holding (0: never), as
            diff_drive_controller's ``cmd_vel_timeout``.
    """

    cmd_vel: str = "cmd_vel"
    stamped: bool | None = None
    timeout: float = 0.5


_ODOMETRY = OdometrySettings()


class OpenLoopOdometryNode(OdometryNode):
    """Odometry from velocity commands on a live graph, as diff_drive_controller's open loop.

    Example::

        with OpenLoopOdometryNode(params, commands=CommandSettings("cmd_vel")) as node:
            node.spin(10.0)
            print(node.odometry.pose, node.counts)

    Args:
        params: the robot (radii, separation, direction signs).
        settings: the odometry's topic, frames, rate (None: :data:`DEFAULT_PUBLISH_RATE`) and
            covariances (``joint_states``, ``feedback`` and ``window`` are not read: the
            twist is the held command's, as the controller publishes it).
        commands: the command topic, its kind and the timeout.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        settings: OdometrySettings = _ODOMETRY,
        commands: CommandSettings = CommandSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_odometry",
    ) -> None:
        finite_in_range(commands.timeout, "timeout", 0.0, MAX_PLAN_DURATION, error=LiveError)
        if settings.publish_rate is not None:
            # the publish rate is this node's own timer: faster would only spin the processor
            finite_in_range(
                settings.publish_rate, "publish_rate", 0.0, MAX_TIMER_RATE, error=LiveError
            )
        # The held commands are fed as wheel angles (position feedback), and the twist is the
        # held command itself, as the controller's open loop publishes it (no rolling window).
        settings = replace(settings, feedback="position", window=1)
        self.command_settings = commands
        #: Commands received.
        self.commands = 0
        #: Commands refused at the boundary (:mod:`diffbot.live.wire`), by reason.
        self.command_refusals = Refusals()
        super().__init__(params, settings, domain=domain, name=name)

    def _subscribe(self, params: DiffDriveParams) -> None:
        """Subscribe the commands and publish on a timer of the publish rate."""
        commands = self.command_settings
        self.held = HeldCommands(params, self.odometry, commands.timeout)
        self.subscriptions: list[Subscription[Any]] = subscribe_twists(
            self, commands.cmd_vel, commands.stamped, self.on_command
        )
        rate = self.settings.publish_rate or DEFAULT_PUBLISH_RATE
        self.create_timer(1.0 / rate, self.on_tick)

    def type_mismatch(self, topic: str, found: str, ours: list[str]) -> str:
        """Name the option that reads the other kind of twist."""
        return twist_mismatch(topic, found)

    def on_command(self, command: tuple[float, float], now_ns: int | None = None) -> None:
        """Hold one velocity command, (linear.x (m/s), angular.z (rad/s)), from ``now_ns``
        (this machine's clock, ns; read when None); one that fails the wire checks is refused
        and counted, and the robot taken to stop."""
        now = time.time_ns() if now_ns is None else now_ns
        self.commands += 1
        linear, angular = command
        if not self.command_refusals.check(twist_problem(linear, angular)):
            linear = angular = 0.0
        self.held.command(linear, angular, now)

    def on_tick(self, now_ns: int | None = None) -> None:
        """Move the odometry by the held command up to ``now_ns`` (this machine's clock, ns;
        read when None) and publish it."""
        now = time.time_ns() if now_ns is None else now_ns
        if self.held.advance(now):
            self.publish(now)

    @property
    def counts(self) -> dict[str, int]:
        """Commands received, odometry messages published, and commands skipped by reason
        (malformed payloads, the wire's reasons)."""
        skipped = dict(self.command_refusals.counts)
        malformed = sum(s.malformed for s in self.subscriptions)
        if malformed:
            skipped["malformed"] = malformed
        received = sum(s.received for s in self.subscriptions) + malformed
        return {"received": received, "published": self.published, **skipped}

    def _tally(self, counts: dict[str, int]) -> str:
        """The status line's head, ``1200 commands, 3000 published`` (the skips follow it)."""
        return f"{counts.pop('received')} commands, {counts.pop('published')} published"
