"""``diffbot plan`` with ramps, sampled command streams, stamped commands and command bags."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner, Result
from robots import bundled_controllers
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from diffbot.cli import main
from diffbot.kinematics import DiffDriveParams
from diffbot.trajectory import advance

TYPESTORE = get_typestore(Stores.ROS2_HUMBLE)


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, ["plan", *args])


def held_end(rows: list[dict[str, str]], rate: float) -> tuple[float, float, float]:
    """The pose the commands reach, each held for one period (exact arcs)."""
    x = y = heading = 0.0
    for row in rows:
        linear, angular = float(row["linear"]), float(row["angular"])
        x, y, heading = advance(x, y, heading, linear / rate, angular / rate)
    return x, y, heading


def test_max_accel_ramps_trajectory_a_and_each_run_takes_v_over_a_longer(
    runner: CliRunner,
) -> None:
    result = run(runner, "--max-accel", "0.05", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    # Each 10 s step segment gains v/a: 0.1/0.05 = 2 s on the straights, 0.0785/0.05 on arcs.
    arc = math.pi * 0.25 / 10
    expected = [10 + arc / 0.05, 12.0, 10 + arc / 0.05, 12.0]
    assert [s["duration"] for s in data["segments"]] == pytest.approx(expected, rel=1e-12)
    assert data["runs"][1] == {"segments": [2], "start": pytest.approx(expected[0]), "duration": 12}
    assert data["final_pose"] == {"x": 0.0, "y": 1.0, "theta": 0.0}


def test_ramped_table_says_the_speeds_are_peaks(runner: CliRunner) -> None:
    result = run(runner, "straight 1; straight 1", "--max-accel", "0.05", "--max-jerk", "0.1")
    assert result.exit_code == 0, result.output
    assert "each segment's peak" in result.output
    assert "total 22" in result.output  # one run of 2 m: 20 s + v/a + a/j = 20 + 2 + 0.5 s


def test_rate_samples_a_ramped_plan_whose_held_commands_end_where_planned(
    runner: CliRunner,
) -> None:
    spec = "straight 1; reverse ccw 0.3 90; spin -45"
    result = run(runner, spec, "--max-accel", "0.1", "--rate", "20", "--format", "csv")
    assert result.exit_code == 0, result.output
    rows = list(csv.DictReader(io.StringIO(result.output)))
    assert list(rows[0]) == ["time", "linear", "angular", "left", "right"]
    assert float(rows[1]["time"]) == 0.05
    assert rows[-1]["linear"] == rows[-1]["angular"] == rows[-1]["left"] == "0.0"
    planned = json.loads(run(runner, spec, "--max-accel", "0.1", "--json").output)["final_pose"]
    x, y, heading = held_end(rows, 20.0)
    assert x == pytest.approx(planned["x"], abs=1e-9)
    assert y == pytest.approx(planned["y"], abs=1e-9)
    turn = math.remainder(heading - planned["theta"], 2 * math.pi)
    assert turn == pytest.approx(0.0, abs=1e-9)


def test_rate_samples_a_step_plan_too_and_json_carries_the_stream(runner: CliRunner) -> None:
    result = run(runner, "straight 0.1 1s; spin 90 2s", "--rate", "4", "--json")
    assert result.exit_code == 0, result.output
    commands = json.loads(result.output)["commands"]
    assert commands["rate"] == 4.0
    assert commands["time"] == [k / 4 for k in range(13)]
    assert commands["linear"] == pytest.approx([0.1] * 4 + [0.0] * 9, abs=1e-15)
    assert commands["angular"][4:] == pytest.approx([math.pi / 4] * 8 + [0.0], rel=1e-14)


@pytest.mark.parametrize("sampled", [[], ["--rate", "10"]])
def test_a_ramped_plans_json_gives_the_shortest_duration_to_write_as_the_error_line_does(
    runner: CliRunner, sampled: list[str]
) -> None:
    # 0.2 m/s turns the bundled wheels at 5.714 rad/s, over 50 rpm (5.236 rad/s); the ramps
    # stretch the 5 s cruise to 7 s, but the duration that fits is one written in the plan.
    spec = ["straight 1 5s", "--max-accel", "0.1"]
    result = run(runner, *spec, "--json", *sampled)
    assert result.exit_code == 1
    (violation, _) = json.loads(result.stdout)["violations"]
    least = 1 / (0.035 * 50 * math.pi / 30)
    assert violation["shortest_duration"] == pytest.approx(least, rel=1e-12)
    assert "shortest duration that fits: 5.457 s" in result.stderr
    refit = run(runner, f"straight 1 {violation['shortest_duration'] * (1 + 1e-9)}s", *spec[1:])
    assert refit.exit_code == 0, refit.output


def test_a_ramped_tables_limit_lines_name_the_segments_the_error_lines_name(
    runner: CliRunner,
) -> None:
    # 1 cm in 0.05 s asks 0.2 m/s, over 50 rpm and --max-linear; the ramp of 0.1 m/s² peaks at
    # 0.032 m/s, but the plan's durations are what the limits are checked on (exit code 1).
    spec = ["straight 0.01 0.05s; spin 90", "--max-accel", "0.1", "--max-linear", "0.15"]
    result = run(runner, *spec)
    assert result.exit_code == 1
    assert "motor limit 50 rpm (5.23599 rad/s): OVER in segment 1\n" in result.stdout
    assert "body limits linear [-0.15, 0.15] m/s: OVER in segment 1\n" in result.stdout
    assert result.stderr.count("error: segment 1 ") == 2


def test_stamped_json_and_ros2_script_name_twist_stamped_and_the_frame(runner: CliRunner) -> None:
    data = json.loads(run(runner, "--stamped", "--frame-id", "odom_base", "--json").output)
    assert data["message_type"] == "geometry_msgs/msg/TwistStamped"
    assert data["frame_id"] == "odom_base"
    script = run(runner, "--stamped", "--format", "ros2").output
    assert "geometry_msgs/msg/TwistStamped" in script
    assert '{header: {stamp: now, frame_id: "base_link"}, twist: {linear: {x: 0.1}' in script
    assert "geometry_msgs/msg/Twist " not in script


def read_bag(path: Path) -> dict[str, list[tuple[int, Any]]]:
    out: dict[str, list[tuple[int, Any]]] = {}
    with Reader(path) as reader:
        for connection, stamp, raw in reader.messages():
            message = TYPESTORE.deserialize_cdr(raw, connection.msgtype)
            out.setdefault(connection.topic, []).append((stamp, message))
    return out


@pytest.mark.parametrize("stamped", [False, True])
def test_command_bags_read_back_give_the_commands_in_order_ending_with_zero(
    runner: CliRunner, tmp_path: Path, stamped: bool
) -> None:
    spec = ["straight 0.5; ccw 0.25 90", "--max-accel", "0.2", "--rate", "10"]
    stream = json.loads(run(runner, *spec, "--json").output)["commands"]
    bag = tmp_path / "cmds"
    flags = ["--stamped"] if stamped else []
    result = run(runner, *spec, "--out", str(bag), "--bag", *flags)
    assert result.exit_code == 0, result.output
    assert f"wrote {stream['count']} commands at 10 Hz" in result.output
    topics = read_bag(bag)
    assert set(topics) == {
        "/cmd_vel",
        "/left_wheel_velocity_controller/commands",
        "/right_wheel_velocity_controller/commands",
    }
    body = topics["/cmd_vel"]
    assert [stamp for stamp, _ in body] == [round(t * 1e9) for t in stream["time"]]
    twists = [message.twist if stamped else message for _, message in body]
    assert [t.linear.x for t in twists] == stream["linear"]
    assert [t.angular.z for t in twists] == stream["angular"]
    assert twists[-1].linear.x == twists[-1].angular.z == 0.0
    if stamped:
        first = body[0][1].header
        assert (first.frame_id, first.stamp.sec, first.stamp.nanosec) == ("base_link", 0, 0)
    for side in ("left", "right"):
        data = [float(m.data[0]) for _, m in topics[f"/{side}_wheel_velocity_controller/commands"]]
        assert data == stream[side]


def test_a_bag_is_not_written_over_an_existing_one_without_force(
    runner: CliRunner, tmp_path: Path
) -> None:
    bag = tmp_path / "cmds"
    assert run(runner, "--out", str(bag), "--bag").exit_code == 0
    again = run(runner, "--out", str(bag), "--bag")
    assert again.exit_code == 2
    assert "--force" in again.output
    assert run(runner, "--out", str(bag), "--bag", "--force").exit_code == 0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--max-accel", "0.1", "--format", "csv"], "a ramped plan is many commands"),
        (["--max-accel", "0.1", "--format", "ros2"], "--out DIR --bag"),
        (["--bag"], "--bag writes the --out directory"),
        (["--bag", "--out", "x", "--json"], "without --format and --json"),
        (["--steps", "--max-jerk", "1"], "--steps plans velocity steps"),
        (["--max-accel", "0"], "--max-accel"),
    ],
)
def test_bad_ramp_options_are_one_error_line(
    runner: CliRunner, args: list[str], message: str
) -> None:
    result = run(runner, *args)
    assert result.exit_code == 2
    assert message in result.output
    assert "Traceback" not in result.output


def test_simulate_with_ramps_ends_where_the_ramped_plan_ends(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "a.csv"
    result = runner.invoke(main, ["simulate", "--max-accel", "0.05", "--out", str(out), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["duration"] == pytest.approx(47.1415926535898, rel=1e-12)
    odom = json.loads(runner.invoke(main, ["odom", str(out), "--json"]).output)
    final = odom["final_pose"]
    assert final["x"] == pytest.approx(0.0, abs=1e-9)
    assert final["y"] == pytest.approx(1.0, abs=1e-9)


def test_reverse_segments_typed_unquoted_join_as_written(runner: CliRunner) -> None:
    result = run(runner, "straight", "-1", "reverse", "ccw", "0.25", "90", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["plan"] == "straight -1; reverse ccw 0.25 90"
    assert data["final_pose"]["x"] == pytest.approx(-1.25, abs=1e-12)
    assert data["final_pose"]["y"] == pytest.approx(-0.25, abs=1e-12)


SLOW_CONTROLLER = bundled_controllers(
    "linear.x.max_acceleration: 0.05", name="diff_drive_controller", update_rate=50
)


def simulate_json(runner: CliRunner, tmp_path: Path, *args: str) -> dict[str, Any]:
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(SLOW_CONTROLLER)
    out = tmp_path / "states.csv"
    result = runner.invoke(
        main,
        [
            "simulate",
            "--controllers",
            str(controllers),
            "--out",
            str(out),
            "--force",
            "--json",
            *args,
        ],
    )
    assert result.exit_code == 0, result.output
    data: dict[str, Any] = json.loads(result.output)
    odom = json.loads(runner.invoke(main, ["odom", str(out), "--json"]).output)
    data["odom_final_pose"] = odom["final_pose"]
    return data


def test_the_seeds_step_plan_through_a_slow_controller_ends_centimetres_off(
    runner: CliRunner, tmp_path: Path
) -> None:
    data = simulate_json(runner, tmp_path, "--steps")
    assert 0.02 < data["offset"] < 0.05  # 36 mm with the bundled robot at 50 Hz
    executed = data["executed_final_pose"]
    # The joint states written are the executed ones: odometry of them ends there.
    assert data["odom_final_pose"]["x"] == pytest.approx(executed["x"], abs=1e-9)
    assert data["odom_final_pose"]["y"] == pytest.approx(executed["y"], abs=1e-9)


def test_a_plan_ramped_by_the_controllers_limits_ends_where_planned(
    runner: CliRunner, tmp_path: Path
) -> None:
    data = simulate_json(runner, tmp_path)
    assert data["offset"] < 1e-9
    assert data["odom_final_pose"]["x"] == pytest.approx(0.0, abs=1e-9)
    assert data["odom_final_pose"]["y"] == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--stamped", "--format", "wheels"], "--stamped changes Twist commands only"),
        (["--frame-id", "odom"], "--frame-id only applies to --stamped"),
    ],
)
def test_stamped_options_that_change_nothing_say_so(
    runner: CliRunner, args: list[str], message: str
) -> None:
    result = run(runner, *args)
    assert result.exit_code == 0
    assert f"warning: {message}" in result.stderr


@pytest.mark.parametrize("as_json", [False, True])
def test_rate_output_is_written_in_pieces_never_as_a_whole_stream(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch, params: DiffDriveParams, as_json: bool
) -> None:
    from diffbot import ramps
    from diffbot.formats.command_stream import stream_csv, stream_json
    from diffbot.planfile import parse_plan
    from diffbot.trajectory import plan

    spec = "straight 0.5; ccw 0.25 90; spin -45"
    made = ramps.ramp(
        plan(parse_plan(spec), params), ramps.controller_limits(None, linear_accel=0.2)
    )
    whole = made.commands(40.0)
    pieces = ramps.RampedPlan.command_chunks
    monkeypatch.setattr(
        ramps.RampedPlan, "command_chunks", lambda self, rate: pieces(self, rate, chunk=7)
    )

    def whole_stream(self: object, rate: float) -> object:
        raise AssertionError("the whole command stream was built in memory")

    monkeypatch.setattr(ramps.RampedPlan, "commands", whole_stream)
    form = ["--json"] if as_json else ["--format", "csv"]
    result = run(runner, spec, "--max-accel", "0.2", "--rate", "40", *form)
    assert result.exit_code == 0, result.output
    assert whole.times.size > 50  # several pieces of 7
    if as_json:
        assert json.loads(result.stdout)["commands"] == stream_json(whole, 40.0)
    else:
        assert result.stdout == stream_csv(whole)


def test_a_command_bag_is_written_in_pieces_never_as_a_whole_stream(
    runner: CliRunner, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    from diffbot import ramps

    pieces = ramps.RampedPlan.command_chunks
    monkeypatch.setattr(
        ramps.RampedPlan, "command_chunks", lambda self, rate: pieces(self, rate, chunk=5)
    )

    def whole_stream(self: object, rate: float) -> object:
        raise AssertionError("the whole command stream was built in memory")

    monkeypatch.setattr(ramps.RampedPlan, "commands", whole_stream)
    bag = tmp_path / "bag"
    result = run(runner, "straight 0.5; spin 90", "--max-accel", "0.2", "--out", str(bag), "--bag")
    assert result.exit_code == 0, result.output
    count = int(result.stdout.split()[1])
    assert count > 20
    with Reader(bag) as reader:
        assert reader.message_count == 3 * count


def test_a_forward_run_cruises_up_to_max_velocity_when_reversing_is_slower(
    runner: CliRunner, tmp_path: Path
) -> None:
    # A controller that reverses at no more than 0.05 m/s: a forward straight asked for 0.15 m/s
    # (within max_velocity 0.18) is driven at 0.15 m/s, as the controller lets it through.
    controllers = tmp_path / "controllers.yaml"
    controllers.write_text(
        bundled_controllers(
            "linear.x.max_velocity: 0.18",
            "linear.x.min_velocity: -0.05",
            "linear.x.max_acceleration: 0.5",
        )
    )
    result = run(runner, "straight 0.3 2s", "--controllers", str(controllers), "--json")
    assert result.exit_code == 0, result.output
    segment = json.loads(result.output)["segments"][0]
    assert segment["linear"] == pytest.approx(0.15, rel=1e-12)
    assert segment["duration"] == pytest.approx(2 + 0.15 / 0.5, rel=1e-12)
