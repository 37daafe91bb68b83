"""Least squares over recordings as the readers give them (diffbot.calibration.fit_recordings)."""

from __future__ import annotations

import numpy as np
import pytest
from calibration_data import TRUE_LEFT, TRUE_RIGHT, TRUE_SEPARATION, recording
from numpy.typing import NDArray
from peak_memory import peak_bytes
from robots import BOT, SKID

from diffbot.calibration import FitResult, fit_recording
from diffbot.calibration.fit_recordings import fit_recordings
from diffbot.errors import CalibrationError
from diffbot.io.poses import PoseTrack
from diffbot.kinematics import norm_angle
from diffbot.samples import ColumnSamples, JointSample, Recording

TRUTH = (TRUE_LEFT, TRUE_RIGHT, TRUE_SEPARATION)


def estimates(result: FitResult) -> tuple[float, float, float]:
    return result.left_wheel_radius, result.right_wheel_radius, result.wheel_separation


def as_recording(
    stamps: NDArray[np.float64], left: NDArray[np.float64], right: NDArray[np.float64]
) -> Recording:
    """Joint samples stamped 1.7e9 s since 1970, one without the right wheel, names reversed."""
    samples = []
    for k, (t, a, b) in enumerate(zip(stamps.tolist(), left.tolist(), right.tolist(), strict=True)):
        stamp_ns = 1_700_000_000_000_000_000 + round(t * 1e9)
        if k == 5:
            samples.append(JointSample(stamp_ns, [BOT.left_joint], [a + 1.0]))
        else:
            samples.append(JointSample(stamp_ns, [BOT.right_joint, BOT.left_joint], [b, a]))
    return Recording("test", "rosbag2", samples)


def test_fit_recording_matches_stamps_since_1970_and_skips_incomplete_samples() -> None:
    stamps, left, right, (x, y, theta) = recording()
    stamps_ns = 1_700_000_000_000_000_000 + np.round(stamps * 1e9).astype(np.int64)
    track = PoseTrack("truth", stamps_ns, x, y, theta)
    result = fit_recording(as_recording(stamps, left, right), track, BOT)
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-7)


def test_fit_recording_needs_two_samples_with_both_wheels() -> None:
    samples = [JointSample(k, [BOT.left_joint], [0.0]) for k in range(5)]
    track = PoseTrack("truth", np.arange(5), np.zeros(5), np.zeros(5), np.zeros(5))
    with pytest.raises(CalibrationError, match="0 samples hold both wheel joints"):
        fit_recording(Recording("r.csv", "csv", samples), track, BOT)


def test_joints_named_without_a_value_are_absent() -> None:
    # JointStates whose velocity (or position) field is empty or shorter than their names, as
    # a bag read for velocities without them gives: no sample holds both wheels, and the fit
    # says so instead of failing on the missing values.
    samples = [
        JointSample(k, [BOT.left_joint, BOT.right_joint], [] if k % 2 else [0.1 * k])
        for k in range(6)
    ]
    track = PoseTrack("truth", np.arange(6), np.zeros(6), np.zeros(6), np.zeros(6))
    with pytest.raises(CalibrationError, match="0 samples hold both wheel joints"):
        fit_recording(Recording("b", "rosbag2", samples), track, BOT)


def test_wheel_stamps_that_repeat_are_refused_naming_the_recording() -> None:
    # A recording's own stamps: the message names it, not the library's stamps= parameter.
    stamps, left, right, (x, y, theta) = recording()
    stamps_ns = np.round(stamps * 1e9).astype(np.int64)
    samples = [
        JointSample(
            int(stamps_ns[3 if k == 4 else k]),  # the fifth repeats the fourth
            [BOT.left_joint, BOT.right_joint],
            [a, b],
        )
        for k, (a, b) in enumerate(zip(left.tolist(), right.tolist(), strict=True))
    ]
    track = PoseTrack("truth", stamps_ns, x, y, theta)
    with pytest.raises(
        CalibrationError, match=r"^bag: the wheel samples' stamps repeat or go back"
    ):
        fit_recording(Recording("bag", "rosbag2", samples), track, BOT)


def test_a_side_of_several_wheels_is_fitted_by_their_mean_as_the_odometry_takes_it() -> None:
    # A skid steer's bag: the front wheels read 2 % short of each side's mean, the rear 2 %
    # long. The odometry moves each side by the mean of its joints; a fit that took the front
    # joints alone put both radii 2 % off.
    stamps, left, right, (x, y, theta) = recording()
    stamps_ns = np.round(stamps * 1e9).astype(np.int64)
    samples = [
        JointSample(
            int(t),
            ["front_left", "front_right", "rear_right", "rear_left"],
            [0.98 * a, 0.98 * b, 1.02 * b, 1.02 * a],
        )
        for t, a, b in zip(stamps_ns.tolist(), left.tolist(), right.tolist(), strict=True)
    ]
    track = PoseTrack("truth", stamps_ns, x, y, theta)
    result = fit_recording(Recording("skid", "rosbag2", samples), track, SKID)
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-7)


@pytest.mark.parametrize("kind", ["csv", "rosbag2"])
def test_samples_with_a_value_not_finite_are_left_out_as_the_odometry_skips_them(
    kind: str,
) -> None:
    # One NaN and one infinite wheel reading among 2001: the odometry skips those samples; the
    # fit failed on them, blaming wheel positions too large.
    stamps, left, right, truth = recording()
    left[510] = np.nan
    right[700] = np.inf
    if kind == "csv":
        ((read, track),) = column_pair(stamps, left, right, truth)
    else:
        read = as_recording(stamps, left, right)
        stamps_ns = 1_700_000_000_000_000_000 + np.round(stamps * 1e9).astype(np.int64)
        track = PoseTrack("truth", stamps_ns, *truth)
    result = fit_recording(read, track, BOT)
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-7)


@pytest.mark.parametrize("swap", [(400, 401), (0, 1), (2000, 1999)])
def test_a_ground_truth_whose_stamps_go_back_is_refused_naming_it(
    swap: tuple[int, int],
) -> None:
    # A track with two poses out of order (a tracker that buffers): interpolated as it stood,
    # adjacent swaps all along it gave a separation 0.6 % off with exit 0.
    stamps, left, right, (x, y, theta) = recording()
    stamps_ns = np.round(stamps * 1e9).astype(np.int64)
    order = np.arange(stamps.size)
    order[list(swap)] = order[list(swap[::-1])]
    track = PoseTrack("mocap.csv", stamps_ns[order], x[order], y[order], theta[order])
    samples = [
        JointSample(int(t), [BOT.left_joint, BOT.right_joint], [a, b])
        for t, a, b in zip(stamps_ns.tolist(), left.tolist(), right.tolist(), strict=True)
    ]
    with pytest.raises(
        CalibrationError, match=r"^mocap.csv: the ground truth's stamps repeat or go back"
    ):
        fit_recording(Recording("bag", "rosbag2", samples), track, BOT)


def column_pair(
    stamps: NDArray[np.float64],
    left: NDArray[np.float64],
    right: NDArray[np.float64],
    truth: tuple[NDArray[np.float64], ...],
) -> list[tuple[Recording, PoseTrack]]:
    """A recording as a CSV file reads (compact columns) and its truth, stamped since 1970."""
    stamps_ns = 1_700_000_000_000_000_000 + np.round(stamps * 1e9).astype(np.int64)
    samples = ColumnSamples(BOT.left_joint, BOT.right_joint)
    samples.stamps_ns.frombytes(stamps_ns.tobytes())
    samples.left.frombytes(left.tobytes())
    samples.right.frombytes(right.tobytes())
    samples.present.extend(b"\x03" * stamps.size)
    x, y, theta = truth
    return [
        (Recording("r.csv", "csv", samples), PoseTrack("t", stamps_ns, x, y, norm_angle(theta)))
    ]


def test_fit_recordings_keeps_little_more_than_the_wheel_angles_of_a_long_recording(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # What the fit allocates on top of a recording and its truth, handed over one at a time,
    # traced by tracemalloc (a count of bytes, not a time): the columns it makes of them must
    # stay under four float64 columns' worth. The old reduction made the truth's x, y and
    # unwrapped heading at every sample, copied the wheel columns and ran numpy.unwrap and
    # numpy.diff over whole columns: thirteen columns' worth.
    import importlib
    import sys

    module = sys.modules["diffbot.calibration.fit"]
    monkeypatch.setattr(module, "CHUNK", 4096)  # the fixed work arrays, out of the figure
    monkeypatch.setattr(module, "_PASS", 4096)
    stamps, left, right, truth = recording(rate=2500.0)
    n = stamps.size
    assert n == 200_001
    pairs = column_pair(stamps, left, right, truth)
    del stamps, left, right, truth
    for name in ("scipy.optimize", "diffbot.conditioning"):  # importing is not the fit's work
        importlib.import_module(name)
    (result, _), peak = peak_bytes(lambda: fit_recordings((pairs.pop() for _ in range(1)), BOT))
    assert peak < 4 * 8 * n, f"{peak / (8 * n):.1f} columns of float64"
    assert estimates(result) == pytest.approx(TRUTH, rel=1e-7)
