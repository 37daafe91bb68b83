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
from types import TracebackType
from typing import TYPE_CHECKING, Final, TypeVar, cast

from diffbot.errors import OutputError, RecordingError
from diffbot.io.outputs import check_bag_output, replace_bag
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
    "BAG_SUFFIXES",
    "DEFAULT_TOPIC",
    "GROUND_TRUTH_TOPIC",
    "JOINT_STATE",
    "JointStatesBagWriter",
    "OdometryBagWriter",
    "bag_suffix",
    "bag_writer",
    "check_stamps",
    "is_bag",
    "read_bag",
    "require_rosbags",
    "typestore",
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


#: The ends of the names of the files read as bags: rosbag2 storage (sqlite3, compressed or
#: not, and mcap) and ROS 1 bags.
BAG_SUFFIXES: Final = (".db3", ".db3.zstd", ".mcap", ".bag")


def bag_suffix(path: str | os.PathLike[str]) -> str | None:
    """The end of a file's name that makes it a bag (:data:`BAG_SUFFIXES`), or None."""
    name = Path(path).name.lower()
    return next((suffix for suffix in BAG_SUFFIXES if name.endswith(suffix)), None)


def is_bag(path: str | os.PathLike[str]) -> bool:
    """Whether a path is read as a bag: a directory, or a file named as
    :data:`BAG_SUFFIXES` says (``.db3``, ``.db3.zstd``, ``.mcap``, a ROS 1 ``.bag``)."""
    return Path(path).is_dir() or bag_suffix(path) is not None


def require_rosbags() -> None:
    """Raise a RecordingError saying what to install when rosbags is missing."""
    try:
        import rosbags.typesys  # noqa: F401
    except ImportError:
        raise RecordingError(
            f"reading and writing ROS 2 bags needs the rosbags library: {BAG_INSTALL_HINT}"
        ) from None


def typestore() -> Typestore:
    """The ROS 2 Humble message types, for reading and writing bags."""
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_HUMBLE)


def read_bag(
    path: str | os.PathLike[str],
    topic: str | None = None,
    field: str = "position",
    sides: tuple[Sequence[str], Sequence[str]] | None = None,
) -> Recording:
    """Read the sensor_msgs/msg/JointState messages of one topic from a bag.

    The bag is opened as :class:`diffbot.io.bag_chunks.TopicChunks` opens it (rosbag2 folders,
    lone storage files, ROS 1 bags) and the messages are decoded with the ROS 2 Humble type
    store.

    One clock stamps the whole topic: the header stamps when every message has a non-zero one,
    otherwise the bag's receive times for all of them (mixing the two would put samples decades
    apart); with ``sides``, every message that names a wheel joint of each side (another
    publisher's messages on the topic, skipped anyway, do not choose the clock).
    :attr:`Recording.clock` says which (:data:`CLOCK_HEADER` or :data:`CLOCK_RECEIVE`).

    Args:
        path: a rosbag2 directory (sqlite3 or mcap storage), one of its storage files, or a ROS 1
            ``.bag``.
        topic: the topic to read (default: ``/joint_states``, or else the only JointState
            topic); other topics are ignored.
        field: ``"position"``, or ``"velocity"`` for samples holding the joints' velocities
            (rad/s) in place of their positions.
        sides: the left and the right wheel joints, when the clock is chosen by the messages
            that hold a wheel of each side.

    Returns:
        One sample per message, stamps in ns. Messages that cannot be decoded are counted in
        ``skipped``.

    Raises:
        RecordingError: rosbags is missing, the path is not a readable bag, the topic is absent
            or does not carry JointState messages.
    """
    from diffbot.io.bag_chunks import TopicChunks

    require_rosbags()
    store = typestore()
    names_seen: list[Sequence[str]] = []
    positions_seen: list[list[float]] = []
    header_ns: list[int] = []
    receive_ns: list[int] = []
    skipped: dict[str, int] = {}
    with contextlib.closing(TopicChunks(path, topic)) as chunks:
        source = chunks.source
        if chunks.msgtype != JOINT_STATE:
            raise RecordingError(
                f"{source}: topic {chunks.topic!r} carries {chunks.msgtype}, not {JOINT_STATE}"
            )
        last_names: list[str] = []
        for chunk in chunks.chunks(receive_times=True):
            assert chunk.receive_ns is not None  # asked for
            for timestamp, raw in zip(chunk.receive_ns.tolist(), chunk.blobs, strict=True):
                try:
                    msg = cast("JointState", store.deserialize_cdr(raw, JOINT_STATE))
                    stamp = msg.header.stamp
                    stamp_ns = int(stamp.sec) * NS_PER_S + int(stamp.nanosec)
                    names = list(msg.name)
                    values = msg.velocity if field == "velocity" else msg.position
                    positions: list[float] = values.tolist()
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
        chosen = chunks.topic
        notes = chunks.notes()
    if sides is None:
        use_header = all(header_ns)
    else:
        left, right = set(sides[0]), set(sides[1])
        sided: dict[int, bool] = {}  # by list: a run of equal names shares one
        for stamp_ns, named in zip(header_ns, names_seen, strict=True):
            key = id(named)
            if key not in sided:
                sided[key] = not left.isdisjoint(named) and not right.isdisjoint(named)
            if sided[key] and not stamp_ns:
                use_header = False
                break
        else:
            use_header = True
    stamps = header_ns if use_header else receive_ns
    samples = [
        JointSample(*sample) for sample in zip(stamps, names_seen, positions_seen, strict=True)
    ]
    clock = CLOCK_HEADER if use_header else CLOCK_RECEIVE
    return Recording(source, "rosbag2", samples, skipped, clock, topic=chosen, notes=notes)


# --------------------------------------------------------------------------------------------
# Odometry over a recording


@contextlib.contextmanager
def bag_writer(path: Path, force: bool) -> Iterator[Writer]:
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


def check_stamps(stamps_ns: Iterable[int], path: Path) -> None:
    """Refuse stamps outside what a bag can hold (0 to 2**31 s)."""
    for stamp_ns in stamps_ns:
        if not 0 <= stamp_ns < 2**31 * NS_PER_S:
            raise RecordingError(
                f"{path}: cannot stamp a bag at {seconds_text(stamp_ns)} s: ROS time must be "
                f"between 0 and 2**31 s"
            )


_Stream = TypeVar("_Stream", bound="_BagStream")


class _BagStream:
    """A bag written message by message as the data comes, whole or not at all: a temporary
    directory beside ``path``, renamed to it when the ``with`` block ends without an error."""

    def __init__(self, path: str | os.PathLike[str], *, force: bool) -> None:
        self.path = Path(path)
        self.force = force
        check_bag_output(self.path, force)
        require_rosbags()
        self.typestore = typestore()
        self._stack: contextlib.ExitStack | None = None

    def _connect(self, writer: Writer) -> None:
        raise NotImplementedError

    def _open(self) -> None:
        self._stack = contextlib.ExitStack()
        self.writer = self._stack.enter_context(bag_writer(self.path, self.force))
        self._connect(self.writer)

    def __enter__(self: _Stream) -> _Stream:
        self._open()
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        stack, self._stack = self._stack, None
        if stack is not None:
            stack.__exit__(exc_type, exc, traceback)

    def restart(self) -> None:
        """Drop every message written so far and start an empty bag."""
        stack, self._stack = self._stack, None
        if stack is not None:
            stack.__exit__(_DroppedError, _DroppedError(), None)
        self._open()

    def _check_stamps(self, stamps_ns: Iterable[int]) -> None:
        check_stamps(stamps_ns, self.path)


class _DroppedError(Exception):
    """Thrown into a bag being written to throw it away."""


class OdometryBagWriter(_BagStream):
    """Poses written as they come to a rosbag2 of nav_msgs/msg/Odometry and
    tf2_msgs/msg/TFMessage (use it as a context manager).

    Args:
        path: the bag directory to create.
        odom: the integrator whose frame ids and covariances the messages carry.
        force: replace an existing file or bag at ``path``.
        odom_topic: the Odometry topic.
        tf_topic: the transform topic (odom -> base_link).

    Raises:
        OutputExistsError: ``path`` exists and ``force`` is false, or it is a directory that is
            not a bag.
        RecordingError: rosbags is missing, or (when writing) a stamp is outside ROS time.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        odom: Odometry,
        *,
        force: bool = False,
        odom_topic: str = "/odom",
        tf_topic: str = "/tf",
    ) -> None:
        import numpy as np

        super().__init__(path, force=force)
        self.frame_id = odom.frame_id
        self.child_frame_id = odom.child_frame_id
        self.pose_cov = np.array(odom.pose_covariance, dtype=np.float64)
        self.twist_cov = np.array(odom.twist_covariance, dtype=np.float64)
        self.topics = (odom_topic, tf_topic)
        self.count = 0

    def _connect(self, writer: Writer) -> None:
        from rosbags.typesys.stores import ros2_humble as m

        self.m = m
        self.odom_type = m.nav_msgs__msg__Odometry.__msgtype__
        self.tf_type = m.tf2_msgs__msg__TFMessage.__msgtype__
        odom_topic, tf_topic = self.topics
        self.odom_conn = writer.add_connection(odom_topic, self.odom_type, typestore=self.typestore)
        self.tf_conn = writer.add_connection(tf_topic, self.tf_type, typestore=self.typestore)
        self.count = 0

    def write(
        self,
        stamps_ns: Sequence[int],
        x: Iterable[float],
        y: Iterable[float],
        theta: Iterable[float],
        linear: Iterable[float],
        angular: Iterable[float],
    ) -> None:
        """Append one message of each topic per pose (theta in (-pi, pi])."""
        self._check_stamps(stamps_ns)
        m, serialize = self.m, self.typestore.serialize_cdr
        for stamp_ns, x_, y_, theta_, linear_, angular_ in zip(
            stamps_ns, x, y, theta, linear, angular, strict=True
        ):
            sec, nanosec = divmod(stamp_ns, NS_PER_S)
            header = m.std_msgs__msg__Header(
                stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec),
                frame_id=self.frame_id,
            )
            q = quaternion_from_yaw(theta_)
            orientation = m.geometry_msgs__msg__Quaternion(x=q.x, y=q.y, z=q.z, w=q.w)
            message = m.nav_msgs__msg__Odometry(
                header=header,
                child_frame_id=self.child_frame_id,
                pose=m.geometry_msgs__msg__PoseWithCovariance(
                    pose=m.geometry_msgs__msg__Pose(
                        position=m.geometry_msgs__msg__Point(x=x_, y=y_, z=0.0),
                        orientation=orientation,
                    ),
                    covariance=self.pose_cov,
                ),
                twist=m.geometry_msgs__msg__TwistWithCovariance(
                    twist=m.geometry_msgs__msg__Twist(
                        linear=m.geometry_msgs__msg__Vector3(x=float(linear_), y=0.0, z=0.0),
                        angular=m.geometry_msgs__msg__Vector3(x=0.0, y=0.0, z=float(angular_)),
                    ),
                    covariance=self.twist_cov,
                ),
            )
            transform = m.geometry_msgs__msg__TransformStamped(
                header=header,
                child_frame_id=self.child_frame_id,
                transform=m.geometry_msgs__msg__Transform(
                    translation=m.geometry_msgs__msg__Vector3(x=x_, y=y_, z=0.0),
                    rotation=orientation,
                ),
            )
            tf_message = m.tf2_msgs__msg__TFMessage(transforms=[transform])
            stamp = int(stamp_ns)
            self.writer.write(self.odom_conn, stamp, serialize(message, self.odom_type))
            self.writer.write(self.tf_conn, stamp, serialize(tf_message, self.tf_type))
            self.count += 1


def write_odometry_bag(
    path: str | os.PathLike[str],
    rows: Sequence[OdometryRow],
    odom: Odometry,
    *,
    force: bool = False,
    odom_topic: str = "/odom",
    tf_topic: str = "/tf",
) -> None:
    """Write poses whole as a rosbag2 of nav_msgs/msg/Odometry and tf2_msgs/msg/TFMessage.

    ``rows`` are the poses and twists, stamped (ns) from the input; the other arguments and the
    errors are those of :class:`OdometryBagWriter` (every stamp is checked before writing).
    """
    records = list(rows)
    check_stamps((row.stamp_ns for row in records), Path(path))
    with OdometryBagWriter(
        path, odom, force=force, odom_topic=odom_topic, tf_topic=tf_topic
    ) as bag:
        bag.write(
            [row.stamp_ns for row in records],
            (float(row.pose.x) for row in records),
            (float(row.pose.y) for row in records),
            (float(row.pose.theta) for row in records),
            (float(row.twist.linear) for row in records),
            (float(row.twist.angular) for row in records),
        )


#: The topic of the ground-truth poses (geometry_msgs/PoseStamped) a simulation writes.
GROUND_TRUTH_TOPIC: Final = "/ground_truth"


class JointStatesBagWriter(_BagStream):
    """Joint states written as they come to a rosbag2 of sensor_msgs/msg/JointState (use it
    as a context manager).

    Args:
        path: the bag directory to create.
        names: the joint names of every message.
        force: replace an existing file or bag at ``path``.
        topic: the topic.

    Raises:
        OutputExistsError, RecordingError: as :class:`OdometryBagWriter`.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        names: Sequence[str],
        *,
        force: bool = False,
        topic: str = DEFAULT_TOPIC,
        poses: bool = False,
    ) -> None:
        super().__init__(path, force=force)
        self.names = list(names)
        self.topic = topic
        self.poses = poses

    def _connect(self, writer: Writer) -> None:
        from rosbags.typesys.stores import ros2_humble as m

        self.m = m
        self.conn = writer.add_connection(self.topic, JOINT_STATE, typestore=self.typestore)
        self.pose_type = m.geometry_msgs__msg__PoseStamped.__msgtype__
        if self.poses:
            self.pose_conn = writer.add_connection(
                GROUND_TRUTH_TOPIC, self.pose_type, typestore=self.typestore
            )

    def write_poses(self, stamps_ns: Sequence[int], poses: ArrayLike) -> None:
        """Append ground-truth poses (rows x, y in m and theta in rad, one column per stamp) as
        geometry_msgs/msg/PoseStamped (frame ``odom``) on :data:`GROUND_TRUTH_TOPIC`; the
        writer must have been made with ``poses=True``."""
        import numpy as np

        m = self.m
        rows = np.asarray(poses, dtype=np.float64).reshape(3, len(stamps_ns)).T.tolist()
        for stamp_ns, (x, y, theta) in zip(stamps_ns, rows, strict=True):
            sec, nanosec = divmod(stamp_ns, NS_PER_S)
            q = quaternion_from_yaw(theta)
            message = m.geometry_msgs__msg__PoseStamped(
                header=m.std_msgs__msg__Header(
                    stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec),
                    frame_id="odom",
                ),
                pose=m.geometry_msgs__msg__Pose(
                    position=m.geometry_msgs__msg__Point(x=x, y=y, z=0.0),
                    orientation=m.geometry_msgs__msg__Quaternion(x=q.x, y=q.y, z=q.z, w=q.w),
                ),
            )
            self.writer.write(
                self.pose_conn, stamp_ns, self.typestore.serialize_cdr(message, self.pose_type)
            )

    def write(self, stamps_ns: Sequence[int], positions: ArrayLike) -> None:
        """Append one message per stamp.

        Args:
            stamps_ns: the stamps (ns), one per message.
            positions: joint angles (rad), shape (len(names), len(stamps_ns)).
        """
        import numpy as np

        self._check_stamps(stamps_ns)
        m = self.m
        columns = np.array(positions, dtype=np.float64).reshape(len(self.names), len(stamps_ns))
        empty = np.empty(0, dtype=np.float64)
        serialize = self.typestore.serialize_cdr
        for k, stamp_ns in enumerate(stamps_ns):
            sec, nanosec = divmod(stamp_ns, NS_PER_S)
            message = m.sensor_msgs__msg__JointState(
                header=m.std_msgs__msg__Header(
                    stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id=""
                ),
                name=self.names,
                position=np.ascontiguousarray(columns[:, k]),
                velocity=empty,
                effort=empty,
            )
            self.writer.write(self.conn, stamp_ns, serialize(message, JOINT_STATE))


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
    check_stamps(stamps_ns, Path(path))
    with JointStatesBagWriter(path, names, force=force, topic=topic) as bag:
        bag.write(stamps_ns, positions)
