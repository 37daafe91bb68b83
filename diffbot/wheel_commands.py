"""Velocity commands to wheel joint commands, one command at a time, as a robot's controller
turns them: speed limiter, inverse kinematics, wheel saturation, direction signs.

The streaming counterpart of :func:`diffbot.execution.execute_plan` for a live node: each call of
:meth:`WheelCommander.step` is one controller update of ``dt`` seconds. The linear and angular
commands go through diff_drive_controller's rate limiter (:func:`diffbot.limiter.limit`) when the
controller configuration has limits, then to wheel speeds (:func:`diffbot.kinematics.inverse`),
then within the motor limit (:func:`diffbot.kinematics.saturate`: one factor for both wheels,
keeping the turning radius, unless the configuration says ``preserve_turning_radius: false``),
then to each joint with its direction sign. A NaN or infinite command is refused: the wheels
are commanded to stop; so they are when a finite command is too large to compute wheel speeds
from (a robot without a motor limit commanded 1e307 m/s): no command is ever infinite.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from diffbot.body_limits import BodyLimits, axis_with_velocity, clamp
from diffbot.controller_config import AxisLimits
from diffbot.kinematics import (
    DiffDriveParams,
    Twist,
    forward,
    inverse,
    joint_from_wheel,
    saturate,
)
from diffbot.limiter import checked, limit
from diffbot.numbers import flag
from diffbot.wheel_topics import LEFT_TOPIC, RIGHT_TOPIC

__all__ = ["LEFT_TOPIC", "RIGHT_TOPIC", "JointCommands", "WheelCommander"]


@dataclass(frozen=True)
class JointCommands:
    """One command per joint of each side (rad/s, direction signs applied), and the body
    velocity they drive (m/s, rad/s) after limits."""

    left: tuple[float, ...]
    right: tuple[float, ...]
    linear: float
    angular: float


class WheelCommander:
    """Turns (linear, angular) commands into joint velocity commands, update by update.

    Args:
        params: the robot: radii, separation, joints of each side, signs, motor limit
            (``max_wheel_speed``); its controller configuration's limits apply when it has one.
        use_limits: run the commands through the controller's limiter (when it has limits).
        body: body velocity limits (:func:`diffbot.body_limits.body_limits`) in place of the
            controller's ``max_velocity`` / ``min_velocity``: linear and angular commands are
            clamped into them apart, as diff_drive_controller's two speed limiters do.

    Attributes:
        refused: commands refused for a NaN or infinite value, or wheel speeds too large to
            compute.
    """

    def __init__(
        self, params: DiffDriveParams, *, use_limits: bool = True, body: BodyLimits | None = None
    ) -> None:
        use_limits = flag(use_limits, "use_limits")
        self.params = params
        controller = params.controller
        self._linear: AxisLimits | None = None
        self._angular: AxisLimits | None = None
        self._body = None if body is None or body.unlimited else body
        if use_limits and controller is not None:
            linear = checked(controller.linear, "linear.x")
            angular = checked(controller.angular, "angular.z")
            if linear != AxisLimits() or angular != AxisLimits():
                # The limiter clamps velocity last: the given limits take the file's place.
                given = BodyLimits() if body is None else body
                self._linear = axis_with_velocity(linear, given.linear)
                self._angular = axis_with_velocity(angular, given.angular)
        preserve = None if controller is None else controller.preserve_turning_radius
        self._preserve = True if preserve is None else preserve
        self._left_count = max(len(params.left_joints), 1)
        self._right_count = max(len(params.right_joints), 1)
        # The commands the limiter executed on the last two updates (v0, v1), per axis.
        self._history = [0.0, 0.0, 0.0, 0.0]
        self.refused = 0

    @property
    def limited(self) -> bool:
        """Whether the controller's limiter is applied."""
        return self._linear is not None

    def reset(self) -> None:
        """Forget the limiter's history (as the controller does when it is activated)."""
        self._history = [0.0, 0.0, 0.0, 0.0]

    def step(self, linear: float, angular: float, dt: float) -> JointCommands:
        """The joint commands of one update of ``dt`` seconds commanding ``linear`` (m/s) and
        ``angular`` (rad/s); a NaN or infinite command commands zero (and is counted)."""
        if not (math.isfinite(linear) and math.isfinite(angular)):
            self.refused += 1
            linear = angular = 0.0
        if self._linear is not None and self._angular is not None:
            v0, v1, w0, w1 = self._history
            linear = limit(self._linear, linear, v0, v1, dt)
            angular = limit(self._angular, angular, w0, w1, dt)
            self._history = [linear, v0, angular, w0]
        elif self._body is not None:
            twist = clamp(Twist(linear, angular), self._body)
            linear, angular = float(twist.linear), float(twist.angular)
        speeds = inverse(self.params, linear, angular)
        if (speeds.left - speeds.left) + (speeds.right - speeds.right) != 0.0:
            # Finite commands too large to compute wheel speeds from (1e307 m/s): refused as a
            # NaN is, never saturated from infinity nor sent as an infinite wheel command.
            self.refused += 1
            self.reset()
            return JointCommands((0.0,) * self._left_count, (0.0,) * self._right_count, 0.0, 0.0)
        wheels = saturate(self.params, speeds, preserve_turning_radius=self._preserve)
        joints = joint_from_wheel(self.params, wheels)
        left, right = float(joints.left), float(joints.right)
        body = forward(self.params, wheels.left, wheels.right)
        return JointCommands(
            (left,) * self._left_count,
            (right,) * self._right_count,
            float(body.linear),
            float(body.angular),
        )
