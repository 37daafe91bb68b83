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
