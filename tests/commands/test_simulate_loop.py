"""``diffbot simulate`` on a disturbed robot: open loop and with ``--follow``, its summary, its
true pose columns and its refusals."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from diffbot.cli import main

DISTURBED = ["--motor-lag", "0.15", "--latency", "0.04", "--drop", "0.05", "--seed", "1"]
KEYS = {
    "final_position_error",
    "final_heading_error",
    "max_cross_track_error",
    "rms_cross_track_error",
    "peak_limit_fraction",
    "duration",
    "arrived",
}


def simulate(runner: CliRunner, tmp_path: Path, *args: str) -> dict[str, object]:
    out = tmp_path / "run.csv"
    result = runner.invoke(main, ["simulate", *args, "-o", str(out), "--json", "--force"])
    assert result.exit_code == 0, result.output + result.stderr
    return json.loads(result.output)


def test_wrong_radii_open_loop_end_far_off_and_a_followed_run_on_truth_arrives(
    runner: CliRunner, tmp_path: Path
) -> None:
    real = ["--true-wheel-radius", "0.0357,0.0343", "--true-separation", "0.139", "--ticks", "4096"]
    common = ["--example", "B", *DISTURBED, *real]
    open_loop = simulate(runner, tmp_path, *common)
    followed = simulate(
        runner, tmp_path, *common, "--follow", "--pose-source", "truth", "--pose-noise", "0.001,0.2"
    )
    assert set(open_loop) >= KEYS
    assert set(followed) >= KEYS
    assert open_loop["control"] == "open-loop"
    assert followed["control"] == "tracking"
    assert open_loop["final_position_error"] > 0.1
    assert followed["final_position_error"] < 0.01
    assert followed["final_heading_error"] < math.radians(1.0)
    assert followed["max_cross_track_error"] < 0.02
    assert followed["arrived"] is True
    assert 0.0 < followed["peak_limit_fraction"] <= 1.0


def test_pure_pursuit_arrives_and_writes_the_true_pose_columns(
    runner: CliRunner, tmp_path: Path
) -> None:
    summary = simulate(
        runner,
        tmp_path,
        "straight 0.5; spin 90; straight 0.3",
        *DISTURBED,
        "--follow",
        "pure-pursuit",
    )
    assert summary["arrived"] is True
    assert summary["final_position_error"] < 0.01
    lines = (tmp_path / "run.csv").read_text().splitlines()
    assert lines[0].split(",")[-3:] == ["x", "y", "theta"]
    x, y, theta = (float(v) for v in lines[-1].split(",")[-3:])
    assert math.hypot(x - 0.5, y - 0.3) < 0.01
    assert abs(theta - math.pi / 2) < math.radians(1.0)


def test_the_json_gives_the_plans_end_and_where_the_robot_really_ended(
    runner: CliRunner, tmp_path: Path
) -> None:
    summary = simulate(runner, tmp_path, "straight 1; spin 90", *DISTURBED, "--slip", "0.05")
    assert summary["final_pose"] == {"x": 1.0, "y": 0.0, "theta": math.pi / 2}  # the plan's
    end = summary["true_final_pose"]
    last = (tmp_path / "run.csv").read_text().splitlines()[-1].split(",")
    assert [float(v) for v in last[-3:]] == [end["x"], end["y"], end["theta"]]
    distance = math.hypot(end["x"] - 1.0, end["y"])
    assert summary["final_position_error"] == pytest.approx(distance, abs=1e-15)
    assert summary["final_position_error"] > 0.01  # slipping, it fell short


@pytest.mark.parametrize("disturbed", [[], DISTURBED])
def test_a_goal_plan_s_json_gives_the_start_its_poses_are_relative_to(
    runner: CliRunner, tmp_path: Path, disturbed: list[str]
) -> None:
    goal = ["--to", "1,1,90", "--from", "2,0,180", *disturbed]
    summary = simulate(runner, tmp_path, *goal)
    assert summary["start_pose"] == {"x": 2.0, "y": 0.0, "theta": math.pi}
    # The start composed with the plan's end is the goal, in the goals' frame.
    end = summary["final_pose"]
    assert isinstance(end, dict)
    x, y = 2.0 - end["x"], -end["y"]  # turned by 180 degrees
    assert (x, y) == (pytest.approx(1.0, abs=1e-9), pytest.approx(1.0, abs=1e-9))
    assert "start_pose" not in simulate(runner, tmp_path, "straight 0.2", *disturbed)


def test_the_table_says_how_far_the_run_ended(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "a.csv"
    result = runner.invoke(
        main, ["simulate", "straight 0.2", *DISTURBED, "--follow", "-o", str(out)]
    )
    assert result.exit_code == 0, result.stderr
    assert "followed (tracking) at 20 Hz" in result.output
    assert "arrived" in result.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--drop", "1"], "--drop"),
        (["--slip", "nan"], "--slip"),
        (["--motor-lag", "-0.1"], "--motor-lag"),
        (["--latency", "inf"], "--latency"),
        (["--follow", "--control-rate", "60"], "--control-rate"),
        (["--control-rate", "0"], "--control-rate"),
        (["--motor-lag", "0.1", "--control-rate", "1e-300"], "'--control-rate': '1e-300' must be"),
        (["--pose-source", "truth"], "--follow"),
        (["--follow", "--pose-noise", "0.001,0.2"], "--pose-source truth"),
        (["--follow", "--pose-source", "truth", "--pose-noise", "-1,0"], "--pose-noise"),
        (["--follow", "stanley"], "--follow"),
        (["--follow", "--lead", "-0.1"], "--lead"),
        (["--follow", "--lead", "nan"], "--lead"),
        (["--follow", "--lead", "inf"], "--lead"),
        (["--follow", "--lead", "2.5"], "--lead"),
        (["--lead", "0.2"], "--follow"),
        (["--follow", "pure-pursuit", "--lead", "0.2"], "--lead"),
        (["--follow", "--latency", "1.5", "--motor-lag", "1"], "--lead"),
    ],
)
def test_bad_options_are_one_error_line(
    runner: CliRunner, tmp_path: Path, args: list[str], message: str
) -> None:
    result = runner.invoke(main, ["simulate", "straight 0.2", *args, "-o", str(tmp_path / "x.csv")])
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("error: ")
    assert message in lines[0]
    assert not (tmp_path / "x.csv").exists()


def test_a_plan_over_the_limit_is_not_followed(runner: CliRunner, tmp_path: Path) -> None:
    result = runner.invoke(
        main, ["simulate", "straight 1 1s", "--follow", "-o", str(tmp_path / "x.csv")]
    )
    assert result.exit_code == 2
    assert "segment 1" in result.stderr
    assert "shortest duration" in result.stderr
    assert not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize(
    ("text", "more"), [("straight 0.3; spin 90", " segment:"), ("straight 1 1s", None)]
)
def test_a_plan_over_the_limit_in_several_segments_is_still_one_error_line(
    runner: CliRunner, tmp_path: Path, text: str, more: str | None
) -> None:
    args = ["simulate", text, "--follow", "--max-rpm", "0.01", "-o", str(tmp_path / "x.csv")]
    result = runner.invoke(main, args)
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith("error: segment 1 (")
    if more is None:
        assert "more segment" not in result.stderr
    else:
        assert f"(and 1 more{more} 'diffbot plan' lists them)" in result.stderr


def test_a_plain_simulation_below_the_control_rate_is_not_refused(
    runner: CliRunner, tmp_path: Path
) -> None:
    # --control-rate only paces a disturbed or followed run; an exact one samples at any rate.
    result = runner.invoke(
        main, ["simulate", "straight 0.2", "--rate", "7", "-o", str(tmp_path / "x.csv")]
    )
    assert result.exit_code == 0, result.stderr
    refused = runner.invoke(
        main,
        ["simulate", "straight 0.2", "--rate", "7", "--drop", "0.1", "-o", str(tmp_path / "y.csv")],
    )
    assert refused.exit_code == 2
    assert "--control-rate" in refused.stderr


def test_the_lead_defaults_to_the_simulated_delay_and_cuts_the_cross_track_error(
    runner: CliRunner, tmp_path: Path
) -> None:
    # Latency 0.04 s, motor lag 0.15 s, half of a 20 Hz period: 0.215 s. Without it the
    # corners of Trajectory A cost 15.2 mm on this robot's true pose, with it 0.6 mm (measured;
    # the bound asks for a quarter).
    common = ["--example", "A", "--motor-lag", "0.15", "--latency", "0.04", "--follow"]
    truth = ["--pose-source", "truth"]
    led = simulate(runner, tmp_path, *common, *truth)
    plain = simulate(runner, tmp_path, *common, *truth, "--lead", "0")
    given = simulate(runner, tmp_path, *common, *truth, "--lead", "0.215")
    assert led["lead"] == pytest.approx(0.215, abs=1e-12)
    assert plain["lead"] == 0.0
    assert given == {**led, "lead": 0.215}
    assert plain["max_cross_track_error"] > 0.01
    assert led["max_cross_track_error"] < 0.25 * plain["max_cross_track_error"]


LOW_RATE = ["--rate", "0.01", "--control-rate", "0.01"]


@pytest.mark.timeout(60)
@pytest.mark.parametrize(
    ("args", "rows"),
    [
        (["straight 0.3", "--motor-lag", "0.1", "--control-rate", "1e-6", "--rate", "1e-6"], 5),
        (["straight 0.001 100000s", "--motor-lag", "0.1", *LOW_RATE], 1004),
        (
            ["straight 0.3", "--follow", "--lead", "0", "--control-rate", "1e-6", "--rate", "1e-6"],
            4,
        ),
    ],
)
def test_a_run_at_a_low_rate_costs_its_samples_not_its_seconds(
    runner: CliRunner, tmp_path: Path, args: list[str], rows: int
) -> None:
    # Millions of simulated seconds, a few samples: they were stepped a millisecond at a time.
    out = tmp_path / "x.csv"
    start = time.process_time()
    result = runner.invoke(main, ["simulate", *args, "-o", str(out)])
    assert result.exit_code == 0, result.output + result.stderr
    assert time.process_time() - start < 10.0
    assert len(out.read_text().splitlines()) == 1 + rows


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["straight 1 20000s", "--motor-lag", "0.1", "--rate", "1000"],
            "error: the run's 20000.6 s at 1000 Hz would take 20000602 samples, more than the "
            "10000000 simulate makes: lower --rate to at most 499.9 Hz for this plan",
        ),
        (
            ["straight 0.2", "--motor-lag", "0.1", "--rate", "1e6", "--follow"],
            "error: the run's up to 18.65 s at 1e+06 Hz would take 18650003 samples, more than "
            "the 10000000 simulate makes: lower --rate to at most 5.361e+05 Hz for this plan",
        ),
        (
            ["straight 1 600000s", "--motor-lag", "0.1"],
            "error: the run's 600001 s at 50 Hz would take 30000032 samples, more than the "
            "10000000 simulate makes: that is too long even at --rate 20 Hz, the "
            "--control-rate: lower both, or shorten the plan",
        ),
    ],
)
def test_a_run_of_too_many_samples_says_how_many_and_the_highest_rate_that_fits(
    runner: CliRunner, tmp_path: Path, args: list[str], message: str
) -> None:
    result = runner.invoke(main, ["simulate", *args, "-o", str(tmp_path / "x.csv")])
    assert result.exit_code == 2
    assert result.stderr == message + "\n"
    assert not (tmp_path / "x.csv").exists()
