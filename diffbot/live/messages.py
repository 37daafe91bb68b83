"""Building and reading the live message types: stamps, headings, odometry and commands.

Plain functions between diffbot's numbers (SI units, stamps in integer ns) and the DDS structs of
:mod:`diffbot.live.types`; the nodes stay thin by calling these.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

from diffbot.live.types import (
    Float64MultiArray,
    Header,
    MultiArrayLayout,
    Odometry,
    Point,
    Pose,
    PoseWithCovariance,
    Quaternion,
    Time,
    Transform,
    TransformStamped,
    Twist,
    TwistWithCovariance,
    Vector3,
)

__all__ = [
    "commands",
    "now_ns",
    "odometry",
    "stamp_ns",
    "time_of",
    "transform",
    "twist_command",
    "twist_mismatch",
    "yaw_of",
    "yaw_quaternion",
]


def now_ns() -> int:
    """The wall clock (ROS time) in integer ns since the epoch."""
    return time.time_ns()


def time_of(ns: int) -> Time:
    """builtin_interfaces/Time of a stamp in ns (floor division: negative stamps too)."""
    sec, nanosec = divmod(ns, 1_000_000_000)
    return Time(sec, nanosec)


def stamp_ns(stamp: Time) -> int:
    """A builtin_interfaces/Time in integer ns."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def yaw_quaternion(yaw: float) -> Quaternion:
    """The rotation by ``yaw`` (rad) about z; the heading wrapped first so that w >= 0."""
    half = 0.5 * math.remainder(yaw, 2.0 * math.pi)
    return Quaternion(0.0, 0.0, math.sin(half), math.cos(half))


def yaw_of(q: Quaternion) -> float:
    """The heading (rad, in [-pi, pi]) of a quaternion, the rotation about z."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def odometry(
    state: tuple[float, float, float, float, float],
    stamp: int,
    frame_id: str,
    child_frame_id: str,
    pose_covariance: Sequence[float],
    twist_covariance: Sequence[float],
) -> Odometry:
    """nav_msgs/Odometry of ``(x, y, heading, linear, angular)`` (m, m, rad, m/s, rad/s) at
    ``stamp`` (ns), with 36-value row-major covariances."""
    x, y, heading, linear, angular = state
    return Odometry(
        Header(time_of(stamp), frame_id),
        child_frame_id,
        PoseWithCovariance(Pose(Point(x, y, 0.0), yaw_quaternion(heading)), list(pose_covariance)),
        TwistWithCovariance(
            Twist(Vector3(linear, 0.0, 0.0), Vector3(0.0, 0.0, angular)), list(twist_covariance)
        ),
    )


def transform(
    stamp: int,
    frame_id: str,
    child_frame_id: str,
    xyz: tuple[float, float, float],
    rotation: Quaternion,
) -> TransformStamped:
    """The transform of ``child_frame_id`` in ``frame_id`` at ``stamp`` (ns)."""
    return TransformStamped(
        Header(time_of(stamp), frame_id), child_frame_id, Transform(Vector3(*xyz), rotation)
    )


def twist_command(linear: float, angular: float) -> Twist:
    """geometry_msgs/Twist of linear.x (m/s) and angular.z (rad/s)."""
    return Twist(Vector3(linear, 0.0, 0.0), Vector3(0.0, 0.0, angular))


def commands(values: Sequence[float]) -> Float64MultiArray:
    """std_msgs/Float64MultiArray of joint commands (rad/s) with an empty layout, as
    ``ros2 topic pub`` sends them (forward_command_controller reads ``data`` only)."""
    return Float64MultiArray(MultiArrayLayout(), [float(v) for v in values])


def twist_mismatch(topic: str, found: str) -> str:
    """The warning when a velocity command topic carries ``found`` (a ROS type name): the
    option that reads it when it is the other kind of twist."""
    if found.endswith("/TwistStamped"):
        return f"{topic!r} carries {found}; use --stamped"
    if found.endswith("/Twist"):
        return f"{topic!r} carries {found}; leave out --stamped"
    return f"{topic!r} carries {found}, not a velocity command"
