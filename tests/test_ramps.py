"""Ramped plans: known durations, exact end poses, junctions, limits, and their command streams."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT, BOT_50_RPM

from diffbot.body_limits import BodyLimits
from diffbot.controller_config import AxisLimits, ControllerConfig
from diffbot.errors import PlanError
from diffbot.kinematics import Pose
from diffbot.planfile import parse_plan
from diffbot.profiles import Limits, PathLimits
from diffbot.ramps import controller_limits, has_ramps, ramp, sampled
from diffbot.trajectory import EXAMPLES, Arc, Segment, Spin, Straight, advance, plan


def accel(a: float, jerk: float | None = None) -> Limits:
    return Limits(linear=PathLimits(None, a, jerk), angular=PathLimits(None, 4 * a, None))


def assert_same_pose(actual: Pose, expected: Pose, tol: float = 1e-9) -> None:
    assert actual.x == pytest.approx(expected.x, abs=tol)
    assert actual.y == pytest.approx(expected.y, abs=tol)
    assert math.remainder(actual.theta - expected.theta, 2 * math.pi) == pytest.approx(0, abs=tol)


def held(linear: np.ndarray, angular: np.ndarray, rate: float) -> Pose:
    """The pose reached when each command is held for one period (exact arcs)."""
    x = y = heading = 0.0
    for v, w in zip(linear.tolist(), angular.tolist(), strict=True):
        x, y, heading = advance(x, y, heading, v / rate, w / rate)
    return Pose(x, y, heading)


@pytest.mark.parametrize(
    ("length", "speed", "a"),
    [(1.0, 0.1, 0.05), (2.0, 0.5, 1.0), (0.01, 0.1, 0.05), (0.05, 0.5, 0.5)],
)
def test_a_straight_takes_d_over_v_plus_v_over_a_or_twice_root_d_over_a(
    length: float, speed: float, a: float
) -> None:
    p = ramp(plan([Straight(length)], BOT, speed=speed), accel(a))
    expected = length / speed + speed / a if length >= speed**2 / a else 2 * math.sqrt(length / a)
    assert p.duration == pytest.approx(expected, rel=1e-12)


segments = st.one_of(
    st.builds(Straight, st.floats(0.05, 3.0) | st.floats(-3.0, -0.05)),
    st.builds(
        Arc,
        st.floats(0.05, 2.0),
        st.floats(0.1, 3.0),
        st.sampled_from(["ccw", "cw"]),
        reverse=st.booleans(),
    ),
    st.builds(Spin, st.floats(0.1, 3.0) | st.floats(-3.0, -0.1)),
)


@settings(max_examples=40, deadline=None)
@given(st.lists(segments, min_size=1, max_size=5), st.floats(0.05, 2.0), st.booleans())
def test_ramped_plans_end_where_the_step_plans_of_their_segments_end(
    items: list[Segment], a: float, jerk: bool
) -> None:
    steps = plan(items, BOT)
    ramped = ramp(steps, accel(a, 10 * a if jerk else None))
    assert_same_pose(ramped.pose_at(ramped.duration * (1 - 1e-15)), steps.final_pose, 1e-6)
    assert ramped.pose_at(ramped.duration) == steps.final_pose
    stream = ramped.commands(50.0)
    assert_same_pose(held(stream.linear, stream.angular, 50.0), steps.final_pose)
    assert stream.linear[-1] == stream.angular[-1] == 0.0
    left, right = ramped.wheel_positions(np.array([ramped.duration]))
    assert left[0] == pytest.approx(sum(s.joints.left * s.duration for s in steps.segments))
    assert right[0] == pytest.approx(sum(s.joints.right * s.duration for s in steps.segments))


def test_junctions_of_equal_curvature_keep_their_speed_and_others_stop() -> None:
    ramped = ramp(plan(parse_plan("straight 1; straight 1; ccw 0.5 90"), BOT), accel(0.05))
    assert [run.segments for run in ramped.runs] == [(0, 1), (2,)]
    first = ramped.runs[0]
    junction = first.ends[0]
    linear, _ = ramped.twist_at(np.array([junction, first.duration]))
    assert linear[0] == pytest.approx(0.1, rel=1e-12)  # still cruising
    assert linear[1] == 0.0  # at rest where the curvature changes
    # Two straights in a row take as long as one of their total length.
    single = ramp(plan(parse_plan("straight 2"), BOT), accel(0.05))
    assert first.duration == pytest.approx(single.duration, rel=1e-15)
    assert junction == pytest.approx(10.0 + 0.5 * 0.1 / 0.05, rel=1e-9)


def test_reverse_and_forward_straights_do_not_share_a_run() -> None:
    ramped = ramp(plan(parse_plan("straight 1; straight -1"), BOT), accel(0.05))
    assert len(ramped.runs) == 2


@settings(max_examples=30, deadline=None)
@given(
    st.lists(segments, min_size=1, max_size=4),
    st.floats(0.05, 2.0),
    st.floats(1.0, 40.0),
    st.one_of(st.none(), st.floats(0.5, 20.0)),
)
def test_fastest_ramps_never_break_a_limit_and_each_run_touches_one(
    items: list[Segment], a: float, wheel_accel: float, jerk: float | None
) -> None:
    limits = Limits(
        linear=PathLimits(None, a, jerk),
        angular=PathLimits(None, 3 * a, None),
        wheel=PathLimits(None, wheel_accel, None),
    )
    ramped = ramp(plan(items, BOT_50_RPM, fastest=True), limits)
    motor = BOT_50_RPM.max_wheel_speed
    assert motor is not None
    for run in ramped.runs:
        profile = run.profile
        t = np.linspace(0.0, profile.duration, 401)
        speed, acc = profile.velocity(t), profile.acceleration(t)
        wheel_gain = max(abs(run.wheel_gains.left), abs(run.wheel_gains.right))
        # Every limit, on the body and on the wheels, with float slack.
        assert np.abs(speed).max() * wheel_gain <= motor * (1 + 1e-9)
        assert np.abs(acc).max() * wheel_gain <= wheel_accel * (1 + 1e-9)
        if run.linear_gain:
            assert np.abs(acc).max() <= a * (1 + 1e-9)
        assert np.abs(acc * run.angular_gain).max() <= 3 * a * (1 + 1e-9)
        if jerk is not None and run.linear_gain:
            assert max(abs(p.jerk) for p in profile.phases) <= jerk * (1 + 1e-9)
        # Time-optimal: the speed or the acceleration runs at a bound somewhere.
        touched = [
            np.abs(speed).max() * wheel_gain / motor,
            np.abs(acc).max() * wheel_gain / wheel_accel,
            np.abs(acc * run.angular_gain).max() / (3 * a),
        ]
        if run.linear_gain:
            touched.append(np.abs(acc).max() / a)
        if jerk is not None and run.linear_gain:
            touched.append(max(abs(p.jerk) for p in profile.phases) / jerk)
        assert max(touched) == pytest.approx(1.0, rel=1e-6)


def test_without_acceleration_limits_the_step_plan_comes_back() -> None:
    steps = plan(parse_plan(EXAMPLES["A"]), BOT)
    ramped = ramp(steps, Limits())
    assert not has_ramps(Limits(linear=PathLimits(velocity=1.0)))
    assert [s.duration for s in ramped.summary.segments] == pytest.approx([10.0] * 4, rel=1e-14)
    got = [v for s in ramped.summary.segments for v in s.twist]
    assert got == pytest.approx([v for s in steps.segments for v in s.twist], rel=1e-14)


def test_controller_limits_take_the_tightest_magnitude_and_options_win() -> None:
    controller = ControllerConfig(
        name="diff_drive_controller",
        source="c.yaml",
        ros_version=2,
        linear=AxisLimits(max_velocity=0.5, max_acceleration=1.0, max_deceleration=-0.5),
        angular=AxisLimits(max_acceleration=2.0, max_jerk=8.0),
    )
    limits = controller_limits(controller)
    assert limits.linear == PathLimits(0.5, 0.5, None)
    assert limits.angular == PathLimits(None, 2.0, 8.0)
    given_limits = controller_limits(controller, linear_accel=0.1, wheel_accel=3.0)
    assert given_limits.linear.acceleration == 0.1
    assert given_limits.wheel == PathLimits(None, 3.0, None)
    assert controller_limits(None) == Limits()


@pytest.mark.parametrize(
    ("linear", "angular", "held"),
    [
        (AxisLimits(max_deceleration=0.0), AxisLimits(), "linear.x.max_deceleration"),
        (AxisLimits(max_jerk=0.0), AxisLimits(), "linear.x.max_jerk"),
        (AxisLimits(), AxisLimits(max_acceleration=0.0), "angular.z.max_acceleration"),
        (AxisLimits(), AxisLimits(min_jerk=0.0), "angular.z.min_jerk"),
    ],
)
def test_a_controller_limit_of_zero_holds_the_speed_and_is_refused_unless_replaced(
    linear: AxisLimits, angular: AxisLimits, held: str
) -> None:
    # The controller's limiter takes 0 as a limit (NaN is none): the axis could never change
    # speed, so a ramp "within" it would be a plan the robot does not follow.
    controller = ControllerConfig(
        name="d", source="c.yaml", ros_version=2, linear=linear, angular=angular
    )
    with pytest.raises(PlanError, match=f"^the controller's {held} is 0: "):
        controller_limits(controller)
    replaced = {"linear_accel": 1.0, "linear_jerk": 1.0, "angular_accel": 1.0}
    if "angular.z" in held and "jerk" in held:
        with pytest.raises(PlanError, match=held):  # no option replaces the angular jerk
            controller_limits(controller, **replaced)
    else:
        assert has_ramps(controller_limits(controller, **replaced))


def test_the_controller_speed_caps_the_cruise() -> None:
    limits = Limits(linear=PathLimits(0.05, 0.1, None))
    ramped = ramp(plan(parse_plan("straight 1"), BOT), limits)
    assert ramped.summary.segments[0].twist.linear == pytest.approx(0.05, rel=1e-12)
    assert ramped.duration == pytest.approx(1 / 0.05 + 0.05 / 0.1, rel=1e-12)


def test_body_limits_cap_each_run_in_its_own_direction() -> None:
    # A controller that drives forward at up to 0.6 m/s but backward at only 0.3 m/s, and
    # turns left faster than right: a forward straight cruises at 0.6, not at 0.3.
    body = BodyLimits(linear=(-0.3, 0.6), angular=(-1.0, 2.0))
    limits = Limits(
        linear=PathLimits(0.3, 0.5, None), angular=PathLimits(1.0, 4.0, None)
    )  # the tightest magnitudes, as controller_limits gives them
    steps = plan(parse_plan("straight 1 2s; straight -1 1s; spin 90 1s; spin -90 1s"), BOT)
    ramped = ramp(steps, limits, body)
    linear = [s.twist.linear for s in ramped.summary.segments[:2]]
    angular = [s.twist.angular for s in ramped.summary.segments[2:]]
    assert linear == pytest.approx([0.5, -0.3], rel=1e-12)
    assert angular == pytest.approx([math.pi / 2, -1.0], rel=1e-12)
    assert ramped.duration == pytest.approx(
        (1 / 0.5 + 0.5 / 0.5)
        + (1 / 0.3 + 0.3 / 0.5)
        + (1.0 + (math.pi / 2) / 4.0)
        + (math.pi / 2 + 1.0 / 4.0),
        rel=1e-12,
    )


@settings(max_examples=40, deadline=None)
@given(st.lists(segments, min_size=1, max_size=4), st.integers(1, 40), st.booleans())
def test_command_chunks_are_the_commands_in_pieces(
    items: list[Segment], chunk: int, ramped_plan: bool
) -> None:
    steps = plan(items, BOT)
    ramped = ramp(steps, accel(0.3) if ramped_plan else Limits())
    whole = ramped.commands(20.0)
    pieces = list(ramped.command_chunks(20.0, chunk=chunk))
    assert all(0 < piece.times.size <= chunk for piece in pieces)
    assert ramped.command_count(20.0) == whole.times.size
    for name in ("times", "linear", "angular", "left", "right"):
        joined = np.concatenate([getattr(piece, name) for piece in pieces])
        assert np.array_equal(joined, getattr(whole, name))  # the same numbers, bit for bit


def test_command_chunks_check_the_rate_before_any_is_made() -> None:
    ramped = ramp(plan(parse_plan("straight 1"), BOT), accel(0.3))
    with pytest.raises(PlanError, match=r"must be a finite number >= 1e-06 Hz"):
        ramped.command_chunks(0.0)
    with pytest.raises(PlanError, match="lower the rate"):
        ramped.command_chunks(1e9)


def test_sampled_takes_a_step_plan_as_a_ramped_plan_without_ramps() -> None:
    steps = plan(parse_plan("straight 1 10s; spin 90 2s"), BOT)
    stream = sampled(steps).commands(10.0)
    assert stream.linear.tolist() == ramp(steps, Limits()).commands(10.0).linear.tolist()
    assert stream.linear[:100].tolist() == pytest.approx([0.1] * 100, abs=1e-12)  # 10 s at 0.1 m/s
    ramped = ramp(steps, accel(0.3))
    assert sampled(ramped) is ramped


@pytest.mark.parametrize("times", [[0.0, math.nan], None, "abc"])
def test_a_ramped_plan_refuses_a_time_that_is_no_number(times: object) -> None:
    """NaN gave speeds and wheel angles of NaN, where pose_at refused."""
    ramped = ramp(plan(parse_plan("straight 1"), BOT), accel(0.5))
    for at in (ramped.twist_at, ramped.wheel_positions):
        with pytest.raises(PlanError, match=r"^times must be numbers \(s\), not NaN"):
            at(times)  # type: ignore[arg-type]
    with pytest.raises(PlanError, match=r"^times must be numbers \(s\), not NaN"):
        ramped.pose_at(times)  # type: ignore[arg-type]
