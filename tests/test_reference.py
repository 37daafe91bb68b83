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
    assert result.final_position_error == pytest.approx(0.5)
    assert result.rms_position_error == pytest.approx(math.sqrt(0.25 / 2))


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
