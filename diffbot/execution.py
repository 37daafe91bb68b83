"""A plan executed through diff_drive_controller's speed limiter, then integrated exactly.

The plan's commands are sampled at the controller's update rate (each the mean velocity over its
period, see :meth:`diffbot.ramps.RampedPlan.commands`), limited as the controller limits them
(:func:`diffbot.limiter.execute`), and each executed command is held for its period: the pose
moves along an exact arc per period (not Euler). A plan whose commands keep every limit is
executed unchanged and ends where it was planned; a step plan through an acceleration limit cuts
its corners and ends elsewhere (:attr:`Execution.offset`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final

import numpy as np

from diffbot.kinematics import Pose, WheelSpeeds, inverse, joint_from_wheel, norm_angle
from diffbot.limiter import LimiterError, execute
from diffbot.profiles import Limits
from diffbot.ramps import RampedPlan, _axis, ramp
from diffbot.trajectory import Plan

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    from diffbot.controller_config import ControllerConfig

__all__ = [
    "DEFAULT_UPDATE_RATE",
    "MAX_EXECUTED_UPDATES",
    "Execution",
    "estimated_updates",
    "execute_plan",
    "limits_apply",
]

#: The controller manager's update rate (Hz) when the configuration gives none (its default).
DEFAULT_UPDATE_RATE: Final = 100.0
#: Most controller updates an execution may take: each is a time a simulation samples at (its
#: command changes there), so their number bounds the work and the memory. At 100 Hz, this is
#: more than two and a half hours of plan.
MAX_EXECUTED_UPDATES: Final = 1_000_000


@dataclass(frozen=True)
class Execution:
    """What the controller executed.

    Attributes:
        planned: the plan (ramped or step) that was executed.
        rate: the controller's update rate (Hz).
        times: update times (s) from 0; each command holds for 1/rate s.
        linear: executed linear.x (m/s), one per update.
        angular: executed angular.z (rad/s), one per update.
        joints: executed joint velocities (rad/s, signs applied), one per update.
        final_pose: the pose after the last update (m, m, rad in (-pi, pi]).
    """

    planned: RampedPlan
    rate: float
    times: NDArray[np.float64]
    linear: NDArray[np.float64]
    angular: NDArray[np.float64]
    joints: WheelSpeeds
    final_pose: Pose

    @property
    def duration(self) -> float:
        """Time (s) until the last executed command has run its period."""
        return float(self.times[-1]) + 1.0 / self.rate if self.times.size else 0.0

    @property
    def boundaries(self) -> tuple[float, ...]:
        """The update times (s) after the first, and the end: where the executed command may
        change."""
        return (*self.times[1:].tolist(), self.duration)

    @property
    def offset(self) -> float:
        """Distance (m) from the planned final pose to the executed one."""
        planned = self.planned.final_pose
        return math.hypot(self.final_pose.x - planned.x, self.final_pose.y - planned.y)

    def wheel_positions(self, times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint angles (rad, signs applied, 0 at the start) at times (s): exact, as each
        executed command holds a constant wheel speed over its period."""
        knots = np.append(self.times, self.duration)
        dt = 1.0 / self.rate
        out = []
        for speeds in self.joints:
            angles = np.concatenate(([0.0], np.cumsum(np.asarray(speeds) * dt)))
            out.append(np.interp(np.asarray(times, dtype=np.float64), knots, angles))
        return out[0], out[1]


def limits_apply(controller: ControllerConfig | None) -> bool:
    """Whether a controller configuration limits any velocity, acceleration or jerk."""
    if controller is None:
        return False
    return any(
        value is not None
        for axis in (controller.linear, controller.angular)
        for value in (
            axis.max_velocity,
            axis.min_velocity,
            axis.max_acceleration,
            axis.max_jerk,
        )
    )


def estimated_updates(plan: RampedPlan, controller: ControllerConfig) -> float:
    """About how many updates (at least) the controller takes to execute a plan: one per period
    of the plan, and the time it needs after the last command to stop at its tightest
    acceleration limit, from the speed it can have reached.

    Returns:
        A float, as it may be huge (``inf`` for an absurd rate or limit).
    """
    rate = controller.update_rate or DEFAULT_UPDATE_RATE
    duration = plan.duration
    settle = 0.0
    segments = plan.summary.segments
    for axis, peak in (
        (controller.linear, max(abs(float(s.twist.linear)) for s in segments)),
        (controller.angular, max(abs(float(s.twist.angular)) for s in segments)),
    ):
        accel = _axis(axis).acceleration
        if accel is not None and peak > 0.0:
            settle = max(settle, min(peak / accel, duration))
    with np.errstate(over="ignore"):
        return float(np.float64(duration + settle) * rate)


def execute_plan(plan: Plan | RampedPlan, controller: ControllerConfig) -> Execution:
    """Execute a plan through the controller's speed limiter, at its update rate.

    Args:
        plan: a step plan or a ramped plan.
        controller: the configuration: its ``linear``/``angular`` limits, its
            ``preserve_turning_radius`` and ``update_rate`` (100 Hz when it gives none).

    Returns:
        The executed commands and the pose they reach.

    Raises:
        LimiterError: a limit with the wrong sign, or an execution of more than
            :data:`MAX_EXECUTED_UPDATES` updates (refused before any is made).
    """
    ramped = plan if isinstance(plan, RampedPlan) else ramp(plan, Limits())
    rate = controller.update_rate or DEFAULT_UPDATE_RATE
    updates = estimated_updates(ramped, controller)
    if updates > MAX_EXECUTED_UPDATES:
        raise LimiterError(
            f"executing this plan through the controller's limiter takes about {updates:.3g} "
            f"updates at its update_rate of {rate:g} Hz (at most {MAX_EXECUTED_UPDATES} are "
            f"simulated): lower update_rate or raise the acceleration limits in "
            f"{controller.source}, or shorten the plan"
        )
    stream = ramped.commands(rate)
    times, linear, angular = execute(
        stream.times,
        stream.linear,
        stream.angular,
        linear_limits=controller.linear,
        angular_limits=controller.angular,
        rate_hz=rate,
        preserve_turning_radius=bool(controller.preserve_turning_radius),
    )
    dt = 1.0 / rate
    params = ramped.steps.params
    ds, turn = linear * dt, angular * dt
    heading = np.concatenate(([0.0], np.cumsum(turn)))
    # Each period an exact arc: the chord ds·sinc(turn/2) along the mean heading.
    chord = ds * np.sinc(turn / (2.0 * math.pi))
    mean = heading[:-1] + turn / 2.0
    x, y = float(np.sum(chord * np.cos(mean))), float(np.sum(chord * np.sin(mean)))
    wheels = inverse(params, linear, angular)
    joints = joint_from_wheel(params, wheels)
    return Execution(
        planned=ramped,
        rate=rate,
        times=times,
        linear=linear,
        angular=angular,
        joints=WheelSpeeds(np.asarray(joints.left), np.asarray(joints.right)),
        final_pose=Pose(x + 0.0, y + 0.0, norm_angle(float(heading[-1])) + 0.0),
    )
