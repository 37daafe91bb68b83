"""What a diff_drive_controller configuration says, as plain records (SI units)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Literal

from diffbot.errors import ParameterError
from diffbot.numbers import (
    MAX_PLAN_DURATION,
    MAX_ROLLING_WINDOW,
    as_number,
    finite_in_range,
    shown,
    sized,
    store_checked,
    store_number,
    whole_number,
)

__all__ = [
    "CONTROLLER_COVARIANCE",
    "CONTROLLER_ROLLING_WINDOW",
    "MAX_UPDATE_RATE",
    "MAX_WHEELS_PER_SIDE",
    "AxisLimits",
    "ControllerConfig",
    "default_of",
    "first_of",
]

#: The covariance diagonals diff_drive_controller publishes when its file leaves them out
#: (``pose_covariance_diagonal``, ``twist_covariance_diagonal`` in its parameter declaration).
CONTROLLER_COVARIANCE = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
#: The controller's ``velocity_rolling_window_size`` when its file leaves it out (steps).
CONTROLLER_ROLLING_WINDOW = 10
#: Fastest controller manager loop accepted (Hz): real ones run at tens to a few thousand.
MAX_UPDATE_RATE = 1e6
#: Largest wheels_per_side accepted.
MAX_WHEELS_PER_SIDE = 1000


def _limit_check(name: str) -> Callable[[object], float | None]:
    """The check of the limit ``name`` of :class:`AxisLimits`: a finite number, or None for NaN
    (the controller's "no limit")."""
    expected = "a finite number, or NaN or None for no limit"

    def check(value: object) -> float | None:
        number = as_number(value, name, expected=expected)
        if math.isnan(number):
            return None
        if math.isinf(number):
            raise ParameterError(f"{name} must be {expected}, got {shown(value)}")
        return number

    return check


def _multiplier_check(name: str) -> Callable[[object], float]:
    """The check of a wheel radius multiplier: finite and not 0 (negative turns the wheels the
    other way, as the controller divides by it)."""
    expected = "a finite number other than 0 (negative: the wheels turn the other way)"

    def check(value: object) -> float:
        number = as_number(value, name, expected=expected)
        if not math.isfinite(number) or number == 0.0:
            raise ParameterError(f"{name} must be {expected}, got {shown(value)}")
        return number

    return check


def _whole_check(name: str, low: int, high: int) -> Callable[[object], int]:
    """The check of a count: an integer from ``low`` to ``high``."""
    return lambda value: whole_number(value, name, low, high)


def _diagonal_check(name: str) -> Callable[[object], tuple[float, ...]]:
    """The check of a covariance diagonal: 6 finite numbers."""

    def check(value: object) -> tuple[float, ...]:
        diagonal = sized(value, 6)
        if diagonal is None:
            raise ParameterError(f"{name} must be 6 finite numbers, got {shown(value)}")
        return tuple(finite_in_range(v, name) for v in diagonal)

    return check


def _axis_check(name: str) -> Callable[[object], AxisLimits]:
    def check(value: object) -> AxisLimits:
        if not isinstance(value, AxisLimits):
            raise ParameterError(f"{name} must be an AxisLimits, got {shown(value)}")
        return value

    return check


@dataclass(frozen=True)
class AxisLimits:
    """Command limits of one axis (linear.x in m/s, m/s², m/s³; angular.z in rad/s, ...).

    Every field is None when the file leaves the limit out, sets it to NaN, or switches its group
    off with a ``has_*_limits: false`` flag: a NaN given is kept as None, the controller's "no
    limit"; an infinity is refused. Signs are those of the controller: ``min_*``,
    ``max_deceleration`` and ``max_acceleration_reverse`` are <= 0 (the limiter checks them).

    Attributes:
        max_velocity: highest velocity.
        min_velocity: lowest velocity (most negative); ``-max_velocity`` when None.
        max_acceleration: highest rate of change while moving forward (or from rest).
        min_acceleration: lowest rate of change, the name of ROS 1 and releases before 2025.
        max_deceleration: lowest rate of change while moving forward (braking).
        max_acceleration_reverse: lowest rate of change while moving backward (speeding up).
        max_deceleration_reverse: highest rate of change while moving backward (braking).
        max_jerk: highest rate of change of the acceleration.
        min_jerk: lowest rate of change of the acceleration; ``-max_jerk`` when None.
    """

    max_velocity: float | None = None
    min_velocity: float | None = None
    max_acceleration: float | None = None
    min_acceleration: float | None = None
    max_deceleration: float | None = None
    max_acceleration_reverse: float | None = None
    max_deceleration_reverse: float | None = None
    max_jerk: float | None = None
    min_jerk: float | None = None

    def __post_init__(self) -> None:
        for item in fields(self):
            store_checked(self, item.name, _limit_check(item.name), optional=True)

    @property
    def velocity_range(self) -> tuple[float, float] | None:
        """The (lowest, highest) velocity the limiter lets through, or None when unlimited."""
        return _range(self.min_velocity, self.max_velocity)

    @property
    def jerk_range(self) -> tuple[float, float] | None:
        """The (lowest, highest) jerk the limiter lets through, or None when unlimited."""
        return _range(self.min_jerk, self.max_jerk)

    def acceleration_range(self, previous: float) -> tuple[float, float] | None:
        """The (lowest, highest) rate of change allowed after a command, or None when unlimited.

        Args:
            previous: the previous command (m/s or rad/s); its sign tells speeding up from braking.

        Returns:
            Bounds on (v - previous) / dt, as the controller's limiter sets them: nothing is limited
            without ``max_acceleration``; the reverse and braking bounds default to the mirror
            images of the forward ones (``min_acceleration`` of older files serves as both
            ``max_deceleration`` and ``max_acceleration_reverse``).
        """
        if self.max_acceleration is None:
            return None
        reverse = first_of(self.max_acceleration_reverse, self.min_acceleration)
        if reverse is None:
            reverse = -self.max_acceleration
        if previous > 0.0:
            braking = first_of(self.max_deceleration, self.min_acceleration)
            return (reverse if braking is None else braking, self.max_acceleration)
        if previous < 0.0:
            braking_reverse = self.max_deceleration_reverse
            if braking_reverse is None:
                braking_reverse = self.max_acceleration
            return (reverse, braking_reverse)
        return (reverse, self.max_acceleration)


@dataclass(frozen=True)
class ControllerConfig:
    """One ``diff_drive_controller/DiffDriveController`` as a controllers file configures it.

    Numbers are None where the file leaves them out (multipliers default to 1.0, as in the
    controller). Lengths in m, times in s, rates in Hz.

    Attributes:
        name: the controller's name (its node name without namespace).
        source: the file it came from.
        namespace: the namespace of its node as the file names it (``a200_0000`` for a section
            ``/a200_0000/diff_cont:``, under namespace keys, or under its controller manager's
            namespaced section); empty for the root namespace or one left to a wildcard.
        ros_version: 1 or 2.
        left_wheel_names: the left wheel joints (``left_wheel_names``, ROS 1 ``left_wheel``).
        right_wheel_names: the right wheel joints.
        wheel_separation: distance between the left and right wheels, before the multiplier
            (> 0).
        wheel_radius: wheel radius, before the multipliers (> 0).
        wheels_per_side: the ``wheels_per_side`` of older releases (0 to 1000).
        wheel_separation_multiplier: correction factor of the separation (> 0).
        left_wheel_radius_multiplier: correction factor of the left radius (not 0; negative:
            the wheels turn the other way).
        right_wheel_radius_multiplier: correction factor of the right radius.
        linear: limits of linear.x (m/s, m/s², m/s³).
        angular: limits of angular.z (rad/s, rad/s², rad/s³).
        preserve_turning_radius: scale both axes alike when limiting (Clearpath and PAL forks).
        open_loop: odometry from the commands instead of the wheel feedback.
        position_feedback: whether the wheels report positions (True, the controller's default)
            or velocities only (False: odometry from the velocities).
        use_stamped_vel: commands as TwistStamped (releases before Jazzy).
        odom_frame_id: the odometry frame.
        base_frame_id: the robot's frame.
        tf_frame_prefix: what goes before both frame ids (``~`` standing for the namespace);
            empty or None: the namespace (see :attr:`frame_prefix`).
        tf_frame_prefix_enable: False: no prefix at all (older releases' switch).
        pose_covariance_diagonal: diagonal of the published pose covariance (6 finite values).
        twist_covariance_diagonal: diagonal of the published twist covariance (6 finite values).
        publish_rate: odometry publishing rate (Hz, > 0).
        enable_odom_tf: whether the odom -> base transform is published.
        velocity_rolling_window_size: samples averaged for the odometry velocity (at least 1).
        cmd_vel_timeout: age after which a command is stale (s); 0 disables the timeout.
        update_rate: the controller manager's update rate (Hz, 1e-6 to 1e6).
        warnings: things worth telling the user about the section, one sentence each.
        arguments: the names of the ``$(arg NAME)`` substitutions of its file (ROS 1).
    """

    name: str
    source: str
    ros_version: Literal[1, 2]
    namespace: str = ""
    left_wheel_names: tuple[str, ...] = ()
    right_wheel_names: tuple[str, ...] = ()
    wheel_separation: float | None = None
    wheel_radius: float | None = None
    wheels_per_side: int | None = None
    wheel_separation_multiplier: float = 1.0
    left_wheel_radius_multiplier: float = 1.0
    right_wheel_radius_multiplier: float = 1.0
    linear: AxisLimits = AxisLimits()
    angular: AxisLimits = AxisLimits()
    preserve_turning_radius: bool | None = None
    open_loop: bool | None = None
    position_feedback: bool | None = None
    use_stamped_vel: bool | None = None
    odom_frame_id: str | None = None
    base_frame_id: str | None = None
    tf_frame_prefix: str | None = None
    tf_frame_prefix_enable: bool | None = None
    pose_covariance_diagonal: tuple[float, ...] | None = None
    twist_covariance_diagonal: tuple[float, ...] | None = None
    publish_rate: float | None = None
    enable_odom_tf: bool | None = None
    velocity_rolling_window_size: int | None = None
    cmd_vel_timeout: float | None = None
    update_rate: float | None = None
    warnings: tuple[str, ...] = field(default=(), compare=False)
    arguments: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        version = self.ros_version
        if type(version) is not int or version not in (1, 2):
            raise ParameterError(f"ros_version must be 1 or 2, got {shown(version)}")
        for name in ("wheel_separation", "wheel_radius", "publish_rate"):
            store_number(self, name, 0.0, open_low=True, optional=True)
        store_number(self, "wheel_separation_multiplier", 0.0, open_low=True)
        for name in ("left_wheel_radius_multiplier", "right_wheel_radius_multiplier"):
            store_checked(self, name, _multiplier_check(name))
        store_checked(
            self,
            "wheels_per_side",
            _whole_check("wheels_per_side", 0, MAX_WHEELS_PER_SIDE),
            optional=True,
        )
        window = "velocity_rolling_window_size"
        store_checked(self, window, _whole_check(window, 1, MAX_ROLLING_WINDOW), optional=True)
        store_number(self, "cmd_vel_timeout", 0.0, unit="s", optional=True)
        store_number(
            self, "update_rate", 1.0 / MAX_PLAN_DURATION, MAX_UPDATE_RATE, unit="Hz", optional=True
        )
        for name in ("pose_covariance_diagonal", "twist_covariance_diagonal"):
            store_checked(self, name, _diagonal_check(name), optional=True)
        for name in ("linear", "angular"):
            store_checked(self, name, _axis_check(name))

    @property
    def node_name(self) -> str:
        """The controller node's absolute name (``/a200_0000/diff_cont``, ``/diff_cont``)."""
        return "/" + "/".join(part for part in (self.namespace, self.name) if part.strip("/"))

    @property
    def odom_topic(self) -> str:
        """The topic the controller publishes its odometry on: ``~/odom``, under its node's
        name (``/a200_0000/diff_cont/odom``)."""
        return self.node_name + "/odom"

    @property
    def frame_prefix(self) -> str:
        """What the controller puts before its odometry and base frame ids, as ROS 2's
        diff_drive_controller resolves it: ``tf_frame_prefix`` (its first ``~`` standing for
        the node's namespace, as the newest releases read it; Kilted and older keep a ``~`` as
        written), else the namespace; with one trailing slash and no leading one
        (``a200_0000/``). Empty with ``tf_frame_prefix_enable: false``, in the root namespace
        (or one left to a wildcard) without a prefix, and for ROS 1, whose controller has none.
        """
        if self.ros_version == 1 or self.tf_frame_prefix_enable is False:
            return ""
        node_namespace = "/" + self.namespace.strip("/")
        prefix = (self.tf_frame_prefix or node_namespace).replace("~", node_namespace, 1)
        if not prefix.endswith("/"):
            prefix += "/"
        return prefix.removeprefix("/")

    @property
    def odom_frame(self) -> str:
        """The frame the controller's odometry is in: the prefix, then ``odom_frame_id``
        (``odom`` when the file leaves it out)."""
        return self.frame_prefix + (self.odom_frame_id or "odom")

    @property
    def base_frame(self) -> str:
        """The robot's frame as the controller publishes it: the prefix, then
        ``base_frame_id`` (``base_link`` when the file leaves it out)."""
        return self.frame_prefix + (self.base_frame_id or "base_link")

    @property
    def pose_covariance(self) -> tuple[float, ...]:
        """The diagonal of the pose covariance the controller publishes: the file's, else its
        default (zeros)."""
        return self.pose_covariance_diagonal or CONTROLLER_COVARIANCE

    @property
    def twist_covariance(self) -> tuple[float, ...]:
        """The diagonal of the twist covariance the controller publishes: the file's, else
        its default (zeros)."""
        return self.twist_covariance_diagonal or CONTROLLER_COVARIANCE

    @property
    def rolling_window(self) -> int:
        """The steps the controller's velocity estimate spans: the file's, else 10."""
        return self.velocity_rolling_window_size or CONTROLLER_ROLLING_WINDOW

    @property
    def effective_separation(self) -> float | None:
        """The separation the controller computes with (m): separation times multiplier, or None."""
        if self.wheel_separation is None:
            return None
        return self.wheel_separation * self.wheel_separation_multiplier

    @property
    def left_radius(self) -> float | None:
        """The left wheel radius the controller computes with (m), or None."""
        if self.wheel_radius is None:
            return None
        return self.wheel_radius * self.left_wheel_radius_multiplier

    @property
    def right_radius(self) -> float | None:
        """The right wheel radius the controller computes with (m), or None."""
        if self.wheel_radius is None:
            return None
        return self.wheel_radius * self.right_wheel_radius_multiplier


def first_of(*values: float | None) -> float | None:
    """The first value that is not None, or None."""
    return next((v for v in values if v is not None), None)


def default_of(value: float | None, default: float) -> float:
    """``value``, or ``default`` when it is None."""
    return default if value is None else value


def _range(low: float | None, high: float | None) -> tuple[float, float] | None:
    if high is None:
        return None
    return (-high if low is None else low, high)
