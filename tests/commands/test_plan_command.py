"""`diffbot plan`: every output format, the limit check, files, and bad input."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import shutil
import signal
import stat
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import yaml
from cli_results import assert_one_error_line as assert_bad_input
from click.testing import CliRunner, Result
from hypothesis import given
from hypothesis import strategies as st

from diffbot import EXAMPLES, DiffDriveParams, parse_plan, plan
from diffbot.cli import main
from diffbot.commands.plan_options import PLAN_FORMATS
from diffbot.formats.text import ceil_text
from diffbot.ros.messages import yaml_float

Write = Callable[[str, str], Path]


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["plan", *args])


# --------------------------------------------------------------------------------------------
# table


def test_the_wide_table_of_trajectory_A(runner: CliRunner) -> None:
    result = run(runner, "--wide")
    assert result.exit_code == 0, result.output
    out = result.stdout
    assert out.startswith(f"Trajectory A: {EXAMPLES['A']}\n")
    assert "motor limit 50 rpm (5.23599 rad/s)" in out
    rows = [line.split() for line in out.splitlines() if line[:1].isdigit()]
    assert [row[0] for row in rows] == ["1", "2", "3", "4"]
    assert rows[0][1:6] == ["ccw", "arc", "r", "0.25", "m"]
    # v, w, left rad/s, rpm, right rad/s, rpm, %, time, x, y, theta
    assert rows[0][8:] == [
        "0.0785",
        "0.3142",
        "1.638",
        "15.64",
        "2.850",
        "27.21",
        "54.4",
        "10",
        "0.0000",
        "0.5000",
        "180.00",
    ]
    assert rows[1][4:] == [
        "0.1000",
        "0.0000",
        "2.857",
        "27.28",
        "2.857",
        "27.28",
        "54.6",
        "10",
        "-1.0000",
        "0.5000",
        "180.00",
    ]
    assert "total 40 s; final pose x 0.0000 m, y 1.0000 m, theta 0.00 deg" in out
    assert "within, peak 54.6% in segment 2" in out
    assert result.stderr == ""


def test_example_B_table(runner: CliRunner) -> None:
    result = run(runner, "--example", "b")
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith(f"Trajectory B: {EXAMPLES['B']}\n")
    assert "final pose x 0.0000 m, y 1.0000 m, theta 0.00 deg" in result.stdout


def test_fastest_table_runs_every_segment_at_the_limit(runner: CliRunner) -> None:
    result = run(runner, "--fastest")
    assert result.exit_code == 0, result.output
    rows = [line.split() for line in result.stdout.splitlines() if line[:1].isdigit()]
    assert [row[-5] for row in rows] == ["100.0"] * 4
    assert "total 21.7992 s" in result.stdout


#: A robot whose description gives no motor limit.
NO_LIMIT_URDF = """<robot name="r">
  <link name="base_link"/>
  <link name="l"><collision><origin rpy="1.5707963 0 0"/>
    <geometry><cylinder radius="0.05" length="0.02"/></geometry></collision></link>
  <link name="r"><collision><origin rpy="1.5707963 0 0"/>
    <geometry><cylinder radius="0.05" length="0.02"/></geometry></collision></link>
  <joint name="left_joint" type="continuous"><parent link="base_link"/><child link="l"/>
    <origin xyz="0 0.1 0"/><axis xyz="0 1 0"/></joint>
  <joint name="right_joint" type="continuous"><parent link="base_link"/><child link="r"/>
    <origin xyz="0 -0.1 0"/><axis xyz="0 1 0"/></joint>
</robot>
"""


def test_fastest_without_a_limit_is_bad_input(runner: CliRunner, write: Write) -> None:
    urdf = write("nolimit.urdf", NO_LIMIT_URDF)
    result = run(runner, "--robot", str(urdf), "--fastest")
    assert_bad_input(result, "--fastest needs a motor limit", "--max-rpm")
    assert "limit=" not in result.stderr
    data = plan_json(runner, "--robot", str(urdf), "--fastest", "--max-rpm", "30", "straight 1")
    assert data["segments"][0]["left_rpm"] == pytest.approx(30.0, rel=1e-9)
    result = run(runner, "--robot", str(urdf), "straight 1 1s")
    assert result.exit_code == 0, result.output
    assert "motor limit: none in the description, not checked" in result.stdout


@pytest.mark.parametrize(
    "command",
    [["simulate"], ["explain", "plan"], ["plot", "-o", "figure.png"], ["drive", "--wait", "0"]],
)
def test_every_plan_command_names_the_option_for_a_missing_limit(
    runner: CliRunner, write: Write, command: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    urdf = write("nolimit.urdf", NO_LIMIT_URDF)
    args = [*command, "--robot", str(urdf), "--fastest", "straight 1"]
    monkeypatch.chdir(urdf.parent)  # where plot would write its figure
    result = runner.invoke(main, args)
    assert_bad_input(result, "--fastest needs a motor limit", "--max-rpm")
    assert "limit=" not in result.stderr


# --------------------------------------------------------------------------------------------
# json and csv


def plan_json(runner: CliRunner, *args: str) -> dict[str, Any]:
    result = run(runner, "--json", *args)
    assert result.exit_code == 0, result.output
    data: dict[str, Any] = json.loads(result.stdout)
    return data


def test_json_holds_every_segment_and_the_robot(runner: CliRunner, params: DiffDriveParams) -> None:
    data = plan_json(runner)
    expected = plan(parse_plan(EXAMPLES["A"]), params)
    assert data["plan"] == EXAMPLES["A"]
    assert data["duration"] == 40.0
    assert data["within_limit"] is True
    assert data["violations"] == []
    assert data["final_pose"]["y"] == pytest.approx(1.0, abs=1e-12)
    assert data["limit_rpm"] == pytest.approx(50.0, rel=1e-12)
    assert data["robot"] == {
        "wheel_radius": 0.035,
        "wheel_separation": 0.135,
        "left_joint": "front_left_wheel_joint",
        "right_joint": "front_right_wheel_joint",
        "left_sign": 1,
        "right_sign": 1,
        "max_wheel_speed": params.max_wheel_speed,
        "max_wheel_rpm": params.max_wheel_rpm,
        "source": "bundled diffbot",
    }
    assert [s["kind"] for s in data["segments"]] == ["ccw", "straight", "cw", "straight"]
    for got, want in zip(data["segments"], expected.segments, strict=True):
        assert got["duration"] == want.duration
        assert got["linear"] == want.twist.linear
        assert got["angular"] == want.twist.angular
        assert got["left"] == want.joints.left
        assert got["right"] == want.joints.right
        assert got["left_rpm"] == pytest.approx(float(want.joints.left) * 60 / (2 * math.pi))
        assert got["end_pose"] == {
            "x": want.end_pose.x,
            "y": want.end_pose.y,
            "theta": want.end_pose.theta,
        }
        assert got["fraction"] == want.fraction
    assert data["segments"][0]["description"] == "ccw arc r 0.25 m 180 deg"


def test_json_flag_and_format_json_agree(runner: CliRunner) -> None:
    flag, option = run(runner, "--json"), run(runner, "--format", "json")
    assert flag.exit_code == option.exit_code == 0
    assert flag.stdout == option.stdout


def test_json_and_another_format_conflict(runner: CliRunner) -> None:
    assert_bad_input(run(runner, "--json", "--format", "csv"), "--json", "csv")


def test_csv_has_a_header_and_one_row_per_segment(runner: CliRunner) -> None:
    result = run(runner, "--format", "csv", "--example", "B")
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert [row["kind"] for row in rows] == ["straight", "ccw", "straight", "cw"]
    assert [row["spec"] for row in rows] == [s.strip() for s in EXAMPLES["B"].split(";")]
    assert float(rows[0]["left"]) == pytest.approx(0.1 / 0.035, rel=1e-15)
    assert float(rows[3]["angular"]) == pytest.approx(-math.pi / 10, rel=1e-15)
    assert float(rows[3]["y"]) == pytest.approx(1.0, abs=1e-12)
    assert float(rows[1]["fraction"]) == pytest.approx(0.5442857142857142, rel=1e-12)


# --------------------------------------------------------------------------------------------
# twist and wheels


def test_twist_lines_are_the_seeds_messages_with_durations(runner: CliRunner) -> None:
    result = run(runner, "--format", "twist")
    assert result.exit_code == 0, result.output
    lines = [line for line in result.stdout.splitlines() if not line.startswith("#")]
    messages = [yaml.safe_load(line.split("  #")[0]) for line in lines]
    assert messages[0] == {"linear": {"x": math.pi / 40}, "angular": {"z": math.pi / 10}}
    assert messages[1] == {"linear": {"x": 0.1}, "angular": {"z": 0.0}}
    assert messages[2]["angular"]["z"] == -math.pi / 10
    assert messages[-1] == {"linear": {"x": 0.0}, "angular": {"z": 0.0}}
    assert len(messages) == 5
    assert lines[0].endswith("# 1/4 ccw arc r 0.25 m 180 deg, 10 s")
    assert lines[-1].endswith("# stop")
    assert "cmd_vel" in result.stdout


def test_wheels_lines_name_the_topics(runner: CliRunner) -> None:
    result = run(runner, "--format", "wheels", "--left-topic", "/l/commands")
    assert result.exit_code == 0, result.output
    commands = [line.split(None, 1) for line in result.stdout.splitlines() if line[:1] != "#"]
    assert [topic for topic, _ in commands] == [
        "/l/commands",
        "right_wheel_velocity_controller/commands",
    ] * 5
    values = [yaml.safe_load(message)["data"][0] for _, message in commands]
    assert [round(v, 2) for v in values[:8]] == [1.64, 2.85, 2.86, 2.86, 2.85, 1.64, 2.86, 2.86]
    assert values[8:] == [0.0, 0.0]
    assert "# 2/4 straight 1 m, 10 s" in result.stdout
    assert "std_msgs/msg/Float64MultiArray" in result.stdout


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_yaml_floats_are_read_back_as_the_same_float(value: float) -> None:
    assert yaml.safe_load(yaml_float(value)) == value
    assert isinstance(yaml.safe_load(yaml_float(value)), float)


# --------------------------------------------------------------------------------------------
# ros2 script

SHELLS = [shell for shell in ("sh", "bash") if shutil.which(shell)]
REAL_SLEEP = shutil.which("sleep") or "sleep"


@dataclass(frozen=True)
class Fakes:
    """Logs of the fake ``ros2`` and ``sleep`` a script ran with."""

    env: dict[str, str]
    calls: Path
    sleeps: Path
    pids: Path

    def call_lines(self) -> list[str]:
        return self.calls.read_text().splitlines() if self.calls.exists() else []


def make_fakes(directory: Path, *, fail: bool = False, sleep_for: float | None = None) -> Fakes:
    """A ``ros2`` that logs its arguments (one line per call) and, when it publishes at a rate,
    runs until killed like the real one (or fails at once with ``fail``); and a ``sleep`` that
    logs its argument and sleeps ``sleep_for`` s instead (the real duration when None)."""
    bin_dir = directory / "bin"
    bin_dir.mkdir()
    fakes = Fakes(
        {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"},
        directory / "calls",
        directory / "sleeps",
        directory / "pids",
    )
    ros2 = bin_dir / "ros2"
    ros2.write_text(
        "#!/bin/sh\n"
        f'printf "%s\\n" "$*" >> {fakes.calls}\n'
        'case "$*" in *--once*) exit 0 ;; esac\n'
        + ("exit 3\n" if fail else f'echo "$$" >> {fakes.pids}\nexec {REAL_SLEEP} 60\n'),
        encoding="utf-8",
    )
    sleep = bin_dir / "sleep"
    sleep.write_text(
        "#!/bin/sh\n"
        f'printf "%s\\n" "$1" >> {fakes.sleeps}\n'
        f"exec {REAL_SLEEP} {'$1' if sleep_for is None else sleep_for}\n",
        encoding="utf-8",
    )
    for fake in (ros2, sleep):
        fake.chmod(0o755)
    return fakes


def running(pid: int) -> bool:
    """Whether a process runs (a zombie does not), from /proc."""
    try:
        stat_line = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat_line.rsplit(")", 1)[1].split()[0] != "Z"


def ros2_script(runner: CliRunner, tmp_path: Path, *args: str) -> Path:
    script = tmp_path / "run.sh"
    result = run(runner, "--format", "ros2", "-o", str(script), *args)
    assert result.exit_code == 0, result.output
    return script


TWIST = "cmd_vel geometry_msgs/msg/Twist"
ARRAY = "std_msgs/msg/Float64MultiArray"


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
@pytest.mark.parametrize("shell", SHELLS)
def test_ros2_script_is_valid_sh_and_publishes_each_twist_then_zero(
    runner: CliRunner, tmp_path: Path, shell: str
) -> None:
    script = ros2_script(runner, tmp_path)
    assert script.read_text().startswith("#!/bin/sh\n")
    assert os.stat(script).st_mode & stat.S_IXUSR
    subprocess.run([shell, "-n", str(script)], check=True)
    fakes = make_fakes(tmp_path, sleep_for=0.2)
    subprocess.run([shell, str(script)], check=True, env=fakes.env, timeout=30)
    assert fakes.call_lines() == [
        f"topic pub -r 10 {TWIST} {{linear: {{x: 0.07853981633974483}}, "
        "angular: {z: 0.3141592653589793}}",
        f"topic pub -r 10 {TWIST} {{linear: {{x: 0.1}}, angular: {{z: 0.0}}}}",
        f"topic pub -r 10 {TWIST} {{linear: {{x: 0.07853981633974483}}, "
        "angular: {z: -0.3141592653589793}}",
        f"topic pub -r 10 {TWIST} {{linear: {{x: 0.1}}, angular: {{z: 0.0}}}}",
        f"topic pub --once {TWIST} {{linear: {{x: 0.0}}, angular: {{z: 0.0}}}}",
    ]
    assert fakes.sleeps.read_text().split() == ["10"] * 4
    publishers = [int(pid) for pid in fakes.pids.read_text().split()]
    assert len(publishers) == 4
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(running(pid) for pid in publishers):
        time.sleep(0.02)
    assert not any(running(pid) for pid in publishers)


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
def test_ros2_script_holds_each_segment_for_exactly_its_duration(
    runner: CliRunner, tmp_path: Path
) -> None:
    script = ros2_script(
        runner,
        tmp_path,
        "straight 1; spin 90 0.01s; straight 1 5.4567409060078s; spin 1e-7 1e-10s",
        "--rate",
        "20",
        "--max-rpm",
        "90000",
    )
    text = script.read_text()
    assert " -t " not in text
    assert "for exactly the segment's duration, timed by 'sleep'" in text
    fakes = make_fakes(tmp_path, sleep_for=0.2)
    subprocess.run([SHELLS[0], str(script)], check=True, env=fakes.env, timeout=30)
    # the sleep's resolution is a nanosecond: durations are written to 9 decimals, no exponent
    assert fakes.sleeps.read_text().split() == ["10", "0.01", "5.456740906", "0"]
    calls = [line.split() for line in fakes.call_lines()]
    assert [call[2:4] for call in calls[:-1]] == [["-r", "20"]] * 4
    assert calls[-1][2] == "--once"


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
def test_ros2_script_takes_the_plans_time(runner: CliRunner, tmp_path: Path) -> None:
    script = ros2_script(runner, tmp_path, "straight 0.05 0.6s; spin 10 0.3s")
    fakes = make_fakes(tmp_path)
    start = time.monotonic()
    subprocess.run([SHELLS[0], str(script)], check=True, env=fakes.env, timeout=30)
    assert 0.9 <= time.monotonic() - start < 3.0
    assert len(fakes.call_lines()) == 3


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
def test_ros2_script_with_wheels_publishes_both_wheels_together_then_zero(
    runner: CliRunner, tmp_path: Path
) -> None:
    script = ros2_script(
        runner, tmp_path, "straight 1 10s; spin -90 2s", "--wheels", "--right-topic", "/r/cmd"
    )
    subprocess.run([SHELLS[0], "-n", str(script)], check=True)
    fakes = make_fakes(tmp_path, sleep_for=0.2)
    subprocess.run([SHELLS[0], str(script)], check=True, env=fakes.env, timeout=30)
    calls = fakes.call_lines()
    left, right = "left_wheel_velocity_controller/commands", "/r/cmd"
    spin = math.pi / 4 * 0.135 / 2 / 0.035
    assert sorted(calls[:2]) == [
        f"topic pub -r 10 {right} {ARRAY} {{data: [2.857142857142857]}}",
        f"topic pub -r 10 {left} {ARRAY} {{data: [2.857142857142857]}}",
    ]
    assert sorted(calls[2:4]) == [
        f"topic pub -r 10 {right} {ARRAY} {{data: [{-spin!r}]}}",
        f"topic pub -r 10 {left} {ARRAY} {{data: [{spin!r}]}}",
    ]
    assert sorted(calls[4:]) == [
        f"topic pub --once {right} {ARRAY} {{data: [0.0]}}",
        f"topic pub --once {left} {ARRAY} {{data: [0.0]}}",
    ]
    assert fakes.sleeps.read_text().split() == ["10", "2"]


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
@pytest.mark.parametrize("wheels", [False, True])
def test_ros2_script_stops_the_robot_when_a_publisher_fails(
    runner: CliRunner, tmp_path: Path, wheels: bool
) -> None:
    script = ros2_script(runner, tmp_path, *(["--wheels"] if wheels else []))
    fakes = make_fakes(tmp_path, fail=True, sleep_for=0.2)
    result = subprocess.run(
        [SHELLS[0], str(script)], env=fakes.env, timeout=30, capture_output=True, text=True
    )
    assert result.returncode == 1
    assert "ros2 topic pub stopped before the end of its segment" in result.stderr
    calls = fakes.call_lines()
    assert len(calls) == (4 if wheels else 2)  # the first segment's, then the zero commands
    assert all("--once" in call for call in calls[-2 if wheels else -1 :])


@pytest.mark.skipif(not SHELLS, reason="needs a POSIX sh")
@pytest.mark.parametrize("shell", SHELLS)
@pytest.mark.parametrize(
    ("wheels", "signum", "code"),
    [
        (False, signal.SIGINT, 130),
        (False, signal.SIGTERM, 143),
        (True, signal.SIGINT, 130),
        (True, signal.SIGTERM, 143),
    ],
)
def test_ros2_script_stops_the_robot_at_once_when_interrupted(
    runner: CliRunner,
    tmp_path: Path,
    shell: str,
    wheels: bool,
    signum: signal.Signals,
    code: int,
) -> None:
    script = ros2_script(
        runner, tmp_path, "straight 0.5 5s; straight 0.5 5s", *(["--wheels"] if wheels else [])
    )
    fakes = make_fakes(tmp_path)
    process = subprocess.Popen(
        [shell, str(script)],
        env=fakes.env,
        # A shell that starts with SIGINT ignored cannot trap it: give it the default.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    started = 2 if wheels else 1  # publishers of the first segment
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and len(fakes.call_lines()) < started:
        time.sleep(0.02)
    time.sleep(0.5)  # well inside the first segment's 5 s
    process.send_signal(signum)
    signalled = time.monotonic()
    zeros = 2 if wheels else 1
    while time.monotonic() < signalled + 10 and len(fakes.call_lines()) < started + zeros:
        time.sleep(0.01)
    stopped_after = time.monotonic() - signalled
    assert process.wait(timeout=30) == code
    assert stopped_after < 2.5  # the old script took the rest of the 5 s segment
    calls = fakes.call_lines()
    assert len(calls) == started + zeros
    assert all("--once" not in call for call in calls[:started])
    assert all(
        "--once" in call and ("0.0]" in call or "z: 0.0" in call) for call in calls[started:]
    )
    publishers = [int(pid) for pid in fakes.pids.read_text().split()]
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and any(running(pid) for pid in publishers):
        time.sleep(0.02)
    assert not any(running(pid) for pid in publishers)


def test_ros2_script_quotes_nothing_unsafe_and_rejects_bad_topics(runner: CliRunner) -> None:
    assert_bad_input(run(runner, "--format", "ros2", "--cmd-vel-topic", "a;rm -rf /"), "'a;rm")
    assert_bad_input(run(runner, "--left-topic", "1abc"), "--left-topic", "'1abc'")


def test_wheels_flag_outside_ros2_format_warns(runner: CliRunner) -> None:
    result = run(runner, "--wheels")
    assert result.exit_code == 0, result.output
    assert result.stderr.startswith("warning: --wheels only changes --format ros2")


@pytest.mark.parametrize("output_format", ["table", "twist", "wheels"])
def test_a_rate_the_format_does_not_sample_is_said_to_change_nothing(
    runner: CliRunner, output_format: str
) -> None:
    plain = run(runner, "straight 0.2", "--format", output_format)
    result = run(runner, "straight 0.2", "--format", output_format, "--rate", "5")
    assert result.exit_code == 0, result.output
    assert result.stdout == plain.stdout
    assert result.stderr == (
        f"warning: --rate changes nothing with --format {output_format} (it samples csv and "
        "json, times --bag and the ros2 script)\n"
    )
    sampled = run(runner, "straight 0.2", "--format", "csv", "--rate", "5")
    assert sampled.stderr == ""


# --------------------------------------------------------------------------------------------
# Limit check


@pytest.mark.parametrize("fmt_option", [[], ["--wheels"]])
def test_a_limit_far_below_the_wheels_shows_its_share_in_a_short_cell(
    runner: CliRunner, fmt_option: list[str]
) -> None:
    result = run(runner, "straight 1", "--max-rpm", "1e-300", *fmt_option)
    assert result.exit_code == 1
    row = next(line for line in result.stdout.splitlines() if line.startswith("1 "))
    # 27.28 rpm against 1e-300 rpm: 2.72837e+303 %, not the 304 digits of a fixed-point float.
    assert "2.72837e+303" in row.split()
    assert max(len(cell) for cell in row.split()) <= 12


def test_plan_over_the_limit_prints_the_results_then_fails_with_exit_1(
    runner: CliRunner,
) -> None:
    result = run(runner, "straight 1 10s; straight 1 5s; ccw 0.1 90 1s")
    assert result.exit_code == 1
    assert "OVER in segments 2, 3" in result.stdout
    errors = result.stderr.splitlines()
    assert errors == [
        "error: segment 2 (straight 1 m, 5 s): left and right wheels at 54.57 rpm exceed the "
        "50 rpm limit; shortest duration that fits: 5.457 s",
        "error: segment 3 (ccw arc r 0.1 m 90 deg, 1 s): right wheel at 71.79 rpm exceeds the "
        "50 rpm limit; shortest duration that fits: 1.436 s",
    ]


def test_suggested_shortest_duration_does_fit(runner: CliRunner) -> None:
    assert run(runner, "straight 1 5.457s; ccw 0.1 90 1.436s").exit_code == 0
    assert run(runner, "straight 1 5.456s").exit_code == 1


@pytest.mark.parametrize(
    "value", [1e-7, 0.9, 5.4567409060078, 1234.5678, 9999.5, 99999.2, 1e29, 1e308, 5e-324]
)
def test_rounded_up_durations_are_never_below_the_value(value: float) -> None:
    text = ceil_text(value)
    assert float(text) >= value
    assert float(text) <= value * (1 + 1e-3)


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (0.9, "0.9000"),
        (5.4567409060078, "5.457"),
        (1234.5678, "1235"),
        (9999.5, "1.000e+04"),
        (545674.9, "5.457e+05"),
        (1e-7, "1.000e-07"),
        (1e29, "1.000e+29"),
        (1.7976931348623157e308, "1.798e+308"),
    ],
)
def test_rounded_up_durations_show_four_significant_digits(value: float, text: str) -> None:
    assert ceil_text(value) == text


def test_huge_shortest_duration_is_reported_not_a_traceback(runner: CliRunner) -> None:
    # The longest straight a plan may hold (1e9 m), in next to no time.
    result = run(runner, "straight 1e9 1e-20s")
    assert result.exit_code == 1
    assert result.stderr.strip().endswith("shortest duration that fits: 5.457e+09 s")
    assert "Traceback" not in result.output


@pytest.mark.parametrize("output_format", PLAN_FORMATS)
@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        ("spin 1e300rad 1e-300s", "its velocity"),
        ("straight 1e308", "its duration (inf s)"),
        ("straight 1 1e-320s", "its velocity"),
    ],
)
def test_plans_that_overflow_are_bad_input_in_every_format(
    runner: CliRunner, output_format: str, spec: str, fragment: str
) -> None:
    result = run(runner, spec, "--format", output_format)
    assert_bad_input(result, "segment 1 (", fragment)
    assert result.stdout == ""


def test_plan_file_that_overflows_is_bad_input(runner: CliRunner, write: Write) -> None:
    path = write("p.yaml", "[{spin: 1e308, duration: 1e-308}]\n")
    assert_bad_input(run(runner, str(path)), "segment 1 (spin 1e+308 deg, 1e-308 s)", "velocity")


@pytest.mark.parametrize("rate", ["1e308", "1001", "inf"])
def test_rate_must_be_finite_and_sane(runner: CliRunner, rate: str) -> None:
    assert_bad_input(run(runner, "--format", "ros2", "--rate", rate), "--rate", repr(rate))


def test_over_the_limit_json_still_printed_with_violations(runner: CliRunner) -> None:
    result = run(runner, "--json", "straight 1 5s")
    assert result.exit_code == 1
    data = json.loads(result.stdout)
    assert data["within_limit"] is False
    assert [(v["segment"], v["wheel"]) for v in data["violations"]] == [(1, "left"), (1, "right")]
    assert data["violations"][0]["shortest_duration"] == pytest.approx(5.45674090600784)
    assert result.stderr.startswith("error: segment 1")


def test_max_rpm_overrides_the_description(runner: CliRunner) -> None:
    result = run(runner, "straight 1 5s", "--max-rpm", "60")
    assert result.exit_code == 0, result.output
    assert "motor limit 60 rpm (6.28319 rad/s): within" in result.stdout
    assert run(runner, "--max-rpm", "20").exit_code == 1
    data = plan_json(runner, "--fastest", "--max-rpm", "25", "straight 1")
    assert data["segments"][0]["left_rpm"] == pytest.approx(25.0, rel=1e-9)


def test_rpm_limit_is_no_longer_an_option(runner: CliRunner) -> None:
    assert_bad_input(run(runner, "--rpm-limit", "30"), "No such option '--rpm-limit'")


@pytest.mark.parametrize(
    ("option", "fragment"),
    [("--max-rpm", "'0' must be > 0")],
)
def test_zero_limit_is_bad_input(runner: CliRunner, option: str, fragment: str) -> None:
    assert_bad_input(run(runner, option, "0"), fragment)


# --------------------------------------------------------------------------------------------
# Input: text, files, xacro arguments


def test_spec_may_be_split_over_several_arguments_with_negative_numbers(
    runner: CliRunner,
) -> None:
    data = plan_json(runner, "straight", "1", "10s;", "spin", "-90", "1s")
    assert data["plan"] == "straight 1 10s; spin -90 1s"
    assert data["final_pose"]["theta"] == pytest.approx(-math.pi / 2, abs=1e-15)


@pytest.mark.parametrize(
    ("args", "spec"),
    [
        (["spin", "-90deg"], "spin -90"),
        (["--", "spin", "-1.5rad"], "spin -85.94366926962348"),
        (["ccw", ".5", "-.5rad"], None),
        (["straight", "1", "-5s"], None),
    ],
)
def test_negative_values_with_a_unit_are_values_not_options(
    runner: CliRunner, args: list[str], spec: str | None
) -> None:
    if spec is not None:
        assert plan_json(runner, *args)["plan"] == spec
    else:
        assert_bad_input(run(runner, *args), "must be > 0")
        assert "No such option" not in run(runner, *args).stderr


def test_several_arguments_are_joined_as_segments(runner: CliRunner) -> None:
    data = plan_json(runner, "straight 1", "spin 90", "straight", "2", "50s")
    assert data["plan"] == "straight 1; spin 90; straight 2 50s"
    assert_bad_input(run(runner, "straight 1", "spin 90x"), "segment 2", "'90x'", "column 18")
    help_text = run(runner, "--help").stdout
    assert "'straight 1' 'spin 90' is 'straight 1;" in " ".join(help_text.split())


def test_speed_and_spin_rate_options(runner: CliRunner) -> None:
    data = plan_json(runner, "straight 1.5; spin 90", "--speed", "0.15", "--spin-rate", "1")
    assert [s["duration"] for s in data["segments"]] == pytest.approx([10.0, math.pi / 2])


def test_xacro_arguments_may_follow_the_spec(runner: CliRunner) -> None:
    data = plan_json(runner, "straight 1 10s", "wheel_radius:=0.05")
    assert data["robot"]["wheel_radius"] == 0.05
    assert data["segments"][0]["left"] == pytest.approx(2.0, rel=1e-12)


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("p.yaml", "- {straight: 1, duration: 10}\n- {arc: ccw, radius: 25cm, angle: 90}\n"),
        (
            "p.json",
            '[{"straight": 1, "duration": 10}, {"arc": "ccw", "radius": 0.25, "angle": 90}]',
        ),
        ("p.txt", "straight 1 10s\nccw 0.25 90  # a quarter circle\n"),
    ],
)
def test_plan_files_are_read(runner: CliRunner, write: Write, name: str, text: str) -> None:
    path = write(name, text)
    data = plan_json(runner, str(path))
    assert data["plan"] == "straight 1 10s; ccw 0.25 90"
    assert data["source"] == str(path)
    assert path.read_text() == text


def test_errors_after_blank_lines_give_the_line(runner: CliRunner, write: Write) -> None:
    path = write("f.txt", "\n\n\nstraight x\n")
    assert_bad_input(run(runner, str(path)), "f.txt: segment 1", "(line 4, column 10)")
    path = write("bom.txt", "\ufeffstraight 1 10s\n")
    assert plan_json(runner, str(path))["plan"] == "straight 1 10s"


def test_missing_plan_file_is_bad_input(runner: CliRunner, tmp_path: Path) -> None:
    assert_bad_input(run(runner, str(tmp_path / "nope.yaml")), "nope.yaml: no such file")


def test_bad_plan_file_names_the_entry(runner: CliRunner, write: Write) -> None:
    path = write("p.yaml", "- {straight: 1}\n- {spin: 90, speed: 3}\n")
    assert_bad_input(run(runner, str(path)), "entry 2", "'speed'")


def test_yaml_alias_bomb_is_one_short_error_line(runner: CliRunner, write: Write) -> None:
    levels = ["- &a0 [x, x, x, x, x, x, x, x, x]"]
    levels += [f"- &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 9)]
    path = write("bomb.yaml", "\n".join(levels) + "\n")
    result = run(runner, str(path))
    assert_bad_input(result, "YAML aliases (*name) are not allowed in a plan file")
    assert len(result.stderr) < 200


def test_duplicate_keys_and_unknown_top_level_keys_are_bad_input(
    runner: CliRunner, write: Write
) -> None:
    path = write("p.json", '[{"straight": 1, "duration": 10, "duration": 20}]')
    assert_bad_input(run(runner, str(path)), "duplicate key 'duration'")
    path = write("p.yaml", "segments: [straight 1]\nspeed: 5\n")
    assert_bad_input(run(runner, str(path)), "unknown top-level key 'speed'")


def test_headings_are_never_reported_as_minus_zero(runner: CliRunner) -> None:
    result = run(runner, "--json", "spin -720")
    assert '"theta": -0.0' not in result.stdout
    assert plan_json(runner, "spin -720")["final_pose"]["theta"] == 0.0


def test_example_and_a_spec_together_are_bad_input(runner: CliRunner) -> None:
    assert_bad_input(run(runner, "--example", "A", "straight 1"), "--example")


def test_unknown_option_is_bad_input_not_a_plan_token(runner: CliRunner) -> None:
    assert_bad_input(run(runner, "--formt", "json"), "No such option '--formt'")
    assert_bad_input(run(runner, "spin", "90", "--bogus"), "No such option '--bogus'")
    assert_bad_input(run(runner, "spin", "-x"), "No such option '-x'")


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["strait 1"], ["'strait'", "segment 1", "column 1"]),
        (["straight 1; ccw 0.25"], ["segment 2", "'ccw' needs ANGLE", "'0.25'"]),
        (["straight 1km"], ["'1km'", "unknown unit 'km'"]),
        (["straight 0"], ["'0'", "must not be zero"]),
        (["ccw 0 90"], ["radius '0'"]),
        (["straight 1 0s"], ["duration '0s'"]),
        (["straight nan"], ["'nan'", "not a finite number"]),
        (["spin inf"], ["'inf'", "not a finite number"]),
        (["spin 0"], ["'0'", "must not be zero"]),
        (["straight 1 2 3"], ["unexpected '3'"]),
        (["straight 1 10 rad"], ["'rad' is a unit"]),
        (["  ;  "], ["empty plan"]),
        (["--speed", "nan"], ["--speed", "'nan'"]),
        (["--rate", "0"], ["--rate"]),
        (["--format", "yaml"], ["--format", "'yaml'"]),
        (["--example", "C"], ["--example", "'C'"]),
    ],
)
def test_every_bad_plan_gives_exit_2_quoting_the_token(
    runner: CliRunner, args: list[str], fragments: list[str]
) -> None:
    assert_bad_input(run(runner, *args), *fragments)


# --------------------------------------------------------------------------------------------
# Output files


def test_output_file_is_written_whole_and_not_overwritten_without_force(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "plan.json"
    result = run(runner, "--json", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert result.stdout == ""
    assert json.loads(out.read_text())["plan"] == EXAMPLES["A"]
    assert not os.stat(out).st_mode & stat.S_IXUSR
    assert_bad_input(run(runner, "--example", "B", "--json", "-o", str(out)), "--force")
    assert json.loads(out.read_text())["plan"] == EXAMPLES["A"]
    result = run(runner, "--example", "B", "--json", "-o", str(out), "--force")
    assert result.exit_code == 0, result.output
    assert json.loads(out.read_text())["plan"] == EXAMPLES["B"]
    assert [p.name for p in tmp_path.iterdir()] == ["plan.json"]


def test_output_over_the_plan_file_is_refused(runner: CliRunner, write: Write) -> None:
    path = write("p.txt", "straight 1\n")
    assert_bad_input(run(runner, str(path), "-o", str(path), "--force"), "plan file itself")
    assert path.read_text() == "straight 1\n"


def test_a_bag_over_the_folder_of_the_plan_file_says_it_contains_it(
    runner: CliRunner, write: Write
) -> None:
    path = write("p.txt", "straight 1\n")
    result = run(runner, str(path), "--bag", "-o", str(path.parent), "--force")
    assert_bad_input(result, f"{path.parent} contains {path}: refusing to overwrite it")
    assert path.read_text() == "straight 1\n"


def test_output_over_the_robot_description_is_refused(runner: CliRunner, tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    assert runner.invoke(main, ["urdf", "-o", str(urdf)]).exit_code == 0
    before = urdf.read_text()
    result = run(runner, "straight 1", "--robot", str(urdf), "-o", str(urdf), "--force")
    assert_bad_input(result, "is an input: refusing to overwrite it")
    assert urdf.read_text() == before
    link = tmp_path / "link.txt"
    link.symlink_to(urdf)
    result = run(runner, "straight 1", "--robot", str(urdf), "-o", str(link), "--force")
    assert_bad_input(result, "is an input")
    assert urdf.read_text() == before


def test_help_describes_the_grammar(runner: CliRunner) -> None:
    result = run(runner, "--help")
    assert result.exit_code == 0
    for fragment in ("straight LENGTH [DURATION]", "--fastest", "--max-rpm", "ros2"):
        assert fragment in result.stdout
    text = " ".join(result.stdout.split())
    assert "(durations given in the plan are ignored)" in text
    json_example = text.split("the same in .json (", 1)[1].split("), or a .txt", 1)[0]
    assert json.loads(json_example) == [{"straight": 1, "duration": 10}, {"spin": 90}]


def test_per_wheel_commands_address_every_joint_of_a_skid_steers_side(
    runner: CliRunner, tmp_path: Path
) -> None:
    wheel = (
        '<link name="{0}"/><joint name="{0}_joint" type="continuous"><parent link="base_link"/>'
        '<child link="{0}"/><origin xyz="{1} {2} 0"/><axis xyz="0 1 0"/></joint>'
    )
    wheels = "".join(
        wheel.format(name, x, y)
        for name, x, y in (
            ("fl", 0.1, 0.2),
            ("rl", -0.1, 0.2),
            ("fr", 0.1, -0.2),
            ("rr", -0.1, -0.2),
        )
    )
    robot = tmp_path / "skid.urdf"
    robot.write_text(f'<robot name="s"><link name="base_link"/>{wheels}</robot>', encoding="utf-8")
    result = runner.invoke(
        main,
        [
            "plan",
            "straight 1 10s",
            "--robot",
            str(robot),
            "--wheel-radius",
            "0.05",
            "--format",
            "wheels",
        ],
    )
    assert result.exit_code == 0, result.output
    assert (
        "# left: left_wheel_velocity_controller/commands (fl_joint, rl_joint, direction +1)"
        in result.stdout
    )
    assert "left_wheel_velocity_controller/commands   {data: [2.0, 2.0]}" in result.stdout
    script = runner.invoke(
        main,
        [
            "plan",
            "straight 1 10s",
            "--robot",
            str(robot),
            "--wheel-radius",
            "0.05",
            "--format",
            "ros2",
            "--wheels",
        ],
    ).stdout
    assert "'{data: [0.0, 0.0]}'" in script


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["--example", "B", "--fastest"],
        ["--example", "umbmark", "--side", "4"],
        ["straight 1; spin 90", "--max-accel", "0.5"],
        ["; ".join(["ccw 0.25 180", "straight 1", "cw 0.25 180", "straight -1"] * 6)],
    ],
)
def test_the_default_table_fits_100_columns_and_wide_is_the_full_one(
    runner: CliRunner, args: list[str]
) -> None:
    narrow = run(runner, *args)
    wide = run(runner, *args, "--wide")
    assert narrow.exit_code == wide.exit_code == 0, narrow.output
    assert max(len(line) for line in narrow.stdout.splitlines()) <= 100
    assert "L rpm" in narrow.stdout
    assert "left rad/s" not in narrow.stdout
    assert "left rad/s" in wide.stdout
    assert max(len(line) for line in wide.stdout.splitlines()) > 100
    # the same plan: the same summary lines under both tables
    assert narrow.stdout.splitlines()[-2:] == wide.stdout.splitlines()[-2:]


def test_a_speed_that_changes_nothing_warns(runner: CliRunner) -> None:
    # Trajectory A's segments all carry durations: --speed cannot change them
    result = run(runner, "--speed", "0.5")
    assert result.exit_code == 0, result.output
    assert "warning: --speed changes nothing: every straight or arc of the plan has its own" in (
        result.stderr
    )
    assert "--speed" not in run(runner, "straight 1", "--speed", "0.05").stderr
    assert "--speed" not in run(runner).stderr  # not given: nothing to say
    spin = run(runner, "straight 1", "--spin-rate", "1")
    assert "warning: --spin-rate changes nothing: the plan has no spin" in spin.stderr


def test_a_ramped_plan_refused_in_a_message_format_names_steps(runner: CliRunner) -> None:
    slow = Path(__file__).parents[2] / "docs" / "examples" / "slow.yaml"
    for fmt in ("twist", "ros2"):
        result = run(runner, "--controllers", str(slow), "--format", fmt)
        assert_bad_input(result, "--steps", "--rate")
        assert run(runner, "--controllers", str(slow), "--format", fmt, "--steps").exit_code == 0
