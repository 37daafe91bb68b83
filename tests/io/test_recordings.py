"""Recordings: CSV and rosbag2 input, odometry over them, CSV and bag output."""

from __future__ import annotations

import io
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from bags import velocity_bag, write_bag
from peak_memory import peak_bytes
from robots import BOT
from rosbags.highlevel import AnyReader
from wheel_motion import TRAJECTORY_A, assert_pose_close, trajectory_a_velocities, wheel_samples

import diffbot
from diffbot.io.bag import read_bag, write_joint_states_bag, write_odometry_bag
from diffbot.io.csv_chunks import CHUNK_BYTES, read_csv
from diffbot.io.csvfile import format_joint_states_csv, format_odometry_csv
from diffbot.kinematics import Pose
from diffbot.odometry import SKIP_MISSING_JOINT, SKIP_NOT_FINITE, Odometry
from diffbot.recordings import read_recording
from diffbot.replay import OdometryRow, OdometryRun, recording_odometry, run_odometry
from diffbot.samples import (
    CLOCK_HEADER,
    CLOCK_RECEIVE,
    SKIP_MISSING_STAMP,
    SKIP_STAMP_RANGE,
    SKIP_UNREADABLE,
    Recording,
    seconds_text,
)

LEFT, RIGHT = BOT.left_joint, BOT.right_joint
EPOCH = 1_700_000_000_000_000_000  # ns: stamps of a recording made in 2023


def trajectory_a_csv(path: Path, left_column: str = LEFT, right_column: str = RIGHT) -> Path:
    stamps, lefts, rights = wheel_samples(BOT, TRAJECTORY_A)
    lines = [f"time,{left_column},battery,{right_column}"]
    lines += [
        f"{stamp!r},{left!r},12.1,{right!r}"
        for stamp, left, right in zip(stamps, lefts, rights, strict=True)
    ]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def trajectory_a_messages() -> list[tuple[int, int, list[str], list[float]]]:
    stamps, lefts, rights = wheel_samples(BOT, TRAJECTORY_A)
    return [
        (
            EPOCH + round(stamp * 1e9),
            EPOCH + round(stamp * 1e9) + 1000,
            [RIGHT, "caster", LEFT],
            [right, 0.5, left],
        )
        for stamp, left, right in zip(stamps, lefts, rights, strict=True)
    ]


# --------------------------------------------------------------------------------------------
# CSV input


def test_csv_of_trajectory_a_gives_the_plans_final_pose(tmp_path: Path) -> None:
    recording = read_recording(trajectory_a_csv(tmp_path / "a.csv"), BOT)
    assert recording.kind == "csv"
    assert len(recording.samples) == 401
    run = run_odometry(recording, Odometry(BOT))
    assert_pose_close(run.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)
    assert run.samples == 401
    assert run.skipped == {}
    assert run.duration == 40.0
    assert run.distance == pytest.approx(2 + 0.5 * math.pi, rel=1e-12)


@pytest.mark.parametrize("time_column", ["time", "stamp", "t", "__time", " Time "])
def test_csv_time_column_may_have_any_of_the_usual_names(tmp_path: Path, time_column: str) -> None:
    path = tmp_path / "a.csv"
    path.write_text(f"{time_column},{LEFT},{RIGHT}\n0,0,0\n1.5,1,1\n", encoding="utf-8")
    samples = read_csv(path, LEFT, RIGHT).samples
    assert [s.stamp_ns for s in samples] == [0, 1_500_000_000]


def test_csv_columns_exported_from_joint_states_are_recognised(tmp_path: Path) -> None:
    path = trajectory_a_csv(
        tmp_path / "a.csv",
        f"/joint_states/{LEFT}/position",
        f"/joint_states/{RIGHT}/position",
    )
    run = run_odometry(read_csv(path, LEFT, RIGHT), Odometry(BOT))
    assert_pose_close(run.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)


def test_csv_velocity_columns_of_the_wheels_are_not_taken_for_positions(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text(
        f"__time,/js/{LEFT}/velocity,/js/{LEFT}/position,/js/{RIGHT}/position\n0,9,0,0\n1,9,2,2\n",
        encoding="utf-8",
    )
    samples = read_csv(path, LEFT, RIGHT).samples
    assert list(samples[1].positions) == [2.0, 2.0]


def test_csv_stamps_are_read_exactly_to_the_nanosecond(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text(
        f"\ufefftime,{LEFT},{RIGHT}\n1700000000.123456789,0,0\n1.7e9,1,1\n-0.5,1,1\n",
        encoding="utf-8",
    )
    stamps = [s.stamp_ns for s in read_csv(path, LEFT, RIGHT).samples]
    assert stamps == [1_700_000_000_123_456_789, 1_700_000_000_000_000_000, -500_000_000]


@pytest.mark.parametrize(
    ("cell", "stamp_ns"),
    [
        ("0.0000000005", 0),  # half a nanosecond: ties go to even
        ("0.0000000015", 2),
        ("0.00000000150000000000000000000000000000000000000000000000000000000000001", 2),
        ("0.00000000049999999999999999999999999999999999999999999999999999999999999", 0),
        ("  12.5  ", 12_500_000_000),
        ("12.", 12_000_000_000),
        (".5", 500_000_000),
        ("+3E-9", 3),
        ("9223372036.854775807", 2**63 - 1),
    ],
)
def test_csv_stamps_are_rounded_to_the_nearest_nanosecond(
    tmp_path: Path, cell: str, stamp_ns: int
) -> None:
    path = tmp_path / "a.csv"
    path.write_text(f"time,{LEFT},{RIGHT}\n{cell},0,0\n", encoding="utf-8")
    assert [s.stamp_ns for s in read_csv(path, LEFT, RIGHT).samples] == [stamp_ns]


def test_csv_times_beyond_ros_time_and_digit_groups_are_skipped_not_fatal(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text(
        f"time,{LEFT},{RIGHT}\n"
        "0,0,0\n"
        "1e400,1,1\n"  # finite as a decimal, infinite as a float
        "1e100000000,1,1\n"
        "-1e400,1,1\n"
        "9223372036.854775808,1,1\n"  # one nanosecond past int64
        f"{'9' * 5000},1,1\n"  # more digits than int() converts
        "1_0,1,1\n"  # Python's digit grouping is no CSV number
        "2,1_0,1\n"
        "3,1,1_0.5\n"
        "4,4,4\n",
        encoding="utf-8",
    )
    recording = read_csv(path, LEFT, RIGHT)
    assert recording.skipped == {SKIP_STAMP_RANGE: 5, SKIP_UNREADABLE: 3}
    assert [s.stamp_ns for s in recording.samples] == [0, 4_000_000_000]
    run = run_odometry(recording, Odometry(BOT))
    assert run.final_pose.x == pytest.approx(4 * BOT.wheel_radius, rel=1e-12)


def test_csv_can_be_read_from_a_text_stream() -> None:
    stream = io.StringIO(f"time,{LEFT},{RIGHT}\n0,0,0\n1,1,1\n")
    recording = read_csv(stream, LEFT, RIGHT, source="-")
    assert recording.source == "-"
    assert [s.stamp_ns for s in recording.samples] == [0, 1_000_000_000]
    with pytest.raises(diffbot.RecordingError, match=r"^-: empty file$"):
        read_csv(io.StringIO(""), LEFT, RIGHT, source="-")


def test_csv_rows_are_kept_in_compact_columns(tmp_path: Path) -> None:
    rows = 50_000
    path = tmp_path / "big.csv"
    lines = [f"time,caster,{LEFT},{RIGHT},battery"]
    lines += [f"{k / 50!r},0.0,{k * 1e-3!r},{k * 2e-3!r},12.5" for k in range(rows)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")

    def read_and_run() -> tuple[Recording, OdometryRun]:
        recording = read_csv(path, LEFT, RIGHT)
        return recording, run_odometry(recording, Odometry(BOT))

    (recording, run), peak = peak_bytes(read_and_run)
    assert run.samples == rows
    # 25 bytes a sample and 48 a pose as columns (a list of records per row took over 600), plus
    # one chunk of text being parsed (CHUNK_BYTES characters and loadtxt's work space).
    assert (peak - 8 * CHUNK_BYTES) / rows < 150
    assert run.rows[-1] == OdometryRow(
        round((rows - 1) / 50 * 1e9), run.final_pose, run.rows[-1].twist
    )
    assert list(run.rows)[-1] == run.rows[-1]
    assert recording.samples[-1] == list(recording.samples)[-1]
    assert recording.samples[-2:] == list(recording.samples)[-2:]


def test_empty_csv_cells_are_missing_joints_and_bad_cells_are_skipped(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text(
        f"time,{LEFT},{RIGHT}\n"
        "0,0,0\n"
        "1,1,\n"  # right missing
        ",2,2\n"  # no stamp
        "nan,2,2\n"  # stamp not finite
        "2,abc,2\n"  # not a number
        "\n"  # blank line: not a sample
        "3,inf,3\n"  # reaches the odometry, which skips it
        "4,4\n"  # short row: right missing
        "5,5,5\n",
        encoding="utf-8",
    )
    recording = read_csv(path, LEFT, RIGHT)
    assert recording.skipped == {SKIP_MISSING_STAMP: 1, SKIP_NOT_FINITE: 1, SKIP_UNREADABLE: 1}
    assert [list(s.names) for s in recording.samples] == [
        [LEFT, RIGHT],
        [LEFT],
        [LEFT, RIGHT],
        [LEFT],
        [LEFT, RIGHT],
    ]
    run = run_odometry(recording, Odometry(BOT))
    assert run.samples == 2
    assert run.skipped == {
        SKIP_MISSING_STAMP: 1,
        SKIP_NOT_FINITE: 2,
        SKIP_UNREADABLE: 1,
        SKIP_MISSING_JOINT: 2,
    }
    assert_pose_close(run.final_pose, Pose(5 * BOT.wheel_radius, 0.0, 0.0), 1e-15)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", r"a\.csv: empty file"),
        ("  \n\n", "empty file"),
        (f"when,{LEFT},{RIGHT}\n0,0,0\n", rf"no time column .*columns found: 'when', '{LEFT}'"),
        (f"time,{LEFT},wheel\n0,0,0\n", rf"no column for the right wheel joint '{RIGHT}'.*'wheel'"),
        (f"time,{RIGHT}\n0,0\n", rf"left wheel joint '{LEFT}'.*columns found: 'time'"),
        (f"time,{LEFT},a/{LEFT}/position,{RIGHT}\n", "several columns for the left wheel"),
        (f'time,{LEFT},{RIGHT}\n0,"{"9" * 200_000}",0\n', "malformed CSV: field larger than"),
    ],
)
def test_unusable_csv_files_are_refused_naming_what_was_found(
    tmp_path: Path, text: str, match: str
) -> None:
    path = tmp_path / "a.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(diffbot.RecordingError, match=match):
        read_recording(path, BOT)


def test_binary_file_is_not_taken_for_a_csv(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\xff\xfe\x00")
    with pytest.raises(diffbot.RecordingError, match="not a text"):
        read_recording(path, BOT)


def test_missing_input_is_refused(tmp_path: Path) -> None:
    with pytest.raises(diffbot.RecordingError, match=r"nope\.csv: no such file"):
        read_recording(tmp_path / "nope.csv", BOT)


def test_a_recording_without_a_usable_sample_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "a.csv"
    path.write_text(f"time,{LEFT},{RIGHT}\n0,,1\n1,nan,1\n", encoding="utf-8")
    with pytest.raises(diffbot.RecordingError, match=r"no usable sample \(skipped: missing"):
        run_odometry(read_csv(path, LEFT, RIGHT), Odometry(BOT))
    path.write_text(f"time,{LEFT},{RIGHT}\n", encoding="utf-8")
    with pytest.raises(diffbot.RecordingError, match="holds no samples"):
        run_odometry(read_csv(path, LEFT, RIGHT), Odometry(BOT))


def test_wheels_read_whole_from_separate_messages_are_named_message_by_message(
    tmp_path: Path,
) -> None:
    # As `diffbot odom` says it: the library's run named only the first message's joints.
    messages = []
    for k in range(3):
        messages.append((10**9 * (k + 1), 10**9 * (k + 1), [LEFT], [0.1 * k]))
        messages.append((10**9 * (k + 1) + 1000, 10**9 * (k + 1) + 1000, [RIGHT], [0.1 * k]))
    bag = write_bag(tmp_path / "bag", messages)
    with pytest.raises(diffbot.RecordingError) as caught:
        run_odometry(read_recording(bag, BOT), Odometry(BOT))
    assert str(caught.value).endswith(
        f"joints found, by message: '{LEFT}' / '{RIGHT}' (each message must hold a joint of "
        "each side)"
    )


def test_a_joint_named_twice_is_converted_from_its_first_value_as_odometry_reads_it(
    tmp_path: Path,
) -> None:
    # Converted counts (or wraps undone) must be those of the value the odometry then uses.
    from diffbot.conditioning import Conditioning

    counts = Conditioning(counts_per_rev=1000, wrap=0)
    plain, twice = [], []
    for k in range(20):
        stamp, value = 10**9 * (k + 1), 25.0 * k
        plain.append((stamp, stamp, [LEFT, RIGHT], [value, 2 * value]))
        twice.append((stamp, stamp, [LEFT, RIGHT, LEFT], [value, 2 * value, 7e5]))
    want = run_odometry(
        read_recording(write_bag(tmp_path / "plain", plain), BOT, conditioning=counts),
        Odometry(BOT),
    )
    got = run_odometry(
        read_recording(write_bag(tmp_path / "twice", twice), BOT, conditioning=counts),
        Odometry(BOT),
    )
    assert got.final_pose == want.final_pose
    assert got.samples == want.samples == 20
    assert want.final_pose.x > 0.1


# --------------------------------------------------------------------------------------------
# Bag input


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_bag_of_trajectory_a_gives_the_plans_final_pose(tmp_path: Path, storage: str) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages(), storage=storage)
    recording = read_recording(bag, BOT)
    assert recording.kind == "rosbag2"
    assert len(recording.samples) == 401  # the /chatter messages are ignored
    assert recording.samples[0].stamp_ns == EPOCH
    run = run_odometry(recording, Odometry(BOT))
    assert_pose_close(run.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)
    assert run.duration == 40.0


def test_a_single_mcap_file_is_read_as_a_bag(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "run", trajectory_a_messages()[:50], storage="mcap")
    single = bag / "run.mcap"
    assert single.is_file()
    assert len(read_recording(single, BOT).samples) == 50


def test_bag_header_stamps_of_zero_fall_back_to_the_bag_time(tmp_path: Path) -> None:
    bag = write_bag(
        tmp_path / "bag",
        [(0, 5_000_000_000, [LEFT, RIGHT], [0.0, 0.0]), (0, 6_000_000_000, [LEFT, RIGHT], [1, 1])],
    )
    assert [s.stamp_ns for s in read_bag(bag).samples] == [5_000_000_000, 6_000_000_000]


def test_bag_topic_can_be_chosen(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages()[:3], topic="/robot/joint_states")
    assert len(read_bag(bag, "/robot/joint_states").samples) == 3
    with pytest.raises(
        diffbot.RecordingError,
        match=r"no topic '/joint_states' in the bag; topics found: '/chatter', '/robot/joint_st",
    ):
        read_bag(bag, "/joint_states")


def test_without_a_topic_the_only_joint_state_topic_is_read(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages()[:3], topic="/robot/joint_states")
    recording = read_bag(bag)
    assert recording.topic == "/robot/joint_states"
    assert len(recording.samples) == 3


def test_bag_topic_of_another_type_is_refused(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages()[:3])
    with pytest.raises(diffbot.RecordingError, match="'/chatter' carries std_msgs/msg/String"):
        read_bag(bag, "/chatter")


@pytest.mark.parametrize("make", ["empty dir", "junk dir", "empty mcap", "junk mcap"])
def test_things_that_are_not_bags_are_refused(tmp_path: Path, make: str) -> None:
    path = tmp_path / ("x.mcap" if "mcap" in make else "x")
    if make == "empty dir":
        path.mkdir()
    elif make == "junk dir":
        path.mkdir()
        (path / "notes.txt").write_text("hello", encoding="utf-8")
    else:
        path.write_bytes(b"" if make == "empty mcap" else b"not an mcap file at all" * 10)
    with pytest.raises(
        diffbot.RecordingError, match=r"x(\.mcap)?: (empty file|not a readable|not a bag folder)"
    ):
        read_recording(path, BOT)


def test_reading_a_bag_leaves_it_untouched(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages()[:20])
    before = {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in bag.iterdir()}
    read_bag(bag)
    assert {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in bag.iterdir()} == before


def test_missing_rosbags_gives_the_install_hint(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bag = write_bag(tmp_path / "bag", trajectory_a_messages()[:2])
    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)
    with pytest.raises(diffbot.RecordingError, match=r"pip install 'rosbags>=0.11'"):
        read_bag(bag)
    with pytest.raises(diffbot.RecordingError, match="needs the rosbags library"):
        write_joint_states_bag(tmp_path / "out", [0], ["a"], [[0.0]])


# --------------------------------------------------------------------------------------------
# Outputs


def test_seconds_text_is_exact_and_short() -> None:
    assert seconds_text(1_500_000_000) == "1.5"
    assert seconds_text(0) == "0"
    assert seconds_text(-1) == "-0.000000001"
    assert seconds_text(EPOCH + 123) == "1700000000.000000123"


def test_odometry_csv_reads_back_exactly() -> None:
    rows = [
        OdometryRow(EPOCH, Pose(0.1, -1 / 3, math.pi), diffbot.Twist(1e-300, -2.5)),
        OdometryRow(EPOCH + 20_000_000, Pose(1e6, 2.0, -0.5), diffbot.Twist(0.0, 0.0)),
    ]
    lines = format_odometry_csv(rows).splitlines()
    assert lines[0] == "time,x,y,theta,linear,angular"
    values = [float(v) for v in lines[1].split(",")[1:]]
    assert values == [0.1, -1 / 3, math.pi, 1e-300, -2.5]
    assert lines[2].startswith("1700000000.02,1000000.0,2.0,-0.5,")


def test_odometry_bag_holds_odom_and_tf_stamped_from_the_input(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "in", trajectory_a_messages())
    odom = Odometry(BOT, child_frame_id="base_footprint")
    run = run_odometry(read_bag(bag), odom)
    out = tmp_path / "odom"
    write_odometry_bag(out, run.rows, odom)
    with AnyReader([out]) as reader:
        assert {c.topic: (c.msgtype, c.msgcount) for c in reader.connections} == {
            "/odom": ("nav_msgs/msg/Odometry", 401),
            "/tf": ("tf2_msgs/msg/TFMessage", 401),
        }
        stamps = []
        messages = {}
        for connection, timestamp, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            messages[connection.topic] = msg
            stamps.append(timestamp)
    assert stamps[::2] == [row.stamp_ns for row in run.rows]
    last = messages["/odom"]
    assert (last.header.frame_id, last.child_frame_id) == ("odom", "base_footprint")
    assert last.header.stamp.sec == EPOCH // 10**9 + 40
    assert last.pose.pose.position.x == pytest.approx(0.0, abs=1e-9)
    assert last.pose.pose.position.y == pytest.approx(1.0, abs=1e-9)
    assert last.pose.pose.orientation.w == pytest.approx(1.0, abs=1e-12)
    assert last.twist.twist.linear.x == pytest.approx(0.1, rel=1e-9)
    assert np.array_equal(last.pose.covariance, np.array(odom.pose_covariance))
    tf = messages["/tf"].transforms[0]
    assert (tf.header.frame_id, tf.child_frame_id) == ("odom", "base_footprint")
    assert tf.transform.translation.y == last.pose.pose.position.y


def test_joint_states_bag_and_csv_round_trip_through_the_readers(tmp_path: Path) -> None:
    stamps = [EPOCH, EPOCH + 10**7, EPOCH + 2 * 10**7]
    names = [LEFT, RIGHT, "caster_wheel_joint"]
    positions = [[0.0, 0.1, 0.2], [0.0, 0.3, 0.6], [0.0, -1.0, -2.0]]
    write_joint_states_bag(tmp_path / "js", stamps, names, positions)
    samples = read_bag(tmp_path / "js").samples
    assert [s.stamp_ns for s in samples] == stamps
    assert [list(s.names) for s in samples] == [names] * 3
    assert [list(s.positions) for s in samples] == [
        list(col) for col in zip(*positions, strict=True)
    ]
    (tmp_path / "js.csv").write_text(format_joint_states_csv(stamps, names, positions))
    from_csv = read_csv(tmp_path / "js.csv", LEFT, RIGHT).samples
    assert [s.stamp_ns for s in from_csv] == stamps
    assert [list(s.positions) for s in from_csv] == [[0.0, 0.0], [0.1, 0.3], [0.2, 0.6]]


def test_bag_outputs_never_replace_without_force_and_leave_no_debris(tmp_path: Path) -> None:
    out = tmp_path / "js"
    write_joint_states_bag(out, [1], [LEFT], [[1.0]])
    with pytest.raises(diffbot.OutputExistsError, match="exists: use force=True"):
        write_joint_states_bag(out, [2, 3], [LEFT], [[2.0, 3.0]])
    assert [s.stamp_ns for s in read_bag(out).samples] == [1]
    write_joint_states_bag(out, [2, 3], [LEFT], [[2.0, 3.0]], force=True)
    assert [s.stamp_ns for s in read_bag(out).samples] == [2, 3]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["js"]


def test_force_never_replaces_a_directory_that_is_not_a_bag(tmp_path: Path) -> None:
    precious = tmp_path / "home"
    precious.mkdir()
    (precious / "thesis.tex").write_text("years of work", encoding="utf-8")
    with pytest.raises(diffbot.OutputExistsError, match="not a rosbag2 recording"):
        write_joint_states_bag(precious, [1], [LEFT], [[1.0]], force=True)
    assert (precious / "thesis.tex").read_text(encoding="utf-8") == "years of work"


def test_a_failed_bag_write_leaves_nothing_behind(tmp_path: Path) -> None:
    with pytest.raises(diffbot.RecordingError, match="ROS time must be between"):
        write_joint_states_bag(tmp_path / "js", [-1], [LEFT], [[1.0]])
    # A failure while messages are written, after the temporary bag was created.
    with pytest.raises(AttributeError, match="encode"):
        write_joint_states_bag(tmp_path / "js", [1], [123], [[1.0]])  # type: ignore[list-item]
    assert list(tmp_path.iterdir()) == []


def test_one_zero_header_stamp_puts_the_whole_topic_on_the_bag_clock(tmp_path: Path) -> None:
    # The first header stamp is 0, the others count from 0.1 s: mixed per message, every later
    # sample would be 54 years before the first and skipped.
    received = [EPOCH + k * 100_000_000 for k in range(11)]
    headers = [0] + [k * 100_000_000 for k in range(1, 11)]
    messages = [
        (header, receive, [LEFT, RIGHT], [float(k), float(k)])
        for k, (header, receive) in enumerate(zip(headers, received, strict=True))
    ]
    recording = read_bag(write_bag(tmp_path / "bag", messages))
    assert recording.clock == CLOCK_RECEIVE
    assert [s.stamp_ns for s in recording.samples] == received
    run = run_odometry(recording, Odometry(BOT))
    assert run.samples == 11
    assert run.skipped == {}
    assert run.final_pose.x == pytest.approx(10 * BOT.wheel_radius, rel=1e-12)


def test_header_stamps_are_used_when_every_one_is_set(tmp_path: Path) -> None:
    messages = [(5 + k, 10**12 + 7 * k, [LEFT, RIGHT], [0.0, 0.0]) for k in range(3)]
    recording = read_bag(write_bag(tmp_path / "bag", messages))
    assert recording.clock == CLOCK_HEADER
    assert [s.stamp_ns for s in recording.samples] == [5, 6, 7]


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_a_rosbag2_directory_named_like_a_ros1_bag_is_read_as_rosbag2(
    tmp_path: Path, storage: str
) -> None:
    bag = write_bag(tmp_path / "run.bag", trajectory_a_messages()[:5], storage=storage)
    assert len(read_recording(bag, BOT).samples) == 5
    storage_file = next(p for p in bag.iterdir() if p.suffix in (".db3", ".mcap"))
    assert len(read_recording(storage_file, BOT).samples) == 5


# --------------------------------------------------------------------------------------------
# Velocity feedback: recordings of wheels that report velocities only


def test_bag_velocities_read_with_velocity_feedback_give_the_plans_final_pose(
    tmp_path: Path,
) -> None:
    bag = velocity_bag(tmp_path / "bag", EPOCH)
    assert read_bag(bag, field="velocity").samples[5].positions[1] == pytest.approx(
        trajectory_a_velocities(EPOCH)[5][1], abs=0.0
    )
    recording = read_recording(bag, BOT, feedback="velocity")
    run = run_odometry(recording, Odometry(BOT))
    assert_pose_close(run.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)
    chunked = recording_odometry(bag, BOT, feedback="velocity")
    assert_pose_close(chunked.summary.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)
    assert chunked.summary.samples == 401


def test_csv_velocity_columns_read_with_velocity_feedback_give_the_plans_final_pose(
    tmp_path: Path,
) -> None:
    lines = [f"time,/js/{LEFT}/position,/js/{LEFT}/velocity,/js/{RIGHT}/velocity"]
    lines += [
        f"{(s - EPOCH) / 1e9!r},0,{lf!r},{r!r}" for s, lf, r in trajectory_a_velocities(EPOCH)
    ]
    path = tmp_path / "v.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    run = run_odometry(read_recording(path, BOT, feedback="velocity"), Odometry(BOT))
    assert_pose_close(run.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)
    chunked = recording_odometry(path, BOT, feedback="velocity")
    assert_pose_close(chunked.summary.final_pose, Pose(0.0, 1.0, 0.0), 1e-9)


def test_an_unknown_feedback_is_refused_by_the_readers(tmp_path: Path) -> None:
    path = trajectory_a_csv(tmp_path / "a.csv")
    with pytest.raises(diffbot.ParameterError, match="feedback"):
        read_recording(path, BOT, feedback="effort")
    with pytest.raises(diffbot.ParameterError, match="feedback"):
        recording_odometry(path, BOT, feedback="effort")
