"""Poses as plain matrices: fixed-axis roll, pitch and yaw, R = Rz Ry Rx, then the translation."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from diffbot.urdf.poses import pose_matrix

ANGLE = st.floats(-4.0, 4.0)


def test_a_quarter_turn_of_yaw_turns_x_into_y() -> None:
    m = np.array(pose_matrix(1.0, 2.0, 3.0, 0.0, 0.0, math.pi / 2))
    assert np.allclose(m[:3, :3] @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
    assert m[:3, 3].tolist() == [1.0, 2.0, 3.0]
    assert m[3].tolist() == [0.0, 0.0, 0.0, 1.0]


@given(ANGLE, ANGLE, ANGLE)
def test_the_rotation_is_yaw_after_pitch_after_roll(roll: float, pitch: float, yaw: float) -> None:
    def about(axis: int, angle: float) -> np.ndarray:
        c, s = math.cos(angle), math.sin(angle)
        i, j = [k for k in range(3) if k != axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
        return r if axis != 1 else r.T  # about y, the sines change places

    expected = about(2, yaw) @ about(1, pitch) @ about(0, roll)
    got = np.array(pose_matrix(0.0, 0.0, 0.0, roll, pitch, yaw))[:3, :3]
    assert np.allclose(got, expected, rtol=0.0, atol=1e-14)
