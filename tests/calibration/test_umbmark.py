"""UMBmark: the test squares, the first-order formulas, the exact model and the refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from calibration_data import B0, R0, square_end
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT
from wheel_motion import angle_error

from diffbot.calibration import (
    UmbmarkResult,
    ground_truth,
    true_robot,
    umbmark,
    umbmark_segments,
)
from diffbot.errors import CalibrationError, DiffbotError, ParameterError, RecordingError
from diffbot.trajectory import Spin, Straight, plan


def synthetic_umbmark(
    side: float, radius_difference: float, separation_error: float
) -> tuple[UmbmarkResult, float, float, float]:
    """UMBmark of a robot whose radii are ``radius_difference`` apart (relative, mean kept) and
    whose separation is off by ``separation_error`` (relative); the result and the truth."""
    left = R0 * (1.0 - 0.5 * radius_difference)
    right = R0 * (1.0 + 0.5 * radius_difference)
    separation = B0 * (1.0 + separation_error)
    cw = [square_end(side, "cw", left, right, separation)]
    ccw = [square_end(side, "ccw", left, right, separation)]
    return umbmark(side, cw, ccw, BOT), left, right, separation


@pytest.mark.parametrize("direction", ["cw", "ccw"])
def test_umbmark_square_closes_and_starts_along_x(direction: str) -> None:
    segments = umbmark_segments(4.0, "cw" if direction == "cw" else "ccw")
    turn = -0.5 * math.pi if direction == "cw" else 0.5 * math.pi
    assert segments[1::2] == [Spin(turn)] * 4
    assert segments[0::2] == [Straight(4.0)] * 4
    end = plan(segments, BOT).final_pose
    assert end.x == pytest.approx(0.0, abs=1e-12)
    assert end.y == pytest.approx(0.0, abs=1e-12)
    assert angle_error(end.theta, 0.0) <= 1e-12


def test_umbmark_square_of_cw_runs_turns_right_first() -> None:
    corners = [p.end_pose for p in plan(umbmark_segments(2.0, "cw"), BOT).segments]
    # after the first side and its turn the robot heads along -y (REP-103: right)
    assert corners[1].x == pytest.approx(2.0, abs=1e-12)
    assert angle_error(corners[1].theta, -0.5 * math.pi) <= 1e-12
    assert corners[2].y == pytest.approx(-2.0, abs=1e-12)


def test_umbmark_of_runs_that_return_home_finds_a_perfect_robot() -> None:
    result = umbmark(4.0, [(0.0, 0.0)] * 3, [(0.0, 0.0)] * 3, BOT)
    assert (result.ed, result.eb, result.alpha, result.beta) == (1.0, 1.0, 0.0, 0.0)
    assert result.left_wheel_radius == pytest.approx(R0, rel=1e-15)
    assert result.right_wheel_radius == pytest.approx(R0, rel=1e-15)
    assert result.wheel_separation == pytest.approx(B0, rel=1e-15)


def test_umbmark_centres_are_the_means_of_the_runs() -> None:
    result = umbmark(4.0, [(0.1, 0.2), (0.3, 0.0)], [(-0.1, 0.05), (0.0, -0.05), (0.1, 0.3)], BOT)
    assert result.cw_centre == pytest.approx((0.2, 0.1), abs=1e-15)
    assert result.ccw_centre == pytest.approx((0.0, 0.1), abs=1e-15)


def test_umbmark_formulas_give_known_values_for_first_order_centres() -> None:
    # Centres built from the first-order model with alpha = 0.01 rad and beta = 0.002 rad.
    side, alpha, beta = 4.0, 0.01, 0.002
    cw = [(2 * side * (alpha - beta), 2 * side * (alpha - beta))]
    ccw = [(2 * side * (alpha + beta), -2 * side * (alpha + beta))]
    result = umbmark(side, cw, ccw, BOT)
    assert result.alpha == pytest.approx(alpha, rel=1e-12)
    assert result.beta == pytest.approx(beta, rel=1e-12)
    assert result.eb == pytest.approx((math.pi / 2) / (math.pi / 2 + alpha), rel=1e-12)
    lean = beta * result.wheel_separation / (2 * side)
    assert result.ed == pytest.approx((1 + lean) / (1 - lean), rel=1e-12)
    assert result.right_wheel_radius / result.left_wheel_radius == pytest.approx(result.ed)
    mean = 0.5 * (result.left_wheel_radius + result.right_wheel_radius)
    assert mean == pytest.approx(R0, rel=1e-15)


@pytest.mark.parametrize(
    ("radius_difference", "separation_error"),
    [(1e-3, 1e-2), (1e-3, -1e-2), (-1e-3, 1e-2), (-1e-3, -1e-2)],
)
def test_umbmark_recovers_a_4_m_square_robot_within_the_small_error_bound(
    radius_difference: float, separation_error: float
) -> None:
    # Radii 0.1 % apart and separation 1 % off on a 4 m square: the first-order formulas leave
    # the separation within 0.05 % of the truth (5 % of its error) and each radius within
    # 0.002 % (2 % of their difference), the bounds docs/calibration.md states.
    result, left, right, separation = synthetic_umbmark(4.0, radius_difference, separation_error)
    assert result.wheel_separation == pytest.approx(separation, rel=5e-4)
    assert result.left_wheel_radius == pytest.approx(left, rel=2e-5)
    assert result.right_wheel_radius == pytest.approx(right, rel=2e-5)
    assert abs(result.wheel_separation - separation) <= 0.05 * abs(separation - B0)
    found = result.right_wheel_radius - result.left_wheel_radius
    assert abs(found - (right - left)) <= 0.02 * abs(right - left)
    assert result.ed == pytest.approx(right / left, rel=5e-5)
    assert result.eb == pytest.approx(separation / B0, rel=5e-4)


def test_umbmark_error_shrinks_with_the_square_of_the_robot_errors() -> None:
    big, _, _, separation = synthetic_umbmark(4.0, 1e-3, 1e-2)
    small, _, _, half_separation = synthetic_umbmark(4.0, 0.5e-3, 0.5e-2)
    ratio = abs(big.wheel_separation - separation) / abs(small.wheel_separation - half_separation)
    assert 3.0 < ratio < 5.0


@pytest.mark.parametrize(
    ("side", "radius_difference", "separation_error"),
    [(4.0, 1e-3, 1e-2), (4.0, -1e-3, -1e-2), (4.0, 5e-3, 2e-2), (1.0, -2e-2, -5e-2), (2.0, 0, 0)],
)
def test_umbmark_exact_model_recovers_the_robot_to_rounding(
    side: float, radius_difference: float, separation_error: float
) -> None:
    left = R0 * (1.0 - 0.5 * radius_difference)
    right = R0 * (1.0 + 0.5 * radius_difference)
    separation = B0 * (1.0 + separation_error)
    cw = [square_end(side, "cw", left, right, separation)] * 2
    ccw = [square_end(side, "ccw", left, right, separation)] * 3
    result = umbmark(side, cw, ccw, BOT, exact=True)
    assert result.wheel_separation == pytest.approx(separation, rel=1e-12)
    assert result.left_wheel_radius == pytest.approx(left, rel=1e-12)
    assert result.right_wheel_radius == pytest.approx(right, rel=1e-12)
    assert result.ed == pytest.approx(right / left, rel=1e-12)


def test_umbmark_exact_model_stays_within_second_order_of_the_formulas() -> None:
    cw = [(-0.31, -0.40), (-0.36, -0.39), (-0.33, -0.41)]
    ccw = [(0.12, -0.09), (0.10, -0.12), (0.11, -0.10)]
    first = umbmark(4.0, cw, ccw, BOT)
    exact = umbmark(4.0, cw, ccw, BOT, exact=True)
    size = abs(first.alpha) + abs(first.beta)
    assert abs(exact.alpha - first.alpha) <= size**2
    assert abs(exact.beta - first.beta) <= size**2
    assert exact.alpha != first.alpha


def test_umbmark_exact_model_refuses_runs_far_from_a_square() -> None:
    with pytest.raises(CalibrationError, match="exact square model does not converge"):
        umbmark(1.0, [(3.0, 0.0)], [(-3.0, 0.0)], BOT, exact=True)


@settings(max_examples=40, deadline=None)
@given(
    side=st.floats(0.5, 10.0),
    cw=st.lists(st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)), min_size=1, max_size=5),
    ccw=st.lists(st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)), min_size=1, max_size=5),
)
def test_umbmark_of_mirrored_runs_swaps_the_wheels(
    side: float, cw: list[tuple[float, float]], ccw: list[tuple[float, float]]
) -> None:
    # Mirroring the world in the x axis turns cw runs into ccw ones and swaps left and right.
    result = umbmark(side, cw, ccw, BOT)
    mirrored = umbmark(side, [(x, -y) for x, y in ccw], [(x, -y) for x, y in cw], BOT)
    assert mirrored.alpha == pytest.approx(result.alpha, rel=1e-9, abs=1e-15)
    assert mirrored.beta == pytest.approx(-result.beta, rel=1e-9, abs=1e-15)
    assert mirrored.eb == pytest.approx(result.eb, rel=1e-12)
    assert mirrored.ed == pytest.approx(1.0 / result.ed, rel=1e-9)
    assert mirrored.left_wheel_radius == pytest.approx(result.right_wheel_radius, rel=1e-9)


def test_umbmark_rejects_a_side_that_is_not_positive() -> None:
    with pytest.raises(ParameterError, match="side must be a finite number > 0"):
        umbmark(0.0, [(0.0, 0.0)], [(0.0, 0.0)], BOT)


def test_umbmark_rejects_no_runs() -> None:
    with pytest.raises(ParameterError, match="cw_ends must be a non-empty sequence"):
        umbmark(4.0, [], [(0.0, 0.0)], BOT)


def test_umbmark_rejects_runs_that_are_not_pairs() -> None:
    with pytest.raises(ParameterError, match=r"ccw_ends .*\(x, y\) pairs"):
        umbmark(4.0, [(0.0, 0.0)], [(0.0, 0.0, 0.0)], BOT)


def test_umbmark_rejects_errors_beyond_the_small_error_approximation() -> None:
    # On a square of 5 cm the wheels 13.5 cm apart cannot bend a side by 80 degrees.
    with pytest.raises(CalibrationError, match="small-error approximation"):
        umbmark(0.05, [(-0.14, -0.14)], [(0.14, -0.14)], BOT)


def test_umbmark_segments_reject_an_unknown_direction() -> None:
    with pytest.raises(ParameterError, match="direction must be 'cw' or 'ccw'"):
        umbmark_segments(1.0, "left")  # type: ignore[arg-type]


def test_calibration_errors_are_recording_errors_of_diffbot() -> None:
    assert issubclass(CalibrationError, RecordingError)
    assert issubclass(CalibrationError, DiffbotError)
    assert CalibrationError.exit_code == 2


@pytest.mark.parametrize("end", [(1e10, 0.0), (0.0, -4.01), (1e308, 1e308)])
def test_a_run_cannot_end_farther_than_the_square_it_drove(end: tuple[float, float]) -> None:
    # Ends of 1e10 m on a 1 m square gave a separation of 8.5e-11 m; a run drives 4 m at most.
    with pytest.raises(CalibrationError, match=r"farther from its start than the 4 m"):
        umbmark(1.0, [end], [(0.0, 0.0)], BOT)
    with pytest.raises(CalibrationError, match=r"farther from its start than the 4 m"):
        umbmark(1.0, [(0.0, 0.0)], [end], BOT, exact=True)


def test_an_exact_fit_that_leaves_the_square_model_is_refused_not_a_math_error() -> None:
    with pytest.raises(CalibrationError, match="does not converge"):
        umbmark(1.0, [(3.9, 0.0)], [(3.9, 0.0)], BOT, exact=True)


def test_umbmark_corrects_each_sides_own_nominal_radius_when_they_differ() -> None:
    # A controller's multipliers make the nominal radii 0.0355 m and 0.0345 m; the real wheels
    # roll 0.3 % larger on the left and 0.3 % smaller on the right than those.
    nominal = BOT.replace(left_wheel_radius=0.0355, right_wheel_radius=0.0345)
    true = true_robot(nominal, (0.0355 * 1.003, 0.0345 * 0.997), B0 * 1.01)
    ends = {}
    for direction in ("cw", "ccw"):
        commanded = plan(umbmark_segments(4.0, direction), nominal)
        times = np.concatenate(([0.0], np.cumsum([s.duration for s in commanded.segments])))
        x, y, _ = ground_truth(commanded, times, true)
        ends[direction] = [(float(x[-1]), float(y[-1]))]
    result = umbmark(4.0, ends["cw"], ends["ccw"], nominal, exact=True)
    assert result.left_wheel_radius == pytest.approx(0.0355 * 1.003, rel=1e-9)
    assert result.right_wheel_radius == pytest.approx(0.0345 * 0.997, rel=1e-9)
    assert result.ed == pytest.approx((0.0345 * 0.997) / (0.0355 * 1.003), rel=1e-9)
    assert result.wheel_separation == pytest.approx(B0 * 1.01, rel=1e-9)


def test_exact_is_a_bool_not_a_truthy_word() -> None:
    ends = [(0.01, 0.02)]
    with pytest.raises(ParameterError, match=r"^exact must be True or False, got 'no'"):
        umbmark(4.0, ends, ends, BOT, exact="no")  # type: ignore[arg-type]
