"""The least-squares fit: it recovers synthetic robots whose truth is known, and refuses data
that cannot determine them."""

from __future__ import annotations

import numpy as np
import pytest
from calibration_data import (
    B0,
    R0,
    TRAJECTORY_A,
    TRUE_LEFT,
    TRUE_RIGHT,
    TRUE_ROBOT,
    TRUE_SEPARATION,
    recording,
)
from numpy.typing import NDArray
from robots import BOT

from diffbot.calibration import FitResult, fit, ground_truth
from diffbot.errors import CalibrationError, ParameterError
from diffbot.kinematics import norm_angle
from diffbot.planfile import parse_plan
from diffbot.simulation import simulate
from diffbot.trajectory import plan

TRUTH = (TRUE_LEFT, TRUE_RIGHT, TRUE_SEPARATION)


def estimates(result: FitResult) -> tuple[float, float, float]:
    return result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation


def fit_trajectory_a(
    ticks: int | None = None, noise: float = 0.0, window_duration: float | None = None
) -> FitResult:
    stamps, left, right, (x, y, theta) = recording(ticks=ticks, noise=noise)
    return fit(stamps, left, right, stamps, x, y, theta, BOT, window_duration=window_duration)


def test_fit_recovers_the_true_robot_from_exact_readings_within_1e_6() -> None:
    result = fit_trajectory_a()
    for estimate, truth in zip(estimates(result), TRUTH, strict=True):
        assert estimate == pytest.approx(truth, rel=1e-9)  # the goal is 1e-6
    assert result.windows == 80  # 4001 samples, 50 intervals a window
    assert result.position_rms_before > 1e-4
    assert result.heading_rms_before > 1e-3
    assert result.position_rms_after < 1e-12
    assert result.heading_rms_after < 1e-12


def test_fit_recovers_the_true_robot_from_noisy_quantised_readings_within_0_2_percent() -> None:
    # 4096 counts per revolution, and Gaussian noise of 1 mrad on each reading.
    result = fit_trajectory_a(ticks=4096, noise=1e-3)
    stderrs = (
        result.left_wheel_radius_stderr,
        result.right_wheel_radius_stderr,
        result.wheel_separation_stderr,
    )
    for estimate, stderr, truth in zip(estimates(result), stderrs, TRUTH, strict=True):
        assert estimate == pytest.approx(truth, rel=2e-3)
        assert 0.0 < stderr < 1e-3 * truth
        assert abs(estimate - truth) < 5.0 * stderr
    assert result.position_rms_after < result.position_rms_before


def test_fit_over_windows_of_a_duration_recovers_the_true_robot() -> None:
    result = fit_trajectory_a(window_duration=2.5)
    assert result.windows == 32
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-9)


def test_fit_honours_joints_that_turn_backwards() -> None:
    # A right joint whose axis points the other way reads the negated angles.
    flipped = BOT.replace(right_sign=-1)
    stamps, left, right, (x, y, theta) = recording()
    result = fit(stamps, left, -right, stamps, x, y, theta, flipped)
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-9)


def test_fit_interpolates_ground_truth_at_its_own_stamps_across_the_heading_wrap() -> None:
    stamps, left, right, _ = recording()
    fine = np.linspace(0.0, TRAJECTORY_A.duration, 40001)
    truth = ground_truth(TRAJECTORY_A, fine, TRUE_ROBOT)
    wrapped = norm_angle(truth.theta)
    assert np.abs(np.diff(wrapped)).max() > 6.0  # the heading passes pi on the way
    result = fit(stamps, left, right, fine, truth.x, truth.y, wrapped, BOT)
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-5)


def drive(text: str) -> tuple[NDArray[np.float64], ...]:
    """Stamps, wheel angles and exact poses of the nominal robot driving a plan (20 Hz)."""
    commanded = plan(parse_plan(text), BOT)
    states = simulate(commanded, BOT, rate=20.0)
    truth = ground_truth(commanded, states.times, BOT)
    return (states.times, states.positions[0], states.positions[1], *truth)


def test_fit_refuses_straight_driving_for_the_separation() -> None:
    t, left, right, x, y, theta = drive("straight 2 20s")
    with pytest.raises(CalibrationError, match="cannot determine wheel_separation"):
        fit(t, left, right, t, x, y, theta, BOT, window=10)


def test_fit_refuses_a_single_kind_of_curve() -> None:
    t, left, right, x, y, theta = drive("ccw 0.5 360 30s")
    with pytest.raises(CalibrationError, match="cannot tell the left wheel_radius"):
        fit(t, left, right, t, x, y, theta, BOT, window=10)


def test_fit_refuses_a_single_kind_of_curve_read_by_noisy_encoders() -> None:
    commanded = plan(parse_plan("ccw 0.5 360 30s"), BOT)
    noisy = simulate(commanded, BOT, rate=20.0, ticks=4096, noise=1e-3, seed=1)
    x, y, theta = ground_truth(commanded, noisy.times, BOT)
    left, right = noisy.positions[0], noisy.positions[1]
    with pytest.raises(
        CalibrationError, match=r"determines .* only to .* % \(standard error; max_relative"
    ):
        fit(noisy.times, left, right, noisy.times, x, y, theta, BOT, window=10)


def test_fit_refuses_a_robot_that_does_not_move() -> None:
    t = np.linspace(0.0, 10.0, 101)
    still = np.zeros_like(t)
    with pytest.raises(CalibrationError, match="does not move"):
        fit(t, still, still, t, still, still, still, BOT)


def test_fit_refuses_a_ground_truth_from_another_time() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    with pytest.raises(CalibrationError, match="within the ground truth's time span"):
        fit(t, left, right, t + 1000.0, x, y, theta, BOT)


def test_fit_refuses_a_recording_of_one_window() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    with pytest.raises(CalibrationError, match=r"at least two are needed \(shorten window=\)"):
        fit(t, left, right, t, x, y, theta, BOT, window=10_000)


def test_fit_rejects_stamps_that_go_back() -> None:
    t = np.array([0.0, 1.0, 0.5, 2.0])
    with pytest.raises(ParameterError, match="stamps must be at least two strictly increasing"):
        fit(t, t, t, [0.0, 3.0], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0], BOT)


def test_fit_rejects_wheel_arrays_of_different_lengths() -> None:
    with pytest.raises(ParameterError, match="must have equal lengths, got 3, 2 and 3"):
        fit([0, 1, 2], [0, 1], [0, 1, 2], [0, 2], [0, 1], [0, 0], [0, 0], BOT)


def test_fit_rejects_a_ground_truth_that_is_not_finite() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    y[3] = np.nan
    with pytest.raises(ParameterError, match="truth_y must be finite: sample 3 is nan"):
        fit(t, left, right, t, x, y, theta, BOT)


def test_fit_rejects_a_window_of_no_samples() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    with pytest.raises(ParameterError, match="window= must be an integer >= 1"):
        fit(t, left, right, t, x, y, theta, BOT, window=0)


def test_fit_rejects_both_kinds_of_window() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    with pytest.raises(ParameterError, match="give window or window_duration, not both"):
        fit(t, left, right, t, x, y, theta, BOT, window=10, window_duration=1.0)


def test_fit_rejects_a_heading_weight_that_is_not_positive() -> None:
    t, left, right, x, y, theta = drive("straight 1 10s; spin 90")
    with pytest.raises(ParameterError, match="heading_weight must be a positive finite"):
        fit(t, left, right, t, x, y, theta, BOT, heading_weight=-1.0)


def test_fit_starts_from_the_nominal_robot() -> None:
    # From a robot that already has the true geometry there is nothing to correct.
    stamps, left, right, (x, y, theta) = recording()
    result = fit(stamps, left, right, stamps, x, y, theta, TRUE_ROBOT)
    assert result.position_rms_before < 1e-12
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-12)
    assert (R0, B0) != (TRUE_LEFT, TRUE_SEPARATION)


def test_fit_integrates_in_chunks_never_the_whole_recording_and_the_result_is_unchanged(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Every residual evaluation used to integrate all 4001 samples into arrays of that length;
    # it must integrate CHUNK steps at a time, with the result of one pass to the last bit.
    import sys

    import diffbot.batch_odometry as batch

    module = sys.modules["diffbot.calibration.fit"]
    lengths: list[int] = []
    original = batch.advance

    def advance(params, x, y, theta, left, right, baseline, **kw):  # type: ignore[no-untyped-def]
        lengths.append(x.shape[0])
        original(params, x, y, theta, left, right, baseline, **kw)

    stamps, left, right, (x, y, theta) = recording()
    monkeypatch.setattr(batch, "advance", advance)
    whole = fit(stamps, left, right, stamps, x, y, theta, BOT)  # CHUNK > 4001: one pass
    assert max(lengths) == 4001
    for chunk in (7, 300, 1024):
        monkeypatch.setattr(module, "CHUNK", chunk)
        lengths.clear()
        assert fit(stamps, left, right, stamps, x, y, theta, BOT) == whole
        assert max(lengths) == chunk + 1
        assert len(lengths) % -(-4000 // chunk) == 0  # whole passes over the recording


def test_the_heading_is_unwrapped_a_piece_at_a_time_as_numpy_unwraps_it_whole(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Steps of exactly +-pi (numpy's boundary rule), steps past pi and wrapped headings, with
    # the pieces' seams falling anywhere: every value equals numpy.unwrap's.
    import sys

    module = sys.modules["diffbot.calibration.fit"]
    rng = np.random.default_rng(3)
    theta = norm_angle(np.cumsum(rng.normal(0.0, 2.0, 1000)))
    theta[::7] = np.pi
    theta[3::7] = -np.pi
    for size in (1, 2, 7, 64, 1000, 4096):
        monkeypatch.setattr(module, "_PASS", size)
        assert np.array_equal(module.unwrapped(theta), np.unwrap(theta))
    assert module.unwrapped(np.empty(0)).size == 0


def test_the_windows_bounds_are_each_sample_once_and_where_each_window_starts_and_ends() -> None:
    from diffbot.calibration.fit import bound_samples

    starts = np.array([0, 5, 5, 9], dtype=np.intp)
    ends = np.array([5, 9, 12, 12], dtype=np.intp)
    bounds = bound_samples(starts, ends)
    np.testing.assert_array_equal(bounds.samples, [0, 5, 9, 12])
    np.testing.assert_array_equal(bounds.samples[bounds.first], starts)
    np.testing.assert_array_equal(bounds.samples[bounds.last], ends)
    with pytest.raises(CalibrationError, match="at least two are needed"):
        bound_samples(starts[:1], ends[:1])
