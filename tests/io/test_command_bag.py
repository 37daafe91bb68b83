"""Command bags written by the library: topics, per-joint wheel messages, refusals."""

from __future__ import annotations

from pathlib import Path

import pytest
from robots import BOT
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from diffbot.errors import RecordingError
from diffbot.io.command_bag import write_command_bag
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits
from diffbot.ramps import CommandStream, ramp
from diffbot.trajectory import plan

TYPESTORE = get_typestore(Stores.ROS2_HUMBLE)


def stream() -> CommandStream:
    return ramp(plan(parse_plan("straight 0.2 1s; spin 90 1s"), BOT), Limits()).commands(4.0)


def test_wheel_messages_hold_the_command_once_per_joint_of_their_side(tmp_path: Path) -> None:
    commands = stream()
    bag = tmp_path / "bag"
    write_command_bag(bag, commands, left_topic="left", right_topic="right", joints=(2, 3))
    seen: dict[str, list[list[float]]] = {}
    with Reader(bag) as reader:
        for connection, _, raw in reader.messages():
            message = TYPESTORE.deserialize_cdr(raw, connection.msgtype)
            if connection.topic != "/cmd_vel":
                seen.setdefault(connection.topic, []).append(message.data.tolist())
    assert seen["/left"] == [[v] * 2 for v in commands.left.tolist()]
    assert seen["/right"] == [[v] * 3 for v in commands.right.tolist()]


def test_without_wheel_topics_only_the_body_commands_are_written(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    write_command_bag(bag, stream(), cmd_vel="/robot/cmd_vel")
    with Reader(bag) as reader:
        assert [c.topic for c in reader.connections] == ["/robot/cmd_vel"]
        assert reader.message_count == stream().times.size


def test_a_private_topic_cannot_be_stored_and_nothing_is_written(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    with pytest.raises(RecordingError, match=r"private topic '~/cmd_vel'"):
        write_command_bag(bag, stream(), cmd_vel="~/cmd_vel")
    assert not bag.exists()


@pytest.mark.parametrize(
    ("topics", "message"),
    [
        ({"left_topic": "w", "right_topic": "/w"}, "left_topic= and right_topic= are both /w"),
        ({"left_topic": "cmd_vel"}, "the command topic and left_topic= are both /cmd_vel"),
    ],
)
def test_one_topic_for_two_kinds_of_command_is_refused_and_nothing_is_written(
    tmp_path: Path, topics: dict[str, str], message: str
) -> None:
    bag = tmp_path / "bag"
    with pytest.raises(RecordingError, match=f"^{message}: each needs a topic of its own$"):
        write_command_bag(bag, stream(), cmd_vel="cmd_vel", **topics)
    assert not bag.exists()


def messages(bag: Path) -> list[tuple[str, int, bytes]]:
    with Reader(bag) as reader:
        return [(c.topic, stamp, bytes(raw)) for c, stamp, raw in reader.messages()]


@pytest.mark.parametrize("stamped", [False, True])
def test_commands_in_pieces_make_the_bag_of_the_whole_stream(tmp_path: Path, stamped: bool) -> None:
    ramped = ramp(plan(parse_plan("straight 0.2 1s; spin 90 1s; ccw 0.3 45"), BOT), Limits())
    options = {"left_topic": "left", "right_topic": "right", "stamped": stamped}
    write_command_bag(tmp_path / "whole", ramped.commands(10.0), **options)  # type: ignore[arg-type]
    pieces = ramped.command_chunks(10.0, chunk=3)
    write_command_bag(tmp_path / "pieces", pieces, **options)  # type: ignore[arg-type]
    assert messages(tmp_path / "pieces") == messages(tmp_path / "whole")
    assert len(messages(tmp_path / "whole")) == 3 * ramped.command_count(10.0)


def test_a_bad_stamp_in_a_later_piece_leaves_nothing(tmp_path: Path) -> None:
    good = stream()
    bad = CommandStream(good.times + 2.0**31, good.linear, good.angular, good.left, good.right)
    bag = tmp_path / "bag"
    with pytest.raises(RecordingError, match="ROS time must be between 0 and 2"):
        write_command_bag(bag, [good, bad])
    assert not bag.exists()
    assert list(tmp_path.iterdir()) == []
