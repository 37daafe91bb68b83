"""The batch JointState decoder against rosbags' own deserializer."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from linear_time import FACTOR, GROWTH, SLACK, cpu_seconds
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.stores import ros2_humble as m

from diffbot.errors import RecordingError
from diffbot.io.jointstate_cdr import CdrError, decode_positions, parse_layout

TYPESTORE = get_typestore(Stores.ROS2_HUMBLE)
JOINT_STATE = "sensor_msgs/msg/JointState"

floats = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [-0.0, 0.0, float("nan"), float("inf"), -float("inf"), 5e-324]
)
joint_names = st.sampled_from(["left", "right", "l", "wheel_left_joint", "ü", ""]) | st.text(
    max_size=6
)


def serialize(
    sec: int,
    nanosec: int,
    frame_id: str,
    names: list[str],
    arrays: tuple[list[float], list[float], list[float]],
    *,
    little_endian: bool = True,
) -> bytes:
    position, velocity, effort = (np.array(a, dtype=np.float64) for a in arrays)
    msg = m.sensor_msgs__msg__JointState(
        header=m.std_msgs__msg__Header(
            stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id=frame_id
        ),
        name=names,
        position=position,
        velocity=velocity,
        effort=effort,
    )
    return bytes(TYPESTORE.serialize_cdr(msg, JOINT_STATE, little_endian=little_endian))


@st.composite
def messages(draw: st.DrawFn, layouts: int = 3) -> list[bytes]:
    """Runs of messages drawn from a few layouts, so that both decoding paths are exercised."""
    shapes = [
        (
            draw(st.text(max_size=5)),
            draw(st.lists(joint_names, max_size=4)),
            draw(st.integers(0, 5)),
            draw(st.integers(0, 3)),
            draw(st.integers(0, 3)),
        )
        for _ in range(draw(st.integers(1, layouts)))
    ]
    out = []
    for _ in range(draw(st.integers(1, 12))):
        frame_id, names, n_pos, n_vel, n_eff = draw(st.sampled_from(shapes))
        arrays = tuple(
            draw(st.lists(floats, min_size=k, max_size=k)) for k in (n_pos, n_vel, n_eff)
        )
        sec = draw(st.integers(-(2**31), 2**31 - 1))
        nanosec = draw(st.integers(0, 2**32 - 1))
        little = draw(st.booleans() | st.just(True))
        out.append(serialize(sec, nanosec, frame_id, names, arrays, little_endian=little))  # type: ignore[arg-type]
    return out


def reference(
    blobs: list[bytes], joints: list[str], field: str = "position"
) -> tuple[list[int], list[list[float]], list[list[bool]], list[bool]]:
    """What rosbags gives, joint by joint, as read_bag and Odometry look the joints up."""
    stamps, positions, present, readable = [], [], [], []
    for blob in blobs:
        try:
            msg = cast(
                "m.sensor_msgs__msg__JointState", TYPESTORE.deserialize_cdr(blob, JOINT_STATE)
            )
        except Exception:
            stamps.append(0)
            positions.append([0.0] * len(joints))
            present.append([False] * len(joints))
            readable.append(False)
            continue
        stamps.append(int(msg.header.stamp.sec) * 10**9 + int(msg.header.stamp.nanosec))
        row, have = [], []
        values = msg.velocity if field == "velocity" else msg.position
        for joint in joints:
            names = list(msg.name)
            k = names.index(joint) if joint in names else len(values)
            have.append(k < len(values))
            row.append(float(values[k]) if k < len(values) else 0.0)
        positions.append(row)
        present.append(have)
        readable.append(True)
    return stamps, positions, present, readable


def assert_same(blobs: list[bytes], joints: list[str], field: str = "position") -> None:
    got = decode_positions(blobs, joints, field)
    stamps, positions, present, readable = reference(blobs, joints, field)
    assert got.stamp_ns.tolist() == stamps
    assert got.present.tolist() == present
    assert got.readable.tolist() == readable
    # Bit patterns, so NaN payloads and the sign of zero count.
    want = np.array(positions, dtype=np.float64).reshape(len(blobs), len(joints))
    assert got.positions.view(np.int64).tolist() == want.view(np.int64).tolist()


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(messages(), st.lists(joint_names, min_size=1, max_size=3))
def test_decoded_positions_equal_rosbags_deserializer_bit_for_bit(
    blobs: list[bytes], joints: list[str]
) -> None:
    assert_same(blobs, joints)


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(messages(), st.lists(joint_names, min_size=1, max_size=3))
def test_decoded_velocities_equal_rosbags_deserializer_bit_for_bit(
    blobs: list[bytes], joints: list[str]
) -> None:
    assert_same(blobs, joints, "velocity")


def test_velocities_are_read_from_their_own_field_by_name() -> None:
    blob = serialize(1, 0, "", ["right", "left"], ([1.0, 2.0], [0.5, -0.25], []))
    got = decode_positions([blob, blob], ["left", "right"], "velocity")
    assert got.positions.tolist() == [[-0.25, 0.5]] * 2
    positions_only = serialize(1, 0, "", ["left", "right"], ([1.0, 2.0], [], []))
    assert decode_positions([positions_only], ["left"], "velocity").present.tolist() == [[False]]
    with pytest.raises(RecordingError, match="field"):
        decode_positions([blob], ["left"], "effort")


@settings(max_examples=40, deadline=None)
@given(messages(layouts=1), st.data())
def test_damaged_messages_are_unreadable_exactly_when_rosbags_rejects_them(
    blobs: list[bytes], data: st.DataObject
) -> None:
    damaged = []
    for blob in blobs:
        k = data.draw(st.integers(0, len(blob) - 1))
        cut = data.draw(st.booleans())
        damaged.append(blob[:k] if cut else blob[:k] + bytes([blob[k] ^ 0xFF]) + blob[k + 1 :])
    assert_same(damaged + blobs, ["left", "right"])


def test_trailing_padding_up_to_three_bytes_is_accepted_like_rosbags() -> None:
    blob = serialize(1, 2, "", ["left"], ([1.5], [], []))
    blobs = [blob + b"\0" * k for k in range(6)]
    assert decode_positions(blobs, ["left"]).readable.tolist() == [True] * 4 + [False] * 2
    assert_same(blobs, ["left"])


def test_known_message_gives_its_stamp_and_positions_by_name() -> None:
    blob = serialize(3, 250_000_000, "base", ["a", "right", "left"], ([0.1, -2.5, 7.25], [], []))
    got = decode_positions([blob] * 3, ["left", "right", "missing"])
    assert got.stamp_ns.tolist() == [3_250_000_000] * 3
    assert got.positions.tolist() == [[7.25, -2.5, 0.0]] * 3
    assert got.present.tolist() == [[True, True, False]] * 3


def test_equal_sized_messages_with_other_names_or_lengths_are_told_apart() -> None:
    # The same byte length with the joints in the other order; messages of other lengths (one
    # position and one velocity, a single joint) between them: each is read by its own names.
    first = serialize(1, 0, "", ["lw", "rw"], ([1.0, 2.0], [], []))
    swapped = serialize(2, 0, "", ["rw", "lw"], ([3.0, 4.0], [], []))
    velocity = serialize(3, 0, "", ["lw", "rw"], ([5.0], [6.0], []))
    short = serialize(4, 0, "", ["lw"], ([7.0], [], []))
    assert len(first) == len(swapped) != len(short)
    got = decode_positions([first, swapped, short, velocity, first], ["lw", "rw"])
    assert got.stamp_ns.tolist() == [n * 1_000_000_000 for n in (1, 2, 4, 3, 1)]
    assert got.positions.tolist() == [[1, 2], [4, 3], [7, 0], [5, 0], [1, 2]]
    assert got.present.tolist() == [[1, 1], [1, 1], [1, 0], [1, 0], [1, 1]]


def test_a_joint_named_but_without_a_position_is_absent() -> None:
    blob = serialize(0, 1, "", ["left", "right"], ([4.0], [], []))
    got = decode_positions([blob], ["left", "right"])
    assert got.present.tolist() == [[True, False]]


def test_layout_offsets_follow_cdr_alignment() -> None:
    # frame id "ab" (4 + 3 bytes, padded to 8), names "l" and "r": position[0] after padding to 8.
    blob = serialize(5, 7, "ab", ["l", "r"], ([1.0, 2.0], [], [3.0]))
    layout = parse_layout(blob)
    assert layout.names == ("l", "r")
    assert layout.frame_id == "ab"
    assert layout.counts == (2, 0, 1)
    assert layout.position_offset % 8 == 4  # 8-aligned within the payload, after 4 header bytes
    assert blob[layout.position_offset : layout.position_offset + 8] == np.float64(1.0).tobytes()


def test_big_endian_messages_are_decoded_through_rosbags() -> None:
    blob = serialize(1, 0, "", ["left"], ([0.25], [], []), little_endian=False)
    with pytest.raises(CdrError, match="not a little-endian CDR message"):
        parse_layout(blob)
    got = decode_positions([blob], ["left"])
    assert got.positions.tolist() == [[0.25]]
    assert got.readable.tolist() == [True]


def test_cdr_errors_are_recording_errors() -> None:
    with pytest.raises(RecordingError, match="bad string of length"):
        parse_layout(b"\x00\x01\x00\x00" + bytes(8) + b"\x05\x00\x00\x00ab")


def test_no_messages_give_empty_arrays_of_the_right_shape() -> None:
    got = decode_positions([], ["left", "right"])
    assert got.positions.shape == (0, 2)
    assert got.stamp_ns.dtype == np.int64


def long_frames(size: int) -> list[bytes]:
    """Six JointStates with frame ids of ``size`` bytes and more, 8 bytes apart: each message
    has a length, so a layout, of its own."""
    return [
        serialize(k + 1, 0, "a" * (size + 8 * k), ["left", "right"], ([0.1 * k, 0.2 * k], [], []))
        for k in range(6)
    ]


#: CPU seconds per megabyte of messages the decoder may take: it measures about 0.001; with a
#: NumPy call per 8 bytes of frame id it took 0.75.
SECONDS_PER_MB = 0.05


def test_long_frame_ids_are_decoded_in_time_linear_in_their_bytes() -> None:
    small, large = long_frames(1 << 17), long_frames(FACTOR << 17)
    got = decode_positions(large, ["left", "right"])
    assert got.readable.all()
    assert got.stamp_ns.tolist() == [(k + 1) * 10**9 for k in range(6)]
    assert got.positions[:, 0] == pytest.approx([0.1 * k for k in range(6)], abs=1e-15)
    assert got.positions[:, 1] == pytest.approx([0.2 * k for k in range(6)], abs=1e-15)
    decode_positions(small, ["left", "right"])
    small_time = min(cpu_seconds(lambda: decode_positions(small, ["left"])) for _ in range(3))
    large_time = min(cpu_seconds(lambda: decode_positions(large, ["left"])) for _ in range(2))
    megabytes = sum(map(len, large)) / 1e6
    assert large_time <= GROWTH * FACTOR * small_time + SLACK
    assert large_time <= SECONDS_PER_MB * megabytes, f"{large_time:.3f} s for {megabytes:.1f} MB"
