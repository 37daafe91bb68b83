"""Recordings as rosbag2 folders, read and written through the ``rosbags`` library.

A rosbag2 recording is a directory with sqlite3 or mcap storage, or one ``.db3`` or ``.mcap``
storage file (``pip install 'rosbags>=0.11'``): the sensor_msgs/msg/JointState messages
of one topic are read, all stamped by their header stamps, or all by the bag's receive times when
any header stamp is zero. Outputs are written whole or not at all.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Final, cast

from diffbot.errors import DiffbotError, OutputError, RecordingError
from diffbot.formats.text import listing
from diffbot.io.outputs import BAG_FILES, check_bag_output, replace_bag
from diffbot.ros.messages import quaternion_from_yaw
from diffbot.samples import (
    CLOCK_HEADER,
    CLOCK_RECEIVE,
    NS_PER_S,
    SKIP_UNREADABLE,
    JointSample,
    Recording,
    seconds_text,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from rosbags.rosbag2 import Writer
    from rosbags.typesys.store import Typestore
    from rosbags.typesys.stores.ros2_humble import sensor_msgs__msg__JointState as JointState

    from diffbot.odometry import Odometry
    from diffbot.replay import OdometryRow

__all__ = [
    "BAG_INSTALL_HINT",
    "DEFAULT_TOPIC",
    "JOINT_STATE",
    "is_bag",
    "read_bag",
    "require_rosbags",
    "write_joint_states_bag",
    "write_odometry_bag",
]

#: The JointState topic read from bags unless another is asked for.
DEFAULT_TOPIC: Final = "/joint_states"
#: The message type read from bags.
JOINT_STATE: Final = "sensor_msgs/msg/JointState"
#: What to install for bag support.
BAG_INSTALL_HINT: Final = "pip install 'rosbags>=0.11' (the bag extra of diffbot-kinematics)"
#: rosbag2 format version written: read by ROS 2 Iron and later.
_BAG_VERSION: Final = 8


def is_bag(path: str | os.PathLike[str]) -> bool:
    """Whether a path is read as a rosbag2 recording (a directory, ``.mcap`` or ``.db3``)."""
    p = Path(path)
    return p.is_dir() or p.suffix.lower() in BAG_FILES


def require_rosbags() -> None:
    """Raise a RecordingError saying what to install when rosbags is missing."""
    try:
        import rosbags.typesys  # noqa: F401
    except ImportError:
        raise RecordingError(
            f"reading and writing ROS 2 bags needs the rosbags library: {BAG_INSTALL_HINT}"
        ) from None


def _typestore() -> Typestore:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_HUMBLE)


def read_bag(path: str | os.PathLike[str], topic: str = DEFAULT_TOPIC) -> Recording:
    """Read the sensor_msgs/msg/JointState messages of one topic from a rosbag2 recording.

    The recording is opened with rosbags' rosbag2 reader (never as ROS 1, whatever its name
    ends with) and the messages are decoded with the ROS 2 Humble type store.

    One clock stamps the whole topic: the header stamps when every message has a non-zero one,
    otherwise the bag's receive times for all of them (mixing the two would put samples decades
    apart). :attr:`Recording.clock` says which (:data:`CLOCK_HEADER` or :data:`CLOCK_RECEIVE`).

    Args:
        path: a rosbag2 directory (sqlite3 or mcap storage), or one of its ``.db3`` or ``.mcap``
            storage files.
        topic: the topic to read; other topics are ignored.

    Returns:
        One sample per message, stamps in ns. Messages that cannot be decoded are counted in
        ``skipped``.

    Raises:
        RecordingError: rosbags is missing, the path is not a readable bag, the topic is absent
            or does not carry JointState messages.
    """
    require_rosbags()
    from rosbags.rosbag2 import Reader

    p = Path(path)
    source = str(p)
    if not p.exists():
        raise RecordingError(f"{source}: no such file or directory")
    if p.is_file() and p.stat().st_size == 0:
        raise RecordingError(f"{source}: empty file")
    typestore = _typestore()
    names_seen: list[Sequence[str]] = []
    positions_seen: list[list[float]] = []
    header_ns: list[int] = []
    receive_ns: list[int] = []
    skipped: dict[str, int] = {}
    try:
        with Reader(p) as reader:
            connections = [c for c in reader.connections if c.topic == topic]
            if not connections:
                topics = sorted({c.topic for c in reader.connections})
                raise RecordingError(
                    f"{source}: no topic {topic!r} in the bag; topics found: {listing(topics)}"
                )
            types = sorted({c.msgtype for c in connections})
            if types != [JOINT_STATE]:
                raise RecordingError(
                    f"{source}: topic {topic!r} carries {', '.join(types)}, not {JOINT_STATE}"
                )
            last_names: list[str] = []
            for _, timestamp, raw in reader.messages(connections=connections):
                try:
                    msg = cast("JointState", typestore.deserialize_cdr(raw, JOINT_STATE))
                    stamp = msg.header.stamp
                    stamp_ns = int(stamp.sec) * NS_PER_S + int(stamp.nanosec)
                    names = list(msg.name)
                    positions: list[float] = msg.position.tolist()
                except Exception:  # a corrupt message is one bad sample, not a bad bag
                    skipped[SKIP_UNREADABLE] = skipped.get(SKIP_UNREADABLE, 0) + 1
                    continue
                if names == last_names:
                    names = last_names  # one list for a run of equal names: less memory
                last_names = names
                names_seen.append(names)
                positions_seen.append(positions)
                header_ns.append(stamp_ns)
                receive_ns.append(int(timestamp))
    except DiffbotError:
        raise
    except Exception as err:
        # rosbags raises assorted errors (its own, sqlite3, struct, OSError) on files that are
        # not bags or are damaged; all of them mean the same thing to the user.
        detail = " ".join(str(err).split()) or type(err).__name__
        raise RecordingError(f"{source}: not a readable rosbag2 recording: {detail}") from None
    use_header = all(header_ns)
    stamps = header_ns if use_header else receive_ns
    samples = [
        JointSample(*sample) for sample in zip(stamps, names_seen, positions_seen, strict=True)
    ]
    clock = CLOCK_HEADER if use_header else CLOCK_RECEIVE
    return Recording(source, "rosbag2", samples, skipped, clock)


# --------------------------------------------------------------------------------------------
# Odometry over a recording


@contextlib.contextmanager
def _bag_writer(path: Path, force: bool) -> Iterator[Writer]:
    """A rosbags Writer on a temporary directory beside ``path``, renamed to it on success.

    Raises:
        OutputError: the bag cannot be written (a full disk, a quota): nothing is left behind.
    """
    import sqlite3

    check_bag_output(path, force)
    require_rosbags()
    from rosbags.rosbag2 import Writer, WriterError

    parent = path.parent if str(path.parent) else Path(".")
    staging = Path(tempfile.mkdtemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp"))
    try:
        # Written under the final name so the storage file inside is named after it.
        try:
            with Writer(staging / path.name, version=_BAG_VERSION) as writer:
                yield writer
        except (sqlite3.Error, WriterError, OSError) as err:
            raise OutputError(f"{path}: cannot write the bag ({err})", path=str(path)) from None
        replace_bag(staging / path.name, path, force)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _check_stamps(stamps_ns: Iterable[int], path: Path) -> None:
    for stamp_ns in stamps_ns:
        if not 0 <= stamp_ns < 2**31 * NS_PER_S:
            raise RecordingError(
                f"{path}: cannot stamp a bag at {seconds_text(stamp_ns)} s: ROS time must be "
                f"between 0 and 2**31 s"
            )


def write_odometry_bag(
    path: str | os.PathLike[str],
    rows: Sequence[OdometryRow],
    odom: Odometry,
    *,
    force: bool = False,
    odom_topic: str = "/odom",
    tf_topic: str = "/tf",
) -> None:
    """Write poses as a rosbag2 of nav_msgs/msg/Odometry and tf2_msgs/msg/TFMessage.

    Args:
        path: the bag directory to create.
        rows: the poses and twists, stamped (ns) from the input.
        odom: the integrator that produced them: its frame ids and covariances are used.
        force: replace an existing file or bag at ``path``.
        odom_topic: the Odometry topic.
        tf_topic: the transform topic (odom -> base_link).

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, or a stamp is outside ROS time.
    """
    import numpy as np

    p = Path(path)
    _check_stamps((row.stamp_ns for row in rows), p)
    require_rosbags()
    from rosbags.typesys.stores import ros2_humble as m

    typestore = _typestore()
    pose_cov = np.array(odom.pose_covariance, dtype=np.float64)
    twist_cov = np.array(odom.twist_covariance, dtype=np.float64)
    odom_type = m.nav_msgs__msg__Odometry.__msgtype__
    tf_type = m.tf2_msgs__msg__TFMessage.__msgtype__
    with _bag_writer(p, force) as writer:
        odom_conn = writer.add_connection(odom_topic, odom_type, typestore=typestore)
        tf_conn = writer.add_connection(tf_topic, tf_type, typestore=typestore)
        for stamp_ns, (x, y, theta), (linear, angular) in rows:
            sec, nanosec = divmod(stamp_ns, NS_PER_S)
            header = m.std_msgs__msg__Header(
                stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec),
                frame_id=odom.frame_id,
            )
            q = quaternion_from_yaw(theta)
            orientation = m.geometry_msgs__msg__Quaternion(x=q.x, y=q.y, z=q.z, w=q.w)
            message = m.nav_msgs__msg__Odometry(
                header=header,
                child_frame_id=odom.child_frame_id,
                pose=m.geometry_msgs__msg__PoseWithCovariance(
                    pose=m.geometry_msgs__msg__Pose(
                        position=m.geometry_msgs__msg__Point(x=x, y=y, z=0.0),
                        orientation=orientation,
                    ),
                    covariance=pose_cov,
                ),
                twist=m.geometry_msgs__msg__TwistWithCovariance(
                    twist=m.geometry_msgs__msg__Twist(
                        linear=m.geometry_msgs__msg__Vector3(x=float(linear), y=0.0, z=0.0),
                        angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=float(angular)),
                    ),
                    covariance=twist_cov,
                ),
            )
            transform = m.geometry_msgs__msg__TransformStamped(
                header=header,
                child_frame_id=odom.child_frame_id,
                transform=m.geometry_msgs__msg__Transform(
                    translation=m.geometry_msgs__msg__Vector3(x=x, y=y, z=0.0),
                    rotation=orientation,
                ),
            )
            tf_message = m.tf2_msgs__msg__TFMessage(transforms=[transform])
            writer.write(odom_conn, stamp_ns, typestore.serialize_cdr(message, odom_type))
            writer.write(tf_conn, stamp_ns, typestore.serialize_cdr(tf_message, tf_type))


def write_joint_states_bag(
    path: str | os.PathLike[str],
    stamps_ns: Sequence[int],
    names: Sequence[str],
    positions: ArrayLike,
    *,
    force: bool = False,
    topic: str = DEFAULT_TOPIC,
) -> None:
    """Write joint positions as a rosbag2 of sensor_msgs/msg/JointState.

    Args:
        path: the bag directory to create.
        stamps_ns: the stamps (ns), one per message.
        names: the joint names of every message.
        positions: joint angles (rad), shape (len(names), len(stamps_ns)): one row per joint.
        force: replace an existing file or bag at ``path``.
        topic: the topic.

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, or a stamp is outside ROS time.
    """
    import numpy as np

    p = Path(path)
    _check_stamps(stamps_ns, p)
    require_rosbags()
    from rosbags.typesys.stores import ros2_humble as m

    typestore = _typestore()
    columns = np.array(positions, dtype=np.float64).reshape(len(names), len(stamps_ns))
    empty = np.empty(0, dtype=np.float64)
    with _bag_writer(p, force) as writer:
        conn = writer.add_connection(topic, JOINT_STATE, typestore=typestore)
        for k, stamp_ns in enumerate(stamps_ns):
            sec, nanosec = divmod(stamp_ns, NS_PER_S)
            message = m.sensor_msgs__msg__JointState(
                header=m.std_msgs__msg__Header(
                    stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id=""
                ),
                name=list(names),
                position=np.ascontiguousarray(columns[:, k]),
                velocity=empty,
                effort=empty,
            )
            writer.write(conn, stamp_ns, typestore.serialize_cdr(message, JOINT_STATE))
