"""Ramped plans: each run of equal curvature driven with one speed profile, poses still exact.

A step plan (:func:`diffbot.trajectory.plan`) jumps from one velocity to the next. With
acceleration or jerk limits, :func:`ramp` drives each run of consecutive segments of equal
curvature (and direction of travel) with the fastest speed profile along its path
(:mod:`diffbot.profiles`: a trapezoid, or an S-curve under a jerk limit) that keeps the
segments' own speeds as its cruise and every limit: the robot comes to rest only where the
curvature changes. As the profile only changes the speed along the path, the path and every
pose stay exact (closed form, not sampled integration).

At time t of a run, with s(t) the profile's position: linear.x = ±s'(t), angular.z =
κ·(±s'(t)) (for a spin, s is the heading and angular.z = ±s'(t)).

:meth:`RampedPlan.commands` samples the plan as a command stream at a rate: each command is the
mean velocity over its period, and each run starts on a period boundary, so that the stream,
each command held for its period, drives the exact path (what a controller running at that rate
executes).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from diffbot.errors import PlanError
from diffbot.kinematics import Pose, Twist, WheelSpeeds, inverse, joint_from_wheel, limit_fraction
from diffbot.numbers import MAX_PLAN_DURATION, MAX_PLAN_SAMPLES
from diffbot.profiles import Limits, PathLimits, Profile, path_limits, time_optimal, trapezoid
from diffbot.trajectory import (
    Plan,
    PlannedSegment,
    Spin,
    advance,
    clipped_times,
    geometry,
    plan_time,
    reported_pose,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    from diffbot.body_limits import BodyLimits
    from diffbot.controller_config import AxisLimits, ControllerConfig

__all__ = [
    "COMMAND_CHUNK",
    "CommandStream",
    "RampedPlan",
    "Run",
    "controller_limits",
    "has_ramps",
    "ramp",
    "sampled",
]


@dataclass(frozen=True)
class Run:
    """Consecutive segments of one curvature, driven with one speed profile.

    Attributes:
        segments: indices of its segments in the plan.
        start: its start time in the plan (s).
        profile: the speed profile of its path coordinate (m; rad of heading for a spin).
        linear_gain: linear.x per unit of path speed (±1; 0 for a spin).
        angular_gain: angular.z per unit of path speed (rad/m; ±1 for a spin).
        wheel_gains: joint velocities (rad/s) per unit of path speed, signs applied.
        ends: time of each segment's end from the run's start (s), the last the run's duration.
        start_pose: pose at its start (m, m, rad; the heading not wrapped).
    """

    segments: tuple[int, ...]
    start: float
    profile: Profile
    linear_gain: float
    angular_gain: float
    wheel_gains: WheelSpeeds
    ends: tuple[float, ...]
    start_pose: Pose

    @property
    def duration(self) -> float:
        """Its duration (s)."""
        return self.profile.duration


#: Commands per piece of :meth:`RampedPlan.command_chunks` unless told otherwise.
COMMAND_CHUNK = 65_536


@dataclass(frozen=True)
class CommandStream:
    """Commands in time: each held from its time until the next; the last is zero.

    Attributes:
        times: command times (s) from 0, increasing.
        linear: linear.x (m/s).
        angular: angular.z (rad/s).
        left: left joint velocity (rad/s, direction sign applied).
        right: right joint velocity (rad/s).
    """

    times: NDArray[np.float64]
    linear: NDArray[np.float64]
    angular: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]


@dataclass(frozen=True)
class RampedPlan:
    """A plan driven with speed profiles.

    Attributes:
        steps: the step plan of the same segments: its speeds are the cruise speeds, its motor
            limit check and its poses hold for the ramped plan too.
        runs: the runs of equal curvature, in order.
        limits: the limits the profiles keep.
        summary: the plan as a step plan would report it, with each segment's ramped duration
            and its peak twist and wheel speeds.
    """

    steps: Plan
    runs: tuple[Run, ...]
    limits: Limits
    summary: Plan

    @property
    def duration(self) -> float:
        """Total time (s)."""
        return self.summary.duration

    @property
    def boundaries(self) -> tuple[float, ...]:
        """Segment ends (s); runs start at the ends of the runs before them."""
        return tuple(run.start + end for run in self.runs for end in run.ends)

    @property
    def final_pose(self) -> Pose:
        """The pose at the end: the step plan's."""
        return self.steps.final_pose

    @property
    def within_limit(self) -> bool:
        """Whether every wheel stays within the motor limit."""
        return self.steps.within_limit

    def _locate(self, times: ArrayLike) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        t = clipped_times(times, self.duration)
        starts = np.array([run.start for run in self.runs])
        index = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.runs) - 1)
        return index, t - starts[index]

    def twist_at(self, times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """linear.x (m/s) and angular.z (rad/s) at times (s), shaped like ``times``."""
        index, tau = self._locate(times)
        speed = np.zeros(np.shape(tau))
        linear, angular = np.zeros_like(speed), np.zeros_like(speed)
        for k, run in enumerate(self.runs):
            mask = index == k
            speed = run.profile.velocity(tau[mask])
            linear[mask] = run.linear_gain * speed
            angular[mask] = run.angular_gain * speed
        return linear, angular

    def pose_at(self, t: float) -> Pose:
        """The pose (m, m, rad in (-pi, pi]) at time ``t`` (s), in closed form."""
        t = plan_time(t)
        if t >= self.duration:
            return self.final_pose
        index, tau = self._locate(t)
        run = self.runs[int(index)]
        s = run.profile.position(float(tau))
        x, y, heading = run.start_pose
        pose = advance(x, y, heading, run.linear_gain * s, run.angular_gain * s)
        return reported_pose(*pose)

    def wheel_positions(self, times: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint angles (rad, signs applied, 0 at the start) at times (s), shaped like
        ``times``."""
        index, tau = self._locate(times)
        sides = []
        for side in (0, 1):
            angles = np.zeros(np.shape(tau))
            before = 0.0
            for k, run in enumerate(self.runs):
                mask = index == k
                gain = float(run.wheel_gains[side])
                angles[mask] = before + gain * run.profile.position(tau[mask])
                before += gain * run.profile.length
            sides.append(angles)
        return sides[0], sides[1]

    def commands(self, rate: float) -> CommandStream:
        """The plan as commands at ``rate`` Hz, each the mean velocity over its period.

        Each run starts on a period boundary (the robot rests a little longer where the
        curvature changes, at most one period per run), so each period lies within one run, and
        the commands, each held for its period, drive the exact path. The stream ends with a
        zero command one period after the last run's last command.

        Args:
            rate: commands per second (Hz), at least one per :data:`MAX_PLAN_DURATION`.

        Returns:
            The commands; their times are ``k / rate``.
        """
        chunks = list(self.command_chunks(rate, chunk=_MAX_COMMANDS))
        return CommandStream(
            *(np.concatenate([getattr(c, name) for c in chunks]) for name in _STREAM_FIELDS)
        )

    def command_count(self, rate: float) -> int:
        """How many commands :meth:`commands` makes at ``rate`` Hz (the final zero included).

        Raises:
            PlanError: the rate is not a positive finite number, or the plan would take more
                than :data:`_MAX_COMMANDS` commands.
        """
        lowest = 1.0 / MAX_PLAN_DURATION
        if not (math.isfinite(rate) and rate >= lowest):
            raise PlanError(
                f"the command rate must be a finite number >= {lowest:g} Hz, got {rate!r}"
            )
        if self.duration * rate + len(self.runs) > _MAX_COMMANDS:
            raise PlanError(
                f"{self.duration:g} s at {rate:g} Hz would take more than {_MAX_COMMANDS} "
                "commands: lower the rate"
            )
        return sum(_periods(run.duration, rate) for run in self.runs) + 1

    def commands_end(self, rate: float) -> float:
        """When the final zero command of :meth:`commands` at ``rate`` Hz is sent (s): each
        run takes whole periods. Unlike :meth:`commands`, it takes no more time or memory for a
        rate too high to make them.
        """
        return sum(_periods(run.duration, rate) for run in self.runs) / rate

    def command_chunks(self, rate: float, chunk: int = COMMAND_CHUNK) -> Iterator[CommandStream]:
        """:meth:`commands` in consecutive pieces of at most ``chunk`` commands, made as they are
        asked for: millions of commands in constant memory. The rate is checked at once.

        Raises:
            PlanError: as :meth:`command_count`.
        """
        self.command_count(rate)
        return self._chunks(rate, max(1, chunk))

    def _chunks(self, rate: float, chunk: int) -> Iterator[CommandStream]:
        at = 0
        for run in self.runs:
            periods = _periods(run.duration, rate)
            left, right = run.wheel_gains
            gain = np.array([run.linear_gain, run.angular_gain, float(left), float(right)])
            for first in range(0, periods, chunk):
                last = min(first + chunk, periods)
                edges = np.minimum(np.arange(first, last + 1) / rate, run.duration)
                positions = run.profile.position(edges)
                if last == periods:
                    positions[-1] = run.profile.length
                speed = np.diff(positions) * rate
                columns = np.outer(gain, speed)
                times = np.arange(at, at + speed.size, dtype=np.float64) / rate
                yield CommandStream(times, *(columns[i] + 0.0 for i in range(4)))
                at += speed.size
        zero = np.zeros(1)
        yield CommandStream(np.array([at], dtype=np.float64) / rate, zero, zero, zero, zero)


def _periods(duration: float, rate: float) -> int:
    """Command periods of a run: each run starts on a period boundary."""
    return max(math.ceil(duration * rate - 1e-9), 1)


_STREAM_FIELDS = ("times", "linear", "angular", "left", "right")


#: Most commands :meth:`RampedPlan.commands` makes.
_MAX_COMMANDS = MAX_PLAN_SAMPLES


def has_ramps(limits: Limits) -> bool:
    """Whether the limits bound an acceleration or a jerk (so plans need ramps)."""
    return any(
        bound is not None
        for triple in (limits.linear, limits.angular, limits.wheel)
        for bound in (triple.acceleration, triple.jerk)
    )


def _magnitude(*values: float | None) -> float | None:
    """The tightest of the non-zero limits given (their magnitudes), or None."""
    given = [abs(v) for v in values if v is not None and math.isfinite(v) and v != 0.0]
    return min(given) if given else None


_ACCELERATIONS = (
    "max_acceleration",
    "min_acceleration",
    "max_deceleration",
    "max_acceleration_reverse",
    "max_deceleration_reverse",
)


def _refuse_held(axis: AxisLimits, name: str, accel: float | None, jerk: float | None) -> None:
    """Refuse an acceleration or jerk limit of exactly 0 that no given limit replaces: the
    controller's limiter then never lets the axis change its speed that way (0 is a limit
    there; no limit is NaN), so no ramp within it exists."""
    for limits, given in ((_ACCELERATIONS, accel), (("max_jerk", "min_jerk"), jerk)):
        held = next((limit for limit in limits if getattr(axis, limit) == 0.0), None)
        if held is not None and given is None:
            raise PlanError(
                f"the controller's {name}.{held} is 0: its limiter never lets {name} change "
                "speed that way, so no ramped plan runs within it (NaN is no limit)"
            )


def _axis(axis: AxisLimits) -> PathLimits:
    return PathLimits(
        _magnitude(axis.max_velocity, axis.min_velocity),
        _magnitude(
            axis.max_acceleration,
            axis.min_acceleration,
            axis.max_deceleration,
            axis.max_acceleration_reverse,
            axis.max_deceleration_reverse,
        ),
        _magnitude(axis.max_jerk, axis.min_jerk),
    )


def controller_limits(
    controller: ControllerConfig | None,
    *,
    linear_accel: float | None = None,
    angular_accel: float | None = None,
    wheel_accel: float | None = None,
    linear_jerk: float | None = None,
) -> Limits:
    """The limits a plan keeps: those given, else the controller's (the tightest magnitude of
    its forward, braking and reverse limits on each axis).

    Args:
        controller: the diff_drive_controller configuration, or None.
        linear_accel: path acceleration limit (m/s²).
        angular_accel: angular acceleration limit (rad/s²).
        wheel_accel: each wheel's angular acceleration limit (rad/s²).
        linear_jerk: path jerk limit (m/s³).
    """
    linear = angular = PathLimits()
    if controller is not None:
        _refuse_held(controller.linear, "linear.x", linear_accel, linear_jerk)
        _refuse_held(controller.angular, "angular.z", angular_accel, None)
        linear, angular = _axis(controller.linear), _axis(controller.angular)
    return Limits(
        linear=PathLimits(
            linear.velocity,
            linear.acceleration if linear_accel is None else linear_accel,
            linear.jerk if linear_jerk is None else linear_jerk,
        ),
        angular=PathLimits(
            angular.velocity,
            angular.acceleration if angular_accel is None else angular_accel,
            angular.jerk,
        ),
        wheel=PathLimits(None, wheel_accel, None),
    )


def _path(planned: PlannedSegment) -> tuple[float, float, float, bool]:
    """Path length (>= 0), linear and angular gains, and whether it turns in place."""
    ds, turn = geometry(planned.segment)
    if isinstance(planned.segment, Spin):
        return abs(turn), 0.0, math.copysign(1.0, turn), True
    return abs(ds), math.copysign(1.0, ds), turn / abs(ds), False


def _times_at(profile: Profile, positions: Sequence[float]) -> list[float]:
    """The times (s) the profile reaches ``positions``: bisection (positions never decrease),
    all of them at once, so that a run of thousands of segments costs one pass per halving."""
    target = np.asarray(positions, dtype=np.float64)
    low = np.zeros_like(target)
    high = np.full_like(target, profile.duration)
    active = np.ones(target.shape, dtype=bool)
    for _ in range(200):
        middle = 0.5 * (low + high)
        active &= (middle != low) & (middle != high)
        if not active.any():
            break
        below = np.asarray(profile.position(middle)) < target
        low = np.where(active & below, middle, low)
        high = np.where(active & ~below, middle, high)
    return [float(time) for time in high]


def sampled(made: Plan | RampedPlan) -> RampedPlan:
    """The plan whose commands are sampled in time: a ramped plan as it is, a step plan as a
    ramped plan without ramps (each segment its own run at its own constant speed)."""
    return ramp(made, Limits()) if isinstance(made, Plan) else made


def ramp(steps: Plan, limits: Limits, body: BodyLimits | None = None) -> RampedPlan:
    """Drive a step plan's segments with speed profiles within ``limits``.

    Consecutive segments of equal curvature and direction of travel form one run (for spins:
    turning the same way), driven with the fastest profile whose cruise is the slowest of its
    segments' step speeds (and within the limits' speeds); without acceleration and jerk
    limits every segment is its own run at its own constant speed (the step plan).

    Args:
        steps: the step plan (its segments, speeds and poses).
        limits: the robot's limits (speed limits cap the cruise; the motor limit is checked
            by the step plan, not imposed).
        body: the body velocity ranges (a controller's ``min_velocity`` to ``max_velocity``);
            when given, each run's speed is capped by the bound of its own direction of travel
            (forward or backward, turning left or right) instead of by ``limits``' linear and
            angular speeds, which bound both directions alike.

    Returns:
        The ramped plan.

    Raises:
        PlanError: a profile cannot be built (a bad limit).
    """
    params = steps.params
    ramped = has_ramps(limits)
    groups: list[list[PlannedSegment]] = []
    key: tuple[float, float, bool] | None = None
    for planned in steps.segments:
        _, linear_gain, angular_gain, spin = _path(planned)
        new_key = (linear_gain, angular_gain, spin)
        if not ramped or new_key != key:
            groups.append([])
        groups[-1].append(planned)
        key = new_key
    runs: list[Run] = []
    start = 0.0
    for group in groups:
        first = group[0]
        lengths = [_path(p)[0] for p in group]
        _, linear_gain, angular_gain, spin = _path(first)
        cruise = min(abs(float(p.twist.angular if spin else p.twist.linear)) for p in group)
        length = math.fsum(lengths)
        if ramped:
            left, right = params.radii
            bounds = path_limits(
                params,
                limits if body is None else _directed(limits, body, linear_gain, angular_gain),
                angular_gain * linear_gain,
                spin=spin,
                left_wheel_radius=left,
                right_wheel_radius=right,
            )
            velocity = cruise if bounds.velocity is None else min(cruise, bounds.velocity)
            profile = time_optimal(length, bounds._replace(velocity=velocity))
        else:
            profile = trapezoid(length, cruise, None)
        ends = _times_at(profile, list(itertools.accumulate(lengths[:-1])))
        ends.append(profile.duration)
        wheels = inverse(params, linear_gain, angular_gain)
        joints = joint_from_wheel(params, WheelSpeeds(float(wheels.left), float(wheels.right)))
        heading = 0.0 if first.index == 0 else steps.segments[first.index - 1].end_heading
        runs.append(
            Run(
                segments=tuple(p.index for p in group),
                start=start,
                profile=profile,
                linear_gain=linear_gain,
                angular_gain=angular_gain,
                wheel_gains=WheelSpeeds(float(joints.left), float(joints.right)),
                ends=tuple(ends),
                start_pose=Pose(first.start_pose.x, first.start_pose.y, heading),
            )
        )
        start += profile.duration
    return RampedPlan(steps, tuple(runs), limits, _summary(steps, runs))


def _directed(limits: Limits, body: BodyLimits, linear: float, angular: float) -> Limits:
    """``limits`` whose speeds are the body velocity bounds in a run's directions of travel:
    v = ``linear``·s' and ω = ``angular``·s' along its path coordinate s. A direction the
    ranges forbid is no bound here: the step plan reports it."""

    def bound(bounds: tuple[float, float] | None, way: float) -> float | None:
        if bounds is None or way == 0.0:
            return None
        found = bounds[1] if way > 0.0 else -bounds[0]
        return found if found > 0.0 else None

    return Limits(
        linear=limits.linear._replace(velocity=bound(body.linear, linear)),
        angular=limits.angular._replace(velocity=bound(body.angular, angular)),
        wheel=limits.wheel,
    )


def _peaks(run: Run) -> list[float]:
    """Each segment's peak speed along the path: the speed peaks where the acceleration ends
    (a phase boundary) or at an end, so the highest of those within the segment; evaluated for
    the whole run at once."""
    bounds = np.array([0.0, *run.ends], dtype=np.float64)
    at_bounds = np.asarray(run.profile.velocity(bounds))
    peaks = np.maximum(at_bounds[:-1], at_bounds[1:])
    starts = np.array([p.start for p in run.profile.phases], dtype=np.float64)
    at_starts = np.asarray(run.profile.velocity(starts))
    for time, speed in zip(starts.tolist(), at_starts.tolist(), strict=True):
        # the segments k with begin_k <= time <= end_k
        first = int(np.searchsorted(bounds[1:], time, side="left"))
        last = int(np.searchsorted(bounds[:-1], time, side="right"))
        peaks[first:last] = np.maximum(peaks[first:last], speed)
    return [float(peak) for peak in peaks]


def _summary(steps: Plan, runs: Sequence[Run]) -> Plan:
    """The step plan with each segment's ramped duration and its peak speeds."""
    segments: list[PlannedSegment] = []
    for run in runs:
        begin = 0.0
        for index, end, peak in zip(run.segments, run.ends, _peaks(run), strict=True):
            planned = steps.segments[index]
            twist = Twist(run.linear_gain * peak + 0.0, run.angular_gain * peak + 0.0)
            speeds = inverse(steps.params, twist.linear, twist.angular)
            wheels = WheelSpeeds(float(speeds.left), float(speeds.right))
            joints = joint_from_wheel(steps.params, wheels)
            fraction = limit_fraction(steps.params, wheels, steps.limit)
            segments.append(
                PlannedSegment(
                    segment=planned.segment,
                    index=index,
                    twist=twist,
                    duration=end - begin,
                    wheels=wheels,
                    joints=WheelSpeeds(float(joints.left), float(joints.right)),
                    fraction=None if fraction is None else float(fraction),
                    start_pose=planned.start_pose,
                    end_pose=planned.end_pose,
                    end_heading=planned.end_heading,
                )
            )
            begin = end
    return Plan(
        segments=tuple(segments),
        params=steps.params,
        limit=steps.limit,
        duration=math.fsum(run.duration for run in runs),
        final_pose=steps.final_pose,
        within_limit=steps.within_limit,
    )
