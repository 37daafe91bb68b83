"""Open-loop odometry: commanded body velocities, each held until the next, integrated exactly."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from bags import twist_message, write_bag, write_topics
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT
from sinks import Collect
from wheel_motion import assert_pose_close

import diffbot
from diffbot.chunk_odometry import ChunkOdometry
from diffbot.conditioning import Conditioning
from diffbot.errors import RecordingError
from diffbot.odometry import SKIP_NOT_FINITE, SKIP_STAMP_NOT_AFTER
from diffbot.open_loop import (
    SKIP_COMMAND_RANGE,
    command_angles,
    open_loop_odometry,
    read_commands,
)
from diffbot.replay import recording_odometry
from diffbot.trajectory import Arc, Spin, Straight

S = 1_000_000_000


def csv(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_the_controllers_open_loop_test_is_reproduced(tmp_path: Path) -> None:
    # ros2_controllers diff_drive_controller/test/test_odometry.cpp, TestOpenLoopUpdate:
    # v = 2 m/s, w = 0.5 rad/s for 1 s.
    run = open_loop_odometry(csv(tmp_path / "c.csv", "t,v,w\n0,2,0.5\n1,0,0\n"), BOT)
    expected = diffbot.Pose(4.0 * math.sin(0.5), -4.0 * (math.cos(0.5) - 1.0), 0.5)
    assert_pose_close(run.summary.final_pose, expected, 1e-12)
    assert run.summary.twist.linear == pytest.approx(2.0, abs=1e-12)
    assert run.summary.twist.angular == pytest.approx(0.5, abs=1e-12)
    assert run.kind == "csv"
    assert run.summary.samples == 2


def test_each_command_holds_until_the_next(tmp_path: Path) -> None:
    text = "t,v,w\n0,1,0\n2,0,0\n2.5,-0.5,0\n4.5,0,0\n"
    run = open_loop_odometry(csv(tmp_path / "c.csv", text), BOT)
    assert run.summary.final_pose.x == pytest.approx(2.0 - 1.0, abs=1e-12)
    assert run.summary.distance == pytest.approx(3.0, abs=1e-12)
    assert run.summary.duration == pytest.approx(4.5)


def test_non_finite_and_late_commands_are_skipped_and_the_one_before_holds(
    tmp_path: Path,
) -> None:
    text = "t,v,w\n0,1,0\n1,nan,0\n2,0.5,0\n1.5,9,0\n3,0,0\n"
    run = open_loop_odometry(csv(tmp_path / "c.csv", text), BOT)
    assert run.summary.final_pose.x == pytest.approx(2.0 + 0.5, abs=1e-12)
    assert run.summary.skipped == {SKIP_NOT_FINITE: 1, SKIP_STAMP_NOT_AFTER: 1}


def test_a_non_numeric_column_is_refused(tmp_path: Path) -> None:
    path = csv(tmp_path / "c.csv", "t,v,w\n0,fast,0\n1,0,0\n")
    with pytest.raises(RecordingError, match="not a number"):
        open_loop_odometry(path, BOT)


def test_a_csv_without_the_command_columns_says_what_it_needs(tmp_path: Path) -> None:
    path = csv(tmp_path / "c.csv", "t,linear\n0,1\n")
    with pytest.raises(RecordingError, match=r"columns v \(m/s\) and w \(rad/s\)"):
        open_loop_odometry(path, BOT)


def test_twist_commands_of_a_bag_are_stamped_by_the_receive_times(tmp_path: Path) -> None:
    bag = write_topics(
        tmp_path / "bag",
        {
            "/cmd_vel": (
                "geometry_msgs/msg/Twist",
                [(10 * S, twist_message(0.5, 0.0)), (12 * S, twist_message(0.0, 0.0))],
            )
        },
    )
    run = open_loop_odometry(bag, BOT)
    assert run.summary.final_pose.x == pytest.approx(1.0, abs=1e-12)
    assert (run.topic, run.clock, run.kind) == ("/cmd_vel", "receive", "rosbag2")


def test_twist_stamped_commands_are_stamped_by_their_headers(tmp_path: Path) -> None:
    messages = [
        (5 * S, twist_message(0.0, 1.0, stamp_ns=1 * S)),
        (5 * S, twist_message(0.0, 0.0, stamp_ns=1 * S + S // 2)),
    ]
    bag = write_topics(
        tmp_path / "bag", {"/diff_cont/cmd_vel": ("geometry_msgs/msg/TwistStamped", messages)}
    )
    commands = read_commands(bag, "/diff_cont/cmd_vel")
    assert commands.stamp_ns.tolist() == [S, S + S // 2]
    run = open_loop_odometry(bag, BOT, "/diff_cont/cmd_vel")
    assert run.summary.final_pose.theta == pytest.approx(0.5, abs=1e-12)
    assert run.clock == "header"


def test_a_command_topic_of_another_type_is_refused(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "bag", [(S, S, [BOT.left_joint, BOT.right_joint], [0.0, 0.0])])
    with pytest.raises(RecordingError, match=r"carries sensor_msgs/msg/JointState, not"):
        open_loop_odometry(bag, BOT, "/joint_states")
    with pytest.raises(RecordingError, match="no topic '/cmd_vel'"):
        open_loop_odometry(bag, BOT)


# --------------------------------------------------------------------------------------------
# The law: the open-loop odometry of a plan's twists ends at the plan's final pose

#: Whole milliseconds: the segment boundaries fall on whole nanoseconds, as stamps do.
durations = st.integers(200, 20_000).map(lambda ms: ms / 1000)
segments = st.one_of(
    st.builds(Straight, st.floats(-3.0, 3.0).filter(lambda v: abs(v) > 1e-3), durations),
    st.builds(
        Arc, st.floats(0.05, 3.0), st.floats(0.1, 6.0), st.sampled_from(["cw", "ccw"]), durations
    ),
    st.builds(Spin, st.floats(-6.0, 6.0).filter(lambda v: abs(v) > 1e-3), durations),
)
robots = st.builds(
    diffbot.DiffDriveParams,
    wheel_radius=st.floats(0.02, 0.5),
    wheel_separation=st.floats(0.1, 2.0),
    left_sign=st.sampled_from([1, -1]),
    right_sign=st.sampled_from([1, -1]),
)


@settings(max_examples=80, deadline=None)
@given(st.lists(segments, min_size=1, max_size=6), robots, st.integers(0, 2 * 10**18))
def test_open_loop_odometry_of_a_plans_twists_ends_at_its_final_pose(
    pieces: list[Straight | Arc | Spin], robot: diffbot.DiffDriveParams, start_ns: int
) -> None:
    plan = diffbot.plan(pieces, robot)
    # One command per segment at its start, then a zero one at the end (as a plan's commands
    # are published), stamped since any epoch.
    ms = [round(s.duration * 1000) for s in plan.segments]
    stamps = start_ns + np.concatenate(([0], np.cumsum(ms))).astype(np.int64) * 1_000_000
    linear = np.array([s.twist.linear for s in plan.segments] + [0.0])
    angular = np.array([s.twist.angular for s in plan.segments] + [0.0])
    left, right = command_angles(stamps, linear, angular, robot)
    odom = ChunkOdometry(robot)
    odom.feed(stamps, left, right)
    scale = max(1.0, *(abs(s.end_pose.x) + abs(s.end_pose.y) for s in plan.segments))
    assert_pose_close(odom.summary("plan").final_pose, plan.final_pose, 1e-9 * scale)


def test_without_a_topic_the_bags_only_command_topic_is_read(tmp_path: Path) -> None:
    commands = [(S, twist_message(0.2, 0.0)), (2 * S, twist_message(0.0, 0.0))]
    bag = write_topics(
        tmp_path / "bag", {"/diff_cont/cmd_vel_unstamped": ("geometry_msgs/msg/Twist", commands)}
    )
    run = open_loop_odometry(bag, BOT)
    assert (run.topic, run.topic_chosen) == ("/diff_cont/cmd_vel_unstamped", True)
    assert run.summary.final_pose.x == pytest.approx(0.2, abs=1e-12)
    two = write_topics(
        tmp_path / "two",
        dict.fromkeys(("/a/cmd_vel", "/b/cmd_vel"), ("geometry_msgs/msg/Twist", commands)),
    )
    with pytest.raises(RecordingError, match=r"several command topics: '/a/cmd_vel', '/b/cmd"):
        open_loop_odometry(two, BOT)


@pytest.mark.parametrize(
    ("rows", "skipped"),
    [
        # beyond the CSV reader's bound for any cell, and beyond the command bound alone
        (["1,1e300,0", "1.5,0,-1e13"], 2),
        (["1,1001,0", "1.5,0,-1000.5"], 2),
        (["1,1000,0", "1.5,0,-1000"], 0),
    ],
)
def test_commands_faster_than_any_robot_are_skipped_as_out_of_range(
    tmp_path: Path, rows: list[str], skipped: int
) -> None:
    text = "\n".join(["t,v,w", "0,1,0", *rows, "2,0,0", ""])
    run = open_loop_odometry(csv(tmp_path / "c.csv", text), BOT)
    if skipped:
        assert run.summary.skipped == {SKIP_COMMAND_RANGE: skipped}
        # the command before holds over the skipped ones: 1 m/s for 2 s
        assert run.summary.final_pose.x == pytest.approx(2.0, abs=1e-12)
    else:
        assert run.summary.skipped == {}


def test_bag_commands_faster_than_any_robot_are_skipped_as_out_of_range(tmp_path: Path) -> None:
    twist = "geometry_msgs/msg/Twist"
    commands = [(k * S, twist_message(v, 0.0)) for k, v in enumerate([1.0, 1e300, 2e3, 0.0])]
    bag = write_topics(tmp_path / "bag", {"/cmd_vel": (twist, commands)})
    run = open_loop_odometry(bag, BOT)
    assert run.summary.skipped == {SKIP_COMMAND_RANGE: 2}
    assert run.summary.final_pose.x == pytest.approx(3.0, abs=1e-12)


def test_the_odometry_of_a_recording_integrates_its_commands_open_loop(tmp_path: Path) -> None:
    path = csv(tmp_path / "c.csv", "t,v,w\n0,2,0.5\n1,0,0\n")
    sink, used = Collect(), []
    run = recording_odometry(path, BOT, sink=sink, progress=used.append, open_loop=True)
    assert run.summary == open_loop_odometry(path, BOT).summary
    assert ([row[0] for row in sink.rows], used) == ([0, S], [2])
    with pytest.raises(diffbot.ParameterError, match="conditioning= and feedback= apply"):
        recording_odometry(path, BOT, conditioning=Conditioning(wrap=0), open_loop=True)
    with pytest.raises(diffbot.ParameterError, match="conditioning= and feedback= apply"):
        recording_odometry(path, BOT, feedback="velocity", open_loop=True)
