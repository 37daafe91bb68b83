"""Stateless differential-drive kinematics.

Conventions (REP-103): x forward, y left, positive angular velocity counter-clockwise. Wheel
speeds are *wheel-ground* angular speeds in rad/s: positive means the wheel rolls the robot
forward, whatever the direction of its joint axis in the description. :func:`joint_from_wheel`
applies the description's direction signs to turn them into joint velocity commands.

Every function takes plain floats or NumPy arrays (broadcast together); NumPy is imported only when
an array is given, so scalar use stays cheap.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, NamedTuple, TypeVar, cast, overload

from diffbot.errors import ParameterError
from diffbot.numbers import as_number, motor_limit, wheel_size

if TYPE_CHECKING:
    from typing import TypeAlias

    import numpy as np
    from numpy.typing import NDArray

    from diffbot.controller_config import ControllerConfig

    FloatOrArray: TypeAlias = float | NDArray[np.float64]

__all__ = [
    "LIMIT_TOLERANCE",
    "DiffDriveParams",
    "Disagreement",
    "Pose",
    "Twist",
    "WheelSpeeds",
    "forward",
    "inverse",
    "joint_from_wheel",
    "limit_fraction",
    "norm_angle",
    "rad_s_from_rpm",
    "range_share",
    "rpm_from_rad_s",
    "saturate",
    "sinc",
    "wheel_from_joint",
    "within_limit",
]

#: Relative slack of the limit check, so a wheel run *exactly* at the limit by a computation that
#: rounds in the last bit (``--fastest``) still counts as within it.
LIMIT_TOLERANCE = 1e-9

_RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)
#: A speed as a float or an array of them: the conversions keep the kind they are given.
_Speed = TypeVar("_Speed", float, "NDArray[np.float64]", "FloatOrArray")


class Twist(NamedTuple):
    """A planar body velocity: geometry_msgs/Twist's linear.x (m/s) and angular.z (rad/s)."""

    linear: FloatOrArray
    angular: FloatOrArray


class WheelSpeeds(NamedTuple):
    """Angular speeds of the left and right drive wheels (rad/s)."""

    left: FloatOrArray
    right: FloatOrArray


class Pose(NamedTuple):
    """A planar pose in the odom frame: x, y (m) and heading theta (rad)."""

    x: float
    y: float
    theta: float


class Disagreement(NamedTuple):
    """Sources that give one quantity different values.

    Attributes:
        field: the quantity (``wheel_separation``, ``wheel_radius``, ``left_joints``, ...).
        values: each source's value, by source name.
        difference: the largest difference between two numeric values (m), or None for names.
    """

    field: str
    values: Mapping[str, object]
    difference: float | None


@dataclass(frozen=True)
class DiffDriveParams:
    """Geometry and limits of a differential-drive robot.

    Sizes lie within :data:`~diffbot.numbers.WHEEL_SIZE_RANGE` and the motor limit is 0 or within
    :data:`~diffbot.numbers.MOTOR_LIMIT_RANGE`; numeric strings are read as their numbers.

    Attributes:
        wheel_radius: radius of the drive wheels (m).
        wheel_separation: distance between the two drive wheel centres (m).
        left_joint: name of the left (+y) drive wheel joint.
        right_joint: name of the right (-y) drive wheel joint.
        left_sign: +1 when a positive velocity of the left joint rolls the robot forward, else -1.
        right_sign: the same for the right joint.
        max_wheel_speed: motor limit (rad/s), or None when the description has none.
        source: where the parameters came from (a file path, or a description of it).
        warnings: things worth telling the user about the description, one sentence each.
        left_wheel_radius: radius (m) the left wheels roll with (a controller's radius
            multiplier applied); ``wheel_radius`` when not given.
        right_wheel_radius: likewise for the right wheels.
        left_joints: every drive wheel joint on the left, ``left_joint`` first (several on a
            skid steer); ``(left_joint,)`` when not given.
        right_joints: likewise on the right.
        passive_joints: the description's other moving joints (a caster's), which a simulation
            reports at 0.
        sources: where each value came from, by field (``description``, ``controllers:<path>``,
            ``plugin``, ``mesh:<file>``, ``override``).
        disagreements: the values on which the sources disagree.
        controller: the diff_drive_controller configuration the robot runs with, if one was
            read (its limits, frame ids, odometry settings).
        description_files: every file the description was read from (outputs never go there).
        xacro_arguments: the xacro arguments the description declares or reads
            (``wheel_radius``...); empty for a URDF without xacro, an SDF model, or no
            description.
        plugin_topics: the ROS topics of the description's simulator diff-drive plugin
            (Gazebo classic's) by their default names, ``cmd_vel`` (the Twist commands it
            takes) and ``odom`` (the odometry it publishes), with its namespace and
            remappings; empty without such a plugin.
    """

    wheel_radius: float
    wheel_separation: float
    left_joint: str = "front_left_wheel_joint"
    right_joint: str = "front_right_wheel_joint"
    left_sign: int = 1
    right_sign: int = 1
    max_wheel_speed: float | None = None
    source: str = "(given)"
    warnings: tuple[str, ...] = field(default=(), compare=False)
    left_wheel_radius: float | None = None
    right_wheel_radius: float | None = None
    left_joints: tuple[str, ...] = ()
    right_joints: tuple[str, ...] = ()
    passive_joints: tuple[str, ...] = ()
    sources: Mapping[str, str] = field(default_factory=dict, compare=False)
    disagreements: tuple[Disagreement, ...] = field(default=(), compare=False)
    controller: ControllerConfig | None = field(default=None, compare=False)
    description_files: tuple[str, ...] = field(default=(), compare=False)
    xacro_arguments: tuple[str, ...] = field(default=(), compare=False)
    plugin_topics: Mapping[str, str] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        # Sizes and the limit within the ranges a robot may have (diffbot.numbers): a radius of
        # 1e308 made the odometry NaN, a separation of 1e-300 lost the turn of every command,
        # a limit of 5e-324 put every moving wheel over it.
        object.__setattr__(self, "wheel_radius", wheel_size(self.wheel_radius, "wheel_radius"))
        for side in ("left", "right"):
            name = f"{side}_wheel_radius"
            value = getattr(self, name)
            radius = self.wheel_radius if value is None else wheel_size(value, name)
            object.__setattr__(self, name, radius)
            joints = tuple(getattr(self, f"{side}_joints"))
            if joints:
                object.__setattr__(self, f"{side}_joint", joints[0])
            else:
                joints = (getattr(self, f"{side}_joint"),)
            object.__setattr__(self, f"{side}_joints", joints)
        object.__setattr__(self, "passive_joints", tuple(self.passive_joints))
        object.__setattr__(self, "sources", dict(self.sources))
        object.__setattr__(self, "disagreements", tuple(self.disagreements))
        separation = wheel_size(self.wheel_separation, "wheel_separation")
        object.__setattr__(self, "wheel_separation", separation)
        if self.max_wheel_speed is not None:
            limit = motor_limit(self.max_wheel_speed, "max_wheel_speed")
            object.__setattr__(self, "max_wheel_speed", limit)
        for name, sign in (("left_sign", self.left_sign), ("right_sign", self.right_sign)):
            if type(sign) is not int or sign not in (1, -1):
                raise ParameterError(f"{name} must be +1 or -1, got {sign!r}")
        if not self.left_joint or not self.right_joint:
            raise ParameterError("wheel joint names must not be empty")
        if self.left_joint == self.right_joint:
            raise ParameterError(f"left and right joints are the same joint {self.left_joint!r}")
        if not all(self.left_joints) or not all(self.right_joints):
            raise ParameterError("wheel joint names must not be empty")
        drive = (*self.left_joints, *self.right_joints)
        if len(set(drive)) != len(drive):
            raise ParameterError(f"a wheel joint is listed twice among {list(drive)}")
        object.__setattr__(self, "warnings", tuple(self.warnings))

    @property
    def radii(self) -> tuple[float, float]:
        """The left and right wheel radii (m) the wheels roll with."""
        return cast(float, self.left_wheel_radius), cast(float, self.right_wheel_radius)

    @property
    def max_wheel_rpm(self) -> float | None:
        """The motor limit in rpm (12 significant digits), or None."""
        if self.max_wheel_speed is None:
            return None
        # rpm is for people: drop the last-bit noise of the rpm -> rad/s -> rpm round trip.
        return float(f"{rpm_from_rad_s(self.max_wheel_speed):.12g}")

    def replace(self, **changes: Any) -> DiffDriveParams:
        """A copy with some fields changed (validated again).

        What follows from a changed field follows it unless given too: a side's joint list from
        its first joint, and a side's radius that equalled ``wheel_radius`` from the new one.
        """
        for side in ("left", "right"):
            if f"{side}_joint" in changes:
                changes.setdefault(f"{side}_joints", ())
            radius = getattr(self, f"{side}_wheel_radius")
            if "wheel_radius" in changes and radius == self.wheel_radius:
                changes.setdefault(f"{side}_wheel_radius", None)
        return replace(self, **changes)


def rpm_from_rad_s(speed: _Speed) -> _Speed:
    """Convert an angular speed from rad/s to revolutions per minute."""
    return speed * _RPM_PER_RAD_S


def rad_s_from_rpm(speed: _Speed) -> _Speed:
    """Convert an angular speed from revolutions per minute to rad/s."""
    return speed / _RPM_PER_RAD_S


@overload
def norm_angle(angle: float) -> float: ...
@overload
def norm_angle(angle: NDArray[np.float64]) -> NDArray[np.float64]: ...
def norm_angle(angle: FloatOrArray) -> FloatOrArray:
    """Map an angle (rad), or each angle of an array, to (-pi, pi]."""
    if isinstance(angle, float | int):
        wrapped = math.remainder(angle, 2.0 * math.pi)  # exact, in [-pi, pi]
        return math.pi if wrapped == -math.pi else wrapped
    import numpy as np

    # pi - ((pi - a) mod 2 pi) lies in (-pi, pi] since the mod lies in [0, 2 pi)
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=float), 2.0 * np.pi)


def sinc(h: float) -> float:
    """sin(h)/h (unnormalised), with its limit 1 at h = 0: an arc's chord over its length."""
    # sin(h)/h has no cancellation: libm's sin is within an ulp of the true value for every h, so
    # the quotient is within about 1.5 ulp of sinc(h). For |h| < 2**-26, sin(h) rounds to h and the
    # quotient is exactly 1.0, which is also the correctly rounded sinc (1 - h²/6 rounds to 1), so
    # tiny angles need no series branch; only h == 0 itself needs the limit.
    return math.sin(h) / h if h != 0.0 else 1.0


def inverse(params: DiffDriveParams, linear: FloatOrArray, angular: FloatOrArray) -> WheelSpeeds:
    """Wheel speeds (rad/s) that produce a body velocity.

    Args:
        params: the robot.
        linear: forward speed (m/s).
        angular: yaw rate (rad/s), positive counter-clockwise.

    Returns:
        Wheel-ground angular speeds (rad/s): ``(v -+ w b/2) / r`` with each side's radius.
    """
    half_track = 0.5 * params.wheel_separation * angular
    left_radius, right_radius = params.radii
    return WheelSpeeds((linear - half_track) / left_radius, (linear + half_track) / right_radius)


def forward(params: DiffDriveParams, left: FloatOrArray, right: FloatOrArray) -> Twist:
    """Body velocity from wheel speeds.

    Args:
        params: the robot.
        left: left wheel-ground angular speed (rad/s).
        right: right wheel-ground angular speed (rad/s).

    Returns:
        ``Twist((rl wl + rr wr) / 2, (rr wr - rl wl) / b)`` in m/s and rad/s.
    """
    left_radius, right_radius = params.radii
    b = params.wheel_separation
    if left_radius == right_radius:  # the usual case, rounded as r (wl + wr) / 2 always was
        return Twist(0.5 * left_radius * (left + right), left_radius * (right - left) / b)
    left_speed, right_speed = left_radius * left, right_radius * right
    return Twist(0.5 * (left_speed + right_speed), (right_speed - left_speed) / b)


def joint_from_wheel(params: DiffDriveParams, speeds: WheelSpeeds) -> WheelSpeeds:
    """Joint velocity commands (rad/s) from wheel-ground speeds, applying the direction signs."""
    return WheelSpeeds(params.left_sign * speeds.left, params.right_sign * speeds.right)


def wheel_from_joint(params: DiffDriveParams, speeds: WheelSpeeds) -> WheelSpeeds:
    """Wheel-ground speeds (rad/s) from joint velocities (or positions), undoing the signs."""
    # The signs are +-1, so the map is its own inverse; the name says which way it is used.
    return joint_from_wheel(params, speeds)


def _to_float(value: Any) -> float:
    return as_number(value, "the value")


def _limit_of(params: DiffDriveParams, limit: float | None) -> float | None:
    if limit is None:
        return params.max_wheel_speed
    value = _to_float(limit)
    if not math.isfinite(value) or value < 0.0:
        raise ParameterError(f"a wheel speed limit must be a finite number >= 0, got {limit!r}")
    return value


def _peak(speeds: WheelSpeeds) -> FloatOrArray:
    """The faster wheel's absolute speed; NaN when either wheel is NaN."""
    left, right = speeds
    if isinstance(left, (int, float)) and isinstance(right, (int, float)):
        if math.isnan(left) or math.isnan(right):
            return math.nan
        return max(abs(left), abs(right))
    import numpy as np

    return np.maximum(np.abs(left), np.abs(right))  # propagates NaN


def limit_fraction(
    params: DiffDriveParams, speeds: WheelSpeeds, limit: float | None = None
) -> FloatOrArray | None:
    """How much of the motor limit the faster wheel uses (1.0 = exactly at the limit).

    Args:
        params: the robot; its ``max_wheel_speed`` is the limit unless ``limit`` is given.
        speeds: wheel speeds (rad/s).
        limit: a limit (rad/s) to use instead of the robot's.

    Returns:
        ``max(|left|, |right|) / limit``, ``inf`` for motion under a zero limit, or None when there
        is no limit.
    """
    lim = _limit_of(params, limit)
    if lim is None:
        return None
    peak = _peak(speeds)
    if lim == 0.0:
        if isinstance(peak, float | int):
            return peak if math.isnan(peak) else (math.inf if peak > 0 else 0.0)
        import numpy as np

        return np.where(peak > 0, np.inf, peak)  # keeps 0 and NaN
    return peak / lim


def within_limit(params: DiffDriveParams, speeds: WheelSpeeds, limit: float | None = None) -> bool:
    """True when both wheels (every sample, for arrays) stay within the limit (or there is none).

    A NaN speed is never within a limit.
    """
    fraction = limit_fraction(params, speeds, limit)
    if fraction is None:
        return True
    if isinstance(fraction, float | int):
        return fraction <= 1.0 + LIMIT_TOLERANCE
    return bool((fraction <= 1.0 + LIMIT_TOLERANCE).all())


def saturate(
    params: DiffDriveParams,
    speeds: WheelSpeeds,
    limit: float | None = None,
    *,
    preserve_turning_radius: bool = True,
    linear_range: tuple[float, float] | None = None,
    angular_range: tuple[float, float] | None = None,
) -> WheelSpeeds:
    """Bring wheel speeds within the wheel limit and, if given, body velocity ranges.

    With ``preserve_turning_radius`` (the default) both wheels are scaled by one factor, the
    smallest that any limit asks for, so the robot keeps its turning radius and only slows down
    along the same curve (the ``preserve_turning_radius`` of PAL's diff_drive_controller fork).
    Without it each limit clamps its own quantity, as ros2_controllers'
    diff_drive_controller does (its SpeedLimiter clamps linear.x and angular.z apart): the linear
    velocity into ``linear_range``, the angular one into ``angular_range``, then each wheel into
    the wheel limit on its own; the path bends instead.

    Args:
        params: the robot; its ``max_wheel_speed`` is the limit unless ``limit`` is given.
        speeds: wheel speeds (rad/s).
        limit: a wheel limit (rad/s) to use instead of the robot's.
        preserve_turning_radius: scale both wheels alike (True) or clamp apart (False).
        linear_range: (lowest, highest) linear velocity (m/s), such as a controller's
            ``linear.velocity_range``; None for no such limit.
        angular_range: (lowest, highest) angular velocity (rad/s); None for no such limit.

    Returns:
        The limited wheel speeds (rad/s); unchanged when within every limit or there is none.
        For arrays, samples with a non-finite speed come out NaN.

    Raises:
        ParameterError: a scalar speed that is NaN or infinite, a negative or non-finite wheel
            limit, or a range that is NaN or does not hold 0.
    """
    lim = _limit_of(params, limit)
    ranges = (_range_of("linear_range", linear_range), _range_of("angular_range", angular_range))
    if ranges == (None, None):
        if lim is None:
            return speeds
        if preserve_turning_radius:
            return _scale_to_limit(speeds, lim)
    peak = _peak(speeds)
    if isinstance(peak, float | int):
        if not math.isfinite(peak):
            raise ParameterError(f"cannot saturate non-finite wheel speeds {tuple(speeds)!r}")
        return _saturate_floats(params, speeds, _Limits(lim, ranges, preserve_turning_radius))
    return _saturate_arrays(params, speeds, _Limits(lim, ranges, preserve_turning_radius))


_Range = tuple[float, float] | None


class _Limits(NamedTuple):
    """What saturate() holds speeds to: the wheel limit, the (linear, angular) ranges, the mode."""

    wheel: float | None
    ranges: tuple[_Range, _Range]
    preserve_turning_radius: bool


def _range_of(name: str, bounds: tuple[float, float] | None) -> _Range:
    """``bounds`` as two floats with low <= 0 <= high (infinite ends allowed), or None."""
    if bounds is None:
        return None
    try:
        low, high = (float(b) for b in bounds)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be two numbers (low, high), got {bounds!r}") from None
    if not low <= 0.0 <= high:  # also refuses NaN
        raise ParameterError(f"{name} must run from <= 0 to >= 0, got {bounds!r}")
    return low, high


def _scale_to_limit(speeds: WheelSpeeds, lim: float) -> WheelSpeeds:
    """Both wheels scaled by one factor so the faster one is within ``lim``."""
    peak = _peak(speeds)
    if isinstance(peak, float | int):
        if not math.isfinite(peak):
            raise ParameterError(f"cannot saturate non-finite wheel speeds {tuple(speeds)!r}")
        # Speeds within_limit() accepts (the limit's rounding slack) are left as they are.
        within = peak <= lim if lim == 0.0 else peak / lim <= 1.0 + LIMIT_TOLERANCE
        scale = 1.0 if within else lim / peak
        return WheelSpeeds(speeds.left * scale, speeds.right * scale)
    import numpy as np

    # Samples with a non-finite speed come out NaN: there is no direction to keep for them.
    with np.errstate(divide="ignore", invalid="ignore"):
        over = peak > lim if lim == 0.0 else peak / lim > 1.0 + LIMIT_TOLERANCE
        factor = np.where(over, lim / np.where(peak > 0, peak, 1.0), 1.0)
        factor = np.where(np.isfinite(peak), factor, np.nan)
        return WheelSpeeds(speeds.left * factor, speeds.right * factor)


def range_share(value: float, bounds: tuple[float, float] | None) -> float:
    """The factor in [0, 1] that brings ``value`` into ``bounds`` (lowest, highest, holding 0;
    None: no bound) by scaling it toward 0."""
    if bounds is None:
        return 1.0
    low, high = bounds
    if value > high:
        return high / value
    if value < low:
        return low / value
    return 1.0


def _saturate_floats(params: DiffDriveParams, speeds: WheelSpeeds, limits: _Limits) -> WheelSpeeds:
    lim, ranges, preserve = limits
    twist = forward(params, speeds.left, speeds.right)
    linear, angular = float(twist.linear), float(twist.angular)
    if preserve:
        scale = min(range_share(linear, ranges[0]), range_share(angular, ranges[1]))
        peak = float(_peak(speeds)) * scale
        if lim is not None and peak > lim:
            scale *= lim / peak
        if scale == 1.0:
            return speeds
        return WheelSpeeds(speeds.left * scale, speeds.right * scale)
    clamped = (_clamp(linear, ranges[0]), _clamp(angular, ranges[1]))
    if clamped != (linear, angular):
        speeds = inverse(params, *clamped)
    if lim is None:
        return speeds
    return WheelSpeeds(min(max(speeds.left, -lim), lim), min(max(speeds.right, -lim), lim))


def _clamp(value: float, bounds: _Range) -> float:
    return value if bounds is None else min(max(value, bounds[0]), bounds[1])


def _saturate_arrays(params: DiffDriveParams, speeds: WheelSpeeds, limits: _Limits) -> WheelSpeeds:
    lim, ranges, preserve = limits
    import numpy as np

    left = np.asarray(speeds.left, dtype=float)
    right = np.asarray(speeds.right, dtype=float)
    left, right = np.broadcast_arrays(left, right)
    bad = ~(np.isfinite(left) & np.isfinite(right))
    twist = forward(params, left, right)
    linear, angular = np.asarray(twist.linear), np.asarray(twist.angular)
    with np.errstate(all="ignore"):  # tiny speeds overflow factors that np.where drops
        if preserve:
            scale = np.ones(left.shape)
            for value, bounds in ((linear, ranges[0]), (angular, ranges[1])):
                if bounds is not None:
                    low, high = bounds
                    scale = np.minimum(scale, np.where(value > high, high / value, 1.0))
                    scale = np.minimum(scale, np.where(value < low, low / value, 1.0))
            if lim is not None:
                peak = np.maximum(np.abs(left), np.abs(right)) * scale
                scale = np.where(peak > lim, scale * (lim / np.where(peak > 0, peak, 1.0)), scale)
            scale = np.where(bad, np.nan, scale)
            return WheelSpeeds(left * scale, right * scale)
        new_linear = linear if ranges[0] is None else np.clip(linear, *ranges[0])
        new_angular = angular if ranges[1] is None else np.clip(angular, *ranges[1])
        changed = (new_linear != linear) | (new_angular != angular)
        wheels = inverse(params, new_linear, new_angular)
        left = np.where(changed, wheels.left, left)
        right = np.where(changed, wheels.right, right)
        if lim is not None:
            left, right = np.clip(left, -lim, lim), np.clip(right, -lim, lim)
        return WheelSpeeds(np.where(bad, np.nan, left), np.where(bad, np.nan, right))
