"""Body velocity limits: read from the controller's linear.x / angular.z velocity limits or given,
clamped apart per axis as diff_drive_controller's two speed limiters do, the least time of a
segment, and the segments over them."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from refusals import assert_refused
from robots import BOT, BOT_50_RPM

from diffbot.body_limits import BodyLimits, body_limits, clamp, violations
from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.errors import ParameterError, PlanError
from diffbot.kinematics import Twist
from diffbot.planfile import parse_plan
from diffbot.trajectory import plan


def with_controller(linear: AxisLimits, angular: AxisLimits | None = None) -> ControllerConfig:
    return ControllerConfig(
        name="diffbot_base_controller",
        source="controllers.yaml",
        ros_version=2,
        linear=linear,
        angular=AxisLimits() if angular is None else angular,
    )


def test_the_controllers_velocity_limits_are_the_body_limits() -> None:
    controller = with_controller(
        AxisLimits(max_velocity=1.0, min_velocity=-0.5), AxisLimits(max_velocity=2.0)
    )
    limits = body_limits(BOT.replace(controller=controller))
    # min_velocity left out is -max_velocity, as in the controller's SpeedLimiter.
    assert limits == BodyLimits((-0.5, 1.0), (-2.0, 2.0))


def test_a_given_limit_bounds_the_speed_both_ways_within_the_controllers_min() -> None:
    controller = with_controller(
        AxisLimits(max_velocity=1.0, min_velocity=-0.5), AxisLimits(max_velocity=2.0)
    )
    robot = BOT.replace(controller=controller)
    # Asked for 0.2 m/s and 0.7 rad/s: no faster either way.
    assert body_limits(robot, max_linear=0.2, max_angular=0.7) == BodyLimits(
        (-0.2, 0.2), (-0.7, 0.7)
    )
    # A reverse limit of the file closer to 0 stays: the controller clamps to it anyway.
    assert body_limits(robot, max_linear=0.8).linear == (-0.5, 0.8)
    never_back = with_controller(AxisLimits(max_velocity=1.0, min_velocity=0.0))
    assert body_limits(BOT.replace(controller=never_back), max_linear=0.3).linear == (0.0, 0.3)


def test_a_direction_the_limits_forbid_is_named_with_the_limits() -> None:
    forward = BodyLimits((0.0, 1.0), (-0.5, 0.0))
    with pytest.raises(PlanError, match=r"linear velocity limits \(0 to 1 m/s\) allow no backward"):
        forward.shortest_duration(-1.0, 0.0)
    with pytest.raises(
        PlanError, match=r"angular velocity limits \(-0.5 to 0 rad/s\) allow no left"
    ):
        forward.shortest_duration(1.0, 0.5)
    assert forward.shortest_duration(2.0, -1.0) == pytest.approx(2.0, rel=1e-15)


def test_a_nan_limit_of_the_file_is_no_limit() -> None:
    # The controller declares its limits NaN by default: unset.
    controller = with_controller(AxisLimits(max_velocity=math.nan))
    assert body_limits(BOT.replace(controller=controller)).unlimited
    assert body_limits(BOT).unlimited


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_a_given_limit_must_be_positive_and_finite(bad: float) -> None:
    with pytest.raises(ParameterError, match="max_linear"):
        body_limits(BOT, max_linear=bad)
    with pytest.raises(ParameterError, match="max_angular"):
        body_limits(BOT, max_angular=bad)


def test_clamping_reproduces_the_controllers_open_loop_clamped_input_test() -> None:
    # ros2_controllers' test_open_loop_odometry_with_clamped_input: limits 0.5 m/s and
    # 0.5 rad/s, commands of 5.0 come out as 0.5 on each axis.
    limits = BodyLimits((-0.5, 0.5), (-0.5, 0.5))
    assert clamp(Twist(5.0, 0.0), limits) == Twist(0.5, 0.0)
    assert clamp(Twist(0.0, 5.0), limits) == Twist(0.0, 0.5)


@given(
    v=st.floats(-5.0, 5.0, allow_nan=False),
    w=st.floats(-5.0, 5.0, allow_nan=False),
)
def test_each_axis_is_clamped_apart(v: float, w: float) -> None:
    limits = BodyLimits((-0.2, 0.5), (-1.0, 1.0))
    out = clamp(Twist(v, w), limits)
    # Each axis alone decides its value: the other one's limit never scales it.
    assert out.linear == min(max(v, -0.2), 0.5)
    assert out.angular == min(max(w, -1.0), 1.0)


def test_a_clamped_turn_changes_its_radius() -> None:
    out = clamp(Twist(0.4, 2.0), BodyLimits(None, (-1.0, 1.0)))
    assert out == Twist(0.4, 1.0)
    assert out.linear / out.angular == pytest.approx(0.4)  # 0.2 m asked, 0.4 m driven


@pytest.mark.parametrize(
    ("distance", "turn", "expected"),
    [
        (1.0, 0.0, 1.0 / 0.25),  # forward at 0.25 m/s
        (-1.0, 0.0, 1.0 / 0.1),  # backward at the lower min_velocity
        (0.0, math.pi, math.pi / 0.5),  # a half turn at 0.5 rad/s
        (1.0, 4.0, 4.0 / 0.5),  # the angular limit is the tighter one
    ],
)
def test_shortest_duration_known_values(distance: float, turn: float, expected: float) -> None:
    limits = BodyLimits((-0.1, 0.25), (-0.5, 0.5))
    assert limits.shortest_duration(distance, turn) == pytest.approx(expected, rel=1e-15)


def test_a_direction_the_limits_forbid_is_refused() -> None:
    with pytest.raises(PlanError, match="no backward"):
        BodyLimits((0.0, 0.25), None).shortest_duration(-1.0, 0.0)


def test_violations_name_the_segment_axis_and_least_duration() -> None:
    limits = BodyLimits((-0.3, 0.3), (-0.5, 0.5))
    p = plan(parse_plan("straight 1 2s; spin 90 10s; ccw 0.25 90 1s"), BOT_50_RPM)
    found = violations(p, limits)
    assert [(v.index, v.axis) for v in found] == [(0, "linear"), (2, "linear"), (2, "angular")]
    assert found[0].value == pytest.approx(0.5)
    assert found[0].shortest_duration == pytest.approx(1.0 / 0.3)
    # The arc: pi/2 rad at 0.5 rad/s is longer than 0.3927 m at 0.3 m/s.
    assert found[2].shortest_duration == pytest.approx(math.pi / 2 / 0.5)


def test_a_plan_within_the_limits_has_no_violation() -> None:
    limits = BodyLimits((-0.3, 0.3), (-0.5, 0.5))
    p = plan(parse_plan("straight 1 4s; spin 90 4s"), BOT, body=limits)
    assert violations(p, limits) == []


def test_given_limits_replace_the_controllers_velocity_limits() -> None:
    from diffbot.body_limits import with_velocity_limits

    controller = with_controller(
        AxisLimits(max_velocity=0.3, max_acceleration=1.0), AxisLimits(max_velocity=2.0)
    )
    robot = BOT.replace(controller=controller)
    replaced = with_velocity_limits(robot, BodyLimits((-0.1, 0.4), None))
    assert replaced.controller is not None
    assert replaced.controller.linear == AxisLimits(
        max_velocity=0.4, min_velocity=-0.1, max_acceleration=1.0
    )
    assert replaced.controller.angular == AxisLimits(max_velocity=2.0)
    assert with_velocity_limits(BOT, BodyLimits((-0.1, 0.4), None)) is BOT


@pytest.mark.parametrize(
    ("limits", "named"),
    [
        ({"linear": (-0.2, -math.inf)}, "linear"),
        ({"linear": (-math.inf, math.inf)}, "linear"),
        ({"linear": ("-0.2", "inf")}, "linear"),
        ({"linear": (math.nan, 0.2)}, "linear"),
        ({"linear": (0.1, 0.2)}, "linear"),
        ({"linear": (-0.2, 10**400)}, "linear"),
        ({"linear": (-0.2, 10**5000)}, "linear"),
        ({"linear": (-0.2, None)}, "linear"),
        ({"linear": "ab"}, "linear"),
        ({"linear": 0.2}, "linear"),
        ({"angular": (-1.0,)}, "angular"),
        ({"angular": (-1.0, 0.0, 1.0)}, "angular"),
        ({"angular": ("-1", "fast")}, "angular"),
        ({"angular": (True, 1.0)}, "angular"),
    ],
)
def test_hostile_ranges_are_refused_naming_the_axis(limits: dict[str, object], named: str) -> None:
    assert_refused(BodyLimits, limits, f"{named} must be (lowest <= 0, highest >= 0)")


def test_numeric_strings_clamp_and_plan_as_their_numbers() -> None:
    as_text = BodyLimits(linear=("-0.2", "0.2"), angular=["-1", "1.5"])  # type: ignore[arg-type]
    as_numbers = BodyLimits(linear=(-0.2, 0.2), angular=(-1.0, 1.5))
    assert as_text == as_numbers
    assert clamp(Twist(5.0, -5.0), as_text) == clamp(Twist(5.0, -5.0), as_numbers)
    p = plan(parse_plan("straight 1 1s; spin 180 1s"), BOT)
    assert violations(p, as_text) == violations(p, as_numbers)
    assert as_text.shortest_duration(1.0, 2.0) == as_numbers.shortest_duration(1.0, 2.0)
