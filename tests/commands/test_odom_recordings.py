"""``diffbot odom`` on recordings as real robots record them: encoder counts on a 16-bit counter,
bags of every kind (ROS 1, lone storage files, folders without metadata), the only JointState
topic of a bag, joints that are not there."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from bags import lone_storage, write_bag, write_ros1_bag
from click.testing import CliRunner
from pioneer import (
    COUNTS_PER_REV,
    RUN_END,
    START_NS,
    TOPIC,
    WRAP,
    counts_csv,
    pioneer_messages,
    reference_bag,
    urdf,
)
from wheel_motion import angle_error

from diffbot.cli import main

COUNTS = ["--counts-per-rev", repr(COUNTS_PER_REV)]


def assert_at_run_end(data: dict[str, object]) -> None:
    pose = data["final_pose"]
    assert isinstance(pose, dict)
    # Counts are whole: 1/128 mm of travel per count bounds the error (a few 1e-5 m).
    assert pose["x"] == pytest.approx(RUN_END.x, abs=1e-4)
    assert pose["y"] == pytest.approx(RUN_END.y, abs=1e-4)
    assert angle_error(pose["theta"], RUN_END.theta) < 1e-4


@pytest.fixture
def robot(tmp_path: Path) -> list[str]:
    return ["--robot", str(urdf(tmp_path))]


def test_raw_counts_read_as_radians_exit_1_naming_the_first_implausible_step(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    csv = counts_csv(tmp_path)
    result = runner.invoke(main, ["odom", str(csv), *robot])
    assert result.exit_code == 1, result.output
    assert "100 implausible steps (a wheel faster than 307.7 rad/s: a rim speed of 30 m/s)" in (
        result.stderr
    )
    assert "the first ends at sample 1, t 0.1 s (left_wheel_joint at 3.2e+04 rad/s)" in (
        result.stderr
    )
    result = runner.invoke(main, ["odom", str(csv), *robot, "--json"])
    assert result.exit_code == 1
    assert json.loads(result.stdout)["implausible_steps"] == 100


def test_counts_per_rev_and_a_detected_wrap_give_the_run_and_say_so(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    csv = counts_csv(tmp_path)
    result = runner.invoke(main, ["odom", str(csv), *robot, *COUNTS])
    assert result.exit_code == 0, result.output
    assert (
        "positions   encoder counts, 78414.15263360123 per revolution; wrapping at 65536 "
        "(detected), 7 wraps undone"
    ) in result.stdout
    assert "distance    1.5 m" in result.stdout
    assert result.stderr.startswith(
        f"warning: {csv}: the wheel positions wrap around at 65536 (a counter, detected by "
        "itself): 7 wraps undone; give --wrap 65536"
    )
    data = json.loads(runner.invoke(main, ["odom", str(csv), *robot, *COUNTS, "--json"]).stdout)
    assert_at_run_end(data)
    assert (data["implausible_steps"], data["wrap"]) == (0, WRAP)


def test_a_given_wrap_is_not_warned_about(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    csv = counts_csv(tmp_path)
    result = runner.invoke(main, ["odom", str(csv), *robot, *COUNTS, "--wrap", "65536"])
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    assert "wrapping at 65536 (--wrap), 7 wraps undone" in result.stdout


def test_wrap_0_reads_the_counts_as_they_are(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    csv = counts_csv(tmp_path)
    result = runner.invoke(main, ["odom", str(csv), *robot, *COUNTS, "--wrap", "0", "--json"])
    # Each wrap read as a jump of 65536 counts (0.512 m in 0.1 s) is within the rim bound, but
    # the pose is not the run's: the detection is what saves it.
    data = json.loads(result.stdout)
    assert data["wrap"] is None
    assert abs(data["final_pose"]["x"] - RUN_END.x) > 0.1


@pytest.mark.parametrize("kind", ["folder", "no metadata", "lone db3", "lone db3.zstd", "mcap"])
def test_every_kind_of_rosbag2_gives_the_run_from_its_only_joint_state_topic(
    runner: CliRunner, tmp_path: Path, robot: list[str], kind: str
) -> None:
    storage = "mcap" if kind == "mcap" else "sqlite3"
    bag = write_bag(tmp_path / "bag", pioneer_messages(), topic=TOPIC, storage=storage)
    if kind == "no metadata":
        (bag / "metadata.yaml").unlink()
    elif kind == "lone db3":
        bag = lone_storage(bag, tmp_path / "run.db3")
    elif kind == "lone db3.zstd":
        bag = lone_storage(bag, tmp_path / "run.db3.zstd")
    elif kind == "mcap":
        bag = lone_storage(bag, tmp_path / "run.mcap")
    result = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS])
    assert result.exit_code == 0, result.output
    assert f"topic {TOPIC} (its only JointState topic), header stamps" in result.stdout
    data = json.loads(runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--json"]).stdout)
    assert_at_run_end(data)


def test_a_lone_database_of_messages_compressed_one_by_one_is_told_so(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # A bag recorded with zstd compression per message keeps the mode in its metadata.yaml;
    # its .db3 alone (or its folder without the metadata) read as "no usable sample (skipped:
    # unreadable value: 101)".
    from bags import TYPESTORE, joint_state
    from rosbags.rosbag2 import Writer
    from rosbags.rosbag2.writer import CompressionFormat, CompressionMode

    bag = tmp_path / "bag"
    writer = Writer(bag, version=9)
    writer.set_compression(CompressionMode.MESSAGE, CompressionFormat.ZSTD)
    with writer:
        conn = writer.add_connection(TOPIC, "sensor_msgs/msg/JointState", typestore=TYPESTORE)
        for stamp, received, names, positions in pioneer_messages():
            writer.write(conn, received, joint_state(stamp, names, positions))
    whole = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--json"])
    assert whole.exit_code == 0, whole.output
    assert_at_run_end(json.loads(whole.stdout))
    lone = lone_storage(bag, tmp_path / "run.db3")
    (bag / "metadata.yaml").unlink()
    for path in (lone, bag):
        result = runner.invoke(main, ["odom", str(path), *robot, *COUNTS])
        assert result.exit_code == 2, result.output
        assert result.stderr.startswith(
            f"error: {path}: its messages are compressed one by one (zstd), which only the "
            "bag's metadata.yaml says: "
        )


def test_a_ros1_bag_is_read_directly(runner: CliRunner, tmp_path: Path, robot: list[str]) -> None:
    bag = write_ros1_bag(tmp_path / "run.bag", pioneer_messages(), topic=TOPIC)
    result = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--topic", TOPIC])
    assert result.exit_code == 0, result.output
    assert f"run.bag (ROS 1 bag, topic {TOPIC}, header stamps)" in result.stdout
    data = json.loads(runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--json"]).stdout)
    assert_at_run_end(data)


def test_two_joint_state_topics_and_none_asked_for_is_refused_naming_both(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    first = write_bag(tmp_path / "a", pioneer_messages(), topic=TOPIC, chatter=False)
    second = write_bag(tmp_path / "b", pioneer_messages(), topic="/other", chatter=False)
    folder = tmp_path / "both"
    folder.mkdir()
    shutil.copy(next(first.glob("*.db3")), folder / "a.db3")
    shutil.copy(next(second.glob("*.db3")), folder / "b.db3")
    result = runner.invoke(main, ["odom", str(folder), *robot])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {folder}: no topic '/joint_states' and several sensor_msgs/msg/JointState "
        f"topics: '/other', '{TOPIC}'; give the one to read (--topic)\n"
    )


def test_missing_joints_are_named_beside_the_joints_found(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = write_bag(tmp_path / "bag", pioneer_messages())
    result = runner.invoke(main, ["odom", str(bag), *COUNTS])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: {bag}: no usable sample (skipped: missing joint: 101)")
    assert result.stderr.endswith(
        "; wheel joints wanted: 'front_left_wheel_joint', 'front_right_wheel_joint'; "
        "joints found: 'left_wheel_joint', 'right_wheel_joint'; none is a wheel joint of this "
        "robot: another robot's recording? give its description (--robot PATH)\n"
    )


def test_wheels_published_in_separate_messages_are_named_message_by_message(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # A driver per wheel, each publishing its own JointState: the error named only the first
    # message's joint, as if the other wheel were absent from the topic.
    split = []
    for stamp, received, names, positions in pioneer_messages():
        split.append((stamp, received, names[:1], positions[:1]))
        split.append((stamp + 1000, received + 1000, names[1:], positions[1:]))
    bag = write_bag(tmp_path / "bag", split, topic=TOPIC)
    result = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {bag}: no usable sample (skipped: missing joint: 202); wheel joints wanted: "
        "'left_wheel_joint', 'right_wheel_joint'; joints found, by message: "
        "'left_wheel_joint' / 'right_wheel_joint' (each message must hold a joint of each "
        "side)\n"
    )


def test_topics_named_without_their_leading_slash_are_found(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # As ROS resolves a relative name in the root namespace: "odom" is "/odom". Both were
    # refused ("no topic 'odom' in the bag; topics found: '/odom', ...").
    bag = reference_bag(tmp_path)
    args = ["odom", str(bag), *robot, *COUNTS, "--wrap", str(WRAP), "--json"]
    named = runner.invoke(main, [*args, "--topic", TOPIC, "--reference", "/odom"])
    relative = runner.invoke(main, [*args, "--topic", TOPIC[1:], "--reference", "odom"])
    assert named.exit_code == 0, named.output
    assert relative.exit_code == 0, relative.output
    assert relative.stdout == named.stdout
    assert json.loads(relative.stdout)["reference"]["topic"] == "/odom"


def test_another_publishers_joints_on_the_topic_are_explained(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # An arm's driver publishing its own JointState on the same topic as the base: half the
    # messages were reported as "missing joint" with nothing to say what they were.
    both = []
    for stamp, received, names, positions in pioneer_messages():
        both.append((stamp, received, names, positions))
        both.append((stamp + 1000, received + 1000, ["shoulder", "elbow"], [0.1, 0.2]))
    bag = write_bag(tmp_path / "bag", both, topic=TOPIC)
    result = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--wrap", str(WRAP)])
    assert result.exit_code == 0, result.output
    assert result.stderr == (
        "warning: skipped 101 of 202 samples: 101 missing joint (messages without a wheel joint "
        "of each side: another publisher's on the topic, such as an arm's, or a side's wheels "
        "published apart)\n"
    )
    data = json.loads(runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--json"]).stdout)
    assert_at_run_end(data)


def test_two_publishers_on_one_topic_are_explained_once_with_the_rule(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    once = pioneer_messages()
    twice = []
    for stamp, received, names, positions in once:
        twice.append((stamp, received, names, positions))
        twice.append((stamp, received + 1000, names, positions))  # the second publisher
    bag = write_bag(tmp_path / "bag", twice, topic=TOPIC)
    result = runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--wrap", "65536"])
    assert result.exit_code == 0, result.output
    first = once[0][0] / 1e9
    assert result.stderr == (
        "warning: skipped 101 of 202 samples: 101 stamp not after previous (from stamp "
        f"{first:.1f} s on, samples whose stamp is not after the one before: two publishers on "
        "the topic, or a clock that went back; the first sample of each stamp is used, and only "
        "samples later than every one used)\n"
    )
    data = json.loads(runner.invoke(main, ["odom", str(bag), *robot, *COUNTS, "--json"]).stdout)
    assert_at_run_end(data)


def test_csv_rows_out_of_order_are_explained_as_rows_not_publishers(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # Two rows swapped in a CSV: the warning spoke of "two publishers on the topic".
    csv = counts_csv(tmp_path)
    header, *rows = csv.read_text(encoding="utf-8").splitlines()
    rows[10], rows[11] = rows[11], rows[10]
    csv.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    result = runner.invoke(main, ["odom", str(csv), *robot, *COUNTS, "--wrap", "65536"])
    assert result.exit_code == 0, result.output
    first = rows[11].split(",")[0]  # the row skipped: earlier than the one before it
    assert result.stderr == (
        "warning: skipped 1 of 101 samples: 1 stamp not after previous (from stamp "
        f"{float(first):.1f} s on, rows whose stamp is not after the one before: rows out of "
        "order or repeated; the first row of each stamp is used, and only rows later than "
        "every one used)\n"
    )


def test_an_implausible_step_in_counts_does_not_ask_for_the_options_already_given(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # A 32-bit counter, 4096 counts per revolution, a glitch of a million counts in sample 50
    # read with --counts-per-rev and --wrap: the warning still asked "encoder counts?
    # --counts-per-rev, --wrap".
    rows = ["time,left_wheel_joint,right_wheel_joint"]
    for k in range(101):
        left = 40 * k + (1_000_000 if k == 50 else 0)
        rows.append(f"{k / 10},{left},{40 * k}")
    csv = tmp_path / "glitch.csv"
    csv.write_text("\n".join(rows) + "\n", encoding="utf-8")
    counts = ["--counts-per-rev", "4096"]
    result = runner.invoke(main, ["odom", str(csv), *robot, *counts, "--wrap", str(2**32)])
    assert result.exit_code == 1, result.output
    assert "2 implausible steps" in result.stderr
    assert result.stderr.endswith(
        "the pose is not to be trusted (a jump in the counts, or --counts-per-rev too small)\n"
    )
    result = runner.invoke(main, ["odom", str(csv), *robot, *counts, "--wrap", "0"])
    assert result.exit_code == 1, result.output
    assert result.stderr.endswith(
        "the pose is not to be trusted (a counter that wraps? --wrap; or --counts-per-rev too "
        "small)\n"
    )


def test_the_table_of_several_inputs_stays_aligned_with_long_names(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    short = counts_csv(tmp_path, "a.csv")
    long = counts_csv(tmp_path, "a_recording_name_well_beyond_twenty_four_characters.csv")
    result = runner.invoke(main, ["odom", str(short), str(long), *robot, *COUNTS])
    assert result.exit_code == 0, result.output
    robot_line, header, *rows = result.stdout.splitlines()
    assert robot_line.startswith("robot ")
    end = header.index("samples") + len("samples")
    assert [row[:end].rstrip().endswith(" 101") for row in rows] == [True, True]
    assert len({row.index(" x ") for row in rows}) == 1


def test_the_robots_own_odometry_is_a_reference_that_agrees(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    bag = reference_bag(tmp_path)
    args = ["odom", str(bag), *robot, *COUNTS, "--reference", "/odom"]
    data = json.loads(runner.invoke(main, [*args, "--json"]).stdout)
    reference = data["reference"]
    assert reference["topic"] == "/odom"
    assert reference["samples"] == 101
    # Whole counts: 1/128 mm of wheel travel per count.
    assert reference["max_position_error"] < 1e-4
    assert abs(reference["final_heading_error"]) < 1e-4
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "reference   /odom, 101 poses: final " in result.stdout


def test_a_drifting_reference_gives_known_final_max_and_rms_errors(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    bag = reference_bag(tmp_path, drift=0.002)
    out = tmp_path / "odom.csv"
    args = ["odom", str(bag), *robot, *COUNTS, "--reference", "/odom", "--json", "--out", str(out)]
    reference = json.loads(runner.invoke(main, args).stdout)["reference"]
    # The reference runs 0.002 m * k ahead at sample k = 0..100 (known values: 0.2 m at the
    # end, and sqrt(mean(k**2)) = sqrt(3350) times 0.002 m in RMS).
    assert reference["final_position_error"] == pytest.approx(0.2, abs=1e-4)
    assert reference["max_position_error"] == pytest.approx(0.2, abs=1e-4)
    assert reference["rms_position_error"] == pytest.approx(0.002 * 3350**0.5, abs=1e-4)
    lines = out.read_text(encoding="utf-8").splitlines()
    assert lines[0] == "time,x,y,theta,linear,angular,reference_x,reference_y,reference_theta"
    last = [float(v) for v in lines[-1].split(",")]
    assert last[6] - last[1] == pytest.approx(0.2, abs=1e-4)


def test_a_reference_on_another_clock_says_both_time_spans(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    # A simulation's joint states stamped in simulated time (from 100 s) beside an /odom
    # stamped by the wall clock: nothing overlaps, and "no pose within its time span" did not
    # say why.
    from bags import write_bag_with_odometry

    messages = [
        (stamp - START_NS + 100 * 10**9, received, names, positions)
        for stamp, received, names, positions in pioneer_messages()
    ]
    poses = [(stamp, 0.0, 0.0, 0.0) for stamp, _, _, _ in pioneer_messages()]
    bag = write_bag_with_odometry(tmp_path / "bag", messages, poses, topic=TOPIC)
    args = ["odom", str(bag), *robot, *COUNTS, "--reference", "/odom"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    first, last = poses[0][0], poses[-1][0]
    span = f"{first // 10**9}.{first % 10**9:09d}".rstrip("0")
    end = f"{last // 10**9}.{last % 10**9:09d}".rstrip("0")
    assert result.stdout.splitlines()[-1] == (
        "reference   /odom: no pose within the odometry's time span (the odometry 100.1 to "
        f"110.1 s, /odom {span} to {end} s: two clocks?)"
    )
    data = json.loads(runner.invoke(main, [*args, "--json"]).stdout)
    assert data["reference"] == {
        "topic": "/odom",
        "samples": 0,
        "final_position_error": None,
        "final_heading_error": None,
        "max_position_error": None,
        "rms_position_error": None,
    }


def test_a_reference_needs_a_bag(runner: CliRunner, tmp_path: Path, robot: list[str]) -> None:
    csv = counts_csv(tmp_path)
    result = runner.invoke(main, ["odom", str(csv), *robot, "--reference", "/odom"])
    assert result.exit_code == 2
    assert result.stderr == (
        f"error: {csv}: a reference topic is read from a bag, and this is a CSV\n"
    )


def test_several_recordings_each_say_how_far_they_are_from_their_reference(
    runner: CliRunner, tmp_path: Path, robot: list[str]
) -> None:
    agrees = reference_bag(tmp_path / "agrees")
    drifts = reference_bag(tmp_path / "drifts", drift=0.002)
    args = ["odom", str(agrees), str(drifts), *robot, *COUNTS, "--reference", "/odom"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    row = next(k for k, line in enumerate(lines) if line.startswith(str(drifts)))
    assert lines[row + 1].split()[:6] == ["reference", "/odom,", "101", "poses:", "final", "0.2"]
    assert sum(line.split()[:1] == ["reference"] for line in lines) == 2
