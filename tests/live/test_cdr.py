"""The hand-written CDR of the per-sample messages is byte for byte the types' own serializer's,
and its JointState reader refuses what is malformed."""

from __future__ import annotations

import struct

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.live import types
from diffbot.live.cdr import (
    JointStateReader,
    OdometryWriter,
    decode_joint_state,
    decode_twist,
    decode_twist_stamped,
    encode_float64_array,
    encode_joint_state,
    encode_odometry,
    encode_tf,
    encode_twist,
)
from diffbot.live.messages import time_of

TEXT = st.text(st.characters(codec="utf-8", exclude_characters="\x00"), max_size=12)
FLOAT = st.floats(allow_nan=False, width=64)
STAMP = st.integers(-(2**31) * 10**9, (2**31 - 1) * 10**9 + 999_999_999)


@given(
    stamp=STAMP,
    frame=TEXT,
    child=TEXT,
    pose=st.lists(FLOAT, min_size=7, max_size=7),
    covariances=st.lists(FLOAT, min_size=72, max_size=72),
    twist=st.lists(FLOAT, min_size=6, max_size=6),
)
def test_odometry_bytes_equal_the_types_serializer(
    stamp: int,
    frame: str,
    child: str,
    pose: list[float],
    covariances: list[float],
    twist: list[float],
) -> None:
    message = types.Odometry(
        types.Header(time_of(stamp), frame),
        child,
        types.PoseWithCovariance(
            types.Pose(types.Point(*pose[:3]), types.Quaternion(*pose[3:])), covariances[:36]
        ),
        types.TwistWithCovariance(
            types.Twist(types.Vector3(*twist[:3]), types.Vector3(*twist[3:])), covariances[36:]
        ),
    )
    ours = encode_odometry(stamp, frame, child, pose, covariances[:36], twist, covariances[36:])
    assert ours == message.serialize()


@given(linear=FLOAT, angular=FLOAT)
def test_twist_bytes_equal_the_types_serializer(linear: float, angular: float) -> None:
    message = types.Twist(types.Vector3(linear, 0.0, 0.0), types.Vector3(0.0, 0.0, angular))
    assert encode_twist(linear, angular) == message.serialize()


@given(st.lists(st.tuples(STAMP, TEXT, TEXT, st.lists(FLOAT, min_size=7, max_size=7)), max_size=3))
def test_tf_bytes_equal_the_types_serializer(
    transforms: list[tuple[int, str, str, list[float]]],
) -> None:
    message = types.TFMessage(
        [
            types.TransformStamped(
                types.Header(time_of(stamp), frame),
                child,
                types.Transform(types.Vector3(*v[:3]), types.Quaternion(*v[3:])),
            )
            for stamp, frame, child, v in transforms
        ]
    )
    assert encode_tf(transforms) == message.serialize()


@given(
    stamp=STAMP,
    frame=TEXT,
    names=st.lists(TEXT, max_size=4),
    arrays=st.lists(st.lists(FLOAT, max_size=4), min_size=3, max_size=3),
)
def test_joint_states_read_as_the_types_serializer_writes_them(
    stamp: int, frame: str, names: list[str], arrays: list[list[float]]
) -> None:
    message = types.JointState(types.Header(time_of(stamp), frame), names, *arrays)
    assert decode_joint_state(message.serialize()) == message
    assert encode_joint_state(stamp, frame, names, *arrays) == message.serialize()


def test_malformed_joint_states_are_refused() -> None:
    payload = types.JointState(name=["left", "right"], position=[1.0, 2.0]).serialize()
    for cut in range(1, len(payload) - 4):
        with pytest.raises((ValueError, struct.error)):
            decode_joint_state(payload[:-cut])
    huge = bytearray(payload)
    huge[20:24] = struct.pack("<I", 2**31)  # two billion names in a few bytes
    with pytest.raises(ValueError, match=r"^more names than the payload holds$"):
        decode_joint_state(bytes(huge))
    # Refused before any name is read: a name takes at least 5 bytes (a length and a NUL).
    for count in (len(payload) // 5 + 1, len(payload)):
        huge[20:24] = struct.pack("<I", count)
        with pytest.raises(ValueError, match=r"^more names than the payload holds$"):
            decode_joint_state(bytes(huge))
    with pytest.raises(ValueError, match="not little-endian plain CDR"):
        decode_joint_state(b"\x00\x00\x00\x00" + payload[4:])


@given(
    st.lists(
        st.tuples(
            STAMP,
            st.sampled_from(["", "base_link"]),
            st.sampled_from([["left", "right"], ["left", "right", "arm"], ["right", "left"], []]),
            st.lists(FLOAT, max_size=3),
            st.lists(FLOAT, max_size=3),
        ),
        min_size=1,
        max_size=6,
    )
)
def test_a_stream_of_joint_states_reads_as_each_decoded_alone(
    stream: list[tuple[int, str, list[str], list[float], list[float]]],
) -> None:
    # Names repeat and change along the stream: the reader's shortcut must never hand on the
    # names of the payload before.
    reader = JointStateReader()
    for stamp, frame, names, position, velocity in stream:
        payload = encode_joint_state(stamp, frame, names, position, velocity)
        message = decode_joint_state(payload)
        sec, nanosec, read_names, read_position = reader.read(payload)
        assert (sec, nanosec) == (message.header.stamp.sec, message.header.stamp.nanosec)
        assert list(read_names) == message.name
        assert list(read_position) == message.position


@given(
    st.lists(
        st.tuples(
            STAMP,
            st.sampled_from(["", "base_link"]),
            st.sampled_from([["left", "right"], ["left", "right", "arm"], []]),
            st.lists(FLOAT, max_size=3),
            st.lists(FLOAT, max_size=3),
            st.lists(FLOAT, max_size=2),
        ),
        min_size=1,
        max_size=6,
    )
)
def test_a_stream_read_for_velocities_gives_each_payload_s_own_velocities(
    stream: list[tuple[int, str, list[str], list[float], list[float], list[float]]],
) -> None:
    # Positions, velocities and efforts of any lengths, changing along the stream: a robot
    # that reports velocities only sends empty positions.
    reader = JointStateReader("velocity")
    for stamp, frame, names, position, velocity, effort in stream:
        payload = encode_joint_state(stamp, frame, names, position, velocity, effort)
        message = decode_joint_state(payload)
        sec, nanosec, read_names, read_velocity = reader.read(payload)
        assert (sec, nanosec) == (message.header.stamp.sec, message.header.stamp.nanosec)
        assert list(read_names) == message.name
        assert list(read_velocity) == message.velocity


@pytest.mark.parametrize("position", [[], [0.5, 0.25]])
@pytest.mark.parametrize("effort", [[], [7.0, 8.0]])
def test_a_repeated_layout_reads_each_payload_s_own_velocities(
    position: list[float], effort: list[float]
) -> None:
    # The second payload takes the one-call shortcut: its velocities, not the first one's, nor
    # its positions or efforts.
    reader = JointStateReader("velocity")
    names = ["left", "right"]
    first = encode_joint_state(1, "base_link", names, position, [1.0, 2.0], effort)
    second = encode_joint_state(2, "base_link", names, position, [3.0, -4.0], effort)
    assert reader.read(first) == (0, 1, ("left", "right"), (1.0, 2.0))
    for _ in range(2):
        assert reader.read(second) == (0, 2, ("left", "right"), (3.0, -4.0))
    # Velocities of another count in a payload of the same length are parsed, not shortcut.
    full = encode_joint_state(3, "base_link", names, position, [1.0, 2.0], [7.0, 8.0])
    third = encode_joint_state(3, "base_link", names, position, [5.0], [7.0, 8.0, 9.0])
    assert len(third) == len(full)
    assert reader.read(full) == (0, 3, ("left", "right"), (1.0, 2.0))
    assert reader.read(third) == (0, 3, ("left", "right"), (5.0,))


def test_a_reader_reads_positions_or_velocities_only() -> None:
    with pytest.raises(ValueError, match=r"^field must be 'position' or 'velocity', got 'effort'$"):
        JointStateReader("effort")
    payload = encode_joint_state(1, "b", ["l", "r"], [1.0, 2.0], [3.0, 4.0], [5.0, 6.0])
    assert JointStateReader()._velocity is False
    assert JointStateReader("position").read(payload)[3] == (1.0, 2.0)
    assert JointStateReader("velocity").read(payload)[3] == (3.0, 4.0)
    velocity = JointStateReader("velocity")
    for cut in range(1, len(payload) - 4):
        with pytest.raises((ValueError, struct.error)):
            velocity.read(payload[:-cut])


@pytest.mark.parametrize("last", [0.0, -0.0, 5e-324, 1.0])
@pytest.mark.parametrize("velocity", [[], [0.0, 0.0]])
def test_a_repeated_layout_reads_each_payloads_own_positions(
    last: float, velocity: list[float]
) -> None:
    # The second payload takes the one-call shortcut; a layout read a byte off would still find
    # zero counts after a position whose top byte is zero, and return shifted bytes as angles.
    reader = JointStateReader()
    first = encode_joint_state(1, "base_link", ["left", "right"], [1.0, 2.0], velocity)
    second = encode_joint_state(2, "base_link", ["left", "right"], [3.0, last], velocity)
    assert reader.read(first)[3] == (1.0, 2.0)
    for _ in range(2):
        assert reader.read(second) == (0, 2, ("left", "right"), (3.0, last))


def test_each_malformed_payload_is_refused_saying_why() -> None:
    reader = JointStateReader()
    payload = encode_joint_state(1, "base", ["left", "right"], [1.0, 2.0], [0.5, 0.5])
    not_cdr = b"\x00\x00\x00\x00" + payload[4:]
    for decode in (decode_twist, decode_twist_stamped, decode_joint_state, reader.read):
        with pytest.raises(ValueError, match=r"^not little-endian plain CDR$"):
            decode(not_cdr)
    many = bytearray(payload)
    many[24:28] = struct.pack("<I", len(payload) // 5 + 1)  # names that cannot fit
    for decode in (decode_joint_state, reader.read):
        with pytest.raises(ValueError, match=r"^more names than the payload holds$"):
            decode(bytes(many))
    unterminated = bytearray(payload)
    unterminated[16 + 4] = ord("x")  # the NUL after the frame "base"
    for decode in (decode_joint_state, reader.read):
        with pytest.raises(ValueError, match=r"^malformed string$"):
            decode(bytes(unterminated))
    long_position = bytearray(payload)
    # The position count: the last 2 before the first position (8-aligned after it).
    at = payload.rindex(struct.pack("<I", 2), 0, payload.index(struct.pack("<d", 1.0)))
    long_position[at : at + 4] = struct.pack("<I", 1000)
    for decode in (decode_joint_state, reader.read):
        with pytest.raises(ValueError, match=r"^sequence longer than the payload$"):
            decode(bytes(long_position))


@pytest.mark.parametrize("sizes", [(3, 2), (2, 3), (2, 2)])
def test_payloads_of_other_lengths_read_alike_after_any_other(sizes: tuple[int, int]) -> None:
    # Efforts end the payload: the last sequence may end exactly at its last byte.
    reader = JointStateReader()
    for n in (*sizes, sizes[0]):
        names = [f"j{i}" for i in range(n)]
        values = [float(i) + 0.5 for i in range(n)]
        payload = encode_joint_state(7, "base", names, values, values, values)
        assert reader.read(payload) == (0, 7, tuple(names), tuple(values))


def test_the_same_joints_with_and_without_velocities_read_alike() -> None:
    # The same frame, names and positions: only the payload's length tells the layouts apart.
    reader = JointStateReader()
    full = encode_joint_state(3, "base", ["l", "r"], [1.0, 2.0], [3.0, 4.0], [5.0, 6.0])
    bare = encode_joint_state(4, "base", ["l", "r"], [1.5, 2.5])
    for payload, stamp, position in ((full, 3, (1.0, 2.0)), (bare, 4, (1.5, 2.5))) * 2:
        assert reader.read(payload) == (0, stamp, ("l", "r"), position)


def test_malformed_joint_states_are_refused_after_good_ones() -> None:
    payload = types.JointState(
        name=["left", "right"], position=[1.0, 2.0], velocity=[0.5, 0.5]
    ).serialize()
    reader = JointStateReader()
    assert reader.read(payload)[3] == (1.0, 2.0)
    for cut in range(1, len(payload) - 4):
        with pytest.raises((ValueError, struct.error)):
            reader.read(payload[:-cut])
    with pytest.raises(ValueError, match="not little-endian plain CDR"):
        reader.read(b"\x00\x00\x00\x00" + payload[4:])
    longer = bytearray(payload)
    longer[-4:] = struct.pack("<I", 1)  # an effort past the end
    with pytest.raises(ValueError, match=r"^sequence longer than the payload$"):
        reader.read(bytes(longer))
    assert reader.read(payload)[2] == ("left", "right")


@given(
    frame=TEXT,
    child=TEXT,
    covariances=st.lists(FLOAT, min_size=72, max_size=72),
    steps=st.lists(
        st.tuples(STAMP, st.lists(FLOAT, min_size=7, max_size=7), FLOAT, FLOAT),
        min_size=1,
        max_size=3,
    ),
)
def test_odometry_writer_bytes_equal_the_encoders(
    frame: str,
    child: str,
    covariances: list[float],
    steps: list[tuple[int, list[float], float, float]],
) -> None:
    writer = OdometryWriter(frame, child, covariances[:36], covariances[36:])
    for stamp, pose, linear, angular in steps:
        twist = (linear, 0.0, 0.0, 0.0, 0.0, angular)
        expected = encode_odometry(
            stamp, frame, child, pose, covariances[:36], twist, covariances[36:]
        )
        assert writer.odometry(stamp, pose, linear, angular) == expected
        assert writer.tf(stamp, pose) == encode_tf([(stamp, frame, child, pose)])


@given(values=st.lists(FLOAT, min_size=6, max_size=6), stamp=STAMP, frame=TEXT)
def test_twists_read_as_the_types_serializer_writes_them(
    values: list[float], stamp: int, frame: str
) -> None:
    twist = types.Twist(types.Vector3(*values[:3]), types.Vector3(*values[3:]))
    stamped = types.TwistStamped(types.Header(time_of(stamp), frame), twist)
    assert decode_twist(twist.serialize()) == (values[0], values[5])
    assert decode_twist_stamped(stamped.serialize()) == (values[0], values[5])


def test_truncated_twists_are_refused() -> None:
    twist = types.Twist(types.Vector3(1.0, 0.0, 0.0), types.Vector3(0.0, 0.0, 2.0)).serialize()
    stamped = types.TwistStamped(
        types.Header(time_of(5), "base_link"), types.Twist(types.Vector3(), types.Vector3())
    ).serialize()
    for payload, decode in ((twist, decode_twist), (stamped, decode_twist_stamped)):
        for cut in range(1, len(payload)):
            with pytest.raises((ValueError, struct.error)):
                decode(payload[:-cut])
        with pytest.raises(ValueError, match="not little-endian plain CDR"):
            decode(b"\x00\x00\x00\x00" + payload[4:])


@given(st.lists(FLOAT, max_size=5))
def test_float64_arrays_equal_the_types_serializer(values: list[float]) -> None:
    message = types.Float64MultiArray(types.MultiArrayLayout(), values)
    assert encode_float64_array(values) == message.serialize()
