"""The live commands at the edges: bad input is one error line, a node ends on a signal with its
counts, the missing extra is named."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path


def test_a_bad_domain_is_one_error_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "node", "odom"],
        capture_output=True,
        text=True,
        env={"ROS_DOMAIN_ID": "300", "PATH": "/usr/bin:/bin"},
        timeout=60,
        check=False,
    )
    assert done.returncode == 2
    assert done.stderr == "error: ROS_DOMAIN_ID must be a whole number from 0 to 232, got '300'\n"


def test_without_cyclonedds_the_live_commands_say_how_to_install_it() -> None:
    probe = (
        "import sys; sys.modules['cyclonedds'] = None\n"
        "from diffbot.cli import main\n"
        "main(['node', 'odom'])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=False
    )
    assert done.returncode == 2
    assert done.stderr == (
        "error: the live commands need cyclonedds (DDS for Python): "
        "pip install 'diffbot-kinematics[live]'\n"
    )


def test_a_plan_over_the_motor_limit_is_refused_before_anything_moves() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "diffbot", "drive", "straight 1 1s", "--wait", "0"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1
    assert done.stderr == (
        "error: segment 1 (straight 1 m, 1 s): left and right wheels at 272.8 rpm exceed the "
        "50 rpm limit; shortest duration that fits: 5.457 s\n"
    )


def test_the_controllers_file_names_the_command_topics(tmp_path: Path) -> None:
    from diffbot.commands.node import command_topics
    from diffbot.urdf import load_params

    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(
        "left_side:\n  ros__parameters:\n    joints: [front_left_wheel_joint]\n"
        "right_side:\n  ros__parameters:\n    joints: [front_right_wheel_joint]\n"
    )
    params = load_params()
    assert command_topics(str(controllers), params) == ("left_side/commands", "right_side/commands")
    assert command_topics(None, params) == (
        "left_wheel_velocity_controller/commands",
        "right_wheel_velocity_controller/commands",
    )
