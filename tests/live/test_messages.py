"""The live message builders: stamps, headings, odometry, transforms and commands."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.live.messages import (
    commands,
    now_ns,
    odometry,
    stamp_ns,
    time_of,
    transform,
    twist_command,
    twist_mismatch,
    yaw_of,
    yaw_quaternion,
)
from diffbot.live.types import Quaternion, Time


def test_stamps_split_into_seconds_and_nanoseconds_both_ways() -> None:
    assert time_of(1_700_000_000_123_456_789) == Time(1_700_000_000, 123_456_789)
    assert time_of(-1) == Time(-1, 999_999_999)  # floor: the nanoseconds stay positive
    assert stamp_ns(Time(3, 5)) == 3_000_000_005
    assert stamp_ns(Time(-1, 999_999_999)) == -1


@given(st.integers(-(2**62), 2**62))
def test_a_stamp_survives_the_round_trip(ns: int) -> None:
    stamp = time_of(ns)
    assert 0 <= stamp.nanosec < 1_000_000_000
    assert stamp_ns(stamp) == ns


def test_the_wall_clock_is_in_nanoseconds_since_the_epoch() -> None:
    assert 1.7e18 < now_ns() < 1e19


def test_a_heading_is_a_rotation_about_z_with_w_not_negative() -> None:
    q = yaw_quaternion(math.pi / 2)
    assert (q.x, q.y) == (0.0, 0.0)
    assert q.z == pytest.approx(math.sqrt(0.5), abs=1e-15)
    assert q.w == pytest.approx(math.sqrt(0.5), abs=1e-15)
    # 3 pi / 2 is -pi / 2 wrapped: w stays positive, z turns negative.
    q = yaw_quaternion(1.5 * math.pi)
    assert q.z == pytest.approx(-math.sqrt(0.5), abs=1e-15)
    assert q.w == pytest.approx(math.sqrt(0.5), abs=1e-15)


@given(st.floats(-100.0, 100.0))
def test_the_heading_of_a_heading_quaternion_is_the_heading_wrapped(yaw: float) -> None:
    q = yaw_quaternion(yaw)
    assert q.w >= 0.0
    assert math.remainder(yaw_of(q) - yaw, math.tau) == pytest.approx(0.0, abs=1e-12)


def test_the_heading_of_a_tilted_quaternion_is_its_rotation_about_z() -> None:
    # A quarter turn about x then a quarter turn about z: heading pi/2.
    h = math.sqrt(0.5)
    about_x, about_z = (h, 0.0, 0.0, h), (0.0, 0.0, h, h)
    x1, y1, z1, w1 = about_z
    x2, y2, z2, w2 = about_x
    q = Quaternion(
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
    )
    assert yaw_of(q) == pytest.approx(math.pi / 2, abs=1e-12)


def test_odometry_puts_each_value_in_its_field() -> None:
    pose_cov = [float(k) for k in range(36)]
    twist_cov = [float(-k) for k in range(36)]
    message = odometry(
        (1.0, -2.0, 0.5, 0.3, -0.7), 5_000_000_001, "odom", "base", pose_cov, twist_cov
    )
    assert message.header.stamp == Time(5, 1)
    assert (message.header.frame_id, message.child_frame_id) == ("odom", "base")
    pose = message.pose.pose
    assert (pose.position.x, pose.position.y, pose.position.z) == (1.0, -2.0, 0.0)
    assert pose.orientation == yaw_quaternion(0.5)
    twist = message.twist.twist
    assert (twist.linear.x, twist.linear.y, twist.linear.z) == (0.3, 0.0, 0.0)
    assert (twist.angular.x, twist.angular.y, twist.angular.z) == (0.0, 0.0, -0.7)
    assert list(message.pose.covariance) == pose_cov
    assert list(message.twist.covariance) == twist_cov


def test_a_transform_and_commands() -> None:
    moved = transform(2_500_000_000, "odom", "base_link", (1.0, 2.0, 3.0), yaw_quaternion(1.0))
    assert moved.header.stamp == Time(2, 500_000_000)
    assert (moved.header.frame_id, moved.child_frame_id) == ("odom", "base_link")
    t = moved.transform.translation
    assert (t.x, t.y, t.z) == (1.0, 2.0, 3.0)
    assert moved.transform.rotation == yaw_quaternion(1.0)
    twist = twist_command(0.2, -1.5)
    assert (twist.linear.x, twist.linear.y, twist.linear.z) == (0.2, 0.0, 0.0)
    assert (twist.angular.x, twist.angular.y, twist.angular.z) == (0.0, 0.0, -1.5)
    sent = commands([1, 2.5])
    assert sent.data == [1.0, 2.5]
    assert all(type(v) is float for v in sent.data)
    assert (sent.layout.dim, sent.layout.data_offset) == ([], 0)


def test_the_other_kind_of_twist_is_named_with_the_option_that_reads_it() -> None:
    stamped = twist_mismatch("/cmd_vel", "geometry_msgs/msg/TwistStamped")
    assert stamped == "'/cmd_vel' carries geometry_msgs/msg/TwistStamped; use --stamped"
    plain = twist_mismatch("/cmd_vel", "geometry_msgs/msg/Twist")
    assert plain == "'/cmd_vel' carries geometry_msgs/msg/Twist; leave out --stamped"
    other = twist_mismatch("/cmd_vel", "std_msgs/msg/String")
    assert other == "'/cmd_vel' carries std_msgs/msg/String, not a velocity command"
