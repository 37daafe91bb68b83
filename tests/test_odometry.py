"""Odometry: exact arc integration, skipped samples, the message records, batch integration."""

from __future__ import annotations

import itertools
import math
import sys
from collections.abc import Sequence

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT
from wheel_motion import (
    TRAJECTORY_A,
    Segment,
    angle_error,
    assert_pose_close,
    closed_form,
    wheel_samples,
)

import diffbot
from diffbot.kinematics import DiffDriveParams, Pose, sinc
from diffbot.odometry import (
    SKIP_MISSING_JOINT,
    SKIP_NOT_FINITE,
    SKIP_STAMP_NOT_AFTER,
    Odometry,
    integrate,
)
from diffbot.ros.messages import covariance_matrix

LEFT, RIGHT = BOT.left_joint, BOT.right_joint


def run(
    odom: Odometry, stamps: Sequence[float], lefts: Sequence[float], rights: Sequence[float]
) -> Pose:
    """Feed samples to ``odom`` one by one; its pose at the end."""
    for stamp, left, right in zip(stamps, lefts, rights, strict=True):
        odom.update(left, right, stamp)
    return odom.pose


linears = st.one_of(st.just(0.0), st.floats(-0.5, 0.5))
angulars = st.one_of(st.just(0.0), st.floats(-3.0, -1e-3), st.floats(1e-3, 3.0))
segments_st = st.lists(
    st.tuples(linears, angulars, st.floats(0.05, 10.0), st.integers(1, 40)), min_size=1, max_size=6
)
robots = st.builds(
    DiffDriveParams,
    wheel_radius=st.floats(0.01, 0.5),
    wheel_separation=st.floats(0.05, 2.0),
    left_sign=st.sampled_from([1, -1]),
    right_sign=st.sampled_from([1, -1]),
)


# --------------------------------------------------------------------------------------------
# Exact integration


def test_first_sample_sets_the_baseline_without_moving() -> None:
    odom = Odometry(BOT)
    assert odom.update(123.4, -56.7, 10.0) is True
    assert odom.pose == Pose(0.0, 0.0, 0.0)
    assert odom.twist == (0.0, 0.0)
    assert odom.samples == 1
    odom.update(123.4 + 1.0, -56.7 + 1.0, 11.0)
    assert odom.pose.x == pytest.approx(0.035, abs=1e-15)


def test_straight_line_moves_along_the_heading() -> None:
    odom = Odometry(BOT, 1.0, 2.0, 0.5)
    run(odom, [0.0, 1.0, 2.5], [0.0, 10.0, 20.0], [0.0, 10.0, 20.0])
    assert_pose_close(odom.pose, Pose(1.0 + 0.7 * math.cos(0.5), 2.0 + 0.7 * math.sin(0.5), 0.5))
    assert odom.heading == 0.5


def test_spin_in_place_turns_without_moving() -> None:
    odom = Odometry(BOT)
    # Opposite wheel angles of b*pi/(4r) each: a quarter turn about the axle's midpoint.
    angle = math.pi * BOT.wheel_separation / 2 / 2 / BOT.wheel_radius
    run(odom, [0.0, 1.0, 2.0], [0.0, -angle / 2, -angle], [0.0, angle / 2, angle])
    assert odom.pose.x == 0.0
    assert odom.pose.y == 0.0
    assert odom.heading == pytest.approx(math.pi / 2, abs=1e-15)


def test_half_circle_counter_clockwise_ends_at_the_closed_form_pose() -> None:
    # The seed's first arc: radius 0.25 m, 180 degrees in 10 s, sampled coarsely on purpose.
    for steps in (1, 2, 7, 100):
        stamps, lefts, rights = wheel_samples(BOT, [(0.025 * math.pi, math.pi / 10, 10.0, steps)])
        odom = Odometry(BOT)
        assert_pose_close(run(odom, stamps, lefts, rights), Pose(0.0, 0.5, math.pi), 1e-12)


def test_trajectory_a_at_10_hz_ends_exactly_where_the_plan_does() -> None:
    odom = Odometry(BOT)
    pose = run(odom, *wheel_samples(BOT, TRAJECTORY_A))
    assert_pose_close(pose, Pose(0.0, 1.0, 0.0), 1e-9)
    assert odom.distance == pytest.approx(2.0 + 0.5 * math.pi, rel=1e-12)


def test_euler_integration_of_the_seed_misses_trajectory_a_where_exact_arcs_do_not() -> None:
    # A guard on the test above: the seed's rule (move along the old heading) is off by ~1e-4 m.
    _, lefts, rights = wheel_samples(BOT, TRAJECTORY_A[:2])
    x = y = theta = 0.0
    for k in range(1, len(lefts)):
        dl = (lefts[k] - lefts[k - 1]) * BOT.wheel_radius
        dr = (rights[k] - rights[k - 1]) * BOT.wheel_radius
        x += (dl + dr) / 2 * math.cos(theta)
        y += (dl + dr) / 2 * math.sin(theta)
        theta += (dr - dl) / BOT.wheel_separation
    assert math.hypot(x - (-1.0), y - 0.5) > 1e-5


@settings(max_examples=200, deadline=None)
@given(robots, segments_st, st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi))
def test_constant_velocity_segments_end_at_the_closed_form_pose(
    params: DiffDriveParams,
    segments: list[Segment],
    x0: float,
    y0: float,
    theta0: float,
) -> None:
    expected = Pose(x0, y0, theta0)
    for linear, angular, duration, _ in segments:
        expected = closed_form(expected, linear, angular, duration)
    odom = Odometry(params, x0, y0, theta0)
    pose = run(odom, *wheel_samples(params, segments, start=(3.0, -7.0)))
    assert_pose_close(pose, expected, 1e-9)
    assert odom.heading == pytest.approx(expected.theta, abs=1e-9)


@settings(max_examples=100, deadline=None)
@given(robots, segments_st)
def test_playing_the_samples_backwards_returns_to_the_start(
    params: DiffDriveParams, segments: list[Segment]
) -> None:
    stamps, lefts, rights = wheel_samples(params, segments)
    odom = Odometry(params, 0.5, -0.25, 1.0)
    run(odom, stamps, lefts, rights)
    later = [stamps[-1] + stamp for stamp in stamps[1:]]
    run(odom, later, lefts[-2::-1], rights[-2::-1])
    assert_pose_close(odom.pose, Pose(0.5, -0.25, 1.0), 1e-9)


def test_direction_signs_of_the_description_are_applied() -> None:
    # A left joint whose axis points the other way reports negative angles when rolling forward.
    flipped = BOT.replace(left_sign=-1)
    odom = Odometry(flipped)
    run(odom, [0.0, 1.0], [0.0, -10.0], [0.0, 10.0])
    assert_pose_close(odom.pose, Pose(0.35, 0.0, 0.0), 1e-15)


def test_twist_is_estimated_from_the_stamps_of_the_last_step() -> None:
    stamps, lefts, rights = wheel_samples(BOT, [(0.2, 0.5, 2.0, 8)])
    odom = Odometry(BOT)
    run(odom, stamps, lefts, rights)
    assert odom.twist.linear == pytest.approx(0.2, rel=1e-12)
    assert odom.twist.angular == pytest.approx(0.5, rel=1e-12)


# --------------------------------------------------------------------------------------------
# Singular cases


def test_sinc_is_one_at_zero_and_exact_for_tiny_angles() -> None:
    assert sinc(0.0) == 1.0
    assert sinc(-0.0) == 1.0
    assert sinc(5e-324) == 1.0
    assert sinc(1e-9) == 1.0  # 1 - 1.7e-19 rounds to 1
    h = 1e-4
    assert sinc(h) == pytest.approx(1 - h * h / 6 + h**4 / 120, rel=1e-16)
    assert sinc(math.pi / 2) == pytest.approx(2 / math.pi, rel=1e-15)


def test_heading_wraps_at_plus_minus_pi_while_the_unwrapped_heading_counts_turns() -> None:
    half_turn = math.pi * BOT.wheel_separation / 2 / BOT.wheel_radius  # joint angle for pi rad
    odom = Odometry(BOT)
    run(odom, [0.0, 1.0], [0.0, -half_turn / 2], [0.0, half_turn / 2])
    assert odom.pose.theta == pytest.approx(math.pi / 2, abs=1e-12)
    odom.update(-half_turn, half_turn, 2.0)
    assert angle_error(odom.pose.theta, math.pi) <= 1e-12
    assert -math.pi < odom.pose.theta <= math.pi
    odom.update(-1.5 * half_turn, 1.5 * half_turn, 3.0)
    assert odom.pose.theta == pytest.approx(-math.pi / 2, abs=1e-12)
    assert odom.heading == pytest.approx(3 * math.pi / 2, abs=1e-12)
    # The quaternion describes the wrapped heading, with w >= 0.
    q = odom.message().pose.orientation
    assert (q.z, q.w) == pytest.approx((-math.sqrt(0.5), math.sqrt(0.5)), abs=1e-12)


def test_heading_of_exactly_minus_pi_is_reported_as_pi() -> None:
    odom = Odometry(BOT, theta=-math.pi)
    assert odom.pose.theta == math.pi
    assert odom.heading == -math.pi


def test_tiny_steps_add_up_without_loss() -> None:
    odom = Odometry(BOT)
    step = 1e-9  # rad of wheel per sample: 35 pm of travel
    for k in range(1001):
        odom.update(k * step, k * step * 1.000001, k * 1e-3)
    distance = 1000 * step * BOT.wheel_radius * (1 + 1.000001) / 2
    turn = 1000 * step * 1e-6 * BOT.wheel_radius / BOT.wheel_separation
    assert odom.pose.x == pytest.approx(distance, rel=1e-9)
    assert odom.pose.y == pytest.approx(distance * turn / 2, rel=1e-6)
    assert odom.heading == pytest.approx(turn, rel=1e-6)


def test_encoders_far_from_zero_still_integrate_exactly() -> None:
    # After days of running, joint angles are large; only their differences matter.
    offset = 1e7
    stamps, lefts, rights = wheel_samples(BOT, [(0.1, 0.3, 5.0, 50)], start=(offset, -offset))
    odom = Odometry(BOT)
    run(odom, stamps, lefts, rights)
    assert_pose_close(odom.pose, closed_form(Pose(0, 0, 0), 0.1, 0.3, 5.0), 1e-7)


def test_one_huge_step_follows_its_arc_exactly() -> None:
    # 50 full turns in one step: the chord of an arc that wraps around many times.
    stamps, lefts, rights = wheel_samples(BOT, [(0.3, 2 * math.pi * 50 / 100, 100.0, 1)])
    odom = Odometry(BOT)
    run(odom, stamps, lefts, rights)
    assert_pose_close(odom.pose, Pose(0.0, 0.0, 0.0), 1e-9)
    assert odom.heading == pytest.approx(100 * math.pi, rel=1e-12)


# --------------------------------------------------------------------------------------------
# Skipped samples


def test_a_sample_without_a_wheel_joint_is_skipped_not_read_as_zero() -> None:
    odom = Odometry(BOT)
    odom.update_joint_state([LEFT, RIGHT], [10.0, 10.0], 0.0)
    assert odom.update_joint_state([LEFT], [11.0], 1.0) is False
    assert odom.pose == Pose(0.0, 0.0, 0.0)
    odom.update_joint_state([LEFT, RIGHT], [12.0, 12.0], 2.0)
    # The motion during the gap is still counted: the angles are absolute.
    assert_pose_close(odom.pose, Pose(2 * BOT.wheel_radius, 0.0, 0.0), 1e-15)
    assert odom.skipped == {SKIP_MISSING_JOINT: 1}
    assert odom.samples == 2


def test_a_joint_state_with_fewer_positions_than_names_is_skipped() -> None:
    odom = Odometry(BOT)
    assert odom.update_joint_state(["caster", LEFT, RIGHT], [0.0, 1.0], 0.0) is False
    assert odom.skipped == {SKIP_MISSING_JOINT: 1}
    assert odom.samples == 0


@pytest.mark.parametrize(
    ("left", "right", "stamp"),
    [
        (math.nan, 1.0, 1.0),
        (1.0, math.inf, 1.0),
        (1.0, 1.0, math.nan),
        (-math.inf, 1.0, 1.0),
        (1.0, 1.0, math.inf),
    ],
)
def test_non_finite_samples_are_skipped(left: float, right: float, stamp: float) -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    assert odom.update(left, right, stamp) is False
    assert odom.skipped == {SKIP_NOT_FINITE: 1}
    assert odom.pose == Pose(0.0, 0.0, 0.0)
    assert odom.stamp == 0.0


def test_a_non_finite_first_sample_does_not_set_the_baseline() -> None:
    odom = Odometry(BOT)
    odom.update(math.nan, 5.0, 0.0)
    odom.update(1.0, 1.0, 1.0)
    odom.update(2.0, 2.0, 2.0)
    assert odom.pose.x == pytest.approx(BOT.wheel_radius, abs=1e-15)


@pytest.mark.parametrize("stamp", [1.0, 0.5, -3.0])
def test_duplicate_and_backward_stamps_are_skipped(stamp: float) -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    odom.update(1.0, 1.0, 1.0)
    before = odom.pose
    assert odom.update(5.0, 5.0, stamp) is False
    assert odom.pose == before
    assert odom.skipped == {SKIP_STAMP_NOT_AFTER: 1}
    assert odom.twist.linear == pytest.approx(BOT.wheel_radius, rel=1e-12)


def test_skip_counters_add_up_by_reason() -> None:
    odom = Odometry(BOT)
    odom.update_joint_state(["other"], [1.0], 0.0)
    odom.update_joint_state([LEFT, RIGHT], [0.0, 0.0], 0.0)
    odom.update_joint_state([RIGHT], [0.0], 1.0)
    odom.update(math.nan, 0.0, 2.0)
    odom.update(1.0, 1.0, 0.0)
    assert odom.skipped == {SKIP_MISSING_JOINT: 2, SKIP_NOT_FINITE: 1, SKIP_STAMP_NOT_AFTER: 1}
    assert odom.samples == 1


# --------------------------------------------------------------------------------------------
# Joint states


@settings(max_examples=100, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-50, 50), st.floats(-50, 50), st.permutations(range(5))),
        min_size=1,
        max_size=20,
    ),
    st.integers(0, 3),
)
def test_joint_order_and_extra_joints_do_not_change_the_result(
    samples: list[tuple[float, float, list[int]]], extras: int
) -> None:
    plain = Odometry(BOT)
    named = Odometry(BOT)
    for k, (left, right, order) in enumerate(samples):
        plain.update(left, right, float(k))
        joints = [(LEFT, left), (RIGHT, right)] + [(f"extra_{e}", 99.0) for e in range(extras)]
        shuffled = [joints[i] for i in order if i < len(joints)]
        named.update_joint_state([n for n, _ in shuffled], [p for _, p in shuffled], float(k))
    assert named.pose == plain.pose
    assert named.samples == plain.samples == len(samples)


def test_a_names_list_changed_in_place_is_looked_up_again() -> None:
    odom = Odometry(BOT)
    names = [LEFT, RIGHT]
    odom.update_joint_state(names, [0.0, 0.0], 0.0)
    names.reverse()  # the same list object, now right first
    odom.update_joint_state(names, [2.0, 1.0], 1.0)
    assert odom.heading == pytest.approx(BOT.wheel_radius / BOT.wheel_separation, rel=1e-12)


def test_joint_states_with_numpy_positions_and_tuple_names_are_accepted() -> None:
    odom = Odometry(BOT)
    names = ("caster_wheel_joint", RIGHT, LEFT)
    odom.update_joint_state(names, np.array([0.0, 0.0, 0.0]), 0.0)
    odom.update_joint_state(names, np.array([7.0, 1.0, 1.0]), 1.0)
    assert type(odom.pose.x) is float
    assert odom.pose.x == pytest.approx(BOT.wheel_radius, rel=1e-15)


# --------------------------------------------------------------------------------------------
# Reset, messages, transform


def test_reset_with_a_new_baseline_moves_the_robot_and_forgets_the_last_sample() -> None:
    odom = Odometry(BOT)
    run(odom, [0.0, 1.0], [0.0, 3.0], [0.0, 5.0])
    odom.reset(1.0, 2.0, 3.0, new_baseline=True)
    assert odom.pose == Pose(1.0, 2.0, 3.0)
    assert odom.twist == (0.0, 0.0)
    assert odom.distance == 0.0
    odom.update(100.0, 100.0, 0.5)  # earlier than before the reset, far from the old baseline
    assert odom.pose == Pose(1.0, 2.0, 3.0)
    odom.update(101.0, 101.0, 1.5)
    assert odom.pose.x == pytest.approx(1.0 + BOT.wheel_radius * math.cos(3.0), abs=1e-15)
    assert odom.samples == 4


def test_a_non_finite_initial_pose_is_refused() -> None:
    with pytest.raises(diffbot.ParameterError, match="x must be a finite number"):
        Odometry(BOT, x=math.nan)


#: Starting poses that are no number or lie beyond any drive (MAX_COORDINATE, and
#: MAX_RECORDED_ANGLE for the heading): 10**400 and None ended in an OverflowError and a
#: TypeError, 1e308 was taken.
HOSTILE_POSES = [
    ({"x": 10**400}, "x"),
    ({"x": None}, "x"),
    ({"x": 1e308}, "x"),
    ({"x": "abc"}, "x"),
    ({"y": -1.1e9}, "y"),
    ({"y": True}, "y"),
    ({"theta": 1e13}, "theta"),
    ({"theta": math.inf}, "theta"),
]


@pytest.mark.parametrize(("pose", "name"), HOSTILE_POSES)
def test_a_starting_pose_beyond_any_drive_is_refused_by_name(
    pose: dict[str, object], name: str
) -> None:
    with pytest.raises(diffbot.ParameterError, match=rf"^{name} must be a finite number"):
        Odometry(BOT, **pose)  # type: ignore[arg-type]
    odom = Odometry(BOT)
    with pytest.raises(diffbot.ParameterError, match=rf"^{name} must be a finite number"):
        odom.reset(**pose)  # type: ignore[arg-type]
    with pytest.raises(diffbot.ParameterError, match=rf"^{name}0 must be a finite number"):
        integrate(BOT, [0.0, 1.0], [0.0, 1.0], **{f"{k}0": v for k, v in pose.items()})  # type: ignore[arg-type]


def test_a_starting_pose_of_numeric_strings_is_its_numbers() -> None:
    text = Odometry(BOT, "1.5", "-2", "0.5")  # type: ignore[arg-type]
    number = Odometry(BOT, 1.5, -2.0, 0.5)
    for odom in (text, number):
        run(odom, [0.0, 1.0, 2.0], [0.0, 3.0, 5.0], [0.0, 4.0, 9.0])
    assert text.state == number.state
    wheels = ([0.0, 3.0], [0.0, 4.0])
    given = integrate(BOT, *wheels, "1e9", "-1e9", "1e12")  # type: ignore[arg-type]
    for got, want in zip(given, integrate(BOT, *wheels, 1e9, -1e9, 1e12), strict=True):
        assert got.tolist() == want.tolist()


@pytest.mark.parametrize(
    "diagonal",
    [
        "abc",
        "abcdef",
        b"abcdef",
        [1.0] * 5,
        [1.0] * 7,
        itertools.repeat(1.0),
        ["a"] * 6,
        [-1] * 6,
        3.0,
    ],
)
def test_a_covariance_that_is_not_six_variances_is_refused_at_once(diagonal: object) -> None:
    with pytest.raises(diffbot.ParameterError, match=r"^pose_covariance diagonal"):
        Odometry(BOT, pose_covariance=diagonal)  # type: ignore[arg-type]
    with pytest.raises(diffbot.ParameterError, match=r"^twist_covariance diagonal"):
        Odometry(BOT, twist_covariance=diagonal)  # type: ignore[arg-type]


def test_a_covariance_of_numeric_strings_is_its_numbers() -> None:
    text = Odometry(BOT, pose_covariance=["1", "2", "3", "4", "5", "6"])  # type: ignore[list-item]
    assert text.pose_covariance == Odometry(BOT, pose_covariance=range(1, 7)).pose_covariance


@pytest.mark.parametrize(
    ("sample", "name"),
    [
        ((None, 0.0, 1.0), "left_position"),
        ((0.0, "abc", 1.0), "right_position"),
        ((10**400, 0.0, 1.0), "left_position"),
        ((0.0, 0.0, "soon"), "stamp"),
        ((0.0, 0.0, 10**400), "stamp"),
    ],
)
def test_a_sample_that_is_no_number_is_refused_by_name(
    sample: tuple[object, object, object], name: str
) -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    with pytest.raises(diffbot.ParameterError, match=rf"^{name} must be a number"):
        odom.update(*sample)  # type: ignore[arg-type]
    with pytest.raises(diffbot.ParameterError, match=rf"^{name} must be a number"):
        odom.update_joint_state([LEFT, RIGHT], sample[:2], sample[2])  # type: ignore[arg-type]


def test_samples_of_numeric_strings_and_ints_are_their_numbers() -> None:
    text, number = Odometry(BOT), Odometry(BOT)
    text.update("0", 0, "0")  # type: ignore[arg-type]
    number.update(0.0, 0.0, 0.0)
    assert text.update("3.5", 4, "0.25")  # type: ignore[arg-type]
    assert number.update(3.5, 4.0, 0.25)
    assert text.state == number.state
    assert text.message() == number.message()


@pytest.mark.parametrize("step", [5e-324, 1e-310, sys.float_info.min / 2])
def test_a_step_too_short_to_divide_by_is_skipped_as_a_stamp_not_after(step: float) -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    assert not odom.update(1.0, 2.0, step)
    assert odom.skipped == {SKIP_STAMP_NOT_AFTER: 1}
    assert odom.twist == (0.0, 0.0)
    assert odom.message().twist.linear == (0.0, 0.0, 0.0)
    # nothing is lost: the next sample moves the robot by the wheels' turn since the baseline
    assert odom.update(1.0, 2.0, 0.5)
    whole = Odometry(BOT)
    whole.update(0.0, 0.0, 0.0)
    whole.update(1.0, 2.0, 0.5)
    assert odom.state == whole.state


def test_the_shortest_step_divided_by_is_the_smallest_normal_float() -> None:
    odom = Odometry(BOT)
    odom.update(0.0, 0.0, 0.0)
    assert odom.update(1e-300, 1e-300, sys.float_info.min)
    assert all(math.isfinite(v) for v in odom.state)


def test_message_has_the_shape_of_nav_msgs_odometry() -> None:
    odom = Odometry(BOT, theta=0.5)
    stamps, lefts, rights = wheel_samples(BOT, [(0.1, 0.2, 1.0, 4)])
    run(odom, [s + 100.0 for s in stamps], lefts, rights)
    msg = odom.message()
    assert msg.header.stamp == 101.0
    assert msg.header.frame_id == "odom"
    assert msg.child_frame_id == "base_link"
    pose = odom.pose
    assert msg.pose.position == (pose.x, pose.y, 0.0)
    q = msg.pose.orientation
    assert (q.x, q.y, q.z, q.w) == (0.0, 0.0, math.sin(pose.theta / 2), math.cos(pose.theta / 2))
    assert msg.twist.linear == pytest.approx((0.1, 0.0, 0.0), rel=1e-12)
    assert msg.twist.angular == pytest.approx((0.0, 0.0, 0.2), rel=1e-12)
    assert len(msg.pose.covariance) == 36
    assert msg.pose.covariance[0] == 0.001
    assert msg.pose.covariance[35] == 0.01
    assert sum(msg.twist.covariance) == pytest.approx(0.015, rel=1e-12)


def test_frames_and_covariances_are_configurable() -> None:
    odom = Odometry(
        BOT,
        frame_id="world",
        child_frame_id="base_footprint",
        pose_covariance=[1, 2, 3, 4, 5, 6],
        twist_covariance=[0] * 6,
    )
    msg = odom.message()
    assert (msg.header.frame_id, msg.child_frame_id) == ("world", "base_footprint")
    matrix = np.array(msg.pose.covariance).reshape(6, 6)
    assert np.array_equal(matrix, np.diag([1.0, 2, 3, 4, 5, 6]))
    assert not any(msg.twist.covariance)
    tf = odom.transform()
    assert (tf.header.frame_id, tf.child_frame_id) == ("world", "base_footprint")


@pytest.mark.parametrize(
    ("diagonal", "match"),
    [([1.0] * 5, "needs 6 values, got 5"), ([1, 1, 1, 1, 1, -1], "finite number >= 0")],
)
def test_bad_covariance_diagonals_are_refused(diagonal: list[float], match: str) -> None:
    with pytest.raises(diffbot.ParameterError, match=match):
        covariance_matrix(diagonal)


def test_transform_is_odom_to_base_link_at_the_pose() -> None:
    odom = Odometry(BOT, 1.0, -2.0, -2.5)
    odom.update(0.0, 0.0, 7.0)
    tf = odom.transform()
    assert tf.header == (7.0, "odom")
    assert tf.child_frame_id == "base_link"
    assert tf.translation == (1.0, -2.0, 0.0)
    assert tf.rotation == pytest.approx((0.0, 0.0, math.sin(-1.25), math.cos(-1.25)), abs=1e-15)


# --------------------------------------------------------------------------------------------
# Batch integration


@settings(max_examples=100, deadline=None)
@given(
    robots,
    st.lists(st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)), min_size=1, max_size=60),
    st.floats(-10, 10),
    st.floats(-10, 10),
    st.floats(-10, 10),
)
def test_batch_integration_equals_streaming(
    params: DiffDriveParams,
    samples: list[tuple[float, float]],
    x0: float,
    y0: float,
    theta0: float,
) -> None:
    lefts = [left for left, _ in samples]
    rights = [right for _, right in samples]
    series = integrate(params, lefts, rights, x0, y0, theta0)
    odom = Odometry(params, x0, y0, theta0)
    for k, (left, right) in enumerate(samples):
        odom.update(left, right, float(k))
        # Rounding scales with the path travelled (metres) and the angles (radians) involved.
        tol = 1e-12 * (1.0 + odom.distance)
        assert series.x[k] == pytest.approx(odom.pose.x, abs=tol)
        assert series.y[k] == pytest.approx(odom.pose.y, abs=tol)
        assert series.theta[k] == pytest.approx(odom.heading, abs=1e-12 * (1.0 + abs(left)))


def test_batch_integration_spans_several_blocks_like_streaming(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import diffbot.batch_odometry as module

    monkeypatch.setattr(module, "BLOCK", 7)
    segments = [(0.1, 0.4, 3.0, 30), (0.0, -1.0, 1.0, 11), (0.2, 0.0, 1.0, 5)]
    stamps, lefts, rights = wheel_samples(BOT, segments)
    series = integrate(BOT, lefts, rights)
    odom = Odometry(BOT)
    run(odom, stamps, lefts, rights)
    assert series.x[-1] == pytest.approx(odom.pose.x, abs=1e-15)
    assert series.y[-1] == pytest.approx(odom.pose.y, abs=1e-15)
    assert series.theta[-1] == pytest.approx(odom.heading, abs=1e-15)
    assert len(series.x) == 47


def test_batch_heading_is_unwrapped() -> None:
    _, lefts, rights = wheel_samples(BOT, [(0.0, 2.0, 10.0, 100)])
    series = integrate(BOT, lefts, rights)
    assert series.theta[-1] == pytest.approx(20.0, rel=1e-12)
    assert np.all(np.diff(series.theta) > 0)


def test_batch_of_one_sample_is_the_start_pose_and_of_none_is_empty() -> None:
    one = integrate(BOT, [5.0], [6.0], 1.0, 2.0, 3.0)
    assert (one.x.tolist(), one.y.tolist(), one.theta.tolist()) == ([1.0], [2.0], [3.0])
    none = integrate(BOT, np.array([]), np.array([]))
    assert none.x.shape == none.y.shape == none.theta.shape == (0,)


@pytest.mark.parametrize(
    ("left", "right", "match"),
    [
        ([0.0, 1.0], [0.0], r"arrays of n samples, .* got shapes \(2,\) and \(1,\)"),
        ([[[0.0, 1.0]]], [[[0.0, 1.0]]], r"shape \(n,\) or \(n, wheels\)"),
        ([[0.0, 1.0]], [0.0, 1.0], r"got shapes \(1, 2\) and \(2,\)"),
        ([0.0, math.nan, 2.0], [0.0, 1.0, 2.0], "must be finite"),
        ([0.0, 1.0, 2.0], [0.0, 1.0, math.inf], "must be finite"),
        ([0.0, 1e308, -1e308], [0.0, 0.0, 0.0], "overflow"),
    ],
)
def test_batch_integration_refuses_bad_arrays(
    left: list[float], right: list[float], match: str
) -> None:
    with pytest.raises(diffbot.ParameterError, match=match):
        integrate(BOT, left, right)


# --------------------------------------------------------------------------------------------
# Integer-nanosecond stamps


def epoch_samples(steps: int) -> list[tuple[int, float, float]]:
    """A straight drive at 0.1 m/s sampled at 1 kHz from 1.7e9 s: (stamp ns, left, right)."""
    start = 1_700_000_000_123_456_789
    rate = 0.1 / BOT.wheel_radius  # rad/s of both wheels
    return [(start + k * 1_000_000, rate * k * 1e-3, rate * k * 1e-3) for k in range(steps)]


def test_float_epoch_stamps_lose_velocity_precision_that_integer_stamps_keep() -> None:
    by_float = Odometry(BOT)
    by_ns = Odometry(BOT)
    joints = Odometry(BOT)
    worst_float = worst_ns = 0.0
    for stamp_ns, left, right in epoch_samples(200):
        sec, nanosec = divmod(stamp_ns, 1_000_000_000)
        assert by_float.update(left, right, sec + nanosec * 1e-9)
        assert by_ns.update(left, right, stamp_ns=stamp_ns)
        assert joints.update_joint_state([RIGHT, LEFT], [right, left], stamp_ns=stamp_ns)
        if by_ns.samples > 1:
            worst_float = max(worst_float, abs(by_float.twist.linear / 0.1 - 1.0))
            worst_ns = max(worst_ns, abs(by_ns.twist.linear / 0.1 - 1.0))
    assert worst_float > 1e-5  # what the docstrings warn about
    assert worst_ns < 1e-12
    assert joints.twist == by_ns.twist
    assert by_ns.stamp_ns == epoch_samples(200)[-1][0]
    assert by_ns.stamp == by_ns.stamp_ns / 1e9
    assert by_float.stamp_ns is None


def test_integer_stamps_skip_duplicates_and_mix_with_float_stamps() -> None:
    odom = Odometry(BOT)
    assert odom.update(0.0, 0.0, stamp_ns=2_000_000_000)
    assert not odom.update(1.0, 1.0, stamp_ns=2_000_000_000)
    assert not odom.update(1.0, 1.0, stamp_ns=2**63)  # no ROS time: like an infinite stamp
    assert odom.skipped == {SKIP_STAMP_NOT_AFTER: 1, SKIP_NOT_FINITE: 1}
    assert odom.update(1.0, 1.0, 2.5)  # a float stamp after an integer one
    assert odom.twist.linear == pytest.approx(2 * BOT.wheel_radius, rel=1e-12)
    assert odom.update(2.0, 2.0, stamp_ns=3_000_000_000)
    assert odom.twist.linear == pytest.approx(2 * BOT.wheel_radius, rel=1e-12)
    assert odom.message().header.stamp == 3.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, r"give the sample's time: stamp \(s\) or stamp_ns \(ns\)"),
        ({"stamp": 1.0, "stamp_ns": 1}, "give the sample's time once"),
        ({"stamp_ns": 1.5}, "stamp_ns must be an integer number of nanoseconds, got 1.5"),
    ],
)
def test_a_sample_needs_exactly_one_stamp(kwargs: dict[str, float], match: str) -> None:
    odom = Odometry(BOT)
    with pytest.raises(diffbot.ParameterError, match=match):
        odom.update(0.0, 0.0, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(diffbot.ParameterError, match=match):
        odom.update_joint_state([LEFT, RIGHT], [0.0, 0.0], **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("left", "right", "match"),
    [
        ([math.nan], [2.0], r"must be finite: sample 0 has left nan, right 2\.0"),
        ([1.0], [-math.inf], r"must be finite: sample 0 has left 1\.0, right -inf"),
        ([0.0, 1.0, math.nan, 3.0], [0.0, 1.0, 2.0, math.nan], "sample 2 has left nan"),
        ([math.nan, 1.0], [0.0, 1.0], "sample 0 has left nan"),
        ([0.0, 1.0], [0.0, math.inf], "sample 1 has left 1.0, right inf"),
    ],
)
def test_batch_integration_names_the_first_non_finite_sample(
    left: list[float], right: list[float], match: str
) -> None:
    with pytest.raises(diffbot.ParameterError, match=match):
        integrate(BOT, left, right)


@pytest.mark.parametrize(
    ("left", "match"),
    [
        ([1j], "left wheel positions must be real numbers"),
        (np.array([1.0 + 0j]), "must be real numbers .*complex128"),
        (["1.0"], "must be real numbers"),
        ([None], "must be real numbers"),
        ([object()], "must be real numbers"),
    ],
)
def test_batch_integration_refuses_what_is_not_a_real_number(left: object, match: str) -> None:
    with pytest.raises(diffbot.ParameterError, match=match):
        integrate(BOT, left, [0.0])  # type: ignore[arg-type]
    with pytest.raises(diffbot.ParameterError, match=match.replace("left", "right")):
        integrate(BOT, [0.0], left)  # type: ignore[arg-type]


# --------------------------------------------------------------------------------------------
# Velocity feedback, as diff_drive_controller's update_from_vel (position_feedback: false)

#: ros2_controllers diff_drive_controller/test/test_odometry.cpp: separation 1 m, radii 1 m.
UNIT = DiffDriveParams(wheel_radius=1.0, wheel_separation=1.0)


@pytest.mark.parametrize(
    ("left", "right", "expected", "twist"),
    [
        # TestLinearMotion: 1 rad/s each for 1 s.
        (1.0, 1.0, Pose(1.0, 0.0, 0.0), (1.0, 0.0)),
        # TestPureRotation: -1 and 1 rad/s.
        (-1.0, 1.0, Pose(0.0, 0.0, 2.0), (0.0, 2.0)),
        # TestCurvedMotion_ExactArc: 1 and 2 rad/s, an arc of radius 1.5 m through 1 rad.
        (1.0, 2.0, Pose(1.5 * math.sin(1.0), -1.5 * (math.cos(1.0) - 1.0), 1.0), (1.5, 1.0)),
    ],
)
def test_velocity_feedback_reproduces_the_controllers_odometry_tests(
    left: float, right: float, expected: Pose, twist: tuple[float, float]
) -> None:
    odom = Odometry(UNIT, feedback="velocity")
    odom.update(123.0, -45.0, 0.0)  # the first velocities only start the clock
    assert odom.update(left, right, 1.0)
    assert_pose_close(odom.pose, expected, 1e-15)
    assert odom.twist.linear == pytest.approx(twist[0], abs=1e-15)
    assert odom.twist.angular == pytest.approx(twist[1], abs=1e-15)


def test_velocity_feedback_reads_the_joint_states_velocities() -> None:
    odom = Odometry(BOT, feedback="velocity")
    names = ["caster", RIGHT, LEFT]
    positions = [0.0, 0.0, 0.0]  # never changing, as a velocity-only driver reports them
    speed = 0.2 / BOT.wheel_radius
    for k in range(11):
        odom.update_joint_state(
            names,
            positions,
            k * 0.1,
            velocities=[0.0, BOT.right_sign * speed, BOT.left_sign * speed],
        )
    assert_pose_close(odom.pose, Pose(0.2, 0.0, 0.0), 1e-12)
    with pytest.raises(diffbot.ParameterError, match="velocities="):
        odom.update_joint_state(names, positions, 2.0)


def test_velocity_feedback_holds_each_velocity_over_the_step_before_its_sample() -> None:
    odom = Odometry(UNIT, feedback="velocity")
    for stamp, speed in [(0.0, 0.0), (1.0, 1.0), (3.0, 0.5), (3.5, 4.0)]:
        odom.update(speed, speed, stamp)
    assert odom.pose.x == pytest.approx(1.0 + 1.0 + 2.0, abs=1e-15)
    odom.update(math.nan, 1.0, 4.0)  # skipped: the next velocity spans the gap
    odom.update(1.0, 1.0, 5.0)
    assert odom.pose.x == pytest.approx(4.0 + 1.5, abs=1e-15)
    assert odom.skipped == {SKIP_NOT_FINITE: 1}


def test_an_unknown_feedback_is_refused() -> None:
    assert Odometry(BOT).feedback == "position"
    assert Odometry(BOT, feedback="velocity").feedback == "velocity"
    with pytest.raises(diffbot.ParameterError, match="feedback"):
        Odometry(BOT, feedback="effort")
