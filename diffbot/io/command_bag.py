"""Command bags: a plan's commands as a rosbag2 that ``ros2 bag play`` publishes to a robot.

The body commands go on one topic as geometry_msgs/msg/Twist (or TwistStamped), the joint
velocity commands on one std_msgs/msg/Float64MultiArray topic per wheel; every message is
stamped (and received) at its time from zero, and the last commands are zero.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from diffbot.errors import RecordingError
from diffbot.io.bag import bag_writer, check_stamps, require_rosbags, typestore
from diffbot.live.names import repeated_topic
from diffbot.ros.messages import command_type
from diffbot.samples import NS_PER_S

if TYPE_CHECKING:
    from diffbot.ramps import CommandStream

__all__ = ["write_command_bag"]


def _topic(name: str) -> str:
    """A topic name as a bag stores it: absolute (a private ``~/`` name cannot be)."""
    if name.startswith("~"):
        raise RecordingError(
            f"a bag cannot hold the private topic {name!r}: give the controller's full topic "
            "name, such as /diff_drive_controller/cmd_vel"
        )
    return name if name.startswith("/") else f"/{name}"


def write_command_bag(
    path: str | os.PathLike[str],
    stream: CommandStream | Iterable[CommandStream],
    *,
    cmd_vel: str = "/cmd_vel",
    left_topic: str | None = None,
    right_topic: str | None = None,
    stamped: bool = False,
    frame_id: str = "base_link",
    joints: tuple[int, int] = (1, 1),
    force: bool = False,
) -> None:
    """Write a command stream as a rosbag2.

    Args:
        path: the bag directory to create.
        stream: the commands (see :meth:`diffbot.ramps.RampedPlan.commands`), or the commands
            in consecutive pieces (:meth:`~diffbot.ramps.RampedPlan.command_chunks`), written
            as they come in constant memory.
        cmd_vel: the body command topic (made absolute).
        left_topic: the left wheel's Float64MultiArray topic, or None for none.
        right_topic: the right wheel's topic, or None for none.
        stamped: write geometry_msgs/TwistStamped commands instead of Twist.
        frame_id: the frame of stamped commands.
        joints: how many joints the left and right controllers drive: each wheel message holds
            the command once per joint.
        force: replace an existing file or bag at ``path``.

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, a topic cannot be stored, or a stamp is outside ROS
            time.
    """
    import numpy as np

    from diffbot.ramps import CommandStream

    p = Path(path)
    pieces = [stream] if isinstance(stream, CommandStream) else stream
    topics = [(left_topic, joints[0]), (right_topic, joints[1])]
    per_wheel = [
        (_topic(topic), side, count)
        for side, (topic, count) in enumerate(topics)
        if topic is not None
    ]
    body_topic = _topic(cmd_vel)
    named = [("the command topic", body_topic)]
    named += [(("{left_topic}", "{right_topic}")[side], topic) for topic, side, _ in per_wheel]
    problem = repeated_topic(named)
    if problem is not None:
        raise RecordingError(problem)
    require_rosbags()
    from rosbags.typesys.stores import ros2_humble as m

    store = typestore()
    twist_type = command_type(frame_id if stamped else None)
    array_type = "std_msgs/msg/Float64MultiArray"
    layout = m.std_msgs__msg__MultiArrayLayout(dim=[], data_offset=0)
    with bag_writer(p, force) as writer:
        body = writer.add_connection(body_topic, twist_type, typestore=store)
        wheels = [
            (writer.add_connection(topic, array_type, typestore=store), side, count)
            for topic, side, count in per_wheel
        ]
        for piece in pieces:
            stamps = [round(t * NS_PER_S) for t in piece.times.tolist()]
            check_stamps(stamps, p)
            linear, angular = piece.linear.tolist(), piece.angular.tolist()
            sides = (piece.left.tolist(), piece.right.tolist())
            for k, stamp_ns in enumerate(stamps):
                twist = m.geometry_msgs__msg__Twist(
                    linear=m.geometry_msgs__msg__Vector3(x=linear[k], y=0.0, z=0.0),
                    angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=angular[k]),
                )
                message: object = twist
                if stamped:
                    sec, nanosec = divmod(stamp_ns, NS_PER_S)
                    header = m.std_msgs__msg__Header(
                        stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec),
                        frame_id=frame_id,
                    )
                    message = m.geometry_msgs__msg__TwistStamped(header=header, twist=twist)
                writer.write(body, stamp_ns, store.serialize_cdr(message, twist_type))
                for connection, side, count in wheels:
                    array = m.std_msgs__msg__Float64MultiArray(
                        layout=layout, data=np.full(count, sides[side][k], dtype=np.float64)
                    )
                    writer.write(connection, stamp_ns, store.serialize_cdr(array, array_type))
