"""Decompression of bag data is bounded: a small bomb is one error line, never gigabytes."""

from __future__ import annotations

import bz2
from collections.abc import Callable
from pathlib import Path
from typing import Any

import lz4.frame
import pytest
from bags import JOINT_STATE, TYPESTORE, joint_state, lone_storage, write_bag
from cli_results import assert_one_error_line
from click.testing import CliRunner
from peak_memory import peak_bytes
from robots import BOT

from diffbot.cli import main
from diffbot.errors import RecordingError
from diffbot.io import bag_inflate
from diffbot.io.bag_inflate import inflate

try:
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:
    from backports import zstd  # type: ignore[no-redef,import-not-found,unused-ignore]

LEFT, RIGHT = BOT.left_joint, BOT.right_joint
#: What each bomb inflates to (bytes): ten thousand times the bounds the tests set.
ZEROS = 10 << 20
COMPRESS: dict[str, Callable[[bytes], bytes]] = {
    "zstd": zstd.compress,
    "lz4": lz4.frame.compress,
    "bz2": bz2.compress,
}


@pytest.mark.parametrize("kind", ["zstd", "lz4", "bz2"])
def test_a_stream_is_inflated_whole_up_to_its_bound(kind: str) -> None:
    data = bytes(range(256)) * 40
    packed = COMPRESS[kind](data) + COMPRESS[kind](b"tail")  # two frames or streams
    assert inflate(packed, kind, len(data) + 4, "x") == data + b"tail"
    with pytest.raises(RecordingError, match=r"^x decompresses to more than 10243 bytes"):
        inflate(packed, kind, len(data) + 3, "x")


@pytest.mark.parametrize("kind", ["zstd", "lz4", "bz2"])
def test_a_bomb_is_refused_without_inflating_it(kind: str) -> None:
    bomb = COMPRESS[kind](bytes(ZEROS))
    caught: list[Exception] = []

    def run() -> None:
        try:
            inflate(bomb, kind, 1024, "a chunk")
        except RecordingError as err:
            caught.append(err)

    assert peak_bytes(run)[1] < 1 << 20
    assert str(caught[0]) == "a chunk decompresses to more than 1024 bytes, refused (a bomb?)"


@pytest.mark.parametrize("kind", ["zstd", "lz4", "bz2"])
def test_truncated_or_foreign_data_is_an_error(kind: str) -> None:
    packed = COMPRESS[kind](bytes(range(256)) * 40)
    with pytest.raises(RecordingError, match=r"truncated|malformed"):
        inflate(packed[: len(packed) // 2], kind, 1 << 20, "x")
    with pytest.raises(RecordingError, match="malformed"):
        inflate(b"not compressed at all", kind, 1 << 20, "x")


def messages(count: int = 20) -> list[tuple[int, int, list[str], list[float]]]:
    return [
        (10**9 + k * 10**8, 10**9 + k * 10**8, [LEFT, RIGHT], [k * 0.1, k * 0.2])
        for k in range(count)
    ]


def odom(path: Path) -> Any:
    return CliRunner().invoke(main, ["odom", str(path)])


@pytest.mark.parametrize("kind", ["lz4", "bz2"])
def test_a_ros1_chunk_inflating_past_its_declared_size_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, kind: str
) -> None:
    from bags import write_ros1_bag
    from rosbags.rosbag1 import Writer as Writer1

    real_open = Writer1.open

    def compressing_open(self: Any, bomb: bool) -> None:
        self.set_compression(Writer1.CompressionFormat[kind.upper()])
        if bomb:  # the chunk's real size declared, ten megabytes of zeros packed after it
            self.compressor = lambda data: COMPRESS[kind](data + bytes(ZEROS))
        real_open(self)

    monkeypatch.setattr(Writer1, "open", lambda self: compressing_open(self, False))
    honest = write_ros1_bag(tmp_path / "honest.bag", messages())
    monkeypatch.setattr(Writer1, "open", lambda self: compressing_open(self, True))
    bomb = write_ros1_bag(tmp_path / "bomb.bag", messages())
    monkeypatch.undo()
    assert bomb.stat().st_size < 1 << 20
    result = odom(honest)
    assert result.exit_code == 0, result.output
    results: list[Any] = []
    assert peak_bytes(lambda: results.append(odom(bomb)))[1] < 5 << 20
    assert_one_error_line(results[0], "bomb.bag: a chunk declaring", "decompresses to more than")


def compressed_bag(
    path: Path, monkeypatch: pytest.MonkeyPatch, mode: str, inflate_to: int = 0
) -> Path:
    """A rosbag2 bag compressed with zstd by ``mode`` (``message`` or ``file``); with
    ``inflate_to``, every compressed message or file has that many zeros packed after it."""
    import rosbags.rosbag2.writer as writer_module
    from rosbags.rosbag2 import Writer
    from rosbags.rosbag2.enums import CompressionFormat, CompressionMode

    class Packing:
        @staticmethod
        def compress(data: bytes) -> bytes:
            return zstd.compress(data + bytes(inflate_to))

        @staticmethod
        def open(target: Any, mode: str) -> Any:
            stream = zstd.open(target, mode)
            if inflate_to:
                stream.write(bytes(inflate_to))
            return stream

    monkeypatch.setattr(writer_module, "zstd", Packing)
    writer = Writer(path, version=9)
    writer.set_compression(CompressionMode[mode.upper()], CompressionFormat.ZSTD)
    with writer:
        conn = writer.add_connection("/joint_states", JOINT_STATE, typestore=TYPESTORE)
        for stamp, received, names, positions in messages():
            writer.write(conn, received, joint_state(stamp, names, positions))
    monkeypatch.undo()
    return path


def test_a_message_inflating_past_its_bound_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    honest = compressed_bag(tmp_path / "honest", monkeypatch, "message")
    assert odom(honest).exit_code == 0
    bomb = compressed_bag(tmp_path / "bomb", monkeypatch, "message", ZEROS)
    monkeypatch.setattr(bag_inflate, "MAX_MESSAGE_BYTES", 1 << 20)
    results: list[Any] = []
    assert peak_bytes(lambda: results.append(odom(bomb)))[1] < 5 << 20
    assert_one_error_line(results[0], "a compressed bag message decompresses to more than 1048576")


def test_a_storage_file_inflating_past_its_bound_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    honest = compressed_bag(tmp_path / "honest", monkeypatch, "file")
    assert odom(honest).exit_code == 0
    bomb = compressed_bag(tmp_path / "bomb", monkeypatch, "file", ZEROS)
    monkeypatch.setattr(bag_inflate, "MIN_FILE_BYTES", 1 << 20)
    result = odom(bomb)
    assert_one_error_line(result, "a compressed bag file decompresses to more than 1048576")


def test_a_lone_compressed_storage_file_inflating_past_its_bound_is_one_error_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bag = write_bag(tmp_path / "rec", messages())
    honest = lone_storage(bag, tmp_path / "honest.db3.zstd")
    assert odom(honest).exit_code == 0
    bomb = tmp_path / "bomb.db3.zstd"
    (storage,) = bag.glob("*.db3")
    bomb.write_bytes(zstd.compress(storage.read_bytes() + bytes(ZEROS)))
    monkeypatch.setattr(bag_inflate, "MIN_FILE_BYTES", 1 << 20)
    assert_one_error_line(odom(bomb), "bomb.db3.zstd decompresses to more than 1048576")
    assert bag_inflate.file_limit(10) == 1 << 20
    assert bag_inflate.file_limit(1 << 20) == 100 << 20


def test_an_mcap_chunk_inflating_past_its_declared_size_is_refused() -> None:
    import rosbags.rosbag2.storage_mcap as mcap

    bag_inflate.bound_rosbags()
    data = bytes(range(256)) * 8
    assert mcap.DECOMPRESSORS["zstd"](zstd.compress(data), len(data)) == data
    with pytest.raises(RecordingError, match="a bag chunk decompresses to more than 2047"):
        mcap.DECOMPRESSORS["zstd"](zstd.compress(data), len(data) - 1)
    with pytest.raises(RecordingError, match="a bag chunk decompresses to more than 2047"):
        mcap.DECOMPRESSORS["lz4"](lz4.frame.compress(data), len(data) - 1)


@pytest.mark.parametrize("kind", ["zstd", "lz4", "bz2"])
def test_a_stream_inflated_whole_is_held_about_twice_at_most(kind: str) -> None:
    data = bytes(16 << 20)
    packed = COMPRESS[kind](data)
    results: list[bytes] = []
    _, peak = peak_bytes(lambda: results.append(inflate(packed, kind, len(data), "x")))
    assert results[0] == data
    # the growing result and its final copy; a whole-size piece beside them made it three
    assert peak < 2.5 * len(data), f"{peak / len(data):.2f} times the data"


def test_a_budget_counts_every_inflation_in_its_block_and_only_there() -> None:
    from diffbot.io.bag_inflate import InflationBudget

    budget = InflationBudget(1000, "rec")  # at least MIN_FILE_BYTES: 64 MiB
    assert budget.limit == bag_inflate.MIN_FILE_BYTES
    packed = zstd.compress(bytes(ZEROS))
    with budget.active():
        for _ in range(6):  # six streams each within their own bound
            inflate(packed, "zstd", ZEROS, "a chunk")
        assert budget.used == 6 * ZEROS
        with pytest.raises(RecordingError, match=r"^rec: reading it decompresses more than"):
            inflate(packed, "zstd", ZEROS, "a chunk")
    spent = budget.used
    assert spent <= budget.limit + (1 << 20)  # refused within a step of its limit
    inflate(packed, "zstd", ZEROS, "a chunk")  # outside the block: counted nowhere
    assert budget.used == spent
    assert InflationBudget(1 << 30, "big").limit == bag_inflate.FILE_RATIO << 30


def interleaved_ros1_bag(path: Path, pad: int) -> Path:
    """A bz2 ROS 1 bag of two chunks, each with ``pad`` zero bytes on another topic: chunk one
    holds the joint states of odd seconds, chunk two of even ones, so that reading them in
    time order goes from one chunk to the other at each message."""
    import numpy as np
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    types = store.types
    writer = Writer1(path)
    writer.set_compression(Writer1.CompressionFormat.BZ2)
    writer.chunk_threshold = pad // 2
    writer.open()
    joints = writer.add_connection("/joint_states", JOINT_STATE, typestore=store)
    padding = writer.add_connection("/pad", "std_msgs/msg/UInt8MultiArray", typestore=store)
    layout = types["std_msgs/msg/MultiArrayLayout"](dim=[], data_offset=0)
    blob = types["std_msgs/msg/UInt8MultiArray"](layout=layout, data=np.zeros(pad, np.uint8))
    for parity in (1, 2):
        for k in range(10):
            second = 2 * k + parity
            msg = types[JOINT_STATE](
                header=types["std_msgs/msg/Header"](
                    seq=0,
                    stamp=types["builtin_interfaces/msg/Time"](sec=second, nanosec=0),
                    frame_id="",
                ),
                name=[LEFT, RIGHT],
                position=np.array([0.1 * second, 0.1 * second]),
                velocity=np.empty(0),
                effort=np.empty(0),
            )
            writer.write(joints, second * 10**9, bytes(store.serialize_ros1(msg, JOINT_STATE)))
        blob_bytes = store.serialize_ros1(blob, "std_msgs/msg/UInt8MultiArray")
        writer.write(padding, 10**12 + parity, bytes(blob_bytes))
    writer.close()
    return path


def test_a_ros1_bag_read_chunk_to_chunk_over_and_over_is_refused_in_time(tmp_path: Path) -> None:
    # two 8 MiB chunks of a few kilobytes each, inflated again at every one of 20 messages:
    # 160 MiB for a bag of kilobytes, and hours for a bag of larger chunks
    bag = interleaved_ros1_bag(tmp_path / "inter.bag", 8 << 20)
    assert bag.stat().st_size < 64 << 10
    result = odom(bag)
    assert_one_error_line(result, "inter.bag: reading it decompresses more than", "refused")
    # the same messages in chunks read once each are read
    small = interleaved_ros1_bag(tmp_path / "small.bag", 1 << 20)
    assert odom(small).exit_code == 0
