"""Encoder units, wrap-around and implausible steps (diffbot.conditioning)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from pioneer import COUNTS_PER_MM, COUNTS_PER_REV, PIONEER, RADIUS, WRAP, counts
from refusals import assert_refused
from robots import BOT, BOT_50_RPM

from diffbot.conditioning import (
    MOTOR_LIMIT_FACTOR,
    RIM_SPEED_BOUND,
    Conditioner,
    Conditioning,
    counter_range,
    detect_wrap,
)
from diffbot.errors import ParameterError

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


@pytest.mark.parametrize("chunk", [1, 2])
@pytest.mark.parametrize(("moved", "implausible"), [(1.0, 0), (1e12, 1)])
def test_a_step_of_more_than_292_years_is_measured_exactly(
    chunk: int, moved: float, implausible: int
) -> None:
    # From the least to the greatest int64 ns: the difference overflows int64.
    conditioner = Conditioner.for_robot(BOT_50_RPM, ("l", "r"), 1)
    low, high = -(2**63) + 1, 2**63 - 1
    stamps = np.array([low, high], dtype=np.int64)
    positions = np.array([[0.0, 0.0], [moved, 0.0]])
    for start in range(0, 2, chunk):
        conditioner.feed(stamps[start : start + chunk], positions[start : start + chunk])
    report = conditioner.report()
    # 1 rad in 585 years is plausible; 1e12 rad is not (54 rad/s).
    assert report.implausible_steps == implausible
    found = report.first_implausible
    if implausible:
        assert found is not None
        assert found.speed == pytest.approx(moved / ((high - low) / 1e9), rel=1e-12)


@pytest.mark.parametrize("chunk", [1, 2, 4])
@pytest.mark.parametrize(
    ("wheel", "implausible", "sample"),
    [
        # the repeated stamp's row is skipped by the odometry: 5 -> 105 in 1 s is the step
        ([0.0, 5.0, 100.0, 105.0], 1, 3),
        # 5 -> 10 in 1 s is: the skipped row's 100 rad ends no step, and starts none
        ([0.0, 5.0, 100.0, 10.0], 0, None),
    ],
)
def test_steps_are_judged_as_the_odometry_integrates_them(
    chunk: int, wheel: list[float], implausible: int, sample: int | None
) -> None:
    conditioner = Conditioner.for_robot(BOT_50_RPM, ("l", "r"), 1)
    stamps = np.array([0, 1, 1, 2]) * 1_000_000_000
    positions = np.column_stack([wheel, wheel])
    for start in range(0, 4, chunk):
        conditioner.feed(stamps[start : start + chunk], positions[start : start + chunk])
    report = conditioner.report()
    assert report.implausible_steps == implausible
    found = report.first_implausible
    assert (found.sample if found is not None else None) == sample
    if found is not None:
        assert found.speed == pytest.approx(100.0)


def test_a_stamp_that_goes_back_ends_no_step() -> None:
    conditioner = Conditioner.for_robot(BOT_50_RPM, ("l", "r"), 1)
    stamps = np.array([0, 2, 1, 3]) * 1_000_000_000
    wheel = [0.0, 2.0, 500.0, 4.0]  # the late row's 500 rad is skipped: 2 rad/s throughout
    conditioner.feed(stamps, np.column_stack([wheel, wheel]))
    assert conditioner.report().implausible_steps == 0


def test_a_late_row_in_the_next_chunk_is_skipped_against_the_last_chunk() -> None:
    # stamps 1 and 1.5 s come after 2 s: both are skipped, whichever chunk they are in, so
    # the 500 rad they hold neither end nor start a step (the next one is 2 -> 3 s, 1 rad)
    conditioner = Conditioner.for_robot(BOT_50_RPM, ("l", "r"), 1)
    ns = 1_000_000_000
    conditioner.feed(np.array([0, 2 * ns]), np.array([[0.0, 0.0], [2.0, 2.0]]))
    late = np.array([[500.0, 500.0], [500.0, 500.0], [3.0, 3.0]])
    conditioner.feed(np.array([1 * ns, 3 * ns // 2, 3 * ns]), late)
    assert conditioner.report().implausible_steps == 0


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


def test_meaningless_settings_are_refused_naming_the_setting() -> None:
    with pytest.raises(ParameterError) as caught:
        Conditioning(counts_per_rev=0)
    assert str(caught.value) == (
        "counts_per_rev= (encoder counts per revolution) must be a finite number >= 1e-09 and "
        "<= 1e+15, got 0"
    )
    with pytest.raises(ParameterError) as caught:
        Conditioning(wrap=-1)
    assert str(caught.value) == (
        "wrap= (0 for none) must be a finite number >= 1e-09 and <= 1e+15, got -1"
    )


@pytest.mark.parametrize(
    ("lowest", "highest", "expected"),
    [
        (-32768, 0, 65536.0),  # signed 16-bit, never positive
        (-1, 127, 256.0),  # signed 8-bit
        (-1, 128, 512.0),  # 128 does not fit a signed 8-bit counter
        (0, 2**32 - 1, 2.0**32),  # unsigned 32-bit, the widest recognised
        (-(2**31), 2**31 - 1, 2.0**32),  # signed 32-bit
        (0, math.inf, None),  # no counter holds it
        (-math.inf, 0, None),
    ],
)
def test_the_counter_range_at_its_edges(lowest: float, highest: float, expected: float) -> None:
    assert counter_range(lowest, highest, True) == expected


@pytest.mark.parametrize(
    ("width", "steps", "typical", "expected"),
    [
        (None, [3200.0, -62336.0], 3200.0, False),  # no counter: no wrap
        (256.0, [256.0], 0.0, False),  # nothing moved: no evidence, even for a whole range
        (256.0, [1.0, -255.0, 1.0], 1.0, True),  # steps of one count
        (256.0, [16.0, -192.0], 16.0, True),  # a jump of exactly three quarters is one
        (256.0, [4.0, -240.0], 4.0, True),  # undone, exactly four ordinary steps long
        (256.0, [4.0, -239.0], 4.0, False),  # undone, longer than four
    ],
)
def test_a_wrap_at_the_edges_of_its_rule(
    width: float | None, steps: list[float], typical: float, expected: bool
) -> None:
    assert detect_wrap(width, np.array(steps), typical) == expected


def test_integer_counts_become_fractional_radians_and_the_input_is_untouched() -> None:
    stamps, left, right = counts()
    positions = np.stack([left, right], axis=1).astype(np.int64)
    floats = positions.astype(np.float64)
    options = Conditioning(counts_per_rev=COUNTS_PER_REV, wrap=WRAP)
    angles = pioneer_conditioner(options).feed(stamps, positions)
    expected = pioneer_conditioner(options).feed(stamps, floats)
    np.testing.assert_array_equal(angles, expected)
    assert angles.dtype == np.float64
    np.testing.assert_array_equal(positions, np.stack([left, right], axis=1))
    np.testing.assert_array_equal(floats, np.stack([left, right], axis=1))


def test_a_sample_without_a_joint_is_neither_changed_nor_taken_for_a_wrap() -> None:
    stamps = np.arange(3, dtype=np.int64) * 100_000_000
    positions = np.array([[65000.0, 1.0], [0.0, 2.0], [65100.0, 3.0]])
    present = np.array([[True, True], [False, True], [True, True]])
    conditioner = Conditioner.for_robot(BOT, ("l", "r"), 1, Conditioning(wrap=WRAP))
    out = conditioner.feed(stamps, positions, present)
    assert out[:, 0].tolist() == [65000.0, 0.0, 65100.0]
    assert conditioner.report().wraps == 0


def test_a_joint_without_samples_in_a_chunk_leaves_the_next_joint_conditioned() -> None:
    stamps = np.arange(2, dtype=np.int64) * 100_000_000
    positions = np.array([[math.nan, 0.0], [math.nan, 100.0]])
    conditioner = Conditioner.for_robot(BOT, ("l", "r"), 1, Conditioning(counts_per_rev=400))
    out = conditioner.feed(stamps, positions)
    assert out[1, 1] == pytest.approx(math.pi / 2, abs=1e-15)
    assert math.isnan(out[1, 0])


def test_no_wrap_means_no_detection_either() -> None:
    stamps, left, right = counts()
    positions = np.stack([left, right], axis=1)
    conditioner = pioneer_conditioner(Conditioning(wrap=0))
    assert conditioner.feed(stamps, positions) is positions
    report = conditioner.report()
    assert (report.wrap, report.wrap_detected, report.wraps) == (None, False, 0)


def test_positions_that_are_not_whole_numbers_are_never_taken_for_a_counter() -> None:
    stamps = np.arange(6, dtype=np.int64) * 10**9
    positions = np.array([[0.5], [60.5], [120.5], [180.5], [240.5], [44.5]])
    conditioner = Conditioner.for_robot(BOT, ("l",), 1)
    assert conditioner.feed(stamps, positions) is positions
    assert conditioner.report().wrap is None


def test_a_counter_stepping_nearly_a_quarter_of_its_range_is_unwrapped() -> None:
    # Steps of 60 counts on an 8-bit counter (a quarter is 64), then a wrap.
    stamps = np.arange(6, dtype=np.int64) * 10**9
    positions = np.array([[0.0], [60.0], [120.0], [180.0], [240.0], [44.0]])
    conditioner = Conditioner.for_robot(BOT, ("l",), 1)
    assert conditioner.feed(stamps, positions)[:, 0].tolist() == [0, 60, 120, 180, 240, 300]
    report = conditioner.report()
    assert (report.wrap, report.wrap_detected, report.wraps) == (256.0, True, 1)


def test_steps_of_a_quarter_of_the_range_are_no_ordinary_steps_to_judge_a_wrap_by() -> None:
    stamps = np.arange(5, dtype=np.int64) * 10**9
    positions = np.array([[0.0], [64.0], [128.0], [192.0], [0.0]])
    conditioner = Conditioner.for_robot(BOT, ("l",), 1)
    assert conditioner.feed(stamps, positions) is positions


def test_a_given_wrap_at_the_edge_of_rounding_is_accepted_and_beyond_it_refused() -> None:
    edge = 300.0 * (1.0 + 1e-9)
    stamps = np.arange(2, dtype=np.int64) * 100_000_000
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=300))
    conditioner.feed(stamps, np.array([[0.0], [edge]]))
    conditioner = Conditioner.for_robot(BOT, ("l",), 1, Conditioning(wrap=300))
    with pytest.raises(ParameterError) as caught:
        conditioner.feed(stamps, np.array([[0.0], [301.0]]))
    assert str(caught.value) == (
        "the counter's modulus (wrap=) of 300 is smaller than the range the positions of 'l' "
        "cover (0 to 301, 301 apart): a counter that wraps at 300 cannot hold them, and its "
        "steps would be taken for wraps; give the counter's real modulus, or 0 for none"
    )


def test_a_recording_that_starts_with_turned_wheels_has_no_step_at_its_first_sample() -> None:
    # The wheels are at 500 rad when the recording starts, 1 ms after the clock's zero.
    stamps = np.array([1, 101, 201, 301]) * 1_000_000
    positions = np.array([[500.0, 500.0], [501.0, 501.0], [502.0, 502.0], [603.0, 503.0]])
    conditioner = Conditioner.for_robot(BOT, ("l", "r"), 1)
    conditioner.feed(stamps[:3], positions[:3])
    assert conditioner.report().implausible_steps == 0
    # The next chunk's first sample does end a step: 101 rad in 0.1 s on the left.
    conditioner.feed(stamps[3:], positions[3:])
    report = conditioner.report()
    assert report.implausible_steps == 1
    assert report.first_implausible is not None
    assert (report.first_implausible.sample, report.first_implausible.joint) == (3, "l")
    assert report.first_implausible.seconds == pytest.approx(0.3, abs=1e-12)
    assert report.first_implausible.speed == pytest.approx(1010.0, rel=1e-12)


def test_chunks_give_the_report_of_the_whole_recording() -> None:
    stamps = np.arange(30, dtype=np.int64) * 100_000_000
    left = np.arange(30) * 0.5
    left[17:] += 200.0  # one step no wheel makes, in the third chunk of seven
    left[24:] += 200.0  # and another in the fourth
    positions = np.stack([left, np.zeros(30)], axis=1)
    whole = Conditioner.for_robot(BOT, ("l", "r"), 1)
    whole.feed(stamps, positions)
    chunked = Conditioner.for_robot(BOT, ("l", "r"), 1)
    for k in range(0, 30, 7):
        chunked.feed(stamps[k : k + 7], positions[k : k + 7])
    assert chunked.report() == whole.report()
    report = whole.report()
    assert report.implausible_steps == 2
    assert report.first_implausible is not None
    assert report.first_implausible.sample == 17
    assert report.first_implausible.seconds == pytest.approx(1.7, abs=1e-12)


def test_a_step_exactly_at_its_bound_is_plausible() -> None:
    # 10 rad/s and 0.5 rad of slack: 10.5 rad in a second is the most a step may turn.
    conditioner = Conditioner(("l",), Conditioning(), [(10.0, 0.5)], "given")
    conditioner.feed(np.array([0, 10**9, 2 * 10**9]), np.array([[0.0], [10.5], [21.5]]))
    report = conditioner.report()
    assert report.implausible_steps == 1
    assert report.first_implausible is not None
    assert report.first_implausible.sample == 2
    assert report.limit_source == "given"


def test_the_report_gives_each_side_its_limit_and_the_counts_asked() -> None:
    robot = BOT.replace(left_wheel_radius=0.05, right_wheel_radius=0.1)
    options = Conditioning(counts_per_rev=4096, wrap=0)
    report = Conditioner.for_robot(robot, ("l", "r"), 1, options).report()
    assert report.speed_limit == (
        pytest.approx(600.0, rel=1e-15),
        pytest.approx(300.0, rel=1e-15),
    )
    assert report.counts_per_rev == 4096


@pytest.mark.parametrize(
    ("settings", "named"),
    [
        ({"counts_per_rev": math.nan}, "counts_per_rev="),
        ({"counts_per_rev": math.inf}, "counts_per_rev="),
        ({"counts_per_rev": -4096}, "counts_per_rev="),
        ({"counts_per_rev": "-4096"}, "counts_per_rev="),
        ({"counts_per_rev": 10**400}, "counts_per_rev="),
        ({"counts_per_rev": "many"}, "counts_per_rev="),
        ({"counts_per_rev": True}, "counts_per_rev="),
        ({"counts_per_rev": [4096]}, "counts_per_rev="),
        ({"wrap": math.nan}, "wrap="),
        ({"wrap": "nan"}, "wrap="),
        ({"wrap": -math.inf}, "wrap="),
        ({"wrap": "-8192"}, "wrap="),
        ({"wrap": 10**400}, "wrap="),
        ({"wrap": "8_192"}, "wrap="),
        ({"wrap": (8192,)}, "wrap="),
        ({"wrap": np.array([0.0, 8192.0])}, "wrap="),
        ({"counts_per_rev": np.array([4096.0, 4096.0])}, "counts_per_rev="),
    ],
)
def test_hostile_settings_are_refused_naming_the_parameter(
    settings: dict[str, object], named: str
) -> None:
    assert_refused(Conditioning, settings, named)


def test_numeric_strings_read_a_recording_as_their_numbers() -> None:
    from diffbot import load_params
    from diffbot.recordings import read_recording

    given = Conditioning(counts_per_rev="4096", wrap="8192")  # type: ignore[arg-type]
    assert given == Conditioning(counts_per_rev=4096, wrap=8192)
    assert (type(given.counts_per_rev), type(given.wrap)) == (float, float)
    assert Conditioning(wrap="0") == Conditioning(wrap=0)  # type: ignore[arg-type]
    example = Path(__file__).parents[1] / "docs" / "examples" / "joints.csv"
    robot = load_params()
    as_text = read_recording(example, robot, counts_per_rev="4096", wrap="8192")  # type: ignore[arg-type]
    as_numbers = read_recording(example, robot, counts_per_rev=4096, wrap=8192)
    assert list(as_text.samples) == list(as_numbers.samples)
    assert len(as_text.samples) > 10
    assert as_text.conditioning == as_numbers.conditioning
