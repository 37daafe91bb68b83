"""diffbot.fleet on its own: its messages name library parameters, never command-line flags."""

from __future__ import annotations

from pathlib import Path

import pytest

from diffbot.cli import FLAGS
from diffbot.errors import RecordingError
from diffbot.fleet import OdometryTask, dask_address, run_task
from diffbot.kinematics import DiffDriveParams


@pytest.mark.parametrize(
    ("address", "reason"),
    [
        ("ftp://host:1", "unknown scheme"),
        ("inproc://", "an inproc address names HOST/PID/N"),
        ("tcp://:8786", "the host is missing or malformed"),
        ("tcp://host:99999", "the port must be a number from 1 to 65535"),
    ],
)
def test_a_malformed_address_is_named_by_its_library_parameter(address: str, reason: str) -> None:
    with pytest.raises(RecordingError, match=reason) as caught:
        dask_address(address)
    assert str(caught.value).startswith("dask_address= ")
    assert "--dask" not in str(caught.value)
    assert caught.value.render(FLAGS.__getitem__).startswith("--dask ")


@pytest.mark.parametrize(
    ("address", "expected"),
    [
        ("host", "tcp://host:8786"),
        ("tls://10.0.0.2:9000", "tls://10.0.0.2:9000"),
        ("tcp://[::1]:8786", "tcp://[::1]:8786"),
    ],
)
def test_a_good_address_is_completed_as_dask_does(address: str, expected: str) -> None:
    assert dask_address(address) == expected


def test_a_task_integrates_the_feedback_or_the_commands_it_names(tmp_path: Path) -> None:
    robot = DiffDriveParams(
        wheel_radius=0.05, wheel_separation=0.2, left_joint="l", right_joint="r"
    )
    velocities = tmp_path / "v.csv"
    velocities.write_text("t,/js/l/velocity,/js/r/velocity\n0,0,0\n1,2,2\n")
    run = run_task(OdometryTask(str(velocities), robot, feedback="velocity")).run
    assert run is not None
    assert run.summary.final_pose.x == pytest.approx(0.1, abs=1e-15)
    commands = tmp_path / "c.csv"
    commands.write_text("t,v,w\n0,0.3,0\n1,0,0\n")
    run = run_task(OdometryTask(str(commands), robot, open_loop=True)).run
    assert run is not None
    assert run.summary.final_pose.x == pytest.approx(0.3, abs=1e-15)
    stdin = run_task(OdometryTask("-", robot, open_loop=True)).error
    assert stdin is not None
    assert stdin.render(FLAGS.__getitem__) == "--open-loop reads a bag or a CSV file, not stdin"
