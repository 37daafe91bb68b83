"""Encoder units, wrap-around and implausible steps (diffbot.conditioning)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from pioneer import COUNTS_PER_MM, COUNTS_PER_REV, PIONEER, RADIUS, WRAP, counts
from robots import BOT, BOT_50_RPM

from diffbot.conditioning import (
    MOTOR_LIMIT_FACTOR,
    RIM_SPEED_BOUND,
    Conditioner,
    Conditioning,
    counter_range,
    detect_wrap,
    estimate_time_offset,
)
from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams

JOINTS = (PIONEER.left_joint, PIONEER.right_joint)


def pioneer_conditioner(conditioning: Conditioning | None = None) -> Conditioner:
    return Conditioner.for_robot(PIONEER, JOINTS, 1, conditioning)


def test_radians_without_wraps_come_back_as_the_very_same_array() -> None:
    stamps = np.arange(5, dtype=np.int64) * 100_000_000
    positions = np.array([[0.0, 0.0], [0.1, 0.2], [0.25, 0.3], [0.3, 0.45], [0.5, 0.5]])
    conditioner = pioneer_conditioner()
    assert conditioner.feed(stamps, positions) is positions
    report = conditioner.report()
    assert (report.wrap, report.wraps, report.implausible_steps) == (None, 0, 0)


def test_a_16_bit_counter_is_unwrapped_by_itself_and_said_so() -> None:
    stamps, left, right = counts()
    conditioner = pioneer_conditioner()
    angles = conditioner.feed(stamps, np.stack([left, right], axis=1))
    report = conditioner.report()
    assert report.wrap == WRAP
    assert report.wrap_detected
    # The left wheel travels 1 m + the spin's arc + 0.5 m: 1.5 m - 0.165 m * pi/2 of travel.
    travel_mm = (1.5 - 0.165 * math.pi / 2) * 1000
    assert angles[-1, 0] - angles[0, 0] == pytest.approx(travel_mm * COUNTS_PER_MM, abs=1)
    assert report.wraps == int(np.count_nonzero(np.abs(np.diff(left)) > WRAP / 2)) + int(
        np.count_nonzero(np.abs(np.diff(right)) > WRAP / 2)
    )
    assert report.wraps >= 4


def test_counts_per_rev_turns_counts_into_radians() -> None:
    stamps, left, right = counts()
    conditioner = pioneer_conditioner(Conditioning(counts_per_rev=COUNTS_PER_REV, wrap=WRAP))
    angles = conditioner.feed(stamps, np.stack([left, right], axis=1))
    travel = (angles[-1] - angles[0]) * RADIUS
    # Known value: the right wheel rolls 1 m + 0.165 m * pi/2 + 0.5 m (to the count, 1/128 mm).
    assert travel[1] == pytest.approx(1.5 + 0.165 * math.pi / 2, abs=2e-5)
    report = conditioner.report()
    assert not report.wrap_detected
    assert report.implausible_steps == 0


def test_chunks_give_the_angles_of_the_whole_recording_to_the_bit() -> None:
    stamps, left, right = counts()
    positions = np.stack([left, right], axis=1)
    options = Conditioning(counts_per_rev=COUNTS_PER_REV)
    whole = pioneer_conditioner(options).feed(stamps, positions)
    chunked = pioneer_conditioner(options)
    parts = [chunked.feed(stamps[k : k + 7], positions[k : k + 7]) for k in range(0, 101, 7)]
    np.testing.assert_array_equal(np.concatenate(parts), whole)


def test_raw_counts_read_as_radians_are_implausible_steps_with_the_first_named() -> None:
    stamps, left, right = counts()
    conditioner = pioneer_conditioner(Conditioning(wrap=0))
    conditioner.feed(stamps, np.stack([left, right], axis=1))
    report = conditioner.report()
    # Each step turns 25 mm of travel into 3200 "rad" in 0.1 s: far over 30 m/s / 0.0975 m.
    assert report.limit_source == "a rim speed of 30 m/s"
    assert report.speed_limit[0] == pytest.approx(RIM_SPEED_BOUND / RADIUS, abs=1e-12)
    assert report.implausible_steps == 100
    first = report.first_implausible
    assert first is not None
    assert (first.sample, first.joint) == (1, PIONEER.left_joint)
    assert first.seconds == pytest.approx(0.1, abs=1e-12)
    assert first.speed == pytest.approx(32000.0, rel=1e-12)


def test_the_motor_limit_sets_the_bound_when_there_is_one() -> None:
    conditioner = Conditioner.for_robot(BOT_50_RPM, ("l", "r"), 1)
    limit = MOTOR_LIMIT_FACTOR * 5.235987755982989
    slack = 0.01 / 0.035
    # One step just within the bound, then one beyond it, 0.1 s each.
    step = limit * 0.1 + slack
    positions = np.array([[0.0, 0.0], [step * 0.999, 0.0], [step * 0.999 + step * 1.01, 0.0]])
    conditioner.feed(np.array([0, 100_000_000, 200_000_000]), positions)
    report = conditioner.report()
    assert report.limit_source == "4 x the motor limit"
    assert report.implausible_steps == 1
    assert report.first_implausible is not None
    assert report.first_implausible.sample == 2


def test_missing_and_non_finite_positions_pass_through_untouched() -> None:
    stamps = np.arange(4, dtype=np.int64) * 100_000_000
    positions = np.array([[65000.0, 1.0], [math.nan, 2.0], [100.0, 3.0], [200.0, 4.0]])
    present = np.array([[True, True], [True, True], [True, False], [True, True]])
    conditioner = Conditioner.for_robot(BOT, ("l", "r"), 1, Conditioning(wrap=WRAP))
    out = conditioner.feed(stamps, positions, present)
    assert math.isnan(out[1, 0])
    assert out[2, 0] == 100.0 + WRAP
    assert out[2, 1] == 3.0  # not present: as given


def test_a_counter_running_backwards_wraps_downwards() -> None:
    positions = np.array([[100.0], [65400.0], [65300.0]])
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=WRAP))
    out = conditioner.feed(np.array([0, 1, 2]) * 100_000_000, positions)
    assert out[:, 0].tolist() == [100.0, -136.0, -236.0]


@pytest.mark.parametrize(
    ("lowest", "highest", "whole", "expected"),
    [
        (0, 65535, True, 65536.0),  # unsigned 16-bit
        (-32768, 32767, True, 65536.0),  # signed 16-bit
        (0, 4000, True, 4096.0),  # 12 bits
        (0, 100, True, 256.0),  # 8 bits at least
        (0, 65535, False, None),  # radians are not counts
        (0, 2**40, True, None),  # wider than 32 bits
    ],
)
def test_the_counter_range_is_the_smallest_power_of_two_holding_the_positions(
    lowest: float, highest: float, whole: bool, expected: float | None
) -> None:
    assert counter_range(lowest, highest, whole) == expected


@pytest.mark.parametrize(
    ("steps", "typical", "expected"),
    [
        ([3200.0, -62336.0, 3200.0], 3200.0, True),  # a wrap like its neighbours, undone
        ([-3200.0, 62336.0], 3200.0, True),  # a counter running backwards
        ([3200.0, -40000.0], 3200.0, False),  # half the range is no wrap
        ([1e5], 1.0, False),  # a jump of 1e5 undone is still 31072 long
        ([3200.0, -62336.0], 0.0, False),  # nothing moved before: no evidence
    ],
)
def test_a_wrap_is_a_jump_over_most_of_the_range_that_undone_looks_ordinary(
    steps: list[float], typical: float, expected: bool
) -> None:
    width = 65536.0 if max(abs(s) for s in steps) < 65536 else 131072.0
    assert detect_wrap(width, np.array(steps), typical) == expected


def test_an_integral_jump_in_radians_is_not_taken_for_a_wrap() -> None:
    # Found by hypothesis in the CSV tests: 0 rad, then 1e5 rad a second later.
    conditioner = Conditioner.for_robot(BOT, ("l", "r"), 1)
    positions = np.array([[0.0, 0.0], [0.0, 1e5]])
    assert conditioner.feed(np.array([0, 10**9]), positions) is positions
    assert conditioner.report().wrap is None


def test_conditioning_refuses_meaningless_settings() -> None:
    with pytest.raises(ParameterError, match="counts per revolution"):
        Conditioning(counts_per_rev=0)
    with pytest.raises(ParameterError, match="wrap"):
        Conditioning(wrap=-1)


@pytest.mark.parametrize(
    "settings",
    [{"counts_per_rev": 1e-320}, {"counts_per_rev": 1e300}, {"wrap": 1e-320}, {"wrap": 1e300}],
)
def test_conditioning_refuses_sizes_no_encoder_has(settings: dict[str, float]) -> None:
    # 2*pi / 1e-320 is inf: the positions became NaN, with a NumPy warning on the terminal.
    with pytest.raises(ParameterError, match=r"finite number >= 1e-09 and <= 1e\+15"):
        Conditioning(**settings)


@given(
    st.lists(st.integers(-3000, 3000), min_size=1, max_size=60),
    st.integers(0, WRAP - 1),
    st.integers(1, 20),
)
def test_unwrapping_recovers_any_travel_of_steps_under_half_the_range(
    steps: list[int], start: int, chunk: int
) -> None:
    travel = np.cumsum([start, *steps]).astype(np.float64)
    recorded = (travel % WRAP).reshape(-1, 1)
    stamps = np.arange(travel.size, dtype=np.int64) * 10**9
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=WRAP))
    parts = [
        conditioner.feed(stamps[k : k + chunk], recorded[k : k + chunk])
        for k in range(0, travel.size, chunk)
    ]
    unwrapped = np.concatenate(parts)[:, 0]
    np.testing.assert_array_equal(unwrapped - unwrapped[0], travel - travel[0])


@pytest.mark.parametrize("wrap", [1.0, 3.0, 1e-9, WRAP / 2])
def test_a_given_wrap_smaller_than_the_counts_it_must_hold_is_refused(wrap: float) -> None:
    # Unwrapped with a modulus smaller than the counter's, every step beyond half of it would be
    # taken for a wrap: a wrong pose, said nowhere.
    stamps, left, right = counts()
    conditioner = pioneer_conditioner(Conditioning(counts_per_rev=COUNTS_PER_REV, wrap=wrap))
    with pytest.raises(ParameterError) as caught:
        conditioner.feed(stamps, np.stack([left, right], axis=1))
    message = str(caught.value)
    assert f"the counter's modulus (wrap=) of {wrap:g} is smaller than the range" in message
    assert f"positions of {PIONEER.left_joint!r} cover" in message


def test_a_wrap_is_checked_against_every_chunk_seen() -> None:
    stamps = np.arange(4, dtype=np.int64) * 100_000_000
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=300))
    assert conditioner.feed(stamps[:2], np.array([[10.0], [250.0]]))[:, 0].tolist() == [
        10.0,
        -50.0,
    ]
    with pytest.raises(ParameterError, match=r"cover \(10 to 320, 310 apart\)"):
        conditioner.feed(stamps[2:], np.array([[290.0], [320.0]]))


def test_angles_wrapping_in_the_closed_circle_fit_a_wrap_of_two_pi() -> None:
    stamps = np.arange(4, dtype=np.int64) * 100_000_000
    positions = np.array([[3.0], [math.pi], [-math.pi], [-3.0]])
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=2 * math.pi))
    out = conditioner.feed(stamps, positions)[:, 0]
    assert out[-1] == pytest.approx(2 * math.pi - 3.0, abs=1e-12)


def test_the_command_line_names_the_option_of_a_wrap_refused(tmp_path: Path) -> None:
    from cli_results import assert_one_error_line
    from click.testing import CliRunner
    from pioneer import counts_csv, urdf

    from diffbot.cli import main

    csv, robot = counts_csv(tmp_path), urdf(tmp_path)
    args = ["odom", str(csv), "--robot", str(robot), "--counts-per-rev", str(COUNTS_PER_REV)]
    good = CliRunner().invoke(main, [*args, "--wrap", str(WRAP)])
    assert good.exit_code == 0, good.output
    result = CliRunner().invoke(main, [*args, "--wrap", "3"])
    assert_one_error_line(result, "the counter's modulus (--wrap) of 3 is smaller")


def test_each_side_is_bounded_by_its_own_wheel_radius() -> None:
    # Left wheels of 0.05 m, a right one of 0.1 m, no motor limit: 30 m/s at the rim is
    # 600 rad/s on the left and 300 rad/s on the right, with 0.2 rad and 0.1 rad of slack.
    robot = BOT.replace(left_wheel_radius=0.05, right_wheel_radius=0.1)
    conditioner = Conditioner.for_robot(robot, ("l1", "l2", "r"), 2)
    assert conditioner.limits == [
        (pytest.approx(600.0, rel=1e-15), pytest.approx(0.2, rel=1e-15)),
        (pytest.approx(600.0, rel=1e-15), pytest.approx(0.2, rel=1e-15)),
        (pytest.approx(300.0, rel=1e-15), pytest.approx(0.1, rel=1e-15)),
    ]
    report = conditioner.report()
    assert report.speed_limit == (
        pytest.approx(600.0, abs=1e-12),
        pytest.approx(300.0, abs=1e-12),
    )
    assert report.limit_source == "a rim speed of 30 m/s"
    # 45 rad in 0.1 s (450 rad/s) on every wheel: within the left's bound, beyond the right's.
    stamps = np.array([0, 100_000_000])
    conditioner.feed(stamps, np.array([[0.0, 0.0, 0.0], [45.0, 45.0, 45.0]]))
    report = conditioner.report()
    assert report.implausible_steps == 1
    first = report.first_implausible
    assert first is not None
    assert (first.sample, first.joint) == (1, "r")
    assert first.speed == pytest.approx(450.0, rel=1e-12)
    assert first.seconds == pytest.approx(0.1, abs=1e-15)


def test_a_step_just_within_its_sides_bound_and_slack_passes() -> None:
    robot = BOT.replace(left_wheel_radius=0.05, right_wheel_radius=0.1)
    conditioner = Conditioner.for_robot(robot, ("l", "r"), 1)
    # 0.1 s at the bound plus the slack, on each side: allowed; a little more: not.
    left_edge, right_edge = 600.0 * 0.1 + 0.2, 300.0 * 0.1 + 0.1
    stamps = np.array([0, 100_000_000, 200_000_000])
    positions = np.array(
        [[0.0, 0.0], [left_edge * 0.999, right_edge * 0.999], [left_edge * (0.999 + 1.01), 0.0]]
    )
    conditioner.feed(stamps, positions)
    report = conditioner.report()
    assert report.implausible_steps == 1
    assert report.first_implausible is not None
    assert (report.first_implausible.sample, report.first_implausible.joint) == (2, "l")


def turning_wheels(
    offset: float, robot: DiffDriveParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Wheel angles of a robot driving and turning, stamped ``offset`` s late, and the pose
    track's heading on its own clock (50 Hz and 25 Hz, 10 s)."""
    t = np.arange(0.0, 10.0, 0.02)
    heading = 0.5 * np.sin(1.3 * t) + 0.2 * np.sin(3.1 * t)
    travel = 0.3 * t + 0.1 * np.sin(0.7 * t)  # forward along the way (m)
    half = robot.wheel_separation / 2
    left_radius, right_radius = robot.radii
    left = (travel - half * heading) / left_radius
    right = (travel + half * heading) / right_radius
    truth_t = np.arange(0.0, 10.0, 0.04)
    truth = 0.5 * np.sin(1.3 * truth_t) + 0.2 * np.sin(3.1 * truth_t)
    return t + offset, left, right, truth_t, np.angle(np.exp(1j * truth))


@pytest.mark.parametrize("offset", [0.1, -0.25])
def test_the_time_offset_of_wheels_of_unequal_radii(offset: float) -> None:
    robot = BOT.replace(left_wheel_radius=0.03, right_wheel_radius=0.05)
    found = estimate_time_offset(*turning_wheels(offset, robot), robot, max_offset=0.5)
    assert found == pytest.approx(offset, abs=1e-3)


def test_the_time_offset_needs_samples_overlap_and_turning() -> None:
    t, left, right, truth_t, truth = turning_wheels(0.0, BOT)
    with pytest.raises(ParameterError, match="at least three samples on each side"):
        estimate_time_offset(t[:2], left[:2], right[:2], truth_t, truth, BOT)
    with pytest.raises(ParameterError, match="at least three samples on each side"):
        estimate_time_offset(t, left, right, truth_t[:2], truth[:2], BOT)
    with pytest.raises(ParameterError, match="overlap too little"):
        estimate_time_offset(t, left, right, truth_t + 30.0, truth, BOT)
    with pytest.raises(ParameterError, match="does not turn"):
        estimate_time_offset(t, left, right, truth_t, np.zeros_like(truth), BOT)
    with pytest.raises(ParameterError, match=r"at the edge of the offsets tried \(0.5 s"):
        estimate_time_offset(t + 0.7, left, right, truth_t, truth, BOT, max_offset=0.5)
