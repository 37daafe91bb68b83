"""Odometry held against a reference track (diffbot.reference)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.reference import ReferenceComparison

#: A quarter circle of radius 1 m, 11 poses a second apart, starting at the origin heading +x.
T = np.arange(11, dtype=np.int64) * 10**9
ANGLE = np.linspace(0.0, math.pi / 2, 11)
X = np.sin(ANGLE)
Y = 1.0 - np.cos(ANGLE)


def moved(dx: float, dy: float, turn: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The quarter circle in another frame: turned by ``turn`` and shifted."""
    c, s = math.cos(turn), math.sin(turn)
    return dx + c * X - s * Y, dy + s * X + c * Y, ANGLE + turn


@given(
    st.floats(-100, 100),
    st.floats(-100, 100),
    st.floats(-math.pi, math.pi),
    st.integers(1, 11),
)
def test_a_reference_in_another_frame_agrees_once_moved_onto_the_odometry(
    dx: float, dy: float, turn: float, chunk: int
) -> None:
    comparison = ReferenceComparison("/odom", T, *moved(dx, dy, turn))
    for k in range(0, 11, chunk):
        comparison.add(T[k : k + chunk], X[k : k + chunk], Y[k : k + chunk], ANGLE[k : k + chunk])
    result = comparison.result()
    assert result.samples == 11
    assert result.max_position_error < 1e-9 * (1 + abs(dx) + abs(dy))
    assert abs(result.final_heading_error) < 1e-9


def test_the_reference_is_interpolated_between_its_poses_and_not_beyond_them() -> None:
    # A reference along x at 1 m/s, known at 0 s and 2 s only.
    comparison = ReferenceComparison("/track", [0, 2 * 10**9], [0.0, 2.0], [0.0, 0.0], [0.0, 0.0])
    stamps = np.array([0, 10**9, 3 * 10**9])
    rx, ry, rth = comparison.add(stamps, [0.0, 1.5, 3.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    assert rx[:2].tolist() == [0.0, 1.0]
    assert ry[:2].tolist() == rth[:2].tolist() == [0.0, 0.0]
    assert math.isnan(rx[2])  # after the reference's span: not compared
    result = comparison.result()
    assert result.samples == 2
    assert result.final_position_error == pytest.approx(0.5, abs=1e-12)
    assert result.rms_position_error == pytest.approx(math.sqrt(0.25 / 2), abs=1e-12)


def test_the_heading_is_interpolated_the_short_way_across_pi() -> None:
    headings = [math.pi - 0.1, -math.pi + 0.1]  # 0.2 rad apart through pi
    comparison = ReferenceComparison("/odom", [0, 10**9], [0.0, 0.0], [0.0, 0.0], headings)
    comparison.add([0, 5 * 10**8], [0.0, 0.0], [0.0, 0.0], [math.pi - 0.1, math.pi])
    assert comparison.result().final_heading_error == pytest.approx(0.0, abs=1e-12)


def test_nothing_compared_gives_unknown_errors_and_reset_forgets() -> None:
    comparison = ReferenceComparison("/odom", [10 * 10**9], [0.0], [0.0], [0.0])
    comparison.add([0], [0.0], [0.0], [0.0])
    result = comparison.result()
    assert result.samples == 0
    assert result.as_dict()["max_position_error"] is None
    comparison.add([10 * 10**9], [1.0], [0.0], [0.0])
    assert comparison.result().samples == 1
    comparison.reset()
    assert comparison.result().samples == 0


def test_errors_across_the_track_and_the_sign_of_the_heading_error() -> None:
    # A reference along x at 1 m/s; the odometry drifts to +0.3 m then -0.4 m across it,
    # turned +0.2 rad then -0.1 rad from it.
    comparison = ReferenceComparison(
        "/track", [0, 10**9, 2 * 10**9], [0.0, 1.0, 2.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    )
    stamps = [0, 10**9, 2 * 10**9]
    rx, ry, rth = comparison.add(stamps, [0.0, 1.0, 2.0], [0.0, 0.3, -0.4], [0.0, 0.2, -0.1])
    assert rx.tolist() == [0.0, 1.0, 2.0]
    assert ry.tolist() == [0.0, 0.0, 0.0]
    assert rth.tolist() == [0.0, 0.0, 0.0]
    result = comparison.result()
    assert result.samples == 3
    assert result.final_position_error == pytest.approx(0.4, abs=1e-15)
    assert result.final_heading_error == pytest.approx(-0.1, abs=1e-15)  # odometry minus track
    assert result.max_position_error == pytest.approx(0.4, abs=1e-15)
    assert result.rms_position_error == pytest.approx(math.sqrt((0.09 + 0.16) / 3), abs=1e-15)
    # The same poses in two chunks: the first chunk's last pose is turned the other way.
    again = ReferenceComparison(
        "/track", [0, 10**9, 2 * 10**9], [0.0, 1.0, 2.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    )
    again.add(stamps[:2], [0.0, 1.0], [0.0, 0.3], [0.0, 0.2])
    assert again.result().final_position_error == pytest.approx(0.3, abs=1e-15)
    assert again.result().final_heading_error == pytest.approx(0.2, abs=1e-15)
    again.add(stamps[2:], [2.0], [-0.4], [-0.1])
    assert again.result() == result


def test_the_heading_error_is_wrapped_the_short_way() -> None:
    # Both head 3.0 rad at first; the odometry then reads -3.0 rad: it turned 2 pi - 6 rad
    # (0.283 rad) left across pi, not 6 rad right.
    comparison = ReferenceComparison("/odom", [0, 10**9], [0.0, 0.0], [0.0, 0.0], [3.0, 3.0])
    _, _, rth = comparison.add([0, 10**9], [0.0, 0.0], [0.0, 0.0], [3.0, -3.0])
    assert rth.tolist() == pytest.approx([3.0, 3.0], abs=1e-15)
    assert comparison.result().final_heading_error == pytest.approx(math.tau - 6.0, abs=1e-12)
    # Returned headings are wrapped into (-pi, pi] even when the reference's are not.
    turning = ReferenceComparison("/odom", [0, 10**9], [0.0, 0.0], [0.0, 0.0], [0.0, 4.0])
    _, _, rth = turning.add([0, 10**9], [0.0, 0.0], [0.0, 0.0], [0.0, 4.0])
    assert rth.tolist() == pytest.approx([0.0, 4.0 - math.tau], abs=1e-15)
    assert turning.result().final_heading_error == pytest.approx(0.0, abs=1e-12)


def test_a_turned_and_shifted_reference_is_placed_on_the_odometry_pose_by_pose() -> None:
    # The reference drives +y in its frame from (5, 1), heading pi/2; the odometry starts at
    # (1, 2) heading 0 and drives +x, drifting 0.1 m to its left at 1 s.
    comparison = ReferenceComparison(
        "/mocap", [0, 10**9], [5.0, 5.0], [1.0, 2.0], [math.pi / 2, math.pi / 2]
    )
    rx, ry, rth = comparison.add([0, 10**9], [1.0, 2.0], [2.0, 2.1], [0.0, 0.05])
    assert rx.tolist() == pytest.approx([1.0, 2.0], abs=1e-15)
    assert ry.tolist() == pytest.approx([2.0, 2.0], abs=1e-15)
    assert rth.tolist() == pytest.approx([0.0, 0.0], abs=1e-15)
    result = comparison.result()
    assert result.final_position_error == pytest.approx(0.1, abs=1e-12)
    assert result.final_heading_error == pytest.approx(0.05, abs=1e-15)
    # Later stamps are placed the same way by at(), which also says what lies inside.
    x, y, th, inside = comparison.at([5 * 10**8, 2 * 10**9])
    assert x[0] == pytest.approx(1.5, abs=1e-15)
    assert y[0] == pytest.approx(2.0, abs=1e-15)
    assert th[0] == pytest.approx(0.0, abs=1e-15)
    assert math.isnan(x[1])
    assert math.isnan(y[1])
    assert math.isnan(th[1])
    assert inside.tolist() == [1.0, 0.0]


def test_poses_out_of_order_are_sorted_by_stamp_and_spans_are_kept() -> None:
    ordered = ReferenceComparison(
        "/t", [10**9, 2 * 10**9, 3 * 10**9], [0, 1, 2], [0, 0, 0], [0, 0, 0]
    )
    shuffled = ReferenceComparison(
        "/t", [3 * 10**9, 10**9, 2 * 10**9], [2, 0, 1], [0, 0, 0], [0, 0, 0]
    )
    for comparison in (ordered, shuffled):
        rx, _, _ = comparison.add([10**9, 2 * 10**9 + 5 * 10**8], [0.0, 1.25], [0.0, 0.0], [0, 0])
        assert rx.tolist() == [0.0, 1.5]
        result = comparison.result()
        assert result.final_position_error == pytest.approx(0.25, abs=1e-15)
        assert result.span_ns == (10**9, 3 * 10**9)
        assert result.odometry_span_ns == (10**9, 2 * 10**9 + 5 * 10**8)
    # The odometry's span grows with each chunk, from its first stamp.
    ordered.add([4 * 10**9], [0.0], [0.0], [0.0])
    assert ordered.result().odometry_span_ns == (10**9, 4 * 10**9)
    x, _, _, inside = ordered.at([0, 10**9, 3 * 10**9])
    assert inside.tolist() == [0.0, 1.0, 1.0]
    assert math.isnan(x[0])


def test_a_reference_without_poses_compares_nothing_and_says_so() -> None:
    empty = ReferenceComparison("/odom", [], [], [], [])
    rx, ry, rth = empty.add([0, 10**9], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    assert np.isnan(rx).all()
    assert np.isnan(ry).all()
    assert np.isnan(rth).all()
    x, y, th, inside = empty.at([0])
    assert math.isnan(x[0])
    assert math.isnan(y[0])
    assert math.isnan(th[0])
    assert inside.tolist() == [0.0]
    result = empty.result()
    assert result.samples == 0
    assert result.span_ns is None
    assert result.no_overlap_text() == "/odom holds no pose"
    assert result.as_dict() == {
        "topic": "/odom",
        "samples": 0,
        "final_position_error": None,
        "final_heading_error": None,
        "max_position_error": None,
        "rms_position_error": None,
    }


def test_no_overlap_names_both_time_spans() -> None:
    comparison = ReferenceComparison(
        "/mocap", [10 * 10**9, 12 * 10**9 + 5 * 10**8], [0, 1], [0, 0], [0, 0]
    )
    assert comparison.result().no_overlap_text() == (
        "no odometry pose to compare with /mocap (10 to 12.5 s)"
    )
    comparison.add([10**9, 2 * 10**9], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    assert comparison.result().no_overlap_text() == (
        "no pose within the odometry's time span (the odometry 1 to 2 s, /mocap 10 to 12.5 s: "
        "two clocks?)"
    )


def test_the_errors_by_name() -> None:
    comparison = ReferenceComparison("/odom", [0, 10**9], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    comparison.add([0, 10**9], [0.0, 1.0], [0.0, 0.5], [0.0, -0.25])
    assert comparison.result().as_dict() == {
        "topic": "/odom",
        "samples": 2,
        "final_position_error": 0.5,
        "final_heading_error": -0.25,
        "max_position_error": 0.5,
        "rms_position_error": pytest.approx(math.sqrt(0.125), abs=1e-15),
    }


def test_both_frames_turned_the_reference_is_turned_by_their_difference() -> None:
    # The odometry starts at (1, 2) heading 0.3; the reference at (0, 0) heading 1.2 drives 1 m
    # along its heading: placed on the odometry, it drives 1 m along 0.3.
    comparison = ReferenceComparison(
        "/mocap", [0, 10**9], [0.0, math.cos(1.2)], [0.0, math.sin(1.2)], [1.2, 1.2]
    )
    rx, ry, rth = comparison.add([0, 10**9], [1.0, 1.0], [2.0, 2.0], [0.3, 0.3])
    assert rx.tolist() == pytest.approx([1.0, 1.0 + math.cos(0.3)], abs=1e-15)
    assert ry.tolist() == pytest.approx([2.0, 2.0 + math.sin(0.3)], abs=1e-15)
    assert rth.tolist() == pytest.approx([0.3, 0.3], abs=1e-15)
    assert comparison.result().final_position_error == pytest.approx(1.0, abs=1e-15)


def test_the_reference_is_placed_at_the_first_odometry_pose_within_its_span() -> None:
    # The odometry begins a second before the reference: its pose at 1.5 s, not at 0 s, is
    # where the reference is placed.
    comparison = ReferenceComparison(
        "/mocap", [10**9, 2 * 10**9], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]
    )
    rx, ry, _ = comparison.add(
        [0, 15 * 10**8, 2 * 10**9], [7.0, 3.0, 3.5], [5.0, 4.0, 4.0], [0, 0, 0]
    )
    assert math.isnan(rx[0])
    assert rx[1:].tolist() == [3.0, 3.5]
    assert ry[1:].tolist() == [4.0, 4.0]
    assert comparison.result().samples == 2
    assert comparison.result().max_position_error == 0.0


def test_stamps_since_1970_are_interpolated_to_the_nanosecond() -> None:
    # Seconds since 1970 as floats are 2.4e-7 s apart: the stamps are taken relative to the
    # reference's first one before they become seconds.
    t0 = 1_700_000_000_123_456_789
    comparison = ReferenceComparison("/odom", [t0, t0 + 10**9], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    rx, _, _ = comparison.add([t0, t0 + 333_333_333], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    assert rx[1] == pytest.approx(0.333333333, abs=1e-15)
    x, _, _, _ = comparison.at([t0 + 777_777_777])
    assert x[0] == pytest.approx(0.777777777, abs=1e-15)
