"""Plans through the controller's speed limiter: ramps within the limits end where planned, a step
plan does not."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT

from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.execution import (
    MAX_EXECUTED_UPDATES,
    estimated_updates,
    execute_plan,
    limits_apply,
)
from diffbot.limiter import LimiterError
from diffbot.odometry import integrate
from diffbot.planfile import parse_plan
from diffbot.ramps import controller_limits, ramp
from diffbot.trajectory import EXAMPLES, plan


def controller(
    a: float, jerk: float | None = None, rate: float | None = 50.0, preserve: bool = False
) -> ControllerConfig:
    return ControllerConfig(
        name="diff_drive_controller",
        source="controllers.yaml",
        ros_version=2,
        linear=AxisLimits(max_velocity=1.0, max_acceleration=a, max_jerk=jerk),
        angular=AxisLimits(max_velocity=3.0, max_acceleration=10 * a, max_jerk=jerk),
        update_rate=rate,
        preserve_turning_radius=preserve,
    )


@settings(max_examples=8, deadline=None)
@given(
    st.sampled_from([EXAMPLES["A"], "straight -1; reverse cw 0.3 120; spin -45; straight 0.2"]),
    st.floats(0.02, 1.0),
    st.one_of(st.none(), st.floats(0.1, 5.0)),
    st.sampled_from([20.0, 50.0, 100.0]),
)
def test_ramps_within_the_limits_run_unchanged_and_end_where_planned(
    text: str, a: float, jerk: float | None, rate: float
) -> None:
    config = controller(a, jerk, rate)
    ramped = ramp(plan(parse_plan(text), BOT), controller_limits(config))
    executed = execute_plan(ramped, config)
    stream = ramped.commands(rate)
    n = stream.linear.size
    np.testing.assert_allclose(executed.linear[:n], stream.linear, rtol=0, atol=1e-9)
    np.testing.assert_allclose(executed.angular[:n], stream.angular, rtol=0, atol=1e-9)
    assert executed.offset < 1e-9
    turn = math.remainder(executed.final_pose.theta - ramped.final_pose.theta, 2 * math.pi)
    assert abs(turn) < 1e-9


def test_the_seeds_step_plan_through_a_slow_limiter_ends_centimetres_off() -> None:
    steps = plan(parse_plan(EXAMPLES["A"]), BOT)
    executed = execute_plan(steps, controller(0.05))
    # Each 0.1 m/s step takes 2 s to reach through 0.05 m/s²: the arcs are cut short.
    assert 0.01 < executed.offset < 0.1
    assert executed.linear.max() == pytest.approx(0.1, rel=1e-12)
    assert np.abs(np.diff(executed.linear)).max() <= 0.05 / 50 * (1 + 1e-12)


def test_the_executed_wheel_angles_give_the_executed_pose_by_odometry() -> None:
    steps = plan(parse_plan("straight 1; ccw 0.3 90; straight 0.5"), BOT)
    executed = execute_plan(steps, controller(0.1))
    knots = np.append(executed.times, executed.duration)
    left, right = executed.wheel_positions(knots)
    x, y, theta = integrate(BOT, left, right)
    assert x[-1] == pytest.approx(executed.final_pose.x, abs=1e-9)
    assert y[-1] == pytest.approx(executed.final_pose.y, abs=1e-9)
    assert math.remainder(theta[-1] - executed.final_pose.theta, 2 * math.pi) == pytest.approx(
        0.0, abs=1e-9
    )


def test_preserving_the_turning_radius_keeps_an_arc_on_its_circle() -> None:
    # A step onto an arc: limited separately, v and w ramp at different paces and the robot
    # leaves the circle; scaled together, it stays on it.
    steps = plan(parse_plan("ccw 0.5 90 5s"), BOT)
    apart = execute_plan(steps, controller(0.05))
    together = execute_plan(steps, controller(0.05, preserve=True))
    ratio = together.linear[together.angular != 0] / together.angular[together.angular != 0]
    np.testing.assert_allclose(ratio, 0.5, rtol=1e-12)
    radius = math.hypot(together.final_pose.x, together.final_pose.y - 0.5)
    assert radius == pytest.approx(0.5, abs=1e-9)
    assert abs(math.hypot(apart.final_pose.x, apart.final_pose.y - 0.5) - 0.5) > 1e-3


def test_the_update_rate_defaults_to_the_controller_managers_100_hz() -> None:
    executed = execute_plan(plan(parse_plan("straight 0.1"), BOT), controller(1.0, rate=None))
    assert executed.rate == 100.0
    assert executed.times[1] == pytest.approx(0.01, rel=1e-15)


def test_limits_apply_only_when_the_configuration_limits_something() -> None:
    assert limits_apply(controller(0.5))
    assert not limits_apply(None)
    bare = ControllerConfig(name="c", source="c.yaml", ros_version=2)
    assert not limits_apply(bare)


def test_updates_are_estimated_as_the_plan_and_the_stop_at_the_tightest_limit() -> None:
    steps = plan(parse_plan("straight 1 10s"), BOT)  # 0.1 m/s for 10 s
    ramped = ramp(steps, controller_limits(None))
    # 10 s of commands, then 0.1 m/s / 0.05 m/s² = 2 s to stop, at 50 Hz
    assert estimated_updates(ramped, controller(0.05)) == pytest.approx(600.0, rel=1e-12)
    # a stop longer than the plan counts as the plan's length: the speed reached is bounded
    assert estimated_updates(ramped, controller(1e-6)) == pytest.approx(1000.0, rel=1e-12)


def test_an_execution_of_more_than_a_million_updates_is_refused_before_it_runs() -> None:
    steps = plan(parse_plan(EXAMPLES["A"]), BOT)
    with pytest.raises(LimiterError, match=r"about 8e\+06 updates at its update_rate of 100000 Hz"):
        execute_plan(steps, controller(1e-4, rate=100_000.0))
    assert MAX_EXECUTED_UPDATES == 1_000_000
    executed = execute_plan(steps, controller(1e-4, rate=10_000.0))  # 8e5 updates: executed
    assert executed.times.size > 400_000
