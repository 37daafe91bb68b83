"""What a chunk of a bag may hold: at most CHUNK_BYTES of messages whatever their count, and no
message larger than MAX_MESSAGE_BYTES, the same for every storage."""

from __future__ import annotations

from contextlib import closing
from pathlib import Path
from typing import Any

import pytest
from bags import JOINT_STATE, TYPESTORE, joint_state, write_bag, write_ros1_bag
from cli_results import assert_one_error_line
from click.testing import CliRunner
from peak_memory import peak_bytes
from robots import BOT, NAMED

from diffbot.cli import main
from diffbot.io import bag_chunks
from diffbot.io.bag_chunks import CHUNK_MESSAGES, MAX_MESSAGE_BYTES, TopicChunks
from diffbot.replay import bag_odometry

#: The storages a bag comes in: rosbag2 sqlite3 (read with sqlite3 itself), rosbag2 mcap,
#: rosbag2 sqlite3 compressed message by message (both read by rosbags), and ROS 1.
KINDS = ["sqlite3", "mcap", "zstd messages", "ros1"]
#: A frame id of this many bytes makes a message of a little more.
FRAME = 300_000

Messages = list[tuple[int, int, list[str], list[float]]]


def messages(count: int, left: str = "left", right: str = "right") -> Messages:
    """Both wheels turning 0.1 rad a message, 0.1 s apart."""
    return [
        ((k + 1) * 10**8, (k + 1) * 10**8, [left, right], [0.1 * k, 0.1 * k]) for k in range(count)
    ]


def write(kind: str, path: Path, content: Messages, frame_id: str) -> Path:
    """A bag of the JointState messages in ``content`` in one of :data:`KINDS`."""
    if kind == "ros1":
        return write_ros1_bag(path.with_suffix(".bag"), content, frame_id=frame_id)
    if kind != "zstd messages":
        return write_bag(path, content, storage=kind, chatter=False, frame_id=frame_id)
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, Writer

    writer = Writer(path, version=9)
    writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    with writer:
        conn = writer.add_connection("/joint_states", JOINT_STATE, typestore=TYPESTORE)
        for stamp, received, names, positions in content:
            writer.write(conn, received, joint_state(stamp, names, positions, frame_id))
    return path


@pytest.mark.parametrize("kind", KINDS)
def test_a_chunk_ends_before_the_message_that_would_take_it_past_chunk_bytes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, kind: str
) -> None:
    monkeypatch.setattr(bag_chunks, "CHUNK_BYTES", 1 << 20)
    bag = write(kind, tmp_path / "rec", messages(12), "f" * FRAME)
    with closing(TopicChunks(bag, "/joint_states", chunk_size=CHUNK_MESSAGES)) as chunks:
        got = list(chunks)
    # three messages of a little over 300 kB fit in a MiB, a fourth would not
    assert [len(chunk.blobs) for chunk in got] == [3, 3, 3, 3]
    assert all(sum(map(len, chunk.blobs)) <= 1 << 20 for chunk in got)
    stamps = [t for chunk in got for t in chunk.receive_ns.tolist()]  # type: ignore[union-attr]
    assert stamps == [(k + 1) * 10**8 for k in range(12)]
    summary = bag_odometry(bag, NAMED).summary
    assert summary.samples == 12
    # 11 steps of 0.1 rad on 0.035 m wheels, straight ahead
    assert summary.final_pose.x == pytest.approx(11 * 0.1 * 0.035, abs=1e-12)
    assert summary.final_pose.y == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("kind", KINDS)
def test_reading_holds_a_bounded_amount_of_memory_however_many_large_messages(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, kind: str
) -> None:
    monkeypatch.setattr(bag_chunks, "CHUNK_BYTES", 1 << 20)
    bag = write(kind, tmp_path / "rec", messages(60), "f" * FRAME)  # 18 MB of messages
    bag_odometry(bag, NAMED)  # what is loaded on first use is not counted
    summaries: list[Any] = []
    _, peak = peak_bytes(lambda: summaries.append(bag_odometry(bag, NAMED).summary))
    # a MiB of messages, the storage's own chunk of about as much, and copies of a few
    assert peak < 6 << 20, f"{peak / 2**20:.1f} MiB"
    assert summaries[0].samples == 60
    assert summaries[0].final_pose.x == pytest.approx(59 * 0.1 * 0.035, abs=1e-12)


@pytest.mark.parametrize("kind", KINDS)
def test_a_message_larger_than_the_bound_is_one_error_line(tmp_path: Path, kind: str) -> None:
    content = messages(3, BOT.left_joint, BOT.right_joint)
    honest = write(kind, tmp_path / "honest", content, "f" * FRAME)
    result = CliRunner().invoke(main, ["odom", str(honest)])
    assert result.exit_code == 0, result.output
    bomb = write(kind, tmp_path / "bomb", content, "f" * MAX_MESSAGE_BYTES)
    result = CliRunner().invoke(main, ["odom", str(bomb)])
    assert_one_error_line(
        result,
        f"{bomb}: a sensor_msgs/msg/JointState message of ",
        " bytes on topic '/joint_states', more than the 1048576 bytes (1 MiB) a message may "
        "take: refused",
    )


def test_a_damaged_ros1_bag_is_named_as_one(tmp_path: Path) -> None:
    bag = write_ros1_bag(tmp_path / "rec.bag", messages(3))
    data = bag.read_bytes()
    record = data.index(b"op=\x02")  # the first message's record, in its (uncompressed) chunk
    bag.write_bytes(data[:record] + b"op=\x01" + data[record + 4 :])
    with pytest.raises(bag_chunks.BagError, match=r"rec\.bag: not a readable ROS 1 bag: "):
        bag_odometry(bag, NAMED)
