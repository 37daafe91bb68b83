"""--max-linear and --max-angular on plan, ik, simulate, drive and node ik, and the same limits
read from a controllers file's linear.x / angular.z velocity limits."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_results import assert_one_error_line
from click.testing import CliRunner, Result
from robots import two_wheel_urdf

from diffbot.cli import main

#: A ros2_control_demos-style controllers file (the diffbot example's layout) with velocity
#: limits only, and a lower reverse speed.
CONTROLLERS = """\
controller_manager:
  ros__parameters:
    update_rate: 10
    diffbot_base_controller:
      type: diff_drive_controller/DiffDriveController
diffbot_base_controller:
  ros__parameters:
    left_wheel_names: ["left_wheel_joint"]
    right_wheel_names: ["right_wheel_joint"]
    wheel_separation: 0.2
    wheel_radius: 0.05
    linear.x.max_velocity: 0.3
    linear.x.min_velocity: -0.1
    angular.z.max_velocity: 1.0
"""


@pytest.fixture
def robot(tmp_path: Path) -> list[str]:
    """The robot options of a two-wheel robot (r 0.05 m, b 0.2 m, 100 rpm) and its
    controllers file."""
    (tmp_path / "robot.urdf").write_text(two_wheel_urdf())
    (tmp_path / "controllers.yaml").write_text(CONTROLLERS)
    return [
        "--robot",
        str(tmp_path / "robot.urdf"),
        "--controllers",
        str(tmp_path / "controllers.yaml"),
        "--max-rpm",
        "100",
    ]


def run(runner: CliRunner, *args: str) -> Result:
    return runner.invoke(main, list(args))


def plan_json(runner: CliRunner, *args: str) -> dict[str, object]:
    result = run(runner, "plan", *args, "--json")
    assert result.exit_code == 0, result.output
    data: dict[str, object] = json.loads(result.stdout)
    return data


def twists(data: dict[str, object]) -> list[tuple[float, float]]:
    segments = data["segments"]
    assert isinstance(segments, list)
    return [(s["linear"], s["angular"]) for s in segments]


def test_a_goal_plan_drives_at_the_given_speed(runner: CliRunner) -> None:
    # The bundled robot's wheels could do 0.1833 m/s; --speed 0.1 asks for 0.1.
    data = plan_json(runner, "--to", "2,0,0", "--speed", "0.1")
    assert twists(data) == [pytest.approx((0.1, 0.0))]
    assert data["duration"] == pytest.approx(20.0)
    fastest = plan_json(runner, "--to", "2,0,0")
    assert twists(fastest) == [pytest.approx((0.18326, 0.0), abs=1e-5)]


def test_a_goal_plan_keeps_within_the_given_body_limits(runner: CliRunner) -> None:
    data = plan_json(runner, "--to", "1,1,90", "--max-linear", "0.1", "--max-angular", "0.5")
    for v, w in twists(data):
        assert abs(v) <= 0.1 * (1 + 1e-12)
        assert abs(w) <= 0.5 * (1 + 1e-12)


def test_the_controllers_velocity_limits_time_a_fastest_plan(
    runner: CliRunner, robot: list[str]
) -> None:
    # 100 rpm on r 0.05 m would be 0.5236 m/s: the file's 0.3 m/s and 1 rad/s bound it, and a
    # backward straight runs at its min_velocity of -0.1 m/s.
    data = plan_json(runner, *robot, "straight 1; spin 90; straight -0.5", "--fastest")
    assert twists(data) == [
        pytest.approx((0.3, 0.0)),
        pytest.approx((0.0, 1.0)),
        pytest.approx((-0.1, 0.0)),
    ]


def test_a_given_limit_overrides_the_files(runner: CliRunner, robot: list[str]) -> None:
    data = plan_json(runner, *robot, "straight 1", "--fastest", "--max-linear", "0.2")
    assert twists(data) == [pytest.approx((0.2, 0.0))]


def test_a_cruise_speed_over_a_body_limit_is_said_and_slowed(
    runner: CliRunner, robot: list[str]
) -> None:
    result = run(runner, "plan", *robot, "straight 1; spin 90", "--speed", "0.4", "--json")
    assert result.exit_code == 0, result.output
    assert twists(json.loads(result.stdout))[0] == pytest.approx((0.3, 0.0))
    assert result.stderr == (
        "warning: --speed 0.4 m/s is over the body velocity limit of 0.3 m/s (the controllers "
        "file's linear.x): the segments it times run at 0.3 m/s\n"
    )
    given = run(runner, "plan", *robot, "spin 90", "--spin-rate", "2", "--max-angular", "0.5")
    assert given.exit_code == 0, given.output
    assert given.stderr == (
        "warning: --spin-rate 2 rad/s is over the body velocity limit of 0.5 rad/s "
        "(--max-angular): the segments it times run at 0.5 rad/s\n"
    )
    # Within the limits, or changing nothing (said so instead), there is no such warning.
    within = run(runner, "plan", *robot, "straight 1", "--speed", "0.3")
    assert within.exit_code == 0
    assert within.stderr == ""
    timed = run(runner, "plan", *robot, "straight 1 10s", "--speed", "0.4")
    assert timed.stderr.count("warning:") == 1
    assert "changes nothing" in timed.stderr


def test_a_segment_over_a_body_limit_fails_naming_it(runner: CliRunner, robot: list[str]) -> None:
    result = run(runner, "plan", *robot, "straight 1 10s; straight 1 2s")
    assert result.exit_code == 1
    assert "segment 1" not in result.stderr
    # 0.5 m/s over the file's 0.3: 1 m takes at least 3.334 s (rounded up).
    assert result.stderr.strip() == (
        "error: segment 2 (straight 1 m, 2 s): linear velocity 0.5 m/s is outside [-0.1, 0.3], "
        "the body velocity limits; shortest duration that fits: 3.334 s"
    )
    assert "straight" in result.stdout  # the plan is still printed


@pytest.mark.parametrize("sampled", [[], ["--rate", "10"]])
def test_a_plans_json_names_the_segments_over_the_body_limits(
    runner: CliRunner, robot: list[str], sampled: list[str]
) -> None:
    # Within the motor limit, over the file's 0.3 m/s: the exit code says so, and the JSON too.
    result = run(runner, "plan", *robot, "straight 1 10s; straight 1 2s", "--json", *sampled)
    assert result.exit_code == 1
    data = json.loads(result.stdout)
    assert data["within_limit"] is True
    assert data["body_limits"] == {"linear": [-0.1, 0.3], "angular": [-1.0, 1.0]}
    assert data["body_violations"] == [
        {
            "segment": 2,
            "axis": "linear",
            "value": 0.5,
            "bounds": [-0.1, 0.3],
            "shortest_duration": pytest.approx(1 / 0.3),
        }
    ]


def test_simulate_refuses_a_plan_over_the_body_limits(
    runner: CliRunner, robot: list[str], tmp_path: Path
) -> None:
    out = tmp_path / "states.csv"
    result = run(runner, "simulate", *robot, "spin 90 1s", "--out", str(out))
    assert result.exit_code == 1
    assert "angular velocity 1.571 rad/s is outside [-1, 1]" in result.stderr


def test_drive_refuses_a_plan_over_the_body_limits_before_any_dds(runner: CliRunner) -> None:
    result = run(runner, "drive", "straight 1 1s", "--max-linear", "0.5", "--wait", "0")
    assert result.exit_code == 1
    assert "linear velocity 1 m/s is outside [-0.5, 0.5]" in result.stderr


def test_ik_reports_and_clamps_each_axis_apart(runner: CliRunner, robot: list[str]) -> None:
    over = run(runner, "ik", *robot, "0.4", "0.5")
    assert_one_error_line(over, "linear velocity exceeds the body limits", code=1)
    result = run(runner, "ik", *robot, "0.5", "2", "--saturate", "--json")
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    # Clamped apart as diff_drive_controller does: 0.3 m/s and 1 rad/s, wheels
    # (0.3 -+ 0.1) / 0.05 = 4 and 8 rad/s, within 100 rpm (10.47 rad/s).
    assert (data["left"], data["right"]) == pytest.approx((4.0, 8.0))
    assert data["body_limits"] == {"linear": [-0.1, 0.3], "angular": [-1.0, 1.0]}
    assert data["within_body_limits"] is True
    assert data["saturated"] is True


@pytest.mark.parametrize("command", ["plan", "ik", "simulate", "drive", "node ik"])
@pytest.mark.parametrize("option", ["--max-linear", "--max-angular"])
@pytest.mark.parametrize("bad", ["0", "-1", "nan", "inf"])
def test_bad_limits_are_one_error_line(
    runner: CliRunner, command: str, option: str, bad: str
) -> None:
    args = [*command.split(), f"{option}={bad}"]
    if command == "ik":
        args += ["0.1", "0"]
    assert_one_error_line(run(runner, *args), option)


def test_the_help_of_the_fastest_shape_says_it_uses_the_whole_motor_limit(
    runner: CliRunner,
) -> None:
    text = " ".join(run(runner, "plan", "--help").stdout.split())
    assert "fastest: the least time at the whole motor limit" in text


def test_simulate_runs_the_controllers_limiter_with_the_given_limits(
    runner: CliRunner, robot: list[str], tmp_path: Path
) -> None:
    # The file says 0.3 m/s; --max-linear 0.4 plans 1 m in 2.5 s and the limiter, given the
    # same limit, executes it as planned (with the file's 0.3 m/s it would end 0.25 m short).
    out = tmp_path / "states.csv"
    result = run(
        runner,
        "simulate",
        *robot,
        "straight 1",
        "--fastest",
        "--max-linear",
        "0.4",
        "--out",
        str(out),
        "--json",
    )
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["executed_final_pose"]["x"] == pytest.approx(1.0, abs=1e-9)
    assert data["offset"] == pytest.approx(0.0, abs=1e-9)


def test_the_table_checks_the_body_limits(runner: CliRunner, robot: list[str]) -> None:
    within = run(runner, "plan", *robot, "straight 1 10s; spin 90")
    assert within.exit_code == 0, within.output
    assert "body limits linear [-0.1, 0.3] m/s, angular [-1, 1] rad/s: within" in within.stdout
    over = run(runner, "plan", *robot, "straight 1 1s; spin 90 1s; straight 1 1s")
    assert (
        "body limits linear [-0.1, 0.3] m/s, angular [-1, 1] rad/s: OVER in segments 1, 2, 3"
        in (over.stdout)
    )
    plain = run(runner, "plan", "straight 1")
    assert "body limits" not in plain.stdout
