"""Plain CDR for the messages a node handles per sample: written and read with :mod:`struct`.

cyclonedds' Python serializer walks a type field by field (about 0.3 ms for a nav_msgs/Odometry
with its two 36-value covariances); a node that must keep up with joint states at kilohertz
rates encodes its Odometry and TFMessage, and decodes JointState, here instead, in one
``struct`` call per run of numbers. The bytes are the same as the type's own serializer writes
(little-endian CDR, XCDR1, behind the encapsulation header ``00 01 00 00``); the tests hold the
two against each other.

Alignment is counted from the end of the 4-byte header: 4 for lengths and 32-bit integers, 8 for
doubles. Strings are a length (including the terminating NUL), the UTF-8 bytes and the NUL.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

from diffbot.live import types
from diffbot.live.messages import time_of

__all__ = [
    "HEADER",
    "JointStateReader",
    "OdometryWriter",
    "decode_joint_state",
    "decode_twist",
    "decode_twist_stamped",
    "encode_float64_array",
    "encode_odometry",
    "encode_tf",
    "encode_twist",
]

#: The encapsulation header of little-endian plain CDR.
HEADER = b"\x00\x01\x00\x00"
_U32 = struct.Struct("<I")
_STAMP = struct.Struct("<iI")
_TRANSFORM = struct.Struct("<7d")
_TWIST = struct.Struct("<6d")
#: A MultiArrayLayout without dimensions: no ``dim``, ``data_offset`` 0.
_EMPTY_LAYOUT = struct.pack("<II", 0, 0)
#: Pose (7), pose covariance (36), twist (6), twist covariance (36).
_ODOMETRY = struct.Struct("<85d")


def _align(buffer: bytearray, size: int) -> None:
    buffer += b"\0" * (-(len(buffer) - 4) % size)


def _string(buffer: bytearray, text: str) -> None:
    _align(buffer, 4)
    data = text.encode("utf-8") + b"\0"
    buffer += _U32.pack(len(data))
    buffer += data


def _stamped(buffer: bytearray, stamp_ns: int, frame_id: str) -> None:
    _align(buffer, 4)
    buffer += _STAMP.pack(*divmod(stamp_ns, 1_000_000_000))
    _string(buffer, frame_id)


def encode_odometry(
    stamp_ns: int,
    frame_id: str,
    child_frame_id: str,
    pose: Sequence[float],
    pose_covariance: Sequence[float],
    twist: Sequence[float],
    twist_covariance: Sequence[float],
) -> bytes:
    """nav_msgs/Odometry as CDR: ``pose`` is (x, y, z, qx, qy, qz, qw), ``twist`` the linear
    then angular velocity (6 values), each covariance 36 values (row-major)."""
    buffer = bytearray(HEADER)
    _stamped(buffer, stamp_ns, frame_id)
    _string(buffer, child_frame_id)
    _align(buffer, 8)
    buffer += _ODOMETRY.pack(*pose, *pose_covariance, *twist, *twist_covariance)
    return bytes(buffer)


def encode_twist(linear: float, angular: float) -> bytes:
    """geometry_msgs/Twist as CDR: linear.x (m/s) and angular.z (rad/s), the rest zero."""
    return HEADER + _TWIST.pack(linear, 0.0, 0.0, 0.0, 0.0, angular)


def encode_float64_array(values: Sequence[float]) -> bytes:
    """std_msgs/Float64MultiArray as CDR, with an empty layout (no dimensions, offset 0)."""
    buffer = bytearray(HEADER)
    buffer += _EMPTY_LAYOUT
    _doubles(buffer, values)
    return bytes(buffer)


def decode_twist(data: bytes) -> tuple[float, float]:
    """linear.x (m/s) and angular.z (rad/s) of a geometry_msgs/Twist payload.

    Raises:
        ValueError, struct.error: not little-endian plain CDR, or truncated.
    """
    if data[:4] != HEADER:
        raise ValueError("not little-endian plain CDR")
    linear, _, _, _, _, angular = _TWIST.unpack_from(data, 4)
    return linear, angular


def decode_twist_stamped(data: bytes) -> tuple[float, float]:
    """linear.x (m/s) and angular.z (rad/s) of a geometry_msgs/TwistStamped payload.

    Raises:
        ValueError, struct.error, UnicodeDecodeError: malformed or truncated.
    """
    reader = _Reader(data)
    reader.at = 12
    reader.string()
    reader.align(8)
    linear, _, _, _, _, angular = _TWIST.unpack_from(data, reader.at)
    return linear, angular


def encode_tf(
    transforms: Sequence[tuple[int, str, str, Sequence[float]]],
) -> bytes:
    """tf2_msgs/TFMessage as CDR: each transform is (stamp ns, frame, child frame, (x, y, z,
    qx, qy, qz, qw))."""
    buffer = bytearray(HEADER)
    buffer += _U32.pack(len(transforms))
    for stamp_ns, frame_id, child_frame_id, values in transforms:
        _stamped(buffer, stamp_ns, frame_id)
        _string(buffer, child_frame_id)
        _align(buffer, 8)
        buffer += _TRANSFORM.pack(*values)
    return bytes(buffer)


def _doubles(buffer: bytearray, values: Sequence[float]) -> None:
    _align(buffer, 4)
    buffer += _U32.pack(len(values))
    if values:
        _align(buffer, 8)
        buffer += struct.pack(f"<{len(values)}d", *values)


def encode_joint_state(
    stamp_ns: int,
    frame_id: str,
    names: Sequence[str],
    position: Sequence[float],
    velocity: Sequence[float] = (),
    effort: Sequence[float] = (),
) -> bytes:
    """sensor_msgs/JointState as CDR."""
    buffer = bytearray(HEADER)
    _stamped(buffer, stamp_ns, frame_id)
    _align(buffer, 4)
    buffer += _U32.pack(len(names))
    for name in names:
        _string(buffer, name)
    for values in (position, velocity, effort):
        _doubles(buffer, values)
    return bytes(buffer)


class _Reader:
    """Reads CDR fields in order from a payload, refusing to read past its end."""

    def __init__(self, data: bytes) -> None:
        if data[:4] != HEADER:
            raise ValueError("not little-endian plain CDR")
        self.data = data
        self.at = 4

    def align(self, size: int) -> None:
        self.at += -(self.at - 4) % size

    def u32(self) -> int:
        self.align(4)
        (value,) = _U32.unpack_from(self.data, self.at)
        self.at += 4
        return int(value)

    def string(self) -> str:
        size = self.u32()
        end = self.at + size
        if size == 0 or end > len(self.data) or self.data[end - 1] != 0:
            raise ValueError("malformed string")
        text = self.data[self.at : end - 1].decode("utf-8")
        self.at = end
        return text

    def doubles(self) -> list[float]:
        count = self.u32()
        if count == 0:
            return []
        self.align(8)
        end = self.at + 8 * count
        if end > len(self.data):
            raise ValueError("sequence longer than the payload")
        values = list(struct.unpack_from(f"<{count}d", self.data, self.at))
        self.at = end
        return values


def decode_joint_state(data: bytes) -> types.JointState:
    """sensor_msgs/JointState from CDR.

    Raises:
        ValueError, struct.error, UnicodeDecodeError: a malformed or truncated payload.
    """
    reader = _Reader(data)
    sec, nanosec = _STAMP.unpack_from(data, 4)
    reader.at = 12
    frame_id = reader.string()
    count = reader.u32()
    if count * 5 > len(data):  # each name takes at least a length and a NUL
        raise ValueError("more names than the payload holds")
    names = [reader.string() for _ in range(count)]
    position = reader.doubles()
    velocity = reader.doubles()
    effort = reader.doubles()
    header = types.Header(time_of(sec * 1_000_000_000 + nanosec), frame_id)
    return types.JointState(header, names, position, velocity, effort)


class JointStateReader:
    """Reads sensor_msgs/JointState payloads as (sec, nanosec, names, values), the values being
    the joints' positions (rad) or, with ``field="velocity"``, their velocities (rad/s); fast for
    a stream whose layout repeats (as a driver's does): the same frame and joint names and the
    same lengths of ``position``, ``velocity`` and ``effort``. A payload of the previous one's
    length whose bytes from the frame through the position count equal that payload's, and
    whose velocity and effort counts are that payload's too, is read with one ``struct`` call
    (its names are the same tuple); any other is parsed field by field. The sequences not read
    are checked to lie within the payload.

    Args:
        field: ``"position"`` or ``"velocity"``, the sequence read.
    """

    def __init__(self, field: str = "position") -> None:
        if field not in ("position", "velocity"):
            raise ValueError(f"field must be 'position' or 'velocity', got {field!r}")
        self._velocity = field == "velocity"
        self._size = -1
        self._prefix = b""
        self._names: tuple[str, ...] = ()
        self._fast: struct.Struct | None = None
        self._counts: tuple[int, int] = (0, 0)

    def read(self, data: bytes) -> tuple[int, int, tuple[str, ...], tuple[float, ...]]:
        """The stamp (sec, nanosec), the joint names and the field's values of a payload.

        Raises:
            ValueError, struct.error, UnicodeDecodeError: a malformed or truncated payload.
        """
        fast = self._fast
        if (
            fast is not None
            and len(data) == self._size
            and data.startswith(self._prefix, 12)
            and data.startswith(HEADER)
        ):
            values = fast.unpack_from(data, 4)
            if self._velocity:
                # (sec, nanosec, velocity count, velocities..., effort count)
                if (values[2], values[-1]) == self._counts:
                    return values[0], values[1], self._names, values[3:-1]
            elif values[-2:] == self._counts:
                # (sec, nanosec, positions..., velocity count, effort count)
                return values[0], values[1], self._names, values[2:-2]
        return self._parse(data)

    def _parse(self, data: bytes) -> tuple[int, int, tuple[str, ...], tuple[float, ...]]:
        reader = _Reader(data)
        reader.at = 12
        reader.string()
        count = reader.u32()
        if count * 5 > len(data):  # each name takes at least a length and a NUL
            raise ValueError("more names than the payload holds")
        names = tuple(reader.string() for _ in range(count))
        position = tuple(reader.doubles())
        first = reader.at - 8 * len(position)  # where position[0] is (or would be)
        at: list[int] = []
        counts: list[int] = []
        starts: list[int] = []
        for _ in range(2):  # velocity, effort: within the payload
            reader.align(4)
            at.append(reader.at)
            counts.append(reader.u32())
            if counts[-1]:
                reader.align(8)
            starts.append(reader.at)
            reader.at += 8 * counts[-1]
            if reader.at > len(data):
                raise ValueError("sequence longer than the payload")
        sec, nanosec = _STAMP.unpack_from(data, 4)
        end = first + 8 * len(position)
        if self._velocity:
            velocity = struct.unpack_from(f"<{counts[0]}d", data, starts[0])
            after = starts[0] + 8 * counts[0]
            self._fast = struct.Struct(
                f"<iI{end - 12}x{at[0] - end}xI{starts[0] - at[0] - 4}x{counts[0]}d"
                f"{at[1] - after}xI"
            )
        else:
            self._fast = struct.Struct(
                f"<iI{first - 12}x{len(position)}d{at[0] - end}xI{at[1] - at[0] - 4}xI"
            )
        self._size = len(data)
        self._prefix = data[12:first]
        self._names = names
        self._counts = (counts[0], counts[1])
        return sec, nanosec, names, velocity if self._velocity else position


class OdometryWriter:
    """nav_msgs/Odometry payloads of fixed frames and covariances, and the odom -> base_link
    TFMessage beside them: the bytes are laid out once, each message only packs its stamp,
    pose and twist into them (the same bytes as :func:`encode_odometry` and
    :func:`encode_tf`)."""

    def __init__(
        self,
        frame_id: str,
        child_frame_id: str,
        pose_covariance: Sequence[float],
        twist_covariance: Sequence[float],
    ) -> None:
        zeros7 = (0.0,) * 7
        self._odometry = bytearray(
            encode_odometry(
                0, frame_id, child_frame_id, zeros7, pose_covariance, (0.0,) * 6, twist_covariance
            )
        )
        self._pose_at = len(self._odometry) - _ODOMETRY.size
        self._twist_at = self._pose_at + 43 * 8
        self._tf = bytearray(encode_tf([(0, frame_id, child_frame_id, zeros7)]))
        self._transform_at = len(self._tf) - _TRANSFORM.size

    def odometry(
        self, stamp_ns: int, pose: Sequence[float], linear: float, angular: float
    ) -> bytearray:
        """The Odometry stamped ``stamp_ns`` at ``pose`` (x, y, z, qx, qy, qz, qw) moving at
        ``linear`` (m/s) and ``angular`` (rad/s): the writer's own buffer, valid until the
        next call (a write copies it)."""
        buffer = self._odometry
        _STAMP.pack_into(buffer, 4, *divmod(stamp_ns, 1_000_000_000))
        _TRANSFORM.pack_into(buffer, self._pose_at, *pose)
        _TWIST.pack_into(buffer, self._twist_at, linear, 0.0, 0.0, 0.0, 0.0, angular)
        return buffer

    def tf(self, stamp_ns: int, pose: Sequence[float]) -> bytearray:
        """The TFMessage of the one transform stamped ``stamp_ns`` to ``pose``: the writer's
        own buffer, valid until the next call."""
        buffer = self._tf
        _STAMP.pack_into(buffer, 8, *divmod(stamp_ns, 1_000_000_000))
        _TRANSFORM.pack_into(buffer, self._transform_at, *pose)
        return buffer
