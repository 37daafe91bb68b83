"""Link transforms from joint positions: a wheel's rotation about its axis, fixed joints at their
origin, quaternions that agree with the rotation matrices."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from robots import two_wheel_urdf

from diffbot.urdf.link_frames import description_joints, link_transform, quaternion_of
from diffbot.urdf.xacro import expand


def matrix_of(q: tuple[float, float, float, float]) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


@given(
    st.lists(st.floats(-1, 1, allow_nan=False), min_size=4, max_size=4).filter(
        lambda v: sum(c * c for c in v) > 1e-3
    )
)
def test_quaternion_of_inverts_the_rotation_matrix(values: list[float]) -> None:
    norm = math.sqrt(sum(c * c for c in values))
    q = tuple(c / norm for c in values)
    found = quaternion_of(matrix_of(q))  # type: ignore[arg-type]
    assert found[3] >= 0.0
    # q and -q are the same rotation: the one with w >= 0 comes out (either when w = 0).
    dot = sum(a * b for a, b in zip(found, q, strict=True))
    assert abs(dot) == pytest.approx(1.0, abs=1e-9)


def test_a_wheel_turns_about_its_axis_at_its_origin() -> None:
    joints = {j.name: j for j in description_joints(two_wheel_urdf())}
    left = link_transform(joints["left_wheel_joint"], math.pi / 2)
    assert (left.parent, left.child) == ("base_link", "left_wheel")
    assert left.translation == pytest.approx((0.0, 0.1, 0.0))
    # A quarter turn about +y: (0, sin 45°, 0, cos 45°).
    assert left.rotation == pytest.approx((0.0, math.sqrt(0.5), 0.0, math.sqrt(0.5)))


def test_the_bundled_robots_links_all_have_a_transform() -> None:
    joints = description_joints(expand().urdf)
    names = {j.name for j in joints}
    assert {"front_left_wheel_joint", "front_right_wheel_joint"} <= names
    fixed = [j for j in joints if j.type == "fixed"]
    assert fixed, "the bundled robot has fixed links (chassis, sensors)"
    for joint in fixed:
        at_rest = link_transform(joint)
        assert at_rest.translation == pytest.approx(tuple(joint.origin[:3, 3]))
