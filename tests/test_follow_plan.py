"""What a follower takes from its plan: the timed reference's pieces and the limits its
commands keep."""

from __future__ import annotations

import math

import pytest
from robots import BOT_50_RPM

from diffbot.body_limits import BodyLimits
from diffbot.follow import Follower
from diffbot.follow_plan import axis_limits, body_share, controller_limits, pieces
from diffbot.kinematics import Pose
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits, PathLimits
from diffbot.ramps import ramp
from diffbot.trajectory import EXAMPLES, Plan, plan

ROBOT = BOT_50_RPM


def made(text: str) -> Plan:
    return plan(parse_plan(text), ROBOT)


def wrap(angle: float) -> float:
    return math.remainder(angle, 2.0 * math.pi)


def test_a_step_plan_is_a_piece_a_segment_at_its_start_time():
    p = made("straight 1 10s; spin 90 2s; ccw 0.5 90 5s")
    found = pieces(p)
    assert [piece[0] for piece in found] == pytest.approx([0.0, 10.0, 12.0])
    # Each piece: its start pose, the segment's twist as gains, a path coordinate of time.
    assert found[1][1:4] == pytest.approx((1.0, 0.0, 0.0))
    assert found[1][4:6] == pytest.approx((0.0, math.radians(90.0) / 2.0))
    assert found[2][3] == pytest.approx(math.radians(90.0))
    assert all(piece[6:] == (0.0, 1.0, 0.0, 0.0) for piece in found)


def test_a_ramped_reference_is_its_plans_pose_and_speed():
    steps = made(EXAMPLES["A"])
    ramped = ramp(
        steps, Limits(linear=PathLimits(acceleration=0.2), angular=PathLimits(acceleration=1.0))
    )
    follower = Follower(ROBOT, ramped)
    for t in (0.0, 0.3, 5.0, 10.2, 17.0, 33.3, ramped.duration - 1e-3):
        x, y, heading, v, w = follower.reference(t)
        expected = ramped.pose_at(t)
        assert math.hypot(x - expected.x, y - expected.y) < 1e-9
        assert abs(wrap(heading - expected.theta)) < 1e-9
        linear, angular = ramped.twist_at(t)
        assert v == pytest.approx(float(linear), abs=1e-9)
        assert w == pytest.approx(float(angular), abs=1e-9)


def test_a_step_plan_on_a_robot_without_a_controller_keeps_no_limits_but_a_ramp_does():
    steps = made("straight 1 10s")
    assert axis_limits(steps, ROBOT) == ()
    ramped = ramp(
        steps, Limits(linear=PathLimits(acceleration=0.1), angular=PathLimits(acceleration=0.5))
    )
    linear, angular = axis_limits(ramped, ROBOT)
    assert (linear.max_acceleration, angular.max_acceleration) == (0.1, 0.5)


def test_pure_pursuits_commands_keep_a_ramped_plans_acceleration_limits():
    steps = made("straight 1 10s")
    ramped = ramp(
        steps, Limits(linear=PathLimits(acceleration=0.1), angular=PathLimits(acceleration=0.5))
    )
    # Untimed, pure pursuit has no ramped reference: the limiter keeps the plan's ramps.
    follower = Follower(ROBOT, ramped, law="pure-pursuit")
    last_v, dt = 0.0, 0.05
    # Far behind: the law asks for a jump the limiter spreads out.
    for k in range(1, 40):
        v, _ = follower.command(k * dt, Pose(-0.5, 0.0, 0.0))
        assert abs(v - last_v) <= 0.1 * dt * (1 + 1e-9) + 1e-12
        last_v = v
    assert last_v > 0.0


def test_the_tracking_law_keeps_its_controllers_limits_and_follows_a_ramp_from_its_reference():
    steps = made("straight 1 10s")
    ramped = ramp(steps, Limits(linear=PathLimits(jerk=0.001)))
    # The ramped plan's limits are its reference's, which uses all of them: the feedback is
    # not held to them (held, the law has no authority left and swings out of control).
    assert controller_limits(ROBOT) == ()
    follower = Follower(ROBOT, ramped)
    x, y, heading, v_r, w_r = follower.reference(3.0)
    assert follower.command(3.0, Pose(x, y, heading)) == pytest.approx((v_r, w_r), abs=1e-12)
    assert follower.command(3.05, Pose(-0.5, 0.0, 0.0))[0] > 0.1


def test_the_body_share_is_the_one_factor_that_brings_both_axes_within_their_limits() -> None:
    body = BodyLimits(linear=(-0.1, 0.2), angular=(-1.0, 1.0))
    assert body_share(0.1, 0.5, body) == 1.0
    assert body_share(0.4, 0.5, body) == 0.5  # the linear axis asks half
    assert body_share(-0.4, 0.5, body) == 0.25  # backwards its limit is 0.1
    assert body_share(0.1, -4.0, body) == 0.25  # the angular axis asks a quarter
    assert body_share(0.4, -4.0, body) == 0.25  # the tighter of the two
    assert body_share(9.0, 9.0, None) == 1.0
    assert body_share(9.0, 9.0, BodyLimits()) == 1.0
