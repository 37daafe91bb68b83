"""The live commands at the edges: bad input is one error line, a node ends on a signal with its
counts, the missing extra is named."""

from __future__ import annotations

import subprocess
import sys


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
