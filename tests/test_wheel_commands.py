"""Velocity commands to joint commands, update by update: the inverse kinematics, the motor limit
kept along the same turning radius, direction signs, the controller's limiter, refusals."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from robots import BOT, BOT_50_RPM

from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.errors import ParameterError
from diffbot.kinematics import inverse
from diffbot.limiter import limit
from diffbot.wheel_commands import WheelCommander


def test_known_wheel_speeds_of_the_course_robot() -> None:
    # v = 0.1 m/s, w = 0.5 rad/s on r = 0.035 m, b = 0.135 m:
    # left (0.1 - 0.5 * 0.0675) / 0.035 = 1.892857..., right (0.1 + 0.03375) / 0.035 = 3.82142...
    out = WheelCommander(BOT).step(0.1, 0.5, 0.0)
    assert out.left == pytest.approx((1.8928571428571428,), rel=1e-15)
    assert out.right == pytest.approx((3.8214285714285716,), rel=1e-15)
    assert (out.linear, out.angular) == pytest.approx((0.1, 0.5), rel=1e-14)


def test_direction_signs_and_several_wheels_per_side() -> None:
    robot = BOT.replace(
        left_sign=-1,
        left_joints=("fl", "rl"),
        right_joints=("fr", "rr"),
        left_joint="fl",
        right_joint="fr",
    )
    out = WheelCommander(robot).step(0.07, 0.0, 0.0)
    assert out.left == pytest.approx((-2.0, -2.0), abs=1e-12)
    assert out.right == pytest.approx((2.0, 2.0), abs=1e-12)


@given(v=st.floats(-2.0, 2.0, allow_nan=False), w=st.floats(-20.0, 20.0, allow_nan=False))
def test_saturation_keeps_the_turning_radius(v: float, w: float) -> None:
    out = WheelCommander(BOT_50_RPM).step(v, w, 0.0)
    limit_rad_s = BOT_50_RPM.max_wheel_speed
    assert limit_rad_s is not None
    assert max(abs(out.left[0]), abs(out.right[0])) <= limit_rad_s * (1 + 1e-12)
    wanted = inverse(BOT_50_RPM, v, w)
    # Both wheels scaled by one factor: the ratio of the wheels (the radius) is kept.
    assert out.left[0] * float(wanted.right) == pytest.approx(
        out.right[0] * float(wanted.left), abs=1e-9
    )


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_non_finite_command_stops_the_wheels(bad: float) -> None:
    commander = WheelCommander(BOT)
    out = commander.step(bad, 0.3, 0.01)
    assert (out.left, out.right) == ((0.0,), (0.0,))
    assert commander.refused == 1


def test_the_controllers_limiter_ramps_the_commands() -> None:
    controller = ControllerConfig(
        name="diff", source="c.yaml", ros_version=2, linear=AxisLimits(max_acceleration=0.5)
    )
    commander = WheelCommander(BOT.replace(controller=controller))
    assert commander.limited
    executed = [commander.step(0.2, 0.0, 0.1).linear for _ in range(6)]
    # 0.5 m/s² for 0.1 s per update: 0.05 m/s more each update until 0.2 m/s.
    assert executed == pytest.approx([0.05, 0.1, 0.15, 0.2, 0.2, 0.2], abs=1e-12)
    # The same numbers as the limiter itself gives.
    assert limit(controller.linear, 0.2, 0.0, 0.0, 0.1) == pytest.approx(0.05, abs=1e-12)
    assert not WheelCommander(BOT.replace(controller=controller), use_limits=False).limited


@pytest.mark.parametrize("robot", [BOT, BOT_50_RPM])
@pytest.mark.parametrize(("v", "w"), [(1e307, 0.0), (0.0, 1e308), (1e308, -1e308)])
def test_commands_too_large_to_compute_stop_the_wheels(robot: object, v: float, w: float) -> None:
    # Finite commands whose wheel speeds overflow: refused as a NaN is, whether or not the robot
    # has a motor limit to scale them down; never an infinite command.
    commander = WheelCommander(robot)  # type: ignore[arg-type]
    out = commander.step(v, w, 0.01)
    assert (out.left, out.right, out.linear, out.angular) == ((0.0,), (0.0,), 0.0, 0.0)
    assert commander.refused == 1
    fine = commander.step(0.07, 0.0, 0.01)
    assert fine.left == pytest.approx((2.0,))


def test_body_limits_clamp_each_axis_as_the_controllers_clamped_input_test() -> None:
    # ros2_controllers' test_open_loop_odometry_with_clamped_input: linear.x.max_velocity 0.5
    # and angular.z.max_velocity 0.5; a command of 5.0 on either axis runs at 0.5.
    from diffbot.body_limits import BodyLimits

    commander = WheelCommander(BOT, body=BodyLimits((-0.5, 0.5), (-0.5, 0.5)))
    out = commander.step(5.0, 0.0, 0.1)
    assert (out.linear, out.angular) == pytest.approx((0.5, 0.0), abs=1e-12)
    out = commander.step(0.0, 5.0, 0.1)
    assert (out.linear, out.angular) == pytest.approx((0.0, 0.5), abs=1e-12)
    # Both at once: each clamped apart, not scaled together (the radius changes).
    out = commander.step(1.0, -0.2, 0.1)
    assert (out.linear, out.angular) == pytest.approx((0.5, -0.2), abs=1e-12)


def test_given_body_limits_replace_the_files_velocity_limits_in_the_limiter() -> None:
    from diffbot.body_limits import BodyLimits

    controller = ControllerConfig(
        name="diff",
        source="c.yaml",
        ros_version=2,
        linear=AxisLimits(max_velocity=1.0, max_acceleration=10.0),
    )
    commander = WheelCommander(
        BOT.replace(controller=controller), body=BodyLimits((-0.3, 0.3), None)
    )
    executed = [commander.step(2.0, 0.0, 0.1).linear for _ in range(3)]
    # 1 m/s per update of acceleration, then held at the given 0.3 m/s (the file says 1.0).
    assert executed == pytest.approx([0.3, 0.3, 0.3], abs=1e-12)


def test_use_limits_is_a_bool_not_a_truthy_word() -> None:
    with pytest.raises(ParameterError, match=r"^use_limits must be True or False, got 'no'"):
        WheelCommander(BOT, use_limits="no")  # type: ignore[arg-type]
