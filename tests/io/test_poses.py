"""Ground-truth pose tracks from CSV files and from the pose topics of bags."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from bags import TYPESTORE, lone_storage, write_bag
from rosbags.rosbag2 import Writer
from rosbags.typesys.stores import ros2_humble as m

from diffbot.errors import RecordingError
from diffbot.io.csv_lines import ROW_CHARS
from diffbot.io.poses import read_pose_track, yaw_from_quaternion
from diffbot.ros.messages import quaternion_from_yaw

POSE_STAMPED = "geometry_msgs/msg/PoseStamped"
ODOMETRY = "nav_msgs/msg/Odometry"


def header(stamp_ns: int) -> m.std_msgs__msg__Header:
    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    return m.std_msgs__msg__Header(
        stamp=m.builtin_interfaces__msg__Time(sec=sec, nanosec=nanosec), frame_id="map"
    )


def pose(x: float, y: float, theta: float) -> m.geometry_msgs__msg__Pose:
    q = quaternion_from_yaw(theta)
    return m.geometry_msgs__msg__Pose(
        position=m.geometry_msgs__msg__Point(x=x, y=y, z=0.3),
        orientation=m.geometry_msgs__msg__Quaternion(x=q.x, y=q.y, z=q.z, w=q.w),
    )


def pose_bag(path: Path, topics: dict[str, str], stamps_ns: list[int]) -> Path:
    """A bag with the poses (k, -k, 3k rad) at the stamps on each topic (PoseStamped or
    Odometry), received a second after their header stamps."""
    with Writer(path, version=9) as writer:
        for topic, msgtype in topics.items():
            conn = writer.add_connection(topic, msgtype, typestore=TYPESTORE)
            for k, stamp_ns in enumerate(stamps_ns):
                msg: object
                if msgtype == POSE_STAMPED:
                    msg = m.geometry_msgs__msg__PoseStamped(header(stamp_ns), pose(k, -k, 3 * k))
                else:
                    cov = np.zeros(36)
                    msg = m.nav_msgs__msg__Odometry(
                        header(stamp_ns),
                        "base_link",
                        m.geometry_msgs__msg__PoseWithCovariance(pose(k, -k, 3 * k), cov),
                        m.geometry_msgs__msg__TwistWithCovariance(
                            m.geometry_msgs__msg__Twist(
                                m.geometry_msgs__msg__Vector3(0, 0, 0),
                                m.geometry_msgs__msg__Vector3(0, 0, 0),
                            ),
                            cov,
                        ),
                    )
                raw = TYPESTORE.serialize_cdr(msg, msgtype)
                writer.write(conn, stamp_ns + 1_000_000_000, raw)
    return path


@pytest.mark.parametrize("theta", [0.0, 1.0, -2.5, math.pi, 3.0])
def test_yaw_from_quaternion_inverts_quaternion_from_yaw(theta: float) -> None:
    q = quaternion_from_yaw(theta)
    assert abs(math.remainder(yaw_from_quaternion(q.x, q.y, q.z, q.w) - theta, math.tau)) < 1e-12
    assert yaw_from_quaternion(2 * q.x, 2 * q.y, 2 * q.z, 2 * q.w) == pytest.approx(
        yaw_from_quaternion(q.x, q.y, q.z, q.w), abs=1e-12
    )


@pytest.mark.parametrize(
    "q",
    [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, math.inf, 1.0), (math.nan, 0.0, 0.0, 1.0), (0, 0, 1e200, 1)],
)
def test_a_quaternion_that_is_no_rotation_gives_no_heading(q: tuple[float, ...]) -> None:
    assert math.isnan(yaw_from_quaternion(*q))


def test_a_bag_pose_whose_orientation_was_never_set_is_refused(tmp_path: Path) -> None:
    # The zero quaternion of an orientation never set: atan2(0, 0) made it heading 0.
    with Writer(tmp_path / "bag", version=9) as writer:
        conn = writer.add_connection("/mocap", POSE_STAMPED, typestore=TYPESTORE)
        for k in range(3):
            msg = m.geometry_msgs__msg__PoseStamped(
                header((k + 1) * 10**9),
                m.geometry_msgs__msg__Pose(
                    position=m.geometry_msgs__msg__Point(x=k, y=0.0, z=0.0),
                    orientation=m.geometry_msgs__msg__Quaternion(x=0.0, y=0.0, z=0.0, w=0.0),
                ),
            )
            writer.write(conn, (k + 1) * 10**9, TYPESTORE.serialize_cdr(msg, POSE_STAMPED))
    with pytest.raises(RecordingError, match=r"/mocap message 1: theta must be a finite number"):
        read_pose_track(tmp_path / "bag")


def test_a_csv_track_reads_time_x_y_theta_and_skips_rows_without_a_pose(tmp_path: Path) -> None:
    path = tmp_path / "truth.csv"
    path.write_text("stamp,X,y,yaw,other\n1.5,1,2,0.5,a\n2,,,,b\n2.25,3,4,-1,c\n", "utf-8")
    track = read_pose_track(path)
    assert track.stamps_ns.tolist() == [1_500_000_000, 2_250_000_000]
    assert track.x.tolist() == [1.0, 3.0]
    assert track.y.tolist() == [2.0, 4.0]
    assert track.theta.tolist() == [0.5, -1.0]


@pytest.mark.parametrize("cell", ["\u0663", "1_0", "\uff11.5"])
def test_a_csv_track_cell_in_other_digits_is_no_number(tmp_path: Path, cell: str) -> None:
    path = tmp_path / "truth.csv"
    path.write_text(f"time,x,y,theta\n0,0,0,0\n1,{cell},0,0\n", "utf-8")
    with pytest.raises(RecordingError, match="line 3: not a finite time and pose"):
        read_pose_track(path)


def test_a_csv_track_without_theta_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "joints.csv"
    path.write_text("time,left,right\n0,0,0\n", "utf-8")
    with pytest.raises(RecordingError, match="no ground truth: needs x, y, theta"):
        read_pose_track(path)


def test_a_csv_track_with_a_bad_cell_names_its_line(tmp_path: Path) -> None:
    path = tmp_path / "truth.csv"
    path.write_text("time,x,y,theta\n0,0,0,0\n1,nan,0,0\n", "utf-8")
    with pytest.raises(RecordingError, match="line 3: not a finite time and pose"):
        read_pose_track(path)


def test_a_csv_track_with_a_row_longer_than_the_bound_names_its_line(tmp_path: Path) -> None:
    path = tmp_path / "truth.csv"
    path.write_text("time,x,y,theta\n0,0,0,0\n1,1,0,0," + "12," * ROW_CHARS + "\n", "utf-8")
    with pytest.raises(RecordingError, match=r"truth.csv: line 3: a row longer than 4194304"):
        read_pose_track(path)


def test_a_csv_track_of_no_rows_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "truth.csv"
    path.write_text("time,x,y,theta\n", "utf-8")
    with pytest.raises(RecordingError, match="no ground-truth pose"):
        read_pose_track(path)


@pytest.mark.parametrize("msgtype", [POSE_STAMPED, ODOMETRY])
def test_a_bag_track_is_found_by_its_type_and_stamped_by_its_headers(
    tmp_path: Path, msgtype: str
) -> None:
    path = pose_bag(tmp_path / "bag", {"/mocap": msgtype}, [10**9, 2 * 10**9, 3 * 10**9])
    track = read_pose_track(path)
    assert track.source.endswith("bag /mocap")
    assert track.stamps_ns.tolist() == [10**9, 2 * 10**9, 3 * 10**9]
    assert track.x.tolist() == [0.0, 1.0, 2.0]
    assert track.y.tolist() == [0.0, -1.0, -2.0]
    assert track.theta == pytest.approx([0.0, 3.0, 6.0 - 2 * math.pi], abs=1e-12)


def test_a_bag_track_without_header_stamps_uses_the_receive_times(tmp_path: Path) -> None:
    path = pose_bag(tmp_path / "bag", {"/mocap": POSE_STAMPED}, [0, 10**9])
    assert read_pose_track(path).stamps_ns.tolist() == [10**9, 2 * 10**9]


def test_a_bag_with_several_pose_topics_needs_one_named(tmp_path: Path) -> None:
    path = pose_bag(tmp_path / "bag", {"/a": POSE_STAMPED, "/b": ODOMETRY}, [10**9, 2 * 10**9])
    with pytest.raises(RecordingError, match=r"several topics of .*'/a', '/b'.*name the ground"):
        read_pose_track(path)
    assert read_pose_track(path, "/b").x.tolist() == [0.0, 1.0]


def test_a_bag_without_the_pose_topic_is_refused(tmp_path: Path) -> None:
    path = write_bag(tmp_path / "bag", [(10**9, 10**9, ["a"], [0.0])])
    with pytest.raises(RecordingError, match=r"no topic of .*Odometry: no ground truth"):
        read_pose_track(path)
    with pytest.raises(RecordingError, match=r"no topic '/joint_states' of .*found: .*JointState"):
        read_pose_track(path, "/joint_states")


def ros1_odometry_bag(path: Path, stamps_ns: list[int]) -> Path:
    """A ROS 1 bag with nav_msgs/Odometry poses (k, -k, 3k rad) on ``/odom`` at the stamps,
    written by rosbags' rosbag1 writer with the ROS 1 Noetic types."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    t = store.types
    with Writer1(path) as writer:
        conn = writer.add_connection("/odom", ODOMETRY, typestore=store)
        for k, stamp_ns in enumerate(stamps_ns):
            sec, nanosec = divmod(stamp_ns, 1_000_000_000)
            q = quaternion_from_yaw(3 * k)
            cov = np.zeros(36)
            zero = t["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
            msg = t[ODOMETRY](
                header=t["std_msgs/msg/Header"](
                    seq=k,
                    stamp=t["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
                    frame_id="odom",
                ),
                child_frame_id="base_link",
                pose=t["geometry_msgs/msg/PoseWithCovariance"](
                    pose=t["geometry_msgs/msg/Pose"](
                        position=t["geometry_msgs/msg/Point"](x=float(k), y=float(-k), z=0.0),
                        orientation=t["geometry_msgs/msg/Quaternion"](x=q.x, y=q.y, z=q.z, w=q.w),
                    ),
                    covariance=cov,
                ),
                twist=t["geometry_msgs/msg/TwistWithCovariance"](
                    twist=t["geometry_msgs/msg/Twist"](linear=zero, angular=zero), covariance=cov
                ),
            )
            writer.write(conn, stamp_ns + 10**9, bytes(store.serialize_ros1(msg, ODOMETRY)))
    return path


def test_a_ros1_bag_track_is_read_like_a_rosbag2_one(tmp_path: Path) -> None:
    stamps = [10**9, 2 * 10**9, 3 * 10**9]
    track = read_pose_track(ros1_odometry_bag(tmp_path / "run.bag", stamps))
    assert track.source.endswith("run.bag /odom")
    assert track.stamps_ns.tolist() == stamps
    assert track.x.tolist() == [0.0, 1.0, 2.0]
    assert track.y.tolist() == [0.0, -1.0, -2.0]
    assert track.theta == pytest.approx([0.0, 3.0, 6.0 - 2 * math.pi], abs=1e-12)


def test_a_lone_db3_and_a_folder_without_metadata_give_the_bag_track(tmp_path: Path) -> None:
    bag = pose_bag(tmp_path / "bag", {"/mocap": POSE_STAMPED}, [10**9, 2 * 10**9])
    lone = lone_storage(bag, tmp_path / "lone.db3")
    (bag / "metadata.yaml").unlink()
    for path in (lone, bag):
        track = read_pose_track(path)
        assert track.stamps_ns.tolist() == [10**9, 2 * 10**9]
        assert track.x.tolist() == [0.0, 1.0]


def test_a_missing_track_is_refused(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match="no such file or directory"):
        read_pose_track(tmp_path / "none.csv")


@pytest.mark.parametrize(
    ("row", "fragment"),
    [
        ("1e10,0,0,0", "line 3: time 1e10 s lies outside the int64 nanosecond stamps"),
        ("-1e10,0,0,0", "line 3: time -1e10 s"),
        ("1,1e306,0,0", "line 3: x must be a finite number >= -1e+09 and <= 1e+09 m"),
        ("1,0,-2e9,0", "line 3: y must be"),
        ("1,0,0,1e13", "line 3: theta must be a finite number >= -1e+12 and <= 1e+12 rad"),
    ],
)
def test_a_truth_beyond_any_clock_or_drive_is_refused_naming_the_line(
    tmp_path: Path, row: str, fragment: str
) -> None:
    path = tmp_path / "truth.csv"
    path.write_text(f"time,x,y,theta\n0,0,0,0\n{row}\n", encoding="utf-8")
    with pytest.raises(RecordingError, match=re.escape(f"{path}: {fragment}")):
        read_pose_track(path)


def test_a_long_csv_track_is_kept_in_typed_arrays(tmp_path: Path) -> None:
    path = tmp_path / "truth.csv"
    rows = [f"{k / 100!r},{k * 0.001!r},{-k * 0.002!r},{k * 1e-4!r}" for k in range(5000)]
    path.write_text("time,x,y,theta\n" + "\n".join(rows) + "\n", encoding="utf-8")
    track = read_pose_track(path)
    assert track.stamps_ns.dtype == np.int64
    assert track.stamps_ns[-1] == 49_990_000_000
    assert track.x[-1] == 4999 * 0.001
    assert track.y[1234] == -1234 * 0.002
    assert track.theta[4321] == 4321 * 1e-4


def test_a_csv_track_takes_its_time_from_the_first_time_name_it_has(tmp_path: Path) -> None:
    # A track has no option naming its time: time before stamp before t before __time, as
    # before the recording reader refused such pairs (a file may be both, with --time-column).
    path = tmp_path / "truth.csv"
    path.write_text("stamp,Time,x,y,theta\n7,1,0,0,0\n8,2,1,0,0\n", "utf-8")
    assert read_pose_track(path).stamps_ns.tolist() == [10**9, 2 * 10**9]
    path.write_text("t,stamp,x,y,theta\n7,1,0,0,0\n8,2,1,0,0\n", "utf-8")
    assert read_pose_track(path).stamps_ns.tolist() == [10**9, 2 * 10**9]
