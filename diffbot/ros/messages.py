"""ROS message shapes: records for nav_msgs/Odometry and the odom -> base_link transform, and
the YAML text of geometry_msgs/Twist and std_msgs/Float64MultiArray commands as ``ros2 topic pub``
reads it.

The records mirror the messages' fields (SI units, stamps in seconds) without depending on ROS.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Sequence
from typing import NamedTuple

from diffbot.errors import ParameterError
from diffbot.numbers import finite_in_range, shown

__all__ = [
    "Header",
    "OdometryMessage",
    "PoseWithCovariance",
    "Quaternion",
    "TransformStamped",
    "TwistWithCovariance",
    "Vector3",
    "array_yaml",
    "command_type",
    "command_yaml",
    "covariance_matrix",
    "quaternion_from_yaw",
    "twist_stamped_yaml",
    "twist_yaml",
    "yaml_float",
]


class Vector3(NamedTuple):
    """geometry_msgs/Vector3 (or Point): x, y, z in m, m/s or rad/s depending on use."""

    x: float
    y: float
    z: float


class Quaternion(NamedTuple):
    """geometry_msgs/Quaternion: a unit quaternion (x, y, z, w)."""

    x: float
    y: float
    z: float
    w: float


class Header(NamedTuple):
    """std_msgs/Header: stamp (s) and frame_id."""

    stamp: float
    frame_id: str


class PoseWithCovariance(NamedTuple):
    """geometry_msgs/PoseWithCovariance: position (m), orientation, 6x6 covariance (row-major)."""

    position: Vector3
    orientation: Quaternion
    covariance: tuple[float, ...]


class TwistWithCovariance(NamedTuple):
    """geometry_msgs/TwistWithCovariance: linear (m/s), angular (rad/s), 6x6 covariance."""

    linear: Vector3
    angular: Vector3
    covariance: tuple[float, ...]


class OdometryMessage(NamedTuple):
    """nav_msgs/Odometry: the pose in ``header.frame_id``, the twist in ``child_frame_id``."""

    header: Header
    child_frame_id: str
    pose: PoseWithCovariance
    twist: TwistWithCovariance


class TransformStamped(NamedTuple):
    """geometry_msgs/TransformStamped: the transform from ``header.frame_id`` to the child."""

    header: Header
    child_frame_id: str
    translation: Vector3
    rotation: Quaternion


def quaternion_from_yaw(yaw: float) -> Quaternion:
    """The quaternion of a rotation by ``yaw`` (rad) about z; w >= 0 for yaw in [-pi, pi]."""
    half = 0.5 * yaw
    return Quaternion(0.0, 0.0, math.sin(half), math.cos(half))


def covariance_matrix(diagonal: Sequence[float], what: str = "covariance") -> tuple[float, ...]:
    """A 6x6 row-major covariance matrix (36 values) with the given diagonal.

    Args:
        diagonal: six variances for x, y, z, rotation about x, y, z.
        what: a name for the values in error messages.

    Returns:
        36 floats, zero off the diagonal.

    Raises:
        ParameterError: not six values (text is none; an endless iterable is refused at its
            seventh), or one is no number, negative, NaN or infinite.
    """
    if isinstance(diagonal, str | bytes | bytearray):
        raise ParameterError(f"{what} diagonal needs 6 numbers, got {shown(diagonal)}")
    try:
        given = list(itertools.islice(diagonal, 7))
    except TypeError:
        raise ParameterError(f"{what} diagonal needs 6 numbers, got {shown(diagonal)}") from None
    if len(given) != 6:
        count = "more than 6" if len(given) > 6 else str(len(given))
        raise ParameterError(f"{what} diagonal needs 6 values, got {count}")
    values = [
        finite_in_range(value, f"{what} diagonal value {i}", 0.0) for i, value in enumerate(given)
    ]
    matrix = [0.0] * 36
    for i, value in enumerate(values):
        matrix[7 * i] = value
    return tuple(matrix)


def yaml_float(value: float) -> str:
    """A float for a YAML 1.1 reader (``ros2 topic pub``): every digit, and always a dot.

    PyYAML reads ``1e-05`` as a string, so an exponent gets a ``.0`` mantissa.
    """
    text = repr(float(value))
    if "e" in text and "." not in text:
        mantissa, _, exponent = text.partition("e")
        text = f"{mantissa}.0e{exponent}"
    return text


def twist_yaml(linear: float, angular: float) -> str:
    """A geometry_msgs/Twist as YAML: linear.x (m/s) and angular.z (rad/s)."""
    return f"{{linear: {{x: {yaml_float(linear)}}}, angular: {{z: {yaml_float(angular)}}}}}"


def twist_stamped_yaml(linear: float, angular: float, frame_id: str) -> str:
    """A geometry_msgs/TwistStamped as YAML, stamped ``now`` (``ros2 topic pub`` fills in the
    time: ROS 2 Iron and later, Humble since its first patch release)."""
    header = f"{{stamp: now, frame_id: {json.dumps(frame_id)}}}"
    return f"{{header: {header}, twist: {twist_yaml(linear, angular)}}}"


def command_yaml(linear: float, angular: float, frame_id: str | None = None) -> str:
    """A velocity command as YAML: a Twist, or a TwistStamped in ``frame_id`` when one is given."""
    if frame_id is None:
        return twist_yaml(linear, angular)
    return twist_stamped_yaml(linear, angular, frame_id)


def command_type(frame_id: str | None = None) -> str:
    """The message type of :func:`command_yaml`'s commands."""
    return "geometry_msgs/msg/Twist" if frame_id is None else "geometry_msgs/msg/TwistStamped"


def array_yaml(value: float, count: int = 1) -> str:
    """A std_msgs/Float64MultiArray of ``count`` equal values as YAML (one per joint of a
    JointGroupVelocityController, as a side of a skid steer has several)."""
    return f"{{data: [{', '.join([yaml_float(value)] * count)}]}}"
