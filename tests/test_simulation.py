"""Simulated joint states of a plan, and ``diffbot simulate``: odometry of them ends where the plan
does."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from peak_memory import peak_bytes
from robots import BOT_50_RPM
from wheel_motion import angle_error

import diffbot
from diffbot.cli import main
from diffbot.errors import ParameterError
from diffbot.io.bag import read_bag
from diffbot.io.csv_chunks import read_csv
from diffbot.kinematics import DiffDriveParams
from diffbot.odometry import integrate
from diffbot.planfile import parse_plan
from diffbot.replay import run_odometry
from diffbot.simulation import (
    Disturbances,
    DisturbedRobot,
    Sampling,
    quantise,
    sample_time_chunks,
    sample_times,
    simulate,
    simulate_chunks,
)
from diffbot.trajectory import EXAMPLES, Arc, Segment, Spin, Straight, plan, wheel_positions

BOT = BOT_50_RPM

durations = st.one_of(st.none(), st.floats(0.05, 20.0))
segments_st = st.lists(
    st.one_of(
        st.builds(Straight, st.floats(0.001, 3.0), durations),
        st.builds(
            Arc,
            st.floats(0.01, 2.0),
            st.floats(0.01, 2 * math.pi),
            st.sampled_from(["cw", "ccw"]),
            durations,
        ),
        st.builds(Spin, st.floats(0.01, 7.0) | st.floats(-7.0, -0.01), durations),
    ),
    min_size=1,
    max_size=6,
)
robots = st.builds(
    DiffDriveParams,
    wheel_radius=st.floats(0.01, 0.3),
    wheel_separation=st.floats(0.05, 1.0),
    left_sign=st.sampled_from([1, -1]),
    right_sign=st.sampled_from([1, -1]),
)


def odometry_end(states: diffbot.simulation.JointStates, params: DiffDriveParams) -> diffbot.Pose:
    series = integrate(params, states.positions[0], states.positions[1])
    return diffbot.Pose(float(series.x[-1]), float(series.y[-1]), float(series.theta[-1]))


# --------------------------------------------------------------------------------------------
# Library


def test_samples_are_at_the_rate_and_include_the_end() -> None:
    assert sample_times(1.0, 4.0).tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert sample_times(0.9, 4.0).tolist() == [0.0, 0.25, 0.5, 0.75, 0.9]
    assert sample_times(0.0, 50.0).tolist() == [0.0]
    assert sample_times(1e-12, 50.0).tolist() == [0.0]  # shorter than a stamp's resolution


def test_segment_boundaries_are_sampled_and_replace_grid_times_a_nanosecond_away() -> None:
    times = sample_times(1.0, 4.0, (0.3, 0.5 + 1e-12, 0.3 + 1e-13, 1.0 - 1e-14))
    assert times.tolist() == [0.0, 0.25, 0.3, 0.5 + 1e-12, 0.75, 1.0]


@settings(max_examples=200, deadline=None)
@given(
    st.floats(1e-6, 100.0),
    st.floats(0.5, 200.0),
    st.lists(st.floats(0.0, 100.0), max_size=10),
)
def test_sample_times_increase_by_at_most_one_period_and_never_share_a_stamp(
    duration: float, rate: float, boundaries: list[float]
) -> None:
    times = sample_times(duration, rate, tuple(boundaries))
    assert times[0] == 0.0
    assert times[-1] == duration
    gaps = np.diff(times)
    assert np.all(gaps > 1e-9)
    assert np.all(gaps <= 1.0 / rate + 1e-9)
    for boundary in boundaries:
        if 0.0 < boundary < duration:
            assert np.min(np.abs(times - boundary)) <= 1e-9


def test_quantised_angles_are_whole_encoder_counts_within_half_a_count() -> None:
    angles = np.linspace(-10.0, 10.0, 1001)
    counts = quantise(angles, 1024) / (2 * math.pi / 1024)
    assert np.allclose(counts, np.round(counts), atol=1e-9)
    assert np.max(np.abs(quantise(angles, 1024) - angles)) <= math.pi / 1024 + 1e-15
    with pytest.raises(diffbot.ParameterError, match=r"an integer from 1 to 2\*\*32, got 0"):
        quantise(angles, 0)


def test_trajectory_a_at_50_hz_has_2001_samples_of_four_joints() -> None:
    p = plan(parse_plan(EXAMPLES["A"]), BOT)
    casters = ("caster_rotation_joint", "caster_wheel_joint")
    states = simulate(p, BOT, 50.0, extra_joints=casters)
    assert states.times.size == 2001
    assert states.times[-1] == 40.0
    assert states.names == (BOT.left_joint, BOT.right_joint, *casters)
    assert states.positions.shape == (4, 2001)
    assert not states.positions[2:].any()
    assert states.positions[:2, 0].tolist() == [0.0, 0.0]
    # 2 m of straights and two half circles of 0.25 m: 2 + pi/2 m per wheel on average.
    mean = (states.positions[0, -1] + states.positions[1, -1]) / 2 * BOT.wheel_radius
    assert mean == pytest.approx(2 + math.pi / 4 * 2, rel=1e-12)


@settings(max_examples=150, deadline=None)
@given(robots, segments_st, st.sampled_from([1.0, 3.0, 7.5, 10.0, 50.0, 200.0]))
def test_odometry_of_a_simulated_plan_ends_at_the_plans_final_pose(
    params: DiffDriveParams, segments: list[Segment], rate: float
) -> None:
    p = plan(segments, params)
    end = odometry_end(simulate(p, params, rate), params)
    assert end.x == pytest.approx(p.final_pose.x, abs=1e-9)
    assert end.y == pytest.approx(p.final_pose.y, abs=1e-9)
    assert angle_error(end.theta, p.final_pose.theta) <= 1e-9


def test_fastest_plans_with_odd_durations_are_reproduced_exactly() -> None:
    p = plan(parse_plan(EXAMPLES["B"]), BOT, fastest=True)
    assert p.segments[1].duration % 0.02 != 0.0  # boundaries off the 50 Hz grid
    end = odometry_end(simulate(p, BOT, 50.0), BOT)
    assert (end.x, end.y) == pytest.approx((0.0, 1.0), abs=1e-9)


def test_noise_is_gaussian_and_reproducible_with_a_seed() -> None:
    p = plan(parse_plan("straight 1 100s"), BOT)
    clean = simulate(p, BOT, 50.0).positions
    noisy = simulate(p, BOT, 50.0, noise=0.01, seed=3).positions
    again = simulate(p, BOT, 50.0, noise=0.01, seed=3).positions
    other = simulate(p, BOT, 50.0, noise=0.01, seed=4).positions
    assert np.array_equal(noisy, again)
    assert not np.array_equal(noisy, other)
    error = noisy[:2] - clean[:2]
    assert np.std(error) == pytest.approx(0.01, rel=0.05)
    assert abs(np.mean(error)) < 0.001
    assert not noisy[2:].any()  # the casters stay still


def test_ticks_quantise_the_wheels_after_the_noise() -> None:
    p = plan(parse_plan("ccw 0.5 90 5s"), BOT)
    states = simulate(p, BOT, 10.0, ticks=360, noise=0.001, seed=1)
    degrees = np.degrees(states.positions[:2])
    assert np.allclose(degrees, np.round(degrees), atol=1e-9)


def test_bad_simulation_settings_are_refused() -> None:
    p = plan(parse_plan("straight 1"), BOT)
    with pytest.raises(diffbot.ParameterError, match="noise must be a finite number >= 0"):
        simulate(p, BOT, noise=-1.0)
    with pytest.raises(diffbot.ParameterError, match=r"rate must be a positive .* got 0"):
        simulate(p, BOT, rate=0.0)


# --------------------------------------------------------------------------------------------
# CLI


def test_simulate_prints_trajectory_a_as_csv_by_default(runner: CliRunner) -> None:
    result = runner.invoke(main, ["simulate"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == (
        "time,front_left_wheel_joint,front_right_wheel_joint,"
        "caster_rotation_joint,caster_wheel_joint"
    )
    assert len(lines) == 2002
    assert lines[1] == "0,0.0,0.0,0.0,0.0"
    assert lines[-1].startswith("40,")


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["--example", "B", "--fastest"],
        ["straight 1 5.555s; ccw 0.2 97 4.7s; spin -45; cw 0.3 33", "--rate", "7"],
        ["--example", "a", "--rate", "10", "wheel_radius:=0.05"],
    ],
)
def test_simulate_then_odom_ends_exactly_at_the_plans_final_pose(
    runner: CliRunner, tmp_path: Path, args: list[str]
) -> None:
    out = tmp_path / "joints.csv"
    result = runner.invoke(main, ["simulate", *args, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert f"output      {out} (CSV)" in result.stdout
    robot = [a for a in args if ":=" in a]
    planned = runner.invoke(main, ["plan", *args, "--json"])
    assert planned.exit_code == 0, planned.output
    expected = json.loads(planned.stdout)["final_pose"]
    odom = runner.invoke(main, ["odom", str(out), *robot, "--json"])
    assert odom.exit_code == 0, odom.output
    final = json.loads(odom.stdout)["final_pose"]
    assert final["x"] == pytest.approx(expected["x"], abs=1e-9)
    assert final["y"] == pytest.approx(expected["y"], abs=1e-9)
    assert angle_error(final["theta"], expected["theta"]) <= 1e-9
    assert json.loads(odom.stdout)["skipped"] == {}


def test_simulate_of_a_true_robot_says_where_it_really_ended(
    runner: CliRunner, tmp_path: Path
) -> None:
    # The real wheels are 2 % larger and 0.139 m apart where the description says 0.035 m and
    # 0.135 m: told to drive 1 m and turn 90 degrees, the robot drives 1.02 m and turns
    # 90 * 1.02 * 0.135 / 0.139 degrees. The summary gave only the plan's end as its final pose.
    out = tmp_path / "run.csv"
    truth = ["--true-wheel-radius", "0.0357,0.0357", "--true-separation", "0.139"]
    args = ["simulate", "straight 1; spin 90", *truth, "-o", str(out)]
    result = runner.invoke(main, [*args, "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["final_pose"] == {"x": 1.0, "y": 0.0, "theta": math.pi / 2}  # the plan's
    turn = math.pi / 2 * 1.02 * 0.135 / 0.139
    end = summary["true_final_pose"]
    assert end["x"] == pytest.approx(1.02, abs=1e-12)
    assert end["y"] == pytest.approx(0.0, abs=1e-12)
    assert end["theta"] == pytest.approx(turn, abs=1e-12)
    # The CSV's last true pose, exactly.
    last = out.read_text().splitlines()[-1].split(",")
    assert [float(v) for v in last[-3:]] == [end["x"], end["y"], end["theta"]]
    assert summary["final_position_error"] == pytest.approx(0.02, abs=1e-12)
    assert summary["final_heading_error"] == pytest.approx(math.pi / 2 - turn, abs=1e-12)
    # The table says it too, beside the plan's end.
    table = runner.invoke(main, [*args, "--force"])
    assert table.exit_code == 0, table.output
    lines = table.stdout.splitlines()
    assert "final pose  x 1 m, y 0 m, theta 1.5708 rad" in lines
    assert (
        f"true end    x 1.02 m, y 0 m, theta {turn:.6g} rad: 20 mm, "
        f"{math.degrees(math.pi / 2 - turn):.3g} deg from the plan's end"
    ) in lines
    # In a bag as well.
    bag = runner.invoke(main, [*args[:-1], str(tmp_path / "bag"), "--bag", "--json"])
    assert bag.exit_code == 0, bag.output
    assert json.loads(bag.stdout)["true_final_pose"] == end
    # A robot as described ends where the plan does: no true pose, as the output has none.
    plain = runner.invoke(main, ["simulate", "straight 1; spin 90", "-o", str(out), "--force"])
    assert plain.exit_code == 0, plain.output
    assert "true end" not in plain.stdout
    described = runner.invoke(main, ["simulate", "straight 1", "-o", str(out), "--force", "--json"])
    assert "true_final_pose" not in json.loads(described.stdout)


def test_simulate_writes_a_bag_of_joint_states_that_odom_reads(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "bag"
    args = ["simulate", "--out", str(out), "--bag", "--start", "1700000000.5", "--json"]
    result = runner.invoke(main, [*args, "--topic", "/bot/joint_states"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["samples"] == 2001
    assert summary["joints"] == [
        "front_left_wheel_joint",
        "front_right_wheel_joint",
        "caster_rotation_joint",
        "caster_wheel_joint",
    ]
    samples = read_bag(out, "/bot/joint_states").samples
    assert samples[0].stamp_ns == 1_700_000_000_500_000_000
    assert samples[-1].stamp_ns == 1_700_000_040_500_000_000
    assert list(samples[5].names) == summary["joints"]
    odom = runner.invoke(main, ["odom", str(out), "--topic", "/bot/joint_states", "--json"])
    assert odom.exit_code == 0, odom.output
    assert json.loads(odom.stdout)["final_pose"]["y"] == pytest.approx(1.0, abs=1e-9)


def test_simulate_with_ticks_and_noise_is_reproducible(runner: CliRunner, tmp_path: Path) -> None:
    args = ["simulate", "straight 0.5 5s", "--ticks", "4096", "--noise", "0.002", "--seed", "9"]
    first = runner.invoke(main, args)
    second = runner.invoke(main, args)
    assert first.exit_code == 0, first.output
    assert first.stdout == second.stdout
    (tmp_path / "j.csv").write_text(first.stdout, encoding="utf-8")
    samples = read_csv(tmp_path / "j.csv", BOT.left_joint, BOT.right_joint).samples
    counts = np.array([s.positions for s in samples]) / (2 * math.pi / 4096)
    assert np.allclose(counts, np.round(counts), atol=1e-6)
    run = run_odometry(
        read_csv(tmp_path / "j.csv", BOT.left_joint, BOT.right_joint), diffbot.Odometry(BOT)
    )
    assert run.final_pose.x == pytest.approx(0.5, abs=0.01)  # close, no longer exact


def test_simulate_of_a_plan_over_the_limit_writes_it_and_exits_1(
    runner: CliRunner, tmp_path: Path
) -> None:
    out = tmp_path / "fast.csv"
    result = runner.invoke(main, ["simulate", "straight 1 1s", "--out", str(out)])
    assert result.exit_code == 1
    assert "exceed the 50 rpm limit; shortest duration that fits: 5.457 s" in result.stderr
    assert out.read_text(encoding="utf-8").splitlines()[-1].startswith("1,")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["straight"], "error: "),
        (["straight 1", "--rate", "0"], "'0' must be > 0"),
        (["straight 1", "--ticks", "0"], "0 is not in the range 1<=x<=4294967296"),
        (["straight 1", "--noise", "-1"], "'-1' must be >= 0"),
        (["straight 1", "--noise", "nan"], "not a finite number"),
        (["straight 1", "--bag"], "--bag writes the --out directory"),
        (["straight 1", "--json"], "--json prints a summary, so the samples need --out"),
        (["--example", "C"], "Invalid value for '--example': 'C' is not one of"),
        (["nope.yaml"], "nope.yaml"),
    ],
)
def test_simulate_refuses_bad_input_with_exit_code_2(
    runner: CliRunner, tmp_path: Path, args: list[str], message: str
) -> None:
    result = runner.invoke(main, ["simulate", *args])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ")
    assert message in result.stderr
    assert "Traceback" not in result.output


def test_simulate_never_overwrites_without_force(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "j.csv"
    out.write_text("keep", encoding="utf-8")
    result = runner.invoke(main, ["simulate", "--out", str(out)])
    assert result.exit_code == 2
    assert result.stderr == f"error: {out} exists: use --force to overwrite it\n"
    assert out.read_text(encoding="utf-8") == "keep"
    assert runner.invoke(main, ["simulate", "--out", str(out), "--force"]).exit_code == 0
    assert out.read_text(encoding="utf-8").startswith("time,")


def test_simulate_force_never_writes_over_its_plan_or_robot_file(
    runner: CliRunner, tmp_path: Path
) -> None:
    plan_file = tmp_path / "plan.yaml"
    plan_file.write_text("- {straight: 1.0, duration: 10}\n", encoding="utf-8")
    robot = tmp_path / "robot.urdf"
    assert runner.invoke(main, ["urdf", "-o", str(robot)]).exit_code == 0
    (tmp_path / "metadata.yaml").write_text("a bag, so that --force would replace it\n")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    base = ["simulate", str(plan_file), "--robot", str(robot), "--force"]
    for extra, fragment in [
        (["--out", str(plan_file)], f"is the input {plan_file}"),
        (["--out", str(robot)], f"is the input {robot}"),
        (["--out", str(tmp_path), "--bag"], f"contains the input {plan_file}"),
    ]:
        result = runner.invoke(main, [*base, *extra])
        assert result.exit_code == 2, result.output
        assert result.stderr.startswith("error: ")
        assert result.stderr.count("\n") == 1
        assert fragment in result.stderr
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--seed", "-1", "--noise", "0.1"], "Invalid value for '--seed': -1 is not in the range"),
        (["--seed", str(2**64)], "Invalid value for '--seed'"),
        (["--start", "1e300"], "'1e300' is past 2262, the end of int64 nanosecond stamps"),
        (["--start", "1e100000000"], "is past 2262"),
        (["--start", "-1"], "'-1' must be >= 0"),
        (["--start", "nan"], "'nan' is not a finite number"),
        (["--start", "1_0"], "'1_0' is not a number"),
        (["--start", "9223372036"], "--start plus the plan's 40 s ends past 2262"),
        (["--ticks", "1" + "0" * 400], "Invalid value for '--ticks'"),
        (["--ticks", str(2**32 + 1)], "Invalid value for '--ticks'"),
        (["--rate", "1e300"], "'1e300' must be <= 1e+06 Hz"),
        (["--rate", "1e10"], "'1e10' must be <= 1e+06 Hz"),
        (["--rate", "inf"], "not a finite number"),
        (["straight 1 1e300s"], "the plan takes 1e+300 s, more than the 9.22337e+09 s"),
        (["straight 1", "--speed", "1e-300"], "the plan takes 1e+300 s, more than the"),
        (["straight 1 1e9s", "--rate", "50"], "would take 5e+10 samples, more than the 10000000"),
        (["straight 1", "--speed", "1e-9"], "would take 5e+10 samples"),
        (
            ["--rate", "1e6"],
            "would take 4e+07 samples, more than the 10000000 simulate makes: "
            "lower --rate to at most 2.5e+05 Hz",
        ),
        (["--topic", ""], "--topic '' is not a valid ROS topic name"),
        (["--topic", "a b"], "--topic 'a b' is not a valid ROS topic name"),
    ],
)
def test_simulate_refuses_out_of_range_options_with_one_error_line(
    runner: CliRunner, tmp_path: Path, args: list[str], message: str
) -> None:
    out = tmp_path / "out"
    result = runner.invoke(main, ["simulate", *args, "--out", str(out), "--bag"])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith("error: ")
    assert result.stderr.count("\n") == 1
    assert message in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_simulate_start_is_read_exactly_to_the_nanosecond(runner: CliRunner) -> None:
    result = runner.invoke(main, ["simulate", "straight 0.1 1s", "--start", "1700000000.123456789"])
    assert result.exit_code == 0, result.output
    times = [line.split(",")[0] for line in result.stdout.splitlines()[1:]]
    assert times[0] == "1700000000.123456789"
    assert times[-1] == "1700000001.123456789"


def test_simulate_at_the_highest_rate_gives_every_sample_its_own_stamp(
    runner: CliRunner, tmp_path: Path
) -> None:
    result = runner.invoke(main, ["simulate", "straight 0.0001 0.002s", "--rate", "1e6"])
    assert result.exit_code == 0, result.output
    (tmp_path / "j.csv").write_text(result.stdout, encoding="utf-8")
    recording = read_csv(tmp_path / "j.csv", BOT.left_joint, BOT.right_joint)
    stamps = [s.stamp_ns for s in recording.samples]
    assert len(stamps) == 2001
    assert stamps == sorted(set(stamps))
    assert min(b - a for a, b in itertools.pairwise(stamps)) == 1000


def test_library_refuses_rates_and_sample_counts_it_cannot_stamp_or_hold() -> None:
    with pytest.raises(
        diffbot.ParameterError, match=r"rate must be a positive number up to 1e\+06"
    ):
        sample_times(1.0, 2e6)
    with pytest.raises(diffbot.ParameterError, match=r"would take 5e\+10 samples, more than"):
        sample_times(1e9, 50.0)
    with pytest.raises(diffbot.ParameterError, match="more than 100: lower the rate"):
        sample_times(10.0, 10.0, max_samples=100)
    with pytest.raises(diffbot.ParameterError, match=r"from 1 to 2\*\*32, got 4294967297"):
        quantise(np.zeros(3), 2**32 + 1)
    p = plan(parse_plan("straight 1"), BOT)
    with pytest.raises(diffbot.ParameterError, match="seed must be an integer >= 0, got -1"):
        simulate(p, BOT, noise=0.1, seed=-1)
    with pytest.raises(diffbot.ParameterError, match=r"from 1 to 2\*\*32, got 0"):
        simulate(p, BOT, ticks=0)


def test_simulate_checks_the_rpm_limit_option_like_plan(runner: CliRunner, tmp_path: Path) -> None:
    out = tmp_path / "slow.csv"
    result = runner.invoke(main, ["simulate", "--max-rpm", "20", "--out", str(out)])
    assert result.exit_code == 1, result.output
    assert out.is_file()  # the joint states are still written
    errors = result.stderr.strip().splitlines()
    assert len(errors) == 4
    assert all(line.startswith("error: segment ") for line in errors)
    assert "exceed the 20 rpm limit" in errors[1]
    within = runner.invoke(main, ["simulate", "--max-rpm", "30", "--out", str(tmp_path / "ok.csv")])
    assert within.exit_code == 0, within.output


def test_the_robots_own_joints_are_written_every_wheel_of_a_side_alike() -> None:
    four = BOT.replace(
        left_joints=("fl", "rl"), right_joints=("fr", "rr"), passive_joints=("castor",)
    )
    states = simulate(plan(parse_plan("ccw 0.5 90"), four), four, 10.0)
    assert states.names == ("fl", "rl", "fr", "rr", "castor")
    assert np.array_equal(states.positions[0], states.positions[1])
    assert np.array_equal(states.positions[2], states.positions[3])
    assert states.positions[2, -1] > states.positions[0, -1] > 0.0
    assert not states.positions[4].any()
    assert simulate(plan(parse_plan("spin 90"), BOT), BOT, 10.0).names == (
        BOT.left_joint,
        BOT.right_joint,
    )


def whole_sample_times(duration: float, rate: float, boundaries: list[float]) -> np.ndarray:
    """The sampling rule over whole arrays, as simulate had it before it made chunks."""
    exact = [0.0]
    for boundary in sorted(b for b in boundaries if 0.0 < b < duration - 1e-9):
        if boundary - exact[-1] > 1e-9:
            exact.append(boundary)
    if duration > 1e-9:
        if duration - exact[-1] <= 1e-9:
            exact.pop()
        exact.append(duration)
    fixed = np.array(exact)
    grid = np.arange(math.ceil(duration * rate) + 1, dtype=np.float64) / rate
    grid = grid[grid < duration]
    after = np.searchsorted(fixed, grid).clip(max=fixed.size - 1)
    before = (after - 1).clip(min=0)
    distance = np.minimum(np.abs(fixed[after] - grid), np.abs(grid - fixed[before]))
    return np.sort(np.concatenate((grid[distance > 1e-9], fixed)))


@settings(max_examples=60, deadline=None)
@given(
    st.floats(0.0, 5.0),
    st.floats(0.5, 200.0),
    st.lists(st.floats(0.0, 5.0), max_size=5),
    st.integers(1, 40),
)
def test_time_chunks_join_into_the_whole_array_sampling(
    duration: float, rate: float, boundaries: list[float], chunk: int
) -> None:
    chunks = list(sample_time_chunks(duration, rate, tuple(boundaries), chunk=chunk))
    got = np.concatenate(chunks)
    want = whole_sample_times(duration, rate, boundaries)
    assert got.tobytes() == want.tobytes()


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_simulated_chunks_equal_the_whole_array_simulation_noise_included(noise: float) -> None:
    p = plan(parse_plan("ccw 0.25 90 2s; straight 0.3 1.5s; spin -45 1s"), BOT)
    states = simulate_chunks(p, BOT, Sampling(97.0, 4096, noise, 7), chunk=13)
    parts = list(states.chunks)
    times = whole_sample_times(p.duration, 97.0, [2.0, 3.5, 4.5])
    left, right = wheel_positions(p, times)
    wheels = np.vstack((left, right))
    if noise:
        wheels += np.random.default_rng(7).normal(0.0, noise, wheels.shape)
    wheels = quantise(wheels, 4096)
    assert states.samples == times.size
    assert np.concatenate([t for t, _ in parts]).tobytes() == times.tobytes()
    got = np.hstack([positions for _, positions in parts])
    assert got[: len(BOT.left_joints)].tobytes() == np.repeat(wheels[:1], 1, axis=0).tobytes()
    assert got[-1].tobytes() == wheels[1].tobytes()


def test_simulated_chunks_keep_memory_flat() -> None:
    p = plan(parse_plan("straight 10 200s"), BOT)
    peaks = []
    for rate in (1000.0, 4000.0):

        def run(rate: float = rate) -> tuple[int, int]:
            states = simulate_chunks(p, BOT, Sampling(rate, noise=0.001, seed=1))
            return sum(t.size for t, _ in states.chunks), states.samples

        (total, samples), peak = peak_bytes(run)
        peaks.append(peak)
        assert total == samples
    # Four times the samples (8e5 at the end, 26 MB as whole arrays): about the same peak.
    assert peaks[1] < 1.3 * peaks[0]
    assert peaks[1] < 12e6


@pytest.mark.parametrize("noise", [7.0, 1e308, -0.1, math.nan])
def test_noise_is_refused_beyond_a_revolution(noise: float) -> None:
    with pytest.raises(
        ParameterError, match=r"noise must be a finite number >= 0 and <= 6\.28319 rad"
    ):
        simulate(plan(parse_plan("straight 1"), BOT), BOT, 50.0, noise=noise)


# --------------------------------------------------------------------------------------------
# A robot that does not do what it is told


def _disturbed(**kwargs: float) -> DisturbedRobot:
    return DisturbedRobot(BOT_50_RPM, Disturbances(**kwargs, seed=3))


def test_a_wheel_follows_its_command_with_the_first_order_lag() -> None:
    robot = _disturbed(motor_lag=0.2)
    robot.command(2.0, 2.0)
    robot.advance(0.2)
    assert robot.speeds[0] == pytest.approx(2.0 * (1.0 - math.exp(-1.0)), rel=1e-9)
    # The angle is the integral of the exponential approach.
    assert robot.angles[0] == pytest.approx(2.0 * (0.2 - 0.2 * (1.0 - math.exp(-1.0))), rel=1e-9)
    assert robot.pose[0] == pytest.approx(robot.angles[0] * 0.035, rel=1e-9)


def test_a_command_arrives_after_the_latency() -> None:
    robot = _disturbed(latency=0.04)
    robot.command(1.0, 1.0)
    robot.advance(0.04)
    assert robot.angles == [0.0, 0.0]
    robot.advance(0.14)
    assert robot.angles[0] == pytest.approx(0.1, rel=1e-9)


def test_the_motor_limit_clamps_what_the_wheel_does() -> None:
    robot = _disturbed()
    robot.command(100.0, -100.0)
    robot.advance(1.0)
    assert robot.angles[0] == pytest.approx(5.235987755982989, rel=1e-9)
    assert robot.angles[1] == pytest.approx(-5.235987755982989, rel=1e-9)


def test_a_share_of_the_commands_is_dropped_reproducibly() -> None:
    counts = []
    for _ in range(2):
        robot = _disturbed(drop=0.25)
        arrived = 0
        for k in range(4000):
            before = len(robot._pending)
            robot.command(float(k), 0.0)
            arrived += len(robot._pending) - before
            robot._pending.clear()
        counts.append(arrived)
    assert counts[0] == counts[1]
    assert 0.72 * 4000 < counts[0] < 0.78 * 4000


def test_slip_loses_ground_travel_the_encoders_still_count() -> None:
    robot = _disturbed(slip=0.1)
    robot.command(2.0, 2.0)
    robot.advance(20.0)
    ground = math.hypot(robot.pose[0], robot.pose[1])
    counted = robot.angles[0] * 0.035
    assert robot.angles[0] == pytest.approx(40.0, rel=1e-9)
    assert ground == pytest.approx(0.9 * counted, rel=0.03)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"motor_lag": -0.1},
        {"latency": math.nan},
        {"drop": 1.0},
        {"slip": -0.01},
        {"slip": 1.0},
        {"motor_lag": math.inf},
        {"seed": -1},
    ],
)
def test_disturbances_outside_their_physical_ranges_are_refused(kwargs: dict[str, float]) -> None:
    with pytest.raises(ParameterError):
        Disturbances(**kwargs)  # type: ignore[arg-type]


def test_a_halted_robot_forgets_what_was_still_to_arrive_and_slows_with_its_lag() -> None:
    from diffbot.simulation import Disturbances, DisturbedRobot

    robot = DisturbedRobot(BOT_50_RPM, Disturbances(motor_lag=0.1, latency=0.2))
    robot.command(2.0, 2.0)
    robot.advance(1.0)
    robot.command(4.0, 4.0)  # due at 1.2 s, never arrives
    robot.halt()
    robot.advance(1.1)
    # Eight time constants after the command arrived at 0.2 s, then one after the halt: the
    # wheels kept e^-1 of their speed, they slow, not snap.
    speed = 2.0 * (1.0 - math.exp(-8.0)) * math.exp(-1.0)
    assert robot.speeds == pytest.approx([speed] * 2, rel=1e-6)
    robot.advance(3.0)
    assert robot.stopped


def _stepped(
    robot: DisturbedRobot, commands: list[tuple[float, float, float]], end: float, dt: float
):
    """Advance ``robot`` to ``end`` in calls ``dt`` apart, commanding each (time, left, right)
    when its time comes."""
    pending = list(commands)
    t = 0.0
    while t < end:
        while pending and pending[0][0] <= t:
            _, left, right = pending.pop(0)
            robot.command(left, right)
        t = min(end, t + dt) if pending == [] or pending[0][0] > t + dt else pending[0][0]
        robot.advance(t)
    return robot


@pytest.mark.parametrize(
    "kwargs",
    [
        {"motor_lag": 0.1},
        {"motor_lag": 0.3, "latency": 0.05, "slip": 0.05},
        {"latency": 0.07, "slip": 0.1},
    ],
)
def test_long_steps_where_the_curvature_holds_move_the_robot_as_millisecond_ones(
    kwargs: dict[str, float],
) -> None:
    # From rest, to rest, and between motions of one curvature the pose is exact over any
    # step; between others (a spin after an arc) the robot is stepped a millisecond at a time.
    commands = [(0.0, 2.0, 3.0), (4.0, -1.0, 1.0), (9.0, 1.5, 1.5), (15.0, 0.0, 0.0)]
    fine_robot = _disturbed(**kwargs)
    fine_robot._steady = lambda: False  # type: ignore[method-assign]
    fine = _stepped(fine_robot, commands, 40.0, 0.25)
    coarse = _stepped(_disturbed(**kwargs), commands, 40.0, 0.25)
    assert coarse.time == fine.time == 40.0
    assert coarse.angles == pytest.approx(fine.angles, rel=1e-12, abs=1e-12)
    assert coarse.pose == pytest.approx(fine.pose, rel=1e-12, abs=1e-12)
    assert coarse.speeds == pytest.approx(fine.speeds, rel=1e-12, abs=1e-300)


@pytest.mark.timeout(60)
@pytest.mark.parametrize("slip", [0.0, 0.05])
def test_a_robot_stepped_rarely_costs_its_events_not_its_seconds(slip: float) -> None:
    import time

    start = time.process_time()
    robot = _disturbed(motor_lag=0.1, latency=0.5, slip=slip)
    robot.advance(5e5)  # at rest: nothing moves, nothing slips
    # The redraw due is left to be drawn before it moves, on the grid of SLIP_PERIOD.
    assert 5e5 - 0.1 < robot._next_slip <= 5e5 or not slip
    robot.command(2.0, 2.0)
    robot.command(-1.0, 1.0)  # a spin after a straight: a changing curvature
    robot.advance(5e5 + 30.0)
    if not slip:
        robot.advance(1e6)  # both wheels at their targets: one step
        robot.command(0.0, 0.0)
        robot.advance(2e6)
        assert robot.speeds == [0.0, 0.0]
        assert robot.stopped
        # Half a million seconds at 1 rad/s, less a lag's worth at the start, plus one at the
        # stop.
        assert robot.angles == pytest.approx([-5e5, 5e5], rel=1e-12)
    assert time.process_time() - start < 5.0


def test_a_rate_or_duration_given_as_text_samples_as_its_number() -> None:
    """rate="10.0" passed the check and then failed in a bare TypeError."""
    steps = diffbot.plan(diffbot.parse_plan("straight 1"), BOT_50_RPM)
    as_text = simulate(steps, BOT_50_RPM, "10.0")  # type: ignore[arg-type]
    as_number = simulate(steps, BOT_50_RPM, 10.0)
    assert np.array_equal(as_text.times, as_number.times)
    assert np.array_equal(as_text.positions, as_number.positions)
    assert np.array_equal(sample_times("2", 5), sample_times(2.0, 5.0))  # type: ignore[arg-type]


@pytest.mark.parametrize("rate", [None, "fast", True, [10.0]])
def test_a_rate_that_is_no_number_is_refused_naming_it(rate: object) -> None:
    with pytest.raises(ParameterError, match=r"^rate must be a positive number up to 1e\+06"):
        sample_times(1.0, rate)  # type: ignore[arg-type]
