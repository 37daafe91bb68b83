"""A side's angle from its several wheels when samples lack some: it moves by the motion of
the wheels present, never by the offsets between their encoders."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import SKID

from diffbot.odometry import Odometry
from diffbot.side_angles import MessageSides, SideAngles, SideOffsets

offsets_st = st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=2, max_size=4)


@st.composite
def runs(draw: st.DrawFn) -> tuple[list[float], list[float], list[list[bool]]]:
    """Encoder offsets per wheel, the side's motion per sample, which wheels each sample has."""
    offsets = draw(offsets_st)
    n = draw(st.integers(1, 40))
    motion = draw(st.lists(st.floats(-50.0, 50.0, allow_nan=False), min_size=n, max_size=n))
    masks = draw(
        st.lists(
            st.lists(st.booleans(), min_size=len(offsets), max_size=len(offsets)).filter(any),
            min_size=n,
            max_size=n,
        )
    )
    # Each sample after the first has a wheel seen before: one of only new wheels tells nothing
    # of the side's motion (the side then stands; see the next tests).
    seen = set()
    for mask in masks:
        if seen and not any(mask[j] for j in seen):
            mask[min(seen)] = True
        seen |= {j for j, m in enumerate(mask) if m}
    return offsets, motion, masks


@settings(max_examples=300)
@given(runs())
def test_the_side_moves_by_its_wheels_motion_whatever_wheels_a_sample_has(
    run: tuple[list[float], list[float], list[list[bool]]],
) -> None:
    offsets, motion, masks = run
    side = SideOffsets(len(offsets))
    angles = []
    for base, mask in zip(motion, masks, strict=True):
        values = [base + c if m else None for c, m in zip(offsets, mask, strict=True)]
        angle = side.angle(values)
        assert angle is not None
        angles.append(angle)
    # Every wheel turns with the side: the angle's changes are the motion's, to rounding.
    scale = 1.0 + max(map(abs, offsets)) + max(map(abs, motion))
    for k in range(1, len(motion)):
        assert angles[k] - angles[0] == pytest.approx(motion[k] - motion[0], abs=1e-12 * scale)


@settings(max_examples=200)
@given(runs(), st.data())
def test_chunks_give_the_angles_of_samples_one_by_one(
    run: tuple[list[float], list[float], list[list[bool]]], data: st.DataObject
) -> None:
    offsets, motion, masks = run
    values = np.array([[b + c for c in offsets] for b in motion])
    present = np.array(masks)
    one = SideOffsets(len(offsets))
    expected = [
        one.angle([float(v) if p else None for v, p in zip(row, mask, strict=True)])
        for row, mask in zip(values, present, strict=True)
    ]
    cuts = sorted(data.draw(st.lists(st.integers(0, len(motion)), max_size=4)))
    chunked = SideOffsets(len(offsets))
    got: list[float] = []
    for start, stop in zip([0, *cuts], [*cuts, len(motion)], strict=True):
        got += chunked.chunk(values[start:stop], present[start:stop]).tolist()
    assert got == expected  # the same sums, to the last bit


def test_every_wheel_present_is_the_mean_of_their_angles() -> None:
    # diff_drive_controller's mean, while every wheel is there.
    side = SideOffsets(2)
    assert side.angle([100.0, 0.0]) == 50.0
    assert side.angle([101.0, 1.0]) == pytest.approx(51.0, abs=1e-13)
    # One wheel missing moves the side by that wheel's motion, not by 50 rad of offset.
    assert side.angle([None, 2.0]) == pytest.approx(52.0, abs=1e-13)
    assert side.angle([103.0, None]) == pytest.approx(53.0, abs=1e-13)


def test_a_wheel_that_comes_later_joins_at_the_side_s_angle() -> None:
    side = SideOffsets(2)
    assert side.angle([5.0, None]) == 5.0
    assert side.angle([None, -40.0]) == 5.0  # nothing known of it yet: the side stands
    assert side.angle([6.0, -39.0]) == pytest.approx(6.0, abs=1e-13)


def test_a_wheel_not_finite_gives_nan_and_teaches_nothing() -> None:
    side = SideOffsets(2)
    assert side.angle([1.0, None]) == 1.0
    assert math.isnan(side.angle([2.0, math.nan]) or 0.0)
    assert side.offsets[1] is None
    assert side.angle([None, None]) is None
    chunk = side.chunk(np.array([[3.0, math.inf], [4.0, 0.0]]), np.array([[1, 1], [1, 0]], bool))
    assert math.isnan(chunk[0])
    assert chunk[1] == 4.0
    # A spoiled row is not the side's last angle: a wheel joining after it joins the side at the
    # last angle taken, 4, not at the spoiled row's 5 or NaN.
    again = side.chunk(np.array([[5.0, math.nan], [0.0, 9.0]]), np.array([[1, 1], [0, 1]], bool))
    assert math.isnan(again[0])
    assert again[1] == 4.0
    assert side.offsets[1] == 5.0


def test_both_sides_and_a_single_wheel_side() -> None:
    sides = SideAngles(1, 2)
    positions = np.array([[-0.0, 10.0, 0.0], [1.0, 11.0, 0.0], [2.0, 0.0, 2.0]])
    present = np.array([[1, 1, 1], [1, 1, 0], [1, 0, 1]], dtype=bool)
    left, right, both = sides.chunk(positions, present)
    assert left.tolist() == [-0.0, 1.0, 2.0]  # one wheel: as it is
    assert math.copysign(1.0, left[0]) == -1.0
    assert right.tolist() == pytest.approx([5.0, 6.0, 7.0], abs=1e-13)
    assert both.tolist() == [True, True, True]


def test_messages_from_two_drivers_give_the_odometry_of_whole_messages() -> None:
    # A skid steer whose front and rear wheels come from two drivers, in messages of their
    # own, each wheel's encoder from its own zero: the odometry of all wheels in each message.
    front = (SKID.left_joints[0], SKID.right_joints[0])
    rear = (SKID.left_joints[1], SKID.right_joints[1])
    alone, split = Odometry(SKID), Odometry(SKID)
    for k in range(1, 60):
        left, right = 0.1 * k, 0.12 * k  # a gentle left turn
        whole = {front[0]: left, front[1]: right, rear[0]: left + 37.0, rear[1]: right - 81.0}
        alone.update_joint_state(list(whole), list(whole.values()), k / 50)
        pair = front if k % 2 else rear
        split.update_joint_state(list(pair), [whole[j] for j in pair], k / 50)
    assert split.pose.x == pytest.approx(alone.pose.x, abs=1e-12)
    assert split.pose.y == pytest.approx(alone.pose.y, abs=1e-12)
    assert split.pose.theta == pytest.approx(alone.pose.theta, abs=1e-12)
    assert split.distance == pytest.approx(alone.distance, abs=1e-12)


def test_message_sides_learn_from_a_sample_the_other_side_leaves_unusable() -> None:
    sides = MessageSides(("l1", "l2"), ("r1", "r2"))
    assert sides.values(["r2"], [1.0], angles=True) is None  # no left wheel: skipped...
    assert sides.offsets[1].offsets == [None, 0.0]  # ... but the right side learned
    assert sides.values(["l1", "r1"], [0.0, -0.0], angles=True) == (0.0, 1.0)
    velocities = MessageSides(("l1", "l2"), ("r1", "r2"))
    assert velocities.values(["l1", "l2", "r1"], [1.0, 3.0, 2.0], angles=False) == (2.0, 2.0)


def test_values_past_the_float_range_poison_no_offset() -> None:
    side = SideOffsets(2)
    assert side.angle([1e308, None]) == 1e308
    # -1e308 less 1e308 is -inf: that offset would spoil every later sample of the wheel.
    assert math.isnan(side.angle([None, -1e308]) or 0.0)
    assert side.offsets == [0.0, None]
    assert side.angle([2.0, None]) == 2.0
    assert side.angle([None, 5.0]) == 2.0  # learned now, at the side's last angle
    assert side.offsets == [0.0, 3.0]
    huge = SideOffsets(2)
    assert math.isnan(huge.angle([1e308, 1e308]) or 0.0)  # their sum overflows
    assert huge.offsets == [None, None]
    assert huge.angle([1.0, 3.0]) == 2.0


def test_a_new_baseline_learns_the_encoders_offsets_afresh() -> None:
    # Two runs of a straight drive, the second with encoders from other zeros, a rear left
    # wheel missing from every third message: after reset(new_baseline=True) the second run's
    # odometry is that of a fresh integrator, not one turned by the first run's offsets.
    def drive(odom: Odometry, offsets: tuple[float, ...]) -> None:
        joints = (*SKID.left_joints, *SKID.right_joints)
        for k in range(20):
            pairs = [(j, 0.1 * k + c) for j, c in zip(joints, offsets, strict=True)]
            if k % 3 == 1:
                del pairs[1]
            odom.update_joint_state([j for j, _ in pairs], [v for _, v in pairs], k / 10)

    again, fresh = Odometry(SKID), Odometry(SKID)
    drive(again, (0.0, 100.0, 0.0, -30.0))
    again.reset(new_baseline=True)
    drive(again, (5.0, 0.0, 7.0, 0.0))
    drive(fresh, (5.0, 0.0, 7.0, 0.0))
    assert tuple(again.pose) == tuple(fresh.pose)
    assert again.distance == fresh.distance
