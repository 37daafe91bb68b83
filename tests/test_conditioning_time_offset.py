"""How late wheel stamps are against a pose track: the offset found by aligning heading rates,
to well within a grid step, and the one error each unusable recording gives
(diffbot.conditioning.estimate_time_offset)."""

from __future__ import annotations

import numpy as np
import pytest
from robots import BOT

from diffbot.conditioning import estimate_time_offset
from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams


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


@pytest.mark.parametrize("offset", [0.1234, -0.0567, 0.3333, -0.4985, 0.4985])
def test_the_time_offset_between_grid_steps_is_found_to_a_twentieth_of_a_step(
    offset: float,
) -> None:
    # The grid steps by 2 ms (a tenth of the wheels' 20 ms); the parabola through the best
    # three finds what lies between them. -0.4985 and 0.4985 are one step in from either edge.
    robot = BOT.replace(left_wheel_radius=0.03, right_wheel_radius=0.05)
    found = estimate_time_offset(*turning_wheels(offset, robot), robot, max_offset=0.5)
    assert found == pytest.approx(offset, abs=1e-4)


def test_a_robot_standing_still_at_first_is_aligned_by_its_turn() -> None:
    # The heading is still until 4 s, then a bump within the grid (1 s to 4.96 s): shifted a
    # whole second back, the grid sees wheels that do not turn at all (no correlation to score).
    def heading(t: np.ndarray) -> np.ndarray:
        inside = (t > 4.0) & (t < 4.8)
        return np.where(inside, 0.4 * (1.0 - np.cos(2.0 * np.pi * (t - 4.0) / 0.8)), 0.0)

    t = np.arange(0.0, 6.0, 0.02)
    half = BOT.wheel_separation / 2
    wheels = half * heading(t - 0.1) / BOT.wheel_radius
    truth_t = np.arange(0.0, 6.0, 0.04)
    found = estimate_time_offset(t, -wheels, wheels, truth_t, heading(truth_t), BOT)
    assert found == pytest.approx(0.1, abs=1e-3)


def test_offsets_up_to_a_second_either_way_are_tried_by_default() -> None:
    assert estimate_time_offset(*turning_wheels(0.9, BOT), BOT) == pytest.approx(0.9, abs=1e-3)
    with pytest.raises(ParameterError) as caught:
        estimate_time_offset(*turning_wheels(1.5, BOT), BOT)
    assert str(caught.value) == (
        "the heading rates align best at the edge of the offsets tried (1 s either way): the "
        "wheel stamps may be further off; give the offset (time_offset=)"
    )


def test_an_offset_beyond_either_edge_is_refused() -> None:
    # Half a grid step beyond the last offset tried is beyond it, not rounded into it.
    for late in (0.7, -0.7, 0.5005, -0.5005):
        with pytest.raises(ParameterError, match=r"at the edge of the offsets tried \(0.5 s"):
            estimate_time_offset(*turning_wheels(late, BOT), BOT, max_offset=0.5)


def test_three_samples_on_each_side_are_enough_to_try() -> None:
    # Three samples say little, but they are enough to give an offset within the range tried.
    t, left, right, truth_t, truth = turning_wheels(0.0, BOT)
    for wheels, track in ((slice(None, None, 200), slice(None)), (slice(None), slice(0, 201, 100))):
        assert min(t[wheels].size, truth_t[track].size) == 3
        found = estimate_time_offset(
            t[wheels], left[wheels], right[wheels], truth_t[track], truth[track], BOT
        )
        assert abs(found) < 1.0


def test_each_unusable_recording_gives_its_own_error() -> None:
    t, left, right, truth_t, truth = turning_wheels(0.0, BOT)
    too_few = "aligning stamps needs at least three samples on each side"
    overlap = "the wheel samples and the pose track overlap too little to align their stamps"
    flat = "the pose track does not turn: no heading rate to align by"
    cases = [
        ((t[:2], left[:2], right[:2], truth_t, truth), too_few),
        ((t, left, right, truth_t[:2], truth[:2]), too_few),
        ((t, left, right, truth_t + 30.0, truth), overlap),
        # Most wheel stamps repeated: no time step to grid by.
        ((np.repeat(t[::2], 2), left, right, truth_t, truth), overlap),
        ((t, left, right, truth_t, np.zeros_like(truth)), flat),
    ]
    for args, message in cases:
        with pytest.raises(ParameterError) as caught:
            estimate_time_offset(*args, BOT)
        assert str(caught.value) == message


def test_an_overlap_of_exactly_ten_grid_steps_beyond_the_offsets_is_enough() -> None:
    # Wheels every 5/64 s (a grid step of 1/128 s), a track every 1/64 s, both from 0 to 45/64 s:
    # with offsets of 20/64 s either way, 5/64 s of overlap is left, ten grid steps. All these
    # numbers are exact in binary.
    def heading(t: np.ndarray) -> np.ndarray:
        return 0.5 * np.sin(9.0 * t) + 0.2 * np.sin(23.0 * t)

    t = np.arange(10) * 0.078125
    truth_t = np.arange(46) / 64
    half = BOT.wheel_separation / 2
    wheels = half * heading(t) / BOT.wheel_radius
    found = estimate_time_offset(t, -wheels, wheels, truth_t, heading(truth_t), BOT, 0.3125)
    assert abs(found) <= 0.3125
    with pytest.raises(ParameterError, match="overlap too little"):
        estimate_time_offset(t, -wheels, wheels, truth_t[:-1], heading(truth_t[:-1]), BOT, 0.3125)


def test_every_lag_is_scored_as_its_own_window_would_be() -> None:
    # Each window's rate as np.gradient gives it (one-sided at its two ends), its mean taken
    # away, correlated with the truth's rate: the scores of one FFT correlation and running
    # sums are those of the loop over the windows.
    from diffbot.conditioning import _lag_scores

    rng = np.random.default_rng(7)
    step, n, reach = 0.01, 300, 40
    heading = np.cumsum(rng.normal(size=n + 2 * reach)) * 0.05
    truth_rate = rng.normal(size=n)
    truth_rate -= truth_rate.mean()
    expected = []
    for j in range(2 * reach + 1):
        rate = np.gradient(heading[j : j + n], step)
        rate -= rate.mean()
        norm = np.sqrt(np.dot(rate, rate) * np.dot(truth_rate, truth_rate))
        expected.append(np.dot(rate, truth_rate) / norm)
    assert _lag_scores(heading, truth_rate, step) == pytest.approx(expected, abs=1e-12)


def test_the_work_does_not_grow_with_the_lags_tried(monkeypatch: pytest.MonkeyPatch) -> None:
    # The wheels' heading is interpolated once for all lags (not once per lag, which made the
    # time grow with the square of the sample rate: minutes for a 200 Hz recording of 40 s).
    calls = []
    interp = np.interp

    def counted(*args: object, **kwargs: object) -> object:
        calls.append(1)
        return interp(*args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(np, "interp", counted)
    found = estimate_time_offset(*turning_wheels(0.1, BOT), BOT)  # 1001 lags
    assert found == pytest.approx(0.1, abs=1e-3)
    assert len(calls) == 2  # the truth's heading and the wheels'
