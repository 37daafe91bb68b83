"""The course's loop end to end on loopback: ``node robot``, ``node ik``, ``node odom`` and
``drive`` of a short plan, as four processes and as four nodes in one process. The odometry at
the end equals the plan's exact final pose, and the robot's ground truth, within a tolerance
derived from the rates.

Where the tolerance comes from: the drive's commands, each held for its period, trace the plan
exactly; what moves the end is when each command takes effect on the robot. The robot applies a
command from its last update (up to one update period early) or later by the transport's latency
(two hops: drive -> ik -> robot), so each command boundary shifts by at most
``D = 1 / robot_rate + LATENCY``. The shifts telescope over a run of equal commands, so the
position ends off by at most ``D`` times the sum of the linear speed's jumps, the heading by
``D`` times the sum of the angular speed's jumps (the plan ends with its spin, so the heading error
does not swing the position). Odometry and ground truth integrate the same wheel angles, so they
agree to rounding.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from collections.abc import Callable
from contextlib import ExitStack

import numpy as np
import pytest
from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsSubscription
from live_graph import PATIENCE, live_process

from diffbot.live import types
from diffbot.live.drive import Driver, DriveSettings
from diffbot.live.inverse_kinematics import InverseKinematicsNode
from diffbot.live.messages import stamp_ns, yaw_of
from diffbot.live.odometry import OdometryNode
from diffbot.live.robot import RobotNode
from diffbot.live.transport import Node
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits
from diffbot.ramps import ramp
from diffbot.trajectory import plan
from diffbot.urdf import load_params
from diffbot.urdf.xacro import expand

PLAN = "straight 0.1 1s; spin 90 1s"
DRIVE_RATE = 20.0
ROBOT_RATE = 100.0
#: The most a command is allowed to take from drive to robot on a loaded machine (s).
LATENCY = 0.03


class Watcher:
    """The test's node: the last odometry and ground truth, and who is on the graph."""

    def __init__(self, node: Node) -> None:
        self.odom: types.Odometry | None = None
        self.truth: types.Odometry | None = None
        node.create_subscription(types.Odometry, "odom", self._odom)
        node.create_subscription(types.Odometry, "ground_truth/odom", self._truth)
        self.subscriptions = BuiltinDataReader(node.participant, BuiltinTopicDcpsSubscription)
        self.node = node

    def _odom(self, message: types.Odometry) -> None:
        self.odom = message

    def _truth(self, message: types.Odometry) -> None:
        self.truth = message

    def subscribed(self, topic: str) -> bool:
        """Whether some node subscribes the ROS topic ``topic``."""
        name = "rt/" + topic
        return any(s.topic_name == name for s in self.subscriptions.read(N=4096))

    def until(self, condition: Callable[[], bool]) -> None:
        end = time.monotonic() + PATIENCE
        while not condition() and time.monotonic() < end:
            self.node.spin_once(0.02)
        assert condition(), "the graph did not get there in time"

    def settled_after(self, ns: int) -> None:
        """Wait until odometry and ground truth stamped after ``ns`` arrived."""

        def after() -> bool:
            return (
                self.odom is not None
                and self.truth is not None
                and stamp_ns(self.odom.header.stamp) > ns
                and stamp_ns(self.truth.header.stamp) > ns
            )

        self.until(after)


def check_final_pose(watcher: Watcher) -> None:
    params = load_params()
    p = plan(parse_plan(PLAN), params)
    stream = ramp(p, Limits()).commands(DRIVE_RATE)
    delay = 1.0 / ROBOT_RATE + LATENCY
    position_tolerance = delay * float(np.sum(np.abs(np.diff(stream.linear, prepend=0.0))))
    heading_tolerance = delay * float(np.sum(np.abs(np.diff(stream.angular, prepend=0.0))))
    assert watcher.odom is not None
    assert watcher.truth is not None
    odom, truth = watcher.odom.pose.pose, watcher.truth.pose.pose
    expected = p.final_pose
    error = math.hypot(odom.position.x - expected.x, odom.position.y - expected.y)
    assert error <= position_tolerance, (error, position_tolerance)
    turn = math.remainder(yaw_of(odom.orientation) - expected.theta, math.tau)
    assert abs(turn) <= heading_tolerance, (turn, heading_tolerance)
    # Odometry integrates the very wheel angles the ground truth does.
    assert odom.position.x == pytest.approx(truth.position.x, abs=1e-9)
    assert odom.position.y == pytest.approx(truth.position.y, abs=1e-9)
    assert math.remainder(yaw_of(odom.orientation) - yaw_of(truth.orientation), math.tau) == (
        pytest.approx(0.0, abs=1e-9)
    )


def test_the_loop_as_four_processes() -> None:
    with ExitStack() as stack:
        watcher = Watcher(stack.enter_context(Node("watcher")))
        robot = stack.enter_context(live_process("node", "robot", "--rate", str(ROBOT_RATE)))
        ik = stack.enter_context(live_process("node", "ik"))
        odom = stack.enter_context(live_process("node", "odom"))
        watcher.until(lambda: watcher.odom is not None and watcher.truth is not None)
        watcher.until(lambda: watcher.subscribed("left_wheel_velocity_controller/commands"))
        watcher.until(lambda: watcher.subscribed("cmd_vel"))
        driven = subprocess.run(
            [sys.executable, "-m", "diffbot", "drive", PLAN, "--rate", str(DRIVE_RATE)],
            capture_output=True,
            text=True,
            env=os.environ.copy(),
            timeout=60,
            check=False,
        )
        assert driven.returncode == 0, driven.stderr
        assert driven.stderr.startswith(
            "drove plan: 41 commands at 20 Hz over 2 s, ending with zero"
        )
        watcher.settled_after(time.time_ns())
        check_final_pose(watcher)
        for process in (robot, ik, odom):
            assert process.poll() is None, process.stderr.read() if process.stderr else ""


def test_the_loop_in_one_process() -> None:
    params = load_params()
    description = expand().urdf
    stream = ramp(plan(parse_plan(PLAN), params), Limits()).commands(DRIVE_RATE)
    from diffbot.live.robot import RobotSettings

    with (
        Node("watcher") as watcher_node,
        RobotNode(params, description, RobotSettings(rate=ROBOT_RATE)).start() as robot,
        InverseKinematicsNode(params).start(),
        OdometryNode(params).start() as odom,
        Driver(stream, DriveSettings()) as driver,
    ):
        watcher = Watcher(watcher_node)
        watcher.until(lambda: watcher.odom is not None and watcher.truth is not None)
        watcher.until(lambda: all(s.publisher_count > 0 for s in robot.subscriptions))
        assert driver.wait_for_subscriber(PATIENCE)
        report = driver.drive()
        assert report.completed
        watcher.settled_after(time.time_ns())
        check_final_pose(watcher)
        assert odom.counts["used"] == odom.counts["received"], odom.counts
