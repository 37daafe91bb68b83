"""A robot description recorded in a bag: the ``/robot_description`` topic (std_msgs/String)
that robot_state_publisher publishes, latched, when a robot starts."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Final

from diffbot.errors import DescriptionError, RecordingError

__all__ = ["DESCRIPTION_TOPIC", "MAX_DESCRIPTION_BYTES", "is_description_bag", "read_description"]

#: The topic read.
DESCRIPTION_TOPIC: Final = "/robot_description"
#: Largest description message read (bytes).
MAX_DESCRIPTION_BYTES: Final = 16 * 1024 * 1024
_STRING: Final = "std_msgs/msg/String"


def is_description_bag(path: Path) -> bool:
    """Whether a description path is a rosbag2 recording: a folder holding ``metadata.yaml``, or
    an ``.mcap`` or ``.db3`` storage file."""
    return (path.is_dir() and (path / "metadata.yaml").exists()) or path.suffix.lower() in (
        ".mcap",
        ".db3",
    )


def read_description(path: str | os.PathLike[str]) -> str:
    """The last ``/robot_description`` message of a rosbag2 recording (the URDF text).

    Raises:
        DescriptionError: the bag has no such topic, it is not std_msgs/String, or it holds no
            message; the message is larger than :data:`MAX_DESCRIPTION_BYTES`.
        RecordingError: rosbags is missing, the bag cannot be read, or one of its files is not a
            regular file.
    """
    from diffbot.io.bag import require_rosbags, typestore
    from diffbot.io.recordings import existing_recording

    require_rosbags()
    # Every file of the bag is a regular file before rosbags opens one: a FIFO named in
    # metadata.yaml, or in its place, blocked the run for good.
    existing_recording(path)
    from rosbags.rosbag2 import Reader

    from diffbot.io.bag_inflate import bound_rosbags

    bound_rosbags()

    source = os.fspath(path)
    store = typestore()
    text: str | None = None
    try:
        with Reader(Path(path)) as reader:
            connections = [c for c in reader.connections if c.topic == DESCRIPTION_TOPIC]
            if not connections:
                raise DescriptionError(
                    f"{source}: the bag has no {DESCRIPTION_TOPIC} topic to take the robot from"
                )
            kinds = {c.msgtype for c in connections}
            if kinds != {_STRING}:
                raise DescriptionError(
                    f"{source}: {DESCRIPTION_TOPIC} carries {sorted(kinds)}, not {_STRING}"
                )
            for _, _, raw in reader.messages(connections=connections):
                if len(raw) > MAX_DESCRIPTION_BYTES:
                    raise DescriptionError(
                        f"{source}: a {DESCRIPTION_TOPIC} message is larger than "
                        f"{MAX_DESCRIPTION_BYTES} bytes"
                    )
                text = str(getattr(store.deserialize_cdr(raw, _STRING), "data", ""))
    except DescriptionError:
        raise
    except Exception as err:  # rosbags raises its own errors, and struct/KeyError on bad data
        raise RecordingError(f"{source}: cannot read the bag: {err}") from None
    if not text:
        raise DescriptionError(f"{source}: {DESCRIPTION_TOPIC} holds no description")
    return text
