"""One boundary for what arrives on the wire: a message with a number that is not finite or out
of its physical range, or a stamp far ahead, is counted and skipped by every node; it never ends
a node and never poisons what the next good message does."""

from __future__ import annotations

import math
import subprocess
import sys
import time

import pytest
from live_graph import PATIENCE, deep, until
from robots import BOT

from diffbot.live import types
from diffbot.live.inverse_kinematics import IkSettings, InverseKinematicsNode
from diffbot.live.messages import commands, time_of, twist_command
from diffbot.live.odometry import OdometryNode
from diffbot.live.robot import RobotNode, RobotSettings
from diffbot.live.transport import Node
from diffbot.live.wire import (
    BAD_STAMP,
    MAX_STAMP_AHEAD_NS,
    NOT_FINITE,
    OUT_OF_RANGE,
    STAMPED_AHEAD,
    WRONG_LENGTH,
    Refusals,
    joint_state_problem,
    planar_pose_problem,
    pose_problem,
    twist_problem,
    wheel_problem,
)
from diffbot.numbers import MAX_COORDINATE, MAX_LINEAR_SPEED, MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED
from diffbot.wheel_commands import LEFT_TOPIC, RIGHT_TOPIC

DEEP = deep()
NOW = 1_800_000_000 * 10**9


def test_the_checks_name_their_reason() -> None:
    assert twist_problem(0.1, -0.5) is None
    assert twist_problem(MAX_LINEAR_SPEED, 0.0) is None
    assert twist_problem(1e308, 0.0) == OUT_OF_RANGE
    assert twist_problem(0.0, -1e4) == OUT_OF_RANGE
    assert twist_problem(math.nan, 0.0) == NOT_FINITE
    assert twist_problem(0.0, -math.inf) == NOT_FINITE
    assert wheel_problem([1.0, -2.0], 2) is None
    assert wheel_problem([1.0], 2) == WRONG_LENGTH
    assert wheel_problem([1e300], 1) == OUT_OF_RANGE
    # The bounds of wheel values in files, the same on the wire.
    assert wheel_problem([-MAX_WHEEL_SPEED], 1) is None
    assert wheel_problem([1.01 * MAX_WHEEL_SPEED], 1) == OUT_OF_RANGE
    assert wheel_problem([math.inf], 1) == NOT_FINITE
    sec = NOW // 10**9
    assert joint_state_problem(sec, 0, [1.0, MAX_RECORDED_ANGLE], NOW) is None
    assert joint_state_problem(sec, 0, [-1.01 * MAX_RECORDED_ANGLE], NOW) == OUT_OF_RANGE
    assert joint_state_problem(sec, 10**9, [1.0], NOW) == BAD_STAMP
    assert joint_state_problem(sec + 61, 0, [1.0], NOW) == STAMPED_AHEAD
    assert joint_state_problem(sec + 59, 0, [1.0], NOW) is None  # clocks a little apart
    assert joint_state_problem(2**31 - 1, 0, [1.0], NOW) == STAMPED_AHEAD
    assert joint_state_problem(sec, 0, [1e300], NOW) == OUT_OF_RANGE
    assert joint_state_problem(sec, 0, [0.0, math.nan], NOW) == NOT_FINITE
    # Wheel velocities (velocity feedback) are held to the wheel speeds' bound, not the angles'.
    assert joint_state_problem(sec, 0, [-MAX_WHEEL_SPEED], NOW, velocity=True) is None
    assert joint_state_problem(sec, 0, [1.01 * MAX_WHEEL_SPEED], NOW, velocity=True) == (
        OUT_OF_RANGE
    )
    assert joint_state_problem(sec, 0, [1.01 * MAX_WHEEL_SPEED], NOW) is None
    assert joint_state_problem(sec, 0, [math.inf], NOW, velocity=True) == NOT_FINITE
    assert joint_state_problem(sec + 61, 0, [1.0], NOW, velocity=True) == STAMPED_AHEAD
    assert MAX_STAMP_AHEAD_NS == 60 * 10**9
    refusals = Refusals()
    assert refusals.check(None)
    assert not refusals.check(OUT_OF_RANGE)
    assert not refusals.check(NOT_FINITE)
    assert not refusals.check(OUT_OF_RANGE)
    assert refusals.counts == {OUT_OF_RANGE: 2, NOT_FINITE: 1}
    assert refusals.total == 3


def test_a_pose_is_finite_in_range_and_a_rotation() -> None:
    sec = NOW // 10**9
    turned = (0.0, 0.0, math.sin(0.3), math.cos(0.3))
    assert pose_problem(sec, 0, (1.0, -MAX_COORDINATE, 0.0), turned, NOW) is None
    assert pose_problem(sec, 0, (2.0 * MAX_COORDINATE, 0.0, 0.0), turned, NOW) == OUT_OF_RANGE
    assert pose_problem(sec, 0, (math.nan, 0.0, 0.0), turned, NOW) == NOT_FINITE
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, math.inf), NOW) == NOT_FINITE
    # A zero quaternion is no rotation; a scaled one is not a unit rotation.
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), NOW) == OUT_OF_RANGE
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.08), NOW) == OUT_OF_RANGE
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.04), NOW) is None
    assert pose_problem(sec, -1, (0.0, 0.0, 0.0), turned, NOW) == BAD_STAMP
    assert pose_problem(sec + 61, 0, (0.0, 0.0, 0.0), turned, NOW) == STAMPED_AHEAD
    # A component beyond 1 + slack is out of range before the norm is looked at.
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.5), NOW) == OUT_OF_RANGE
    assert pose_problem(sec, 0, (0.0, 0.0, 0.0), (1.5, 0.0, 0.0, math.nan), NOW) == OUT_OF_RANGE


def test_a_planar_pose_asked_for_is_held_to_the_bounds_of_poses_and_angles() -> None:
    assert planar_pose_problem(MAX_COORDINATE, -MAX_COORDINATE, -MAX_RECORDED_ANGLE) is None
    assert planar_pose_problem(1.01 * MAX_COORDINATE, 0.0, 0.0) == OUT_OF_RANGE
    assert planar_pose_problem(0.0, -1.01 * MAX_COORDINATE, 0.0) == OUT_OF_RANGE
    assert planar_pose_problem(0.0, 0.0, 1.01 * MAX_RECORDED_ANGLE) == OUT_OF_RANGE
    assert planar_pose_problem(0.0, math.nan, 0.0) == NOT_FINITE
    assert planar_pose_problem(0.0, 0.0, -math.inf) == NOT_FINITE


@pytest.mark.parametrize("check", ["joint state", "pose"])
def test_stamps_are_refused_at_the_edges_of_their_ranges(check: str) -> None:
    def problem(sec: int, nanosec: int, now: int | None = NOW) -> str | None:
        if check == "pose":
            return pose_problem(sec, nanosec, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), now)
        return joint_state_problem(sec, nanosec, [0.0], now)

    sec = NOW // 10**9
    assert problem(sec, 999_999_999) is None
    assert problem(sec, 1_000_000_000) == BAD_STAMP
    # ROS time starts at 0 (simulated time too); a negative second is no time at all.
    assert problem(0, 0) is None
    assert problem(-1, 999_999_999) == BAD_STAMP
    assert problem(-(2**31), 0) == BAD_STAMP
    # Ahead by exactly the most allowed is taken; a nanosecond more is not.
    edge = NOW + MAX_STAMP_AHEAD_NS - 7
    assert problem(edge // 10**9, edge % 10**9, NOW - 7) is None
    assert problem(edge // 10**9, edge % 10**9 + 1, NOW - 7) == STAMPED_AHEAD
    odd = NOW + MAX_STAMP_AHEAD_NS + 123_456_789
    assert problem(odd // 10**9, odd % 10**9, NOW + 123_456_789) is None
    assert problem(odd // 10**9, odd % 10**9, NOW + 123_456_788) == STAMPED_AHEAD
    # Without a clock given, this machine's is read: now is taken, two minutes ahead is not.
    now_s = time.time_ns() // 10**9
    assert problem(now_s, 0, None) is None
    assert problem(now_s + 120, 0, None) == STAMPED_AHEAD


def joint_state(positions: list[float], ns: int) -> types.JointState:
    names = ["front_left_wheel_joint", "front_right_wheel_joint"]
    return types.JointState(types.Header(time_of(ns), ""), names, positions)


def test_odometry_skips_a_future_stamp_and_a_huge_angle_and_goes_on() -> None:
    t0 = time.time_ns() - 10 * 10**9
    with OdometryNode(BOT) as node, Node("probe") as probe:
        joint_states = probe.create_publisher(types.JointState, "joint_states")
        assert joint_states.wait_for_subscribers(PATIENCE)
        sent = [
            joint_state([0.0, 0.0], t0),
            joint_state([1.0, 1.0], t0 + 10**9),
            joint_state([5.0, 5.0], (2**31 - 1) * 10**9),  # year 2038: would block the rest
            joint_state([1e300, 1e300], t0 + 2 * 10**9),  # would make the pose NaN for good
            joint_state([2.0, 2.0], t0 + 3 * 10**9),
            joint_state([3.0, 3.0], t0 + 4 * 10**9),
        ]
        for message in sent:
            joint_states.publish(message)
            node.spin_once()
        until(node, lambda: node.counts["received"] == len(sent))
    assert node.counts == {
        "received": 6,
        "used": 4,
        "published": 4,
        STAMPED_AHEAD: 1,
        OUT_OF_RANGE: 1,
    }
    assert node.status() == (
        "6 joint states, 4 used, 4 published; skipped: 1 stamped in the future, 1 out of range"
    )
    # Three radians of each wheel forward, as the good messages say: 3 r.
    assert node.odometry.pose.x == pytest.approx(3 * BOT.wheel_radius, abs=1e-12)
    assert math.isfinite(node.odometry.pose.y)


def test_ik_refuses_a_twist_of_1e308_and_keeps_working() -> None:
    left: list[list[float]] = []
    with InverseKinematicsNode(BOT, IkSettings(timeout=0.0)) as node, Node("probe") as probe:
        graph = (node, probe)
        cmd_vel = probe.create_publisher(types.Twist, "cmd_vel")
        probe.create_subscription(
            types.Float64MultiArray, LEFT_TOPIC, lambda m: left.append(list(m.data)), DEEP
        )
        assert cmd_vel.wait_for_subscribers(PATIENCE)
        until(graph, lambda: node.left.subscription_count > 0)
        cmd_vel.publish(twist_command(0.07, 0.0))
        until(graph, lambda: len(left) == 1)
        cmd_vel.publish(twist_command(1e308, 0.0))
        until(graph, lambda: len(left) == 2)
        cmd_vel.publish(twist_command(-1e3, 0.0))  # the fastest taken: finite on a robot
        until(graph, lambda: len(left) == 3)  # without a motor limit
    assert left[0] == pytest.approx([2.0])
    assert left[1] == [0.0]  # refused: the wheels stop
    assert left[2] == pytest.approx([-1e3 / BOT.wheel_radius])
    assert all(math.isfinite(v) for values in left for v in values)
    assert node.status() == "3 commands, 1 refused (1 out of range), 0 timeouts, 0 malformed"


def test_robot_refuses_out_of_range_commands_and_keeps_working() -> None:
    settings = RobotSettings(rate=100.0, timeout=0.0)
    with RobotNode(BOT, None, settings) as robot, Node("probe") as probe:
        graph = (robot, probe)
        left = probe.create_publisher(types.Float64MultiArray, LEFT_TOPIC)
        right = probe.create_publisher(types.Float64MultiArray, RIGHT_TOPIC)
        assert left.wait_for_subscribers(PATIENCE)
        assert right.wait_for_subscribers(PATIENCE)
        left.publish(commands([1e300]))
        right.publish(commands([2.0]))
        until(graph, lambda: sum(s.received for s in robot.subscriptions) == 2)
        assert robot.velocities == {"front_left_wheel_joint": 0.0, "front_right_wheel_joint": 2.0}
        left.publish(commands([3.0]))
        until(graph, lambda: sum(s.received for s in robot.subscriptions) == 3)
        assert robot.velocities["front_left_wheel_joint"] == 3.0
        until(graph, lambda: robot.updates > 3)
    assert robot.refusals.counts == {OUT_OF_RANGE: 1}
    assert robot.status().endswith("3 commands, 1 refused, 0 timeouts, 0 malformed")
    assert all(math.isfinite(p) for p in robot.positions.values())


def test_robot_refuses_a_twist_of_1e308() -> None:
    settings = RobotSettings(rate=100.0, timeout=0.0, cmd_vel="cmd_vel")
    with RobotNode(BOT, None, settings) as robot, Node("probe") as probe:
        graph = (robot, probe)
        cmd_vel = probe.create_publisher(types.Twist, "cmd_vel")
        assert cmd_vel.wait_for_subscribers(PATIENCE)
        cmd_vel.publish(twist_command(0.07, 0.0))
        until(graph, lambda: robot.velocities["front_left_wheel_joint"] == pytest.approx(2.0))
        cmd_vel.publish(twist_command(1e308, 0.0))
        until(graph, lambda: robot.refused == 1)
        assert robot.velocities["front_left_wheel_joint"] == 0.0
        until(graph, lambda: robot.updates > 3)
    assert robot.refusals.counts == {OUT_OF_RANGE: 1}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["node", "odom", "--publish-rate", "5e-324"],
            "error: Invalid value for '--publish-rate': '5e-324' must be >= 1e-06",
        ),
        (["node", "ik", "--rate", "5e-324"], "error: Invalid value for '--rate': '5e-324'"),
        (["node", "robot", "--rate", "5e-324"], "error: Invalid value for '--rate': '5e-324'"),
        (["drive", "straight 0.1", "--rate", "5e-324"], "error: Invalid value for '--rate'"),
        (["node", "ik", "--timeout", "1e308"], "error: Invalid value for '--timeout'"),
    ],
)
def test_rates_out_of_range_are_one_error_line(args: list[str], message: str) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", *args, "--duration", "0.1"]
        if args[0] == "node"
        else [sys.executable, "-m", "diffbot", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.startswith(message), done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
