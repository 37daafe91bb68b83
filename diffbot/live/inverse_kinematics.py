"""The inverse-kinematics node: geometry_msgs/Twist (or TwistStamped) on ``cmd_vel`` in, one
std_msgs/Float64MultiArray per side out, to the wheels' velocity controllers.

The maths is :class:`diffbot.wheel_commands.WheelCommander`'s (limiter, inverse kinematics,
saturation, signs). The node publishes each command as it comes when no limiter applies, and on a
timer of the controller's update rate when one does (the limiter works per update). When
``cmd_vel`` stays quiet for ``timeout`` seconds the wheels are commanded to stop, as
diff_drive_controller's ``cmd_vel_timeout`` does; a command that is not finite or out of range
(:mod:`diffbot.live.wire`) is refused and stops them at once; so does the node's end.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from diffbot.body_limits import BodyLimits
from diffbot.execution import DEFAULT_UPDATE_RATE
from diffbot.kinematics import DiffDriveParams
from diffbot.live import types
from diffbot.live.cdr import encode_float64_array
from diffbot.live.messages import commands, twist_mismatch
from diffbot.live.names import check_distinct_topics
from diffbot.live.transport import LiveError, Node, Subscription
from diffbot.live.twist_subscriptions import subscribe_twists
from diffbot.live.wire import NOT_FINITE, Refusals, twist_problem
from diffbot.numbers import MAX_PLAN_DURATION, finite_in_range
from diffbot.wheel_commands import WheelCommander
from diffbot.wheel_topics import LEFT_TOPIC, RIGHT_TOPIC

__all__ = ["IkSettings", "InverseKinematicsNode"]

#: The shortest period of the timeout's watch (s).
_SHORTEST_WATCH = 1e-3
#: How long the last zero may wait for reliable subscribers' acknowledgements (s).
_FLUSH = 1.0


@dataclass(frozen=True)
class IkSettings:
    """Topics, message kind and timing of the inverse-kinematics node.

    Attributes:
        cmd_vel: the velocity command topic.
        stamped: commands are geometry_msgs/TwistStamped (diff_drive_controller since Jazzy)
            (True), geometry_msgs/Twist (False), or either, as the publisher offers (None: a
            subscription of each kind, and only the one of the publisher's type matches).
        left_topic: the left side's Float64MultiArray topic.
        right_topic: the right side's.
        timeout: seconds without a command after which the wheels are stopped (0: never).
        rate: controller updates per second (Hz) when the limiter applies.
        use_limits: apply the controller configuration's limiter.
        body: body velocity limits (m/s, rad/s) that replace the configuration's velocity
            limits; linear and angular commands are clamped apart, as the controller does.
    """

    cmd_vel: str = "cmd_vel"
    stamped: bool | None = None
    left_topic: str = LEFT_TOPIC
    right_topic: str = RIGHT_TOPIC
    timeout: float = 0.5
    rate: float = DEFAULT_UPDATE_RATE
    use_limits: bool = True
    body: BodyLimits | None = None


class InverseKinematicsNode(Node):
    """Wheel commands from velocity commands on a live graph.

    Args:
        params: the robot.
        settings: topics, kind, timeout, update rate.
        domain: the DDS domain (``ROS_DOMAIN_ID`` when None).
        name: the node's name.
    """

    def __init__(
        self,
        params: DiffDriveParams,
        settings: IkSettings = IkSettings(),
        *,
        domain: int | None = None,
        name: str = "diffbot_ik",
    ) -> None:
        finite_in_range(settings.timeout, "timeout", 0.0, MAX_PLAN_DURATION, error=LiveError)
        finite_in_range(settings.rate, "rate", 1.0 / MAX_PLAN_DURATION, error=LiveError)
        self.settings = settings
        self.commander = WheelCommander(params, use_limits=settings.use_limits, body=settings.body)
        self.commands = 0
        #: Commands refused (:mod:`diffbot.live.wire`), by reason.
        self.refusals = Refusals()
        self.timeouts = 0
        self._command = (0.0, 0.0)
        self._last: float | None = None
        self._moving = False
        check_distinct_topics(
            [
                ("the command topic", settings.cmd_vel),
                ("{left_topic}", settings.left_topic),
                ("{right_topic}", settings.right_topic),
            ],
            name,
        )
        super().__init__(name, domain=domain)
        self.left = self.create_publisher(types.Float64MultiArray, settings.left_topic)
        self.right = self.create_publisher(types.Float64MultiArray, settings.right_topic)
        self.subscriptions: list[Subscription[Any]] = subscribe_twists(
            self, settings.cmd_vel, settings.stamped, self.on_command
        )
        period = 1.0 / settings.rate
        if self.commander.limited:
            self.create_timer(period, self.update)
        elif settings.timeout > 0.0:
            # A quarter of the timeout, but not a busy loop for a timeout of nanoseconds.
            self.create_timer(max(min(period, settings.timeout / 4), _SHORTEST_WATCH), self.watch)

    def type_mismatch(self, topic: str, found: str, ours: list[str]) -> str:
        """Name the option that reads the other kind of twist."""
        return twist_mismatch(topic, found)

    def on_twist(self, twist: types.Twist) -> None:
        """Take one velocity command (linear.x, angular.z); one that fails the wire checks
        (:func:`~diffbot.live.wire.twist_problem`) is refused and stops the wheels at once."""
        self.on_command((twist.linear.x, twist.angular.z))

    def on_command(self, command: tuple[float, float]) -> None:
        """Take one velocity command as (linear.x (m/s), angular.z (rad/s)), as
        :meth:`on_twist` does."""
        self.commands += 1
        self._last = time.monotonic()
        linear, angular = command
        if not self.refusals.check(twist_problem(linear, angular)):
            # Refused: the wheels stop now, without the limiter's ramp down.
            self._command = (0.0, 0.0)
            self.commander.reset()
            self._send(0.0, 0.0, 0.0)
            return
        self._command = (linear, angular)
        if not self.commander.limited:
            self._send(*self._command, 0.0)

    @property
    def refused(self) -> int:
        """Commands refused at the boundary."""
        return self.refusals.total

    def _stale(self) -> bool:
        timeout = self.settings.timeout
        last = self._last
        return last is not None and timeout > 0.0 and time.monotonic() - last > timeout

    def update(self) -> None:
        """One controller update through the limiter: the last command, or zero when stale."""
        if self._stale():
            if self._command != (0.0, 0.0):
                self.timeouts += 1
            self._command = (0.0, 0.0)
        self._send(*self._command, 1.0 / self.settings.rate)

    def watch(self) -> None:
        """Stop the wheels once when commands went quiet for the timeout."""
        if self._moving and self._stale():
            self.timeouts += 1
            self._command = (0.0, 0.0)
            self._send(0.0, 0.0, 0.0)

    def _send(self, linear: float, angular: float, dt: float) -> None:
        joints = self.commander.step(linear, angular, dt)
        self.left.publish_serialized(encode_float64_array(joints.left))
        self.right.publish_serialized(encode_float64_array(joints.right))
        self._moving = joints.linear != 0.0 or joints.angular != 0.0

    def destroy_node(self) -> None:
        """Command zero on both sides, then go: the wheels stop when the node ends (however it
        ends), as diff_drive_controller's do when it is deactivated."""
        if not self._destroyed:
            params = self.commander.params
            for publisher, joints in (
                (self.left, params.left_joints),
                (self.right, params.right_joints),
            ):
                publisher.publish(commands([0.0] * max(len(joints), 1)))
            for publisher in (self.left, self.right):
                publisher.flush(_FLUSH)
        super().destroy_node()

    def status(self) -> str:
        """One line of counts for people."""
        counts = self.refusals.counts
        if set(counts) <= {NOT_FINITE}:
            refused = f"{self.refused} refused (not finite)"
        else:
            reasons = ", ".join(f"{n} {reason}" for reason, n in counts.items())
            refused = f"{self.refused} refused ({reasons})"
        return (
            f"{self.commands} commands, {refused}, {self.timeouts} timeouts, "
            f"{self.malformed} malformed"
        )
