"""Write small rosbag2 recordings with rosbags itself, as test inputs."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.stores import ros2_humble as m

TYPESTORE = get_typestore(Stores.ROS2_HUMBLE)
JOINT_STATE = "sensor_msgs/msg/JointState"

#: One message: header stamp (ns), bag receive time (ns), joint names, positions (rad); or a
#: receive time (ns) and raw bytes, for a damaged message.
Message = tuple[int, int, Sequence[str], Sequence[float]] | tuple[int, bytes]


def joint_state(
    stamp_ns: int,
    names: Sequence[str],
    positions: Sequence[float],
    frame_id: str = "",
    velocities: Sequence[float] = (),
) -> bytes:
    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    msg = m.sensor_msgs__msg__JointState(
        header=m.std_msgs__msg__Header(
            stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id=frame_id
        ),
        name=list(names),
        position=np.array(positions, dtype=np.float64),
        velocity=np.array(velocities, dtype=np.float64),
        effort=np.empty(0),
    )
    return bytes(TYPESTORE.serialize_cdr(msg, JOINT_STATE))


def write_bag(
    path: Path,
    messages: Sequence[Message],
    *,
    topic: str = "/joint_states",
    storage: str = "sqlite3",
    chatter: bool = True,
    frame_id: str = "",
) -> Path:
    """A rosbag2 directory with JointState messages on ``topic`` (and a String on /chatter)."""
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    with Writer(path, version=9, storage_plugin=plugin) as writer:
        conn = writer.add_connection(topic, JOINT_STATE, typestore=TYPESTORE)
        other = None
        if chatter:
            other = writer.add_connection("/chatter", "std_msgs/msg/String", typestore=TYPESTORE)
        for message in messages:
            if len(message) == 2:
                received_ns, raw = message
            else:
                stamp_ns, received_ns, names, positions = message
                raw = joint_state(stamp_ns, names, positions, frame_id)
            writer.write(conn, received_ns, raw)
            if other is not None:
                text = TYPESTORE.serialize_cdr(
                    m.std_msgs__msg__String(data="hi"), "std_msgs/msg/String"
                )
                writer.write(other, received_ns, bytes(text))
    return path


def write_ros1_bag(
    path: Path,
    messages: Sequence[tuple[int, int, Sequence[str], Sequence[float]]],
    *,
    topic: str = "/joint_states",
    frame_id: str = "",
) -> Path:
    """A ROS 1 bag with JointState messages on ``topic`` (stamp, receive time, names, positions),
    written by rosbags' rosbag1 writer with the ROS 1 Noetic types."""
    from rosbags.rosbag1 import Writer as Writer1

    store = get_typestore(Stores.ROS1_NOETIC)
    types = store.types
    with Writer1(path) as writer:
        conn = writer.add_connection(topic, JOINT_STATE, typestore=store)
        for stamp_ns, received_ns, names, positions in messages:
            sec, nanosec = divmod(stamp_ns, 1_000_000_000)
            msg = types[JOINT_STATE](
                header=types["std_msgs/msg/Header"](
                    seq=0,
                    stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
                    frame_id=frame_id,
                ),
                name=list(names),
                position=np.array(positions, dtype=np.float64),
                velocity=np.empty(0),
                effort=np.empty(0),
            )
            writer.write(conn, received_ns, bytes(store.serialize_ros1(msg, JOINT_STATE)))
    return path


def lone_storage(bag: Path, target: Path) -> Path:
    """The storage file of a one-file bag folder, copied alone to ``target`` (compressed with
    zstd when ``target`` ends with ``.zstd``)."""
    (storage,) = [p for p in bag.iterdir() if p.suffix in (".db3", ".mcap")]
    data = storage.read_bytes()
    if target.name.endswith(".zstd"):
        try:
            from compression import zstd  # type: ignore[import-not-found,unused-ignore]
        except ImportError:
            from backports import zstd  # type: ignore[no-redef,import-not-found,unused-ignore]
        data = zstd.compress(data)
    target.write_bytes(data)
    return target


def odometry_message(stamp_ns: int, x: float, y: float, theta: float) -> bytes:
    """A nav_msgs/Odometry at a pose (m, m, rad), frames odom and base_link."""
    import math

    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    msg = m.nav_msgs__msg__Odometry(
        header=m.std_msgs__msg__Header(
            stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id="odom"
        ),
        child_frame_id="base_link",
        pose=m.geometry_msgs__msg__PoseWithCovariance(
            pose=m.geometry_msgs__msg__Pose(
                position=m.geometry_msgs__msg__Point(x=x, y=y, z=0.0),
                orientation=m.geometry_msgs__msg__Quaternion(
                    x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2)
                ),
            ),
            covariance=np.zeros(36),
        ),
        twist=m.geometry_msgs__msg__TwistWithCovariance(
            twist=m.geometry_msgs__msg__Twist(
                linear=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=0.0),
                angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=0.0),
            ),
            covariance=np.zeros(36),
        ),
    )
    return bytes(TYPESTORE.serialize_cdr(msg, "nav_msgs/msg/Odometry"))


def write_bag_with_odometry(
    path: Path,
    messages: Sequence[tuple[int, int, Sequence[str], Sequence[float]]],
    poses: Sequence[tuple[int, float, float, float]],
    *,
    topic: str = "/joint_states",
    odom_topic: str = "/odom",
) -> Path:
    """A rosbag2 directory with JointState messages on ``topic`` and nav_msgs/Odometry poses
    (stamp ns, x, y, theta) on ``odom_topic``."""
    with Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        joints = writer.add_connection(topic, JOINT_STATE, typestore=TYPESTORE)
        odom = writer.add_connection(odom_topic, "nav_msgs/msg/Odometry", typestore=TYPESTORE)
        for stamp_ns, received_ns, names, positions in messages:
            writer.write(joints, received_ns, joint_state(stamp_ns, names, positions))
        for stamp_ns, x, y, theta in poses:
            writer.write(odom, stamp_ns, odometry_message(stamp_ns, x, y, theta))
    return path


def twist_message(linear: float, angular: float, stamp_ns: int | None = None) -> bytes:
    """A geometry_msgs/Twist, or a TwistStamped when ``stamp_ns`` is given."""
    twist = m.geometry_msgs__msg__Twist(
        linear=m.geometry_msgs__msg__Vector3(x=linear, y=0.0, z=0.0),
        angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=angular),
    )
    if stamp_ns is None:
        return bytes(TYPESTORE.serialize_cdr(twist, "geometry_msgs/msg/Twist"))
    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    stamped = m.geometry_msgs__msg__TwistStamped(
        header=m.std_msgs__msg__Header(
            stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id="base_link"
        ),
        twist=twist,
    )
    return bytes(TYPESTORE.serialize_cdr(stamped, "geometry_msgs/msg/TwistStamped"))


def write_topics(path: Path, topics: dict[str, tuple[str, Sequence[tuple[int, bytes]]]]) -> Path:
    """A rosbag2 directory with each topic's (type, [(receive time ns, raw message)])."""
    with Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        for topic, (msgtype, messages) in topics.items():
            conn = writer.add_connection(topic, msgtype, typestore=TYPESTORE)
            for received_ns, raw in messages:
                writer.write(conn, received_ns, raw)
    return path


def velocity_bag(path: Path, start_ns: int = 0, positions: bool = True) -> Path:
    """Trajectory A of the course's robot as wheel velocities, its positions stuck at 0 (or
    absent without ``positions``), as a driver that reports velocities only records it."""
    from wheel_motion import trajectory_a_velocities

    names = ["front_right_wheel_joint", "front_left_wheel_joint"]
    messages: list[Message] = [
        (stamp, joint_state(stamp, names, [0.0, 0.0] if positions else [], "", [right, left]))
        for stamp, left, right in trajectory_a_velocities(start_ns)
    ]
    return write_bag(path, messages)
