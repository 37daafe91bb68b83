"""Bags read in chunks: the storage reader, and odometry equal to the message-by-message run."""

from __future__ import annotations

import math
from collections.abc import Sequence
from contextlib import closing
from pathlib import Path
from typing import cast

import bags
import numpy as np
import pytest
from bags import JOINT_STATE, TYPESTORE, Message
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from robots import NAMED
from rosbags.typesys.stores import ros2_humble as m
from sinks import Collect

from diffbot.errors import RecordingError
from diffbot.io.bag_chunks import BagError, TopicChunks
from diffbot.odometry import Odometry
from diffbot.reading import Reading
from diffbot.recordings import read_recording
from diffbot.replay import bag_odometry, run_odometry
from diffbot.samples import CLOCK_HEADER, CLOCK_RECEIVE, SKIP_UNREADABLE


def write_bag(path: Path, messages: Sequence[Message], storage: str = "sqlite3") -> Path:
    """A bag of these messages, with header frame ids set (and a String topic beside them)."""
    return bags.write_bag(path, messages, storage=storage, frame_id="odom")


def reference(path: Path) -> tuple[Odometry, str, list[tuple[int, float, float, float]]]:
    """The odometry as read message by message with rosbags (the recording reader's rules)."""
    from rosbags.rosbag2 import Reader

    samples = []
    with Reader(path) as reader:
        conns = [c for c in reader.connections if c.topic == "/joint_states"]
        for _, received, raw in reader.messages(connections=conns):
            try:
                msg = cast(
                    "m.sensor_msgs__msg__JointState", TYPESTORE.deserialize_cdr(raw, JOINT_STATE)
                )
            except Exception:
                continue
            header = int(msg.header.stamp.sec) * 10**9 + int(msg.header.stamp.nanosec)
            samples.append((header, received, list(msg.name), msg.position.tolist()))
    # the clock: header stamps when every message holding a wheel of each side has one
    sides = set(NAMED.left_joints), set(NAMED.right_joints)
    use_header = all(s[0] for s in samples if all(not side.isdisjoint(s[2]) for side in sides))
    odom = Odometry(NAMED)
    stamps = [s[0] if use_header else s[1] for s in samples]
    origin = stamps[0] if stamps else 0
    rows = []
    for stamp, (_, _, names, positions) in zip(stamps, samples, strict=True):
        if odom.update_joint_state(names, positions, (stamp - origin) / 10**9):
            rows.append((stamp, odom.pose.x, odom.pose.y, odom.heading))
    return odom, CLOCK_HEADER if use_header else CLOCK_RECEIVE, rows


def bits(values: Sequence[float]) -> list[int]:
    return [int(v) for v in np.array(values, dtype=np.float64).view(np.int64)]


wheel = st.floats(-20.0, 20.0) | st.sampled_from([math.nan, math.inf, -0.0])


@st.composite
def recordings(draw: st.DrawFn) -> list[Message]:
    received = 1_700_000_000 * 10**9
    header = draw(st.sampled_from([0, 5 * 10**9, 1_700_000_000 * 10**9]))
    out: list[Message] = []
    for _ in range(draw(st.integers(1, 30))):
        received += draw(st.integers(1, 10**8))
        header += draw(st.integers(-(10**7), 10**8))
        kind = draw(st.sampled_from(["both", "both", "both", "swapped", "left only", "damaged"]))
        left, right = draw(wheel), draw(wheel)
        if kind == "damaged":
            out.append((received, b"\x00\x01\x00\x00\xff"))
        elif kind == "left only":
            out.append((max(header, 0), received, ["left"], [left]))
        elif kind == "swapped":
            out.append((max(header, 0), received, ["right", "x", "left"], [right, 0.0, left]))
        else:
            out.append((max(header, 0), received, ["left", "right"], [left, right]))
    return out


@settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(recordings(), st.integers(1, 7), st.sampled_from(["sqlite3", "mcap"]))
def test_bag_odometry_equals_the_message_by_message_run_bit_for_bit(
    tmp_path_factory: pytest.TempPathFactory,
    messages: list[Message],
    chunk_size: int,
    storage: str,
) -> None:
    path = write_bag(tmp_path_factory.mktemp("bag") / "rec", messages, storage)
    want, want_clock, want_rows = reference(path)
    if want.samples == 0:
        with pytest.raises(RecordingError, match="no usable sample"):
            bag_odometry(path, NAMED, chunk_size=chunk_size)
        return
    sink = Collect()
    told: list[int] = []
    reading = Reading(sink=sink, progress=told.append)
    got = bag_odometry(path, NAMED, reading=reading, chunk_size=chunk_size)
    assert got.clock == want_clock
    assert sink.restarts == (got.clock == CLOCK_RECEIVE)  # header pass dropped
    # Read twice or once, each message is reported once: a progress bar ends at its total.
    assert sum(told) == len(messages)
    assert all(n > 0 for n in told)
    rows = sink.rows
    assert [r[0] for r in rows] == [r[0] for r in want_rows]
    for k in (1, 2, 3):
        assert bits([r[k] for r in rows]) == bits([r[k] for r in want_rows])
    summary = got.summary
    assert bits([*summary.final_pose, summary.distance]) == bits([*want.pose, want.distance])
    assert summary.samples == want.samples
    unreadable = sum(1 for msg in messages if len(msg) == 2)
    expected = dict(want.skipped)
    if unreadable:
        expected[SKIP_UNREADABLE] = unreadable
    assert summary.skipped == expected


def test_chunks_hold_the_topic_in_receive_order_and_no_other(tmp_path: Path) -> None:
    messages: list[Message] = [(k + 1, 30 - k, ["left"], [float(k)]) for k in range(10)]
    path = write_bag(tmp_path / "rec", messages)
    with closing(TopicChunks(path, "/joint_states", chunk_size=4)) as chunks:
        assert chunks.msgtype == JOINT_STATE
        assert chunks.message_count == 10
        got = list(chunks)
    assert [len(c.blobs) for c in got] == [4, 4, 2]
    assert np.concatenate([c.receive_ns for c in got]).tolist() == list(range(21, 31))


def test_cells_that_hold_no_bytes_become_empty_messages_and_the_rest_are_kept(
    tmp_path: Path,
) -> None:
    import sqlite3

    messages: list[Message] = [(k + 1, k + 1, ["left"], [float(k)]) for k in range(9)]
    path = write_bag(tmp_path / "rec", messages)
    with closing(TopicChunks(path, "/joint_states", chunk_size=4)) as chunks:
        before = [blob for chunk in chunks for blob in chunk.blobs]
    (database,) = path.glob("*.db3")
    with closing(sqlite3.connect(database)) as connection:
        joint_states = "topic_id = (SELECT id FROM topics WHERE name = '/joint_states')"
        for value, stamp in (("'text'", 2), ("1.5", 5), ("7", 9)):  # receive times k + 1
            connection.execute(
                f"UPDATE messages SET data = {value} WHERE timestamp = {stamp} AND {joint_states}"
            )
        connection.commit()
    with closing(TopicChunks(path, "/joint_states", chunk_size=4)) as chunks:
        after = [blob for chunk in chunks for blob in chunk.blobs]
    assert all(type(blob) is bytes for blob in after)
    assert after == [b"" if k in (1, 4, 8) else blob for k, blob in enumerate(before)]


def test_a_bag_stamped_with_zero_headers_is_read_on_the_receive_clock(tmp_path: Path) -> None:
    messages: list[Message] = [
        (10**9, 10**9, ["left", "right"], [0.0, 0.0]),
        (0, 2 * 10**9, ["left", "right"], [1.0, 1.0]),
    ]
    got = bag_odometry(write_bag(tmp_path / "rec", messages), NAMED)
    assert got.clock == CLOCK_RECEIVE
    assert got.summary.final_pose.x == pytest.approx(0.035, abs=1e-15)
    assert got.summary.duration == 1.0


def test_a_message_without_the_wheels_does_not_choose_the_clock(tmp_path: Path) -> None:
    # header stamps 1 s apart, received 0.5 s apart (simulated time at half speed), and one
    # message of another publisher on the topic (an arm's, its header stamp zero)
    messages: list[Message] = [
        (s * 10**9, s * 5 * 10**8, ["left", "right"], [float(s), float(s)]) for s in (1, 2, 3)
    ]
    messages.insert(2, (0, 11 * 10**8, ["arm"], [0.5]))
    path = write_bag(tmp_path / "rec", messages)
    chunked = bag_odometry(path, NAMED)
    assert chunked.clock == CLOCK_HEADER
    assert chunked.summary.duration == 2.0
    assert chunked.summary.skipped == {"missing joint": 1}
    recording = read_recording(path, NAMED)
    assert recording.clock == CLOCK_HEADER
    odometry = Odometry(NAMED)
    whole = run_odometry(recording, odometry)
    assert whole.duration == 2.0
    assert odometry.pose == chunked.summary.final_pose
    # a message of the wheels with a zero stamp still asks for the receive clock
    messages[2] = (0, 11 * 10**8, ["left", "right"], [1.5, 1.5])
    path = write_bag(tmp_path / "rec2", messages)
    assert bag_odometry(path, NAMED).clock == CLOCK_RECEIVE
    assert read_recording(path, NAMED).clock == CLOCK_RECEIVE


def test_a_missing_topic_names_the_topics_found(tmp_path: Path) -> None:
    path = write_bag(tmp_path / "rec", [(1, 1, ["left"], [0.0])])
    with pytest.raises(
        BagError, match=r"no topic '/odom' in the bag; topics found: '/chatter', '/joint_states'"
    ):
        bag_odometry(path, NAMED, "/odom")


def test_a_topic_of_another_type_is_refused(tmp_path: Path) -> None:
    path = write_bag(tmp_path / "rec", [(1, 1, ["left"], [0.0])])
    with pytest.raises(
        BagError, match=r"topic '/chatter' carries std_msgs/msg/String, not sensor_msgs"
    ):
        bag_odometry(path, NAMED, "/chatter")


def test_a_file_that_is_no_bag_is_a_recording_error(tmp_path: Path) -> None:
    path = tmp_path / "rec.db3"
    path.write_bytes(b"not sqlite at all" * 10)
    with pytest.raises(RecordingError, match="not a readable rosbag2 recording"):
        bag_odometry(path, NAMED)


def _stretch_message_record(storage: Path, index: int) -> None:
    """Damage an uncompressed MCAP file: the ``index``-th record of its first chunk, a message,
    claims the rest of the chunk as its own."""
    import struct

    data = bytearray(storage.read_bytes())
    at = 8  # past the magic
    while data[at] != 0x06:  # the first chunk record
        at += 9 + struct.unpack_from("<Q", data, at + 1)[0]
    size = struct.unpack_from("<Q", data, at + 9 + 16)[0]  # its records' (uncompressed) size
    compression = struct.unpack_from("<I", data, at + 9 + 28)[0]
    assert compression == 0
    start = at + 9 + 32 + 8  # its records begin
    record = start
    for _ in range(index):
        record += 9 + struct.unpack_from("<Q", data, record + 1)[0]
    assert data[record] == 0x05
    struct.pack_into("<Q", data, record + 1, start + size - record - 9)
    storage.write_bytes(bytes(data))


def test_messages_a_damaged_mcap_file_loses_are_an_error_not_a_shorter_run(
    tmp_path: Path,
) -> None:
    # rosbags' walk through the chunk ends at the stretched record and the later messages are
    # gone; the run came out 458 samples long instead of 2001, exit 0.
    messages: list[Message] = [
        (k + 1, k + 1, ["left", "right"], [0.01 * k, 0.02 * k]) for k in range(50)
    ]
    bag = bags.write_bag(tmp_path / "rec", messages, storage="mcap", chatter=False)
    (storage,) = bag.glob("*.mcap")
    _stretch_message_record(storage, 20)  # the 19th message, after a schema and a channel
    for path in (bag, storage):
        with pytest.raises(
            BagError, match=r"rec.*: 19 of the 50 messages the bag lists on '/joint_states' "
        ):
            bag_odometry(path, NAMED)


def test_a_missing_path_is_a_recording_error(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match="no such file or directory"):
        TopicChunks(tmp_path / "absent", "/joint_states")


def test_a_lone_storage_file_is_read_through_its_topics_table(tmp_path: Path) -> None:
    messages: list[Message] = [(k + 1, k + 1, ["left", "right"], [0.0, float(k)]) for k in range(5)]
    bag = write_bag(tmp_path / "rec", messages)
    (storage,) = bag.glob("*.db3")
    with closing(TopicChunks(storage, "/joint_states")) as chunks:
        assert chunks.msgtype == JOINT_STATE
        assert chunks.message_count is None  # counting would read the whole file
        assert [len(c.blobs) for c in chunks] == [5]
        without = list(chunks.chunks(receive_times=False))
        assert [c.receive_ns for c in without] == [None]
        assert without[0].blobs == next(iter(chunks)).blobs
    assert bag_odometry(storage, NAMED).summary == bag_odometry(bag, NAMED).summary


def test_wheel_positions_too_large_are_skipped_as_read_recording_skips_them(
    tmp_path: Path,
) -> None:
    messages: list[Message] = [
        (10**9, 10**9, ["left", "right"], [0.0, 0.0]),
        (2 * 10**9, 2 * 10**9, ["left", "right"], [2e12, 1.0]),
        (3 * 10**9, 3 * 10**9, ["left", "right"], [1.0, 1.0]),
    ]
    path = write_bag(tmp_path / "rec", messages)
    got = bag_odometry(path, NAMED).summary
    want = run_odometry(read_recording(path, NAMED), Odometry(NAMED))
    assert got.skipped == want.skipped == {"position out of range": 1}
    assert got.final_pose == want.final_pose
    assert got.samples == want.samples == 2


def test_a_split_recording_without_metadata_is_read_in_the_order_of_its_file_numbers(
    tmp_path: Path,
) -> None:
    # Straight for the first half, then a spin in place: read out of order, the wheels jump
    # and the pose differs.
    messages: list[Message] = []
    for k in range(120):
        turn = max(0, k - 60) * 0.2
        left, right = 0.5 * min(k, 60) - turn, 0.5 * min(k, 60) + turn
        messages.append(((k + 1) * 10**8, (k + 1) * 10**8, ["left", "right"], [left, right]))
    whole = write_bag(tmp_path / "whole", messages)
    split = tmp_path / "split"
    split.mkdir()
    for part in range(12):  # as ros2 bag record --max-bag-size names them: split_0 ... split_11
        bag = write_bag(tmp_path / f"part{part}", messages[10 * part : 10 * part + 10])
        (storage,) = bag.glob("*.db3")
        storage.rename(split / f"split_{part}.db3")
    with closing(TopicChunks(split, "/joint_states", chunk_size=7)) as chunks:
        received = np.concatenate([c.receive_ns for c in chunks]).tolist()
    assert received == [(k + 1) * 10**8 for k in range(120)]
    got, want = bag_odometry(split, NAMED).summary, bag_odometry(whole, NAMED).summary
    assert got.samples == want.samples == 120
    assert got.final_pose.x == pytest.approx(want.final_pose.x, abs=1e-12)
    assert got.final_pose.y == pytest.approx(want.final_pose.y, abs=1e-12)
    assert got.final_pose.theta == pytest.approx(want.final_pose.theta, abs=1e-12)
    # 59 steps of 0.2 rad each way on 0.035 m wheels 0.135 m apart
    assert want.final_pose.theta == pytest.approx(
        math.remainder(2 * 11.8 * 0.035 / 0.135, math.tau), abs=1e-9
    )


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize(
    ("key", "value", "said"),
    [
        ("message_count", None, "a message count of None"),
        ("message_count", "3", "a message count of '3'"),
        ("message_count", -1, "a message count of -1"),
        ("type", 5, "a message type of 5"),
        ("type", None, "a message type of None"),
        ("name", ["/joint_states"], "a topic name of \\['/joint_states'\\]"),
    ],
)
def test_metadata_of_the_wrong_kind_is_one_error(
    tmp_path: Path, storage: str, key: str, value: object, said: str
) -> None:
    import yaml

    path = write_bag(tmp_path / "rec", [(1, 1, ["left", "right"], [0.0, 0.0])], storage)
    metadata = path / "metadata.yaml"
    info = yaml.safe_load(metadata.read_text(encoding="utf-8"))
    topics = info["rosbag2_bagfile_information"]["topics_with_message_count"]
    entry = next(t for t in topics if t["topic_metadata"]["name"] == "/joint_states")
    (entry if key == "message_count" else entry["topic_metadata"])[key] = value
    metadata.write_text(yaml.safe_dump(info), encoding="utf-8")
    with pytest.raises(BagError, match=f"malformed bag metadata: {said}$"):
        bag_odometry(path, NAMED)


def test_a_write_ahead_log_left_beside_the_storage_is_said_not_read(tmp_path: Path) -> None:
    import shutil
    import sqlite3

    messages: list[Message] = [
        (s * 10**9, s * 10**9, ["left", "right"], [float(s), float(s)]) for s in (1, 2, 3)
    ]
    made = write_bag(tmp_path / "made", messages)
    storage = next(made.glob("*.db3"))
    # a recorder that died with messages in its write-ahead log: copied while it is open
    connection = sqlite3.connect(storage)
    try:
        connection.execute("PRAGMA journal_mode=WAL")
        connection.execute("PRAGMA wal_autocheckpoint=0")
        connection.execute("DELETE FROM messages WHERE timestamp > 1000000000")
        connection.commit()
        crashed = tmp_path / "crashed"
        shutil.copytree(made, crashed)
    finally:
        connection.close()
    log = crashed / f"{storage.name}-wal"
    assert log.stat().st_size > 0
    before = {p.name: p.read_bytes() for p in crashed.iterdir()}
    got = bag_odometry(crashed, NAMED)
    assert got.notes == (
        f"'{log.name}': a write-ahead log of a recording that did not close; the messages it "
        "holds are not read (open the bag once with sqlite3 to merge them)",
    )
    assert read_recording(crashed, NAMED).notes == got.notes
    assert {p.name: p.read_bytes() for p in crashed.iterdir()} == before  # nothing added
    assert bag_odometry(made, NAMED).notes == ()


def test_a_topic_read_again_for_a_late_zero_stamp_reports_its_messages_once(
    tmp_path: Path,
) -> None:
    """A zero header stamp found after chunks were reported reads the topic a second time: the
    progress bar went to 36384/20000 on such a bag."""
    messages: list[Message] = [
        (s * 10**9, s * 10**9, ["left", "right"], [float(s), float(s)]) for s in range(1, 9)
    ]
    messages.append((0, 9 * 10**9, ["left", "right"], [9.0, 9.0]))
    told: list[int] = []
    got = bag_odometry(
        write_bag(tmp_path / "rec", messages),
        NAMED,
        reading=Reading(progress=told.append),
        chunk_size=2,
    )
    assert got.clock == CLOCK_RECEIVE
    assert sum(told) == len(messages)
    assert told == [2, 2, 2, 2, 1]
