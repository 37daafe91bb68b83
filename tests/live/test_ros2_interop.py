"""diffbot's nodes against the real ROS 2 command-line tools (``ros2 topic pub``, ``ros2 topic
echo``, ``ros2 topic info``): the same wire format seen from a stock ROS 2 install. These run only
where ``ros2`` is on the PATH (a sourced Humble or Jazzy); elsewhere they are skipped and say why.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest
from live_graph import PATIENCE, live_process

pytestmark = pytest.mark.skipif(
    shutil.which("ros2") is None,
    reason="ros2 is not on the PATH: these checks need a sourced ROS 2 install (Humble, Jazzy)",
)


def ros2(*args: str, timeout: float = PATIENCE) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        ["ros2", *args],
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        timeout=timeout,
        check=False,
    )


def test_ros2_tools_see_diffbots_odometry() -> None:
    joint_state = (
        "{header: {stamp: now}, name: [front_left_wheel_joint, front_right_wheel_joint], "
        "position: [1.0, 1.0]}"
    )
    with live_process("node", "odom"):
        echo = subprocess.Popen(
            ["ros2", "topic", "echo", "--once", "/odom", "nav_msgs/msg/Odometry"],
            stdout=subprocess.PIPE,
            text=True,
            env=os.environ.copy(),
        )
        published = ros2(
            "topic",
            "pub",
            "--times",
            "20",
            "--rate",
            "10",
            "/joint_states",
            "sensor_msgs/msg/JointState",
            joint_state,
        )
        assert published.returncode == 0, published.stderr
        out, _ = echo.communicate(timeout=PATIENCE)
        assert "frame_id: odom" in out
        assert "child_frame_id: base_link" in out
        info = ros2("topic", "info", "-v", "/odom")
        assert "nav_msgs/msg/Odometry" in info.stdout
        assert "RELIABLE" in info.stdout


def test_ros2_tools_see_a_drive() -> None:
    echo = subprocess.Popen(
        ["ros2", "topic", "echo", "--once", "/cmd_vel", "geometry_msgs/msg/Twist"],
        stdout=subprocess.PIPE,
        text=True,
        env=os.environ.copy(),
    )
    driven = subprocess.run(
        [sys.executable, "-m", "diffbot", "drive", "straight 0.1 1s", "--wait", str(PATIENCE)],
        capture_output=True,
        text=True,
        env=os.environ.copy(),
        timeout=60,
        check=False,
    )
    out, _ = echo.communicate(timeout=PATIENCE)
    assert driven.returncode == 0, driven.stderr
    assert "x: 0.1" in out
