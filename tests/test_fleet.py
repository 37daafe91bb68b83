"""diffbot.fleet on its own: its messages name library parameters, never command-line flags."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from diffbot.cli import FLAGS
from diffbot.errors import RecordingError
from diffbot.fleet import OdometryTask, dask_address, run_task, run_tasks
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


def test_results_left_unread_stop_the_pool_and_their_tasks(tmp_path: Path) -> None:
    # A run that ends early (Ctrl-C, SIGTERM, an error while reading the results) leaves the
    # tasks not yet done undone: no output of theirs appears, half written or whole.
    robot = DiffDriveParams(
        wheel_radius=0.05, wheel_separation=0.2, left_joint="l", right_joint="r"
    )
    rows = "".join(f"{k / 100},{k / 10},{k / 9}\n" for k in range(200_000))
    tasks = []
    for number in range(12):
        recording = tmp_path / f"r{number}.csv"
        recording.write_text("t,l,r\n" + rows)
        tasks.append(OdometryTask(str(recording), robot, output=str(tmp_path / f"o{number}.csv")))
    results = run_tasks(tasks, jobs=2)
    assert next(results).error is None
    results.close()
    written = sorted(path.name for path in tmp_path.glob("o*"))
    assert "o0.csv" in written
    assert len(written) < 6, written
    assert not [path.name for path in tmp_path.iterdir() if path.name.startswith(".")]


def test_ctrl_c_ends_a_run_of_several_processes_at_once(tmp_path: Path) -> None:
    # Ctrl-C reaches every process of the group: the workers leave it to the run, which stops
    # them; one taken in a worker mid-task left the pool waiting for it forever.
    rows = "".join(f"{k / 100},{k / 10},{k / 9}\n" for k in range(200_000))
    recordings = []
    for number in range(8):
        recording = tmp_path / f"r{number}.csv"
        recording.write_text("t,front_left_wheel_joint,front_right_wheel_joint\n" + rows)
        recordings.append(str(recording))
    out = tmp_path / "poses"
    command = [sys.executable, "-m", "diffbot", "odom", *recordings, "-j", "2", "-o", str(out)]
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # Ctrl-C as on a terminal, whatever the test runner ignores.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        end = time.monotonic() + 60
        while not (out.is_dir() and any(out.iterdir())) and time.monotonic() < end:
            time.sleep(0.05)
        time.sleep(0.3)  # the workers are in their tasks
        os.killpg(process.pid, signal.SIGINT)
        _, err = process.communicate(timeout=30)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130, err
    assert err.strip().splitlines()[-1] == "error: aborted"
    assert len(list(out.iterdir())) < len(recordings)
    assert not [path.name for path in out.iterdir() if path.name.startswith(".")]
