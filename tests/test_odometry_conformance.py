"""Odometry where it shares behaviour with ros2_controllers' diff_drive_controller: several
wheels per side, per-wheel radii, reset keeping the baseline, the rolling velocity window.

The cases marked "ros2_controllers" are ported from ros-controls/ros2_controllers,
``diff_drive_controller/test/test_odometry.cpp`` and ``test_diff_drive_controller.cpp`` (read at
commit 94e74de35f9d), the test named in each; the differences that remain are listed in
docs/odometry-conformance.md.
"""

from __future__ import annotations

import doctest
import math
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from robots import BOT
from wheel_motion import Segment, angle_error, assert_pose_close, closed_form, wheel_samples

import diffbot
from diffbot.kinematics import DiffDriveParams, Pose, forward, inverse
from diffbot.odometry import SKIP_MISSING_JOINT, SKIP_NOT_FINITE, Odometry, integrate

#: A skid steer with two wheels per side: the course's geometry, front and rear joints.
SKID = BOT.replace(
    left_joints=("front_left_wheel_joint", "rear_left_wheel_joint"),
    right_joints=("front_right_wheel_joint", "rear_right_wheel_joint"),
)
FL, RL = SKID.left_joints
FR, RR = SKID.right_joints
NAMES = ["caster_joint", FL, FR, RL, RR]
DOC = Path(__file__).resolve().parents[1] / "docs" / "odometry-conformance.md"

segments_st = st.lists(
    st.tuples(st.floats(-0.5, 0.5), st.floats(-3.0, 3.0), st.floats(0.05, 5.0), st.integers(1, 20)),
    min_size=1,
    max_size=4,
)


def skid_odometry(samples: list[tuple[float, list[float]]], **kwargs: int) -> Odometry:
    """A skid steer's odometry fed (stamp, positions of NAMES) samples."""
    odom = Odometry(SKID, **kwargs)
    for stamp, positions in samples:
        odom.update_joint_state(NAMES, positions, stamp)
    return odom


# --------------------------------------------------------------------------------------------
# Several wheels per side


@given(segments_st, st.floats(-50.0, 50.0), st.floats(-50.0, 50.0))
def test_skid_steer_of_identical_pairs_equals_the_two_wheel_result(
    segments: list[Segment], left0: float, right0: float
) -> None:
    stamps, lefts, rights = wheel_samples(BOT, segments, (left0, right0))
    pair = Odometry(BOT)
    skid = Odometry(SKID)
    for stamp, left, right in zip(stamps, lefts, rights, strict=True):
        pair.update_joint_state([BOT.left_joint, BOT.right_joint], [left, right], stamp)
        skid.update_joint_state(NAMES, [0.0, left, right, left, right], stamp)
    assert skid.state == pair.state  # bit for bit: (p + p) / 2 == p
    assert skid.distance == pair.distance
    assert skid.samples == pair.samples == len(stamps)


def test_a_side_moves_as_the_mean_of_its_wheels() -> None:
    # Front wheels turn 1 rad, rear wheels 3 rad: the sides turn 2 rad, the robot goes 2 r.
    odom = skid_odometry([(0.0, [9.0, 0.0, 0.0, 0.0, 0.0]), (1.0, [9.0, 1.0, 1.0, 3.0, 3.0])])
    assert odom.pose.x == pytest.approx(2.0 * BOT.wheel_radius, abs=1e-15)
    assert odom.pose.y == 0.0
    assert odom.twist.linear == pytest.approx(2.0 * BOT.wheel_radius, abs=1e-15)


def test_the_mean_adds_in_joint_order_then_divides_by_the_count() -> None:
    # 0.1 + 0.2 + 0.3 depends on the order in floats: the rule fixes params' order.
    three = BOT.replace(left_joints=("a", "b", "c"), right_joints=("d", "e", "f"))
    odom = Odometry(three)
    names = ["c", "b", "a", "f", "e", "d"]  # the message's order is not the one that counts
    odom.update_joint_state(names, [0.0] * 6, 0.0)
    odom.update_joint_state(names, [0.3, 0.2, 0.1, 0.3, 0.2, 0.1], 1.0)
    side = (0.1 + 0.2 + 0.3) / 3
    reference = Odometry(BOT)
    reference.update(0.0, 0.0, 0.0)
    reference.update(side, side, 1.0)
    assert odom.state == reference.state


def test_a_wheel_missing_from_a_message_leaves_the_mean_of_the_others() -> None:
    odom = Odometry(SKID)
    odom.update_joint_state(NAMES, [0.0, 1.0, 1.0, 1.0, 1.0], 0.0)
    assert odom.update_joint_state([FL, FR, RR], [2.0, 2.0, 2.0], 1.0)
    assert odom.pose.x == pytest.approx(BOT.wheel_radius, abs=1e-15)
    assert odom.skipped == {}


def test_a_joint_named_without_a_position_counts_as_absent() -> None:
    odom = Odometry(SKID)
    odom.update_joint_state([FL, FR, RL, RR], [0.0, 0.0, 0.0, 0.0], 0.0)
    assert odom.update_joint_state([FL, FR, RL, RR], [1.0, 1.0, 5.0], 1.0)  # RR has none
    reference = Odometry(BOT)
    reference.update(0.0, 0.0, 0.0)
    reference.update(3.0, 1.0, 1.0)  # left (1 + 5) / 2, right FR's 1 alone
    assert odom.state == reference.state
    assert odom.pose.theta == pytest.approx(-2.0 * BOT.wheel_radius / BOT.wheel_separation)


def test_a_skid_steer_names_list_changed_in_place_is_looked_up_again() -> None:
    odom = Odometry(SKID)
    names = [FL, FR, RL, RR]
    assert odom.update_joint_state(names, [0.0, 0.0, 0.0, 0.0], stamp_ns=0)
    names[0], names[1] = FR, FL  # the same list, now right first
    assert odom.update_joint_state(names, [2.0, 0.0, 0.0, 2.0], stamp_ns=10**9)
    reference = Odometry(BOT)
    reference.update(0.0, 0.0, stamp_ns=0)
    reference.update(0.0, 2.0, stamp_ns=10**9)  # left (0 + 0) / 2, right (2 + 2) / 2
    assert odom.state == reference.state
    assert odom.stamp_ns == 10**9


@pytest.mark.parametrize(
    ("names", "positions"),
    [
        ([FL, RL, "caster_joint"], [1.0, 1.0, 0.0]),  # no right wheel named
        ([FR, RR], [1.0, 1.0]),  # no left wheel named
        ([FL, FR, RL, RR], [1.0]),  # the right wheels named, without positions
    ],
)
def test_a_sample_is_skipped_only_when_a_whole_side_is_missing(
    names: list[str], positions: list[float]
) -> None:
    odom = Odometry(SKID)
    assert odom.update_joint_state(NAMES, [0.0] * 5, 0.0)
    assert not odom.update_joint_state(names, positions, 1.0)
    assert odom.skipped == {SKIP_MISSING_JOINT: 1}
    assert odom.update_joint_state(NAMES, [0.0, 1.0, 1.0, 1.0, 1.0], 2.0)  # nothing lost
    assert odom.pose.x == pytest.approx(BOT.wheel_radius, abs=1e-15)


def test_a_nan_of_one_wheel_skips_the_sample_as_not_finite() -> None:
    odom = Odometry(SKID)
    odom.update_joint_state(NAMES, [0.0] * 5, 0.0)
    assert not odom.update_joint_state(NAMES, [0.0, 1.0, 1.0, math.nan, 1.0], 1.0)
    assert odom.skipped == {SKIP_NOT_FINITE: 1}
    assert odom.pose == Pose(0.0, 0.0, 0.0)


@given(segments_st, st.floats(-0.5, 0.5))
def test_batch_skid_steer_averages_like_streaming_and_like_identical_pairs(
    segments: list[Segment], offset: float
) -> None:
    stamps, lefts, rights = wheel_samples(BOT, segments)
    left, right = np.array(lefts), np.array(rights)
    # Identical pairs: the two-wheel result to the last bit.
    pair = integrate(BOT, left, right)
    skid = integrate(SKID, np.column_stack([left, left]), np.column_stack([right, right]))
    for got, expected in zip(skid, pair, strict=True):
        np.testing.assert_array_equal(got, expected)
    # Rear wheels off by a constant: the mean the streaming odometry takes, sample by sample.
    rear_left, rear_right = left + offset, right - offset
    batch = integrate(
        SKID, np.column_stack([left, rear_left]), np.column_stack([right, rear_right])
    )
    odom = Odometry(SKID)
    for k, stamp in enumerate(stamps):
        odom.update_joint_state(
            NAMES, [0.0, lefts[k], rights[k], rear_left[k], rear_right[k]], stamp
        )
        assert batch.x[k] == pytest.approx(odom.state[0], abs=1e-12)
        assert batch.y[k] == pytest.approx(odom.state[1], abs=1e-12)
        assert batch.theta[k] == odom.state[2]  # linear in the angles: the same sums


# --------------------------------------------------------------------------------------------
# A controller's multipliers: per-wheel radii and the effective separation


@given(
    st.floats(0.02, 0.5),
    st.floats(0.1, 1.0),
    st.floats(0.8, 1.2),
    st.floats(0.8, 1.2),
    st.floats(0.8, 1.5),
    st.floats(-1.0, 1.0),
    st.one_of(st.just(0.0), st.floats(-2.0, -1e-3), st.floats(1e-3, 2.0)),
    st.floats(0.1, 5.0),
)
def test_kinematics_and_odometry_agree_with_the_multiplied_geometry(
    radius: float,
    separation: float,
    left_multiplier: float,
    right_multiplier: float,
    separation_multiplier: float,
    linear: float,
    angular: float,
    duration: float,
) -> None:
    robot = DiffDriveParams(
        wheel_radius=radius,
        wheel_separation=separation * separation_multiplier,
        left_wheel_radius=radius * left_multiplier,
        right_wheel_radius=radius * right_multiplier,
    )
    wheels = inverse(robot, linear, angular)
    # The multiplied geometry, written out: v -+ w b m_b / 2 over r m_side.
    half_track = 0.5 * separation * separation_multiplier * angular
    assert wheels.left == pytest.approx((linear - half_track) / (radius * left_multiplier))
    assert wheels.right == pytest.approx((linear + half_track) / (radius * right_multiplier))
    twist = forward(robot, wheels.left, wheels.right)
    assert twist.linear == pytest.approx(linear, abs=1e-12)
    assert twist.angular == pytest.approx(angular, abs=1e-12)
    odom = Odometry(robot)
    odom.update(0.0, 0.0, 0.0)
    odom.update(float(wheels.left) * duration, float(wheels.right) * duration, duration)
    assert_pose_close(odom.pose, closed_form(Pose(0.0, 0.0, 0.0), linear, angular, duration))
    assert odom.twist.linear == pytest.approx(linear, abs=1e-12)
    assert odom.twist.angular == pytest.approx(angular, abs=1e-12)


# --------------------------------------------------------------------------------------------
# Reset keeps the encoder baseline


def test_reset_keeps_the_baseline_so_the_next_step_is_not_lost() -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    odom.update(2.0, 2.0, 1.0)
    odom.reset(1.0, -1.0, math.pi / 2)
    assert odom.pose == Pose(1.0, -1.0, math.pi / 2)
    assert odom.twist == (0.0, 0.0)
    assert odom.distance == 0.0
    odom.update(3.0, 3.0, 2.0)  # one more radian of each wheel since the last sample
    assert odom.pose.x == pytest.approx(1.0, abs=1e-15)
    assert odom.pose.y == pytest.approx(-1.0 + BOT.wheel_radius, abs=1e-15)
    assert angle_error(odom.pose.theta, math.pi / 2) <= 1e-15
    assert odom.twist.linear == pytest.approx(BOT.wheel_radius, abs=1e-15)
    assert odom.distance == pytest.approx(BOT.wheel_radius, abs=1e-15)


@given(segments_st, st.floats(-3.0, 3.0), st.floats(-3.0, 3.0), st.floats(-math.pi, math.pi))
def test_a_reset_pose_then_moves_as_a_fresh_odometry_from_the_last_sample(
    segments: list[Segment], x: float, y: float, theta: float
) -> None:
    stamps, lefts, rights = wheel_samples(BOT, segments)
    half = len(stamps) // 2
    odom = Odometry(BOT)
    fresh = Odometry(BOT, x, y, theta)
    for k, (stamp, left, right) in enumerate(zip(stamps, lefts, rights, strict=True)):
        if k == half:
            odom.reset(x, y, theta)
        if k >= half - 1:
            fresh.update(left, right, stamp)
        odom.update(left, right, stamp)
    assert odom.state == fresh.state


def test_reset_before_the_first_sample_leaves_it_the_baseline() -> None:
    odom = Odometry(BOT)
    odom.reset(1.0, 2.0, 0.0)
    odom.update(5.0, 5.0, 0.0)
    assert odom.pose == Pose(1.0, 2.0, 0.0)


def test_odometry_set_service_moves_on_from_the_set_pose() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, odometry_set_service.

    b = 0.4 m, r = 1.0 m, wheel positions at (0.1, 0.2). The controller's odometry starts from
    wheel angles 0 (a first sample at 0 here); set to (5.0, -2.0, 1.5708), then both wheels +0.1
    move the robot along +y: y > -2.0 (here exactly 0.1 m along the heading).
    """
    robot = DiffDriveParams(wheel_radius=1.0, wheel_separation=0.4)
    odom = Odometry(robot)
    odom.update(0.0, 0.0, 0.0)
    odom.update(0.1, 0.2, 0.1)
    assert odom.pose.x > 0.0
    odom.reset(5.0, -2.0, 1.57079632679)  # the update that serves the request integrates nothing
    assert odom.pose.x == pytest.approx(5.0, abs=1e-6)
    assert odom.pose.y == pytest.approx(-2.0, abs=1e-6)
    assert odom.pose.theta == pytest.approx(1.57079632679, abs=1e-5)
    odom.update(0.2, 0.3, 0.2)
    assert odom.pose.y > -2.0
    assert odom.pose.y == pytest.approx(-2.0 + 0.1 * math.sin(1.57079632679), abs=1e-15)
    assert odom.pose.x == pytest.approx(5.0 + 0.1 * math.cos(1.57079632679), abs=1e-15)


# --------------------------------------------------------------------------------------------
# The rolling velocity window


def test_the_window_spans_the_displacement_over_the_time_of_its_steps() -> None:
    odom = Odometry(BOT, velocity_rolling_window_size=3)
    r = BOT.wheel_radius
    # Steps of 1, 2, 3 and 4 rad of both wheels, over 1, 1, 2 and 4 s.
    for stamp, angle in ((0.0, 0.0), (1.0, 1.0), (2.0, 3.0), (4.0, 6.0), (8.0, 10.0)):
        odom.update(angle, angle, stamp)
    assert odom.twist.linear == pytest.approx(r * (2.0 + 3.0 + 4.0) / (1.0 + 2.0 + 4.0), rel=1e-15)
    assert odom.twist.angular == 0.0
    assert odom.velocity_rolling_window_size == 3


def test_a_window_not_yet_full_spans_the_steps_so_far() -> None:
    """ros2_controllers test_odometry.cpp, fixture OdometryTest (window 10) with
    TestLinearMotion's robot (b = 1 m, r = 1 m): after one step of 1 rad/s the velocity is
    1.0; after a second one of 2 rad/s, the mean of the two (1.5)."""
    robot = DiffDriveParams(wheel_radius=1.0, wheel_separation=1.0)
    odom = Odometry(robot, velocity_rolling_window_size=10)
    odom.update(0.0, 0.0, 0.0)
    odom.update(1.0, 1.0, 1.0)
    assert odom.twist == (1.0, 0.0)
    odom.update(3.0, 3.0, 2.0)
    assert odom.twist == (1.5, 0.0)
    odom.update(3.0, 5.0, 3.0)  # a turn of 2 rad/s: angular (0 + 0 + 2) / 3
    assert odom.twist.angular == pytest.approx(2.0 / 3.0, rel=1e-15)


def test_a_tiny_stamp_gap_does_not_spike_the_windowed_velocity() -> None:
    # 0.1 m/s sampled every 20 ms, but one sample stamped 0.1 µs after the one before it.
    speed = 0.1 / BOT.wheel_radius
    stamps = [0.02 * k for k in range(12)]
    stamps[5] = stamps[4] + 1e-7
    peaks = {}
    for window in (1, 5):
        odom = Odometry(BOT, velocity_rolling_window_size=window)
        linears = []
        for k, stamp in enumerate(stamps):
            odom.update(speed * 0.02 * k, speed * 0.02 * k, stamp)
            linears.append(odom.twist.linear)
        peaks[window] = max(linears)
    assert peaks[1] > 1e4  # the one-step estimate: 2 mm over 0.1 µs
    assert peaks[5] == pytest.approx(0.1 * 0.1 / 0.08, rel=1e-5)  # 25 % over, at worst


@given(segments_st, st.integers(1, 12))
def test_at_a_constant_speed_and_rate_every_window_gives_the_speed(
    segments: list[Segment], window: int
) -> None:
    linear, angular, duration, steps = segments[0]
    _, lefts, rights = wheel_samples(BOT, [(linear, angular, duration, steps)])
    odom = Odometry(BOT, velocity_rolling_window_size=window)
    dt = duration / steps
    for k, (left, right) in enumerate(zip(lefts, rights, strict=True)):
        odom.update(left, right, k * dt)
    assert odom.twist.linear == pytest.approx(linear, abs=1e-9)
    assert odom.twist.angular == pytest.approx(angular, abs=1e-9)


def test_reset_clears_the_window() -> None:
    odom = Odometry(BOT, velocity_rolling_window_size=4)
    odom.update(0.0, 0.0, 0.0)
    odom.update(10.0, 10.0, 1.0)
    odom.reset()
    odom.update(11.0, 11.0, 2.0)  # only the step after the reset counts
    assert odom.twist.linear == pytest.approx(BOT.wheel_radius, rel=1e-15)


def test_a_robot_at_rest_for_a_whole_window_reads_exactly_zero() -> None:
    odom = Odometry(BOT, velocity_rolling_window_size=5)
    for k in range(40):  # wheels at odd speeds, then at rest for five steps and more
        angle = 0.1 * math.sqrt(k) * (1.0 + 1e-3 * k) if k < 30 else 0.1 * math.sqrt(29) * 1.029
        odom.update(angle, 0.7 * angle, 0.013 * k)
    assert odom.twist == (0.0, 0.0)


def windowed_cost(window: int, updates: int) -> float:
    odom = Odometry(BOT, velocity_rolling_window_size=window)
    started = time.process_time()
    for k in range(updates):
        odom.update(0.01 * k, 0.012 * k, 0.01 * k)
    return time.process_time() - started


def test_a_window_of_a_million_steps_costs_a_step_what_one_of_two_does() -> None:
    # Summed again at each step, a million-step window made each joint state cost its size.
    small = min(windowed_cost(2, 20_000) for _ in range(3))
    large = min(windowed_cost(1_000_000, 20_000) for _ in range(3))
    assert large < 2.0 * small + 0.05, (small, large)


@pytest.mark.parametrize("size", [0, -3, 2.5, True, "4", None, 1_000_001, 2**32])
def test_a_window_size_that_is_not_a_whole_number_from_one_is_refused(size: object) -> None:
    with pytest.raises(diffbot.ParameterError, match="velocity_rolling_window_size must be"):
        Odometry(BOT, velocity_rolling_window_size=size)  # type: ignore[arg-type]


def test_small_dt_steps_are_integrated_not_rejected() -> None:
    """ros2_controllers test_odometry.cpp, TestSmallDtRejection: the controller rejects a step of
    dt < 1e-6 s (1 rad/s for 1e-7 s leaves x at 0). Here the pose comes from the wheel angles
    alone and the step is kept: x is the 1e-7 m the wheels rolled (a documented difference)."""
    robot = DiffDriveParams(wheel_radius=1.0, wheel_separation=1.0)
    odom = Odometry(robot)
    odom.update(0.0, 0.0, 0.0)
    assert odom.update(1e-7, 1e-7, 1e-7)
    assert odom.pose.x == pytest.approx(1e-7, rel=1e-15)
    assert odom.twist.linear == pytest.approx(1.0, rel=1e-9)


def test_the_conformance_page_examples_print_what_it_shows() -> None:
    result = doctest.testfile(str(DOC), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 20
    assert result.failed == 0
