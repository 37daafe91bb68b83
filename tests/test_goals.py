"""Plans to a goal pose: every shape ends exactly at the goal; fastest is the fastest."""

from __future__ import annotations

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffbot import DiffDriveParams, PlanError, Spin, Straight, plan
from diffbot.goals import (
    SHAPES,
    plan_through,
    plan_to,
    relative_pose,
    shape_times,
    waypoint_poses,
)
from diffbot.kinematics import Pose

#: The bundled robot's size (m) and limit (rad/s): r = 0.035, b = 0.135, 50 rpm.
ROBOT = DiffDriveParams(0.035, 0.135, max_wheel_speed=50 * 2 * math.pi / 60)
V_MAX = ROBOT.wheel_radius * 50 * 2 * math.pi / 60  # m/s, both wheels forward at the limit
W_MAX = 2 * V_MAX / ROBOT.wheel_separation  # rad/s, the wheels opposite at the limit

distance = st.floats(-6.0, 3.0).map(lambda e: 10.0**e)  # 1e-6 m to 1e3 m
bearing = st.floats(-math.pi, math.pi)
heading = st.floats(-4 * math.pi, 4 * math.pi)  # wrapping included
radius = st.floats(-2.0, 1.0).map(lambda e: 10.0**e)
starts = st.tuples(st.floats(-10, 10), st.floats(-10, 10), heading)


def goal_of(start: tuple[float, float, float], d: float, b: float, h: float) -> tuple[float, ...]:
    return start[0] + d * math.cos(b), start[1] + d * math.sin(b), h


def assert_reaches(final: Pose, expected: Pose) -> None:
    assert abs(final.x - expected.x) <= 1e-12
    assert abs(final.y - expected.y) <= 1e-12
    assert abs(math.remainder(final.theta - expected.theta, 2 * math.pi)) <= 1e-12


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(SHAPES), distance, bearing, heading, radius, st.booleans())
def test_every_shape_ends_exactly_at_the_goal(
    shape: str, d: float, b: float, h: float, r: float, forward_only: bool
) -> None:
    forward_only = forward_only and shape != "reeds-shepp"
    goal = (d * math.cos(b), d * math.sin(b), h)
    p = plan_to(goal, ROBOT, shape=shape, min_radius=r, forward_only=forward_only)  # type: ignore[arg-type]
    assert_reaches(p.final_pose, Pose(*goal))
    if forward_only or shape == "dubins":
        assert all(s.twist.linear >= 0.0 for s in p.segments)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(SHAPES), distance, bearing, heading, st.booleans(), st.booleans())
def test_goal_plans_equal_plans_of_checked_segments(
    shape: str, d: float, b: float, h: float, fastest: bool, mirrored: bool
) -> None:
    # plan_to makes its segments and plan without the checks that hold by construction: the
    # result is the plan that plan() makes of the same segments through their constructors.
    robot = ROBOT.replace(left_sign=-1) if mirrored else ROBOT
    goal = (d * math.cos(b), d * math.sin(b), h)
    p = plan_to(goal, robot, shape=shape, min_radius=0.25, fastest=fastest)  # type: ignore[arg-type]
    assert p.segments
    checked = [type(s.segment)(**dataclasses.asdict(s.segment)) for s in p.segments]
    assert checked == [s.segment for s in p.segments]
    at_limit = fastest or shape == "fastest"
    assert p == plan(checked, robot, fastest=at_limit)
    assert p.final_pose == p.segments[-1].end_pose


@settings(deadline=None)
@given(starts, distance, bearing, heading, st.sampled_from(SHAPES))
def test_from_a_start_the_plan_ends_at_the_goal_seen_from_it(
    start: tuple[float, float, float], d: float, b: float, h: float, shape: str
) -> None:
    goal = goal_of(start, d, b, h)
    p = plan_to(goal, ROBOT, start=start, shape=shape, min_radius=0.25)  # type: ignore[arg-type]
    assert_reaches(p.final_pose, relative_pose(Pose(*start), Pose(*goal)))


@settings(deadline=None)
@given(distance, bearing, heading, st.booleans())
def test_fastest_within_its_bounds(d: float, b: float, h: float, forward_only: bool) -> None:
    goal = (d * math.cos(b), d * math.sin(b), h)
    fastest = plan_to(goal, ROBOT, forward_only=forward_only)
    sss = plan_to(goal, ROBOT, shape="spin-straight-spin", fastest=True)
    assert fastest.duration <= sss.duration * (1 + 1e-12)
    turn = abs(math.remainder(h, 2 * math.pi))
    assert fastest.duration >= max(d / V_MAX, turn / W_MAX) * (1 - 1e-12)
    # It runs at the motor limit: every segment's faster wheel is at it.
    assert all(s.fraction == pytest.approx(1.0, rel=1e-12) for s in fastest.segments)


def test_ties_go_to_fewest_segments_then_no_backing_up() -> None:
    assert [s.segment for s in plan_to((1.0, 0.0, 0.0), ROBOT).segments] == [Straight(1.0)]
    # Backing up one straight beats turning around (three segments).
    assert [s.segment for s in plan_to((-1.0, 0.0, 0.0), ROBOT).segments] == [Straight(-1.0)]
    ahead = plan_to((-1.0, 0.0, 0.0), ROBOT, forward_only=True)
    assert all(s.twist.linear >= 0.0 for s in ahead.segments)
    assert [s.segment for s in plan_to((0.0, 0.0, math.pi / 2), ROBOT).segments] == [
        Spin(math.pi / 2)
    ]
    # A goal straight to the side: a quarter turn either way then driving forwards, or backing
    # up after turning the other way, take as long: the one without backing up wins.
    side = plan_to((0.0, 1.0, 0.0), ROBOT)
    assert [s.kind for s in side.segments] == ["spin", "straight", "spin"]
    assert all(s.twist.linear >= 0.0 for s in side.segments)


def test_trajectory_a_goal_known_value() -> None:
    # (0, 1, 0): a quarter turn, 1 m, a quarter turn back: pi/2 / W_MAX twice plus 1 / V_MAX.
    p = plan_to((0.0, 1.0, 0.0), ROBOT)
    assert p.duration == pytest.approx(math.pi / W_MAX + 1.0 / V_MAX, rel=1e-12)


def test_goal_at_the_start_is_an_empty_plan() -> None:
    p = plan_to((1.0, 2.0, math.radians(30)), ROBOT, start=(1.0, 2.0, math.radians(390)))
    assert p.segments == ()
    assert p.duration == 0.0
    assert p.final_pose == Pose(0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("goal", "options", "message"),
    [
        ((math.nan, 0.0, 0.0), {}, "the goal must be a finite number"),
        ((1.0, math.inf, 0.0), {}, "the goal must be a finite number"),
        ((1.0, 0.0, 0.0), {"start": (0.0, 0.0, math.nan)}, "the start must be a finite"),
        ((1.0, 0.0, 0.0), {"shape": "dubins"}, "needs a minimum turning radius: give min_radius="),
        (
            (1.0, 0.0, 0.0),
            {"shape": "reeds-shepp"},
            "needs a minimum turning radius: give min_radius=",
        ),
        ((1.0, 0.0, 0.0), {"shape": "dubins", "min_radius": 0.0}, "positive finite"),
        ((1.0, 0.0, 0.0), {"shape": "dubins", "min_radius": -1.0}, "positive finite"),
        ((1.0, 0.0, 0.0), {"min_radius": math.nan}, "positive finite"),
        ((1.0, 0.0, 0.0), {"shape": "zigzag"}, "unknown shape"),
        (
            (1.0, 0.0, 0.0),
            {"shape": "reeds-shepp", "min_radius": 1.0, "forward_only": True},
            "with forward_only=True, the shape is dubins",
        ),
        ((1.0, 0.0), {}, "x, y and a heading"),
        # Beyond any drive: a heading of 1e308 has no digit left below a turn.
        ((1.0, 0.0, 1e308), {}, r"the goal must be a finite number within ±1e\+09, got 1e\+308"),
        ((1e10, 0.0, 0.0), {}, r"the goal must be a finite number within ±1e\+09"),
        ((1.0, 0.0, 0.0), {"start": (0.0, -1e12, 0.0)}, r"the start must be a finite number"),
        ((1.0, 1.0, 0.0), {"shape": "dubins", "min_radius": 1e-300}, r"from 0.0001 to 1e\+09"),
    ],
)
def test_bad_input(goal: tuple[float, ...], options: dict[str, object], message: str) -> None:
    with pytest.raises(PlanError, match=message):
        plan_to(goal, ROBOT, **options)  # type: ignore[arg-type]


def test_waypoints_without_heading_face_the_next_leg() -> None:
    poses = waypoint_poses([(1.0, 0.0), (1.0, 1.0, None), (1.0, 1.0), (0.0, 1.0, 0.5)])
    assert [p.theta for p in poses] == [math.pi / 2, math.pi / 2, math.pi, 0.5]
    # The last waypoint without a heading keeps the direction of the leg that reaches it.
    assert waypoint_poses([(0.0, -2.0)], (0.0, 0.0, 1.0))[0].theta == -math.pi / 2
    p = plan_through([(1.0, 0.0), (1.0, 1.0)], ROBOT, shape="spin-straight-spin")
    assert_reaches(p.final_pose, Pose(1.0, 1.0, math.pi / 2))
    # Two legs: 1 m, a quarter turn, 1 m (the first waypoint already faces the second).
    assert [s.kind for s in p.segments] == ["straight", "spin", "straight"]


@settings(deadline=None)
@given(st.lists(st.tuples(st.floats(-5, 5), st.floats(-5, 5), heading), min_size=1, max_size=5))
def test_through_waypoints_ends_at_the_last(points: list[tuple[float, float, float]]) -> None:
    p = plan_through(points, ROBOT)
    x, y, h = points[-1]
    if p.segments:
        assert abs(p.final_pose.x - x) <= 1e-11
        assert abs(p.final_pose.y - y) <= 1e-11
        assert abs(math.remainder(p.final_pose.theta - h, 2 * math.pi)) <= 1e-11


def test_bad_waypoints() -> None:
    with pytest.raises(PlanError, match="no waypoints"):
        plan_through([], ROBOT)
    with pytest.raises(PlanError, match="waypoint 2 must be a finite number"):
        plan_through([(1.0, 0.0), (math.nan, 1.0)], ROBOT)
    with pytest.raises(PlanError, match="waypoint 1 must be x, y"):
        plan_through([(1.0,)], ROBOT)


def test_shape_times_compare_alike() -> None:
    times = {t.shape: t for t in shape_times([(0.0, 1.0, 0.0)], ROBOT, min_radius=0.25)}
    assert set(times) == set(SHAPES)
    fastest = times["fastest"].duration
    assert fastest is not None
    assert all(t.duration is not None and t.duration >= fastest for t in times.values())
    assert times["reeds-shepp"].duration <= times["dubins"].duration  # type: ignore[operator]
    without = {t.shape: t.duration for t in shape_times([(0.0, 1.0, 0.0)], ROBOT)}
    assert without["dubins"] is None
    assert without["reeds-shepp"] is None


def test_pieces_of_rounding_size_are_left_out() -> None:
    # A Dubins word can start with an arc of 5e-324 rad (mod 2 pi of a rounding error): as a
    # segment its duration would round to zero. It is left out, and so are straights of 1e-16 m.
    from diffbot.goals import _arcs, _turns
    from diffbot.planning import Piece

    assert _arcs([Piece("L", 5e-324), Piece("S", 10.0), Piece("R", 1e-17)], 0.1) == [Straight(1.0)]
    assert _turns([Piece("T", -4e-16), Piece("S", 1e-15), Piece("T", 0.5)], 0.0675) == [Spin(0.5)]


def test_a_goal_plan_at_cruise_speed_drives_at_it_not_at_the_motor_limit() -> None:
    robot = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, max_wheel_speed=5.0)
    fast = plan_to((2.0, 0.0, 0.0), robot)
    slow = plan_to((2.0, 0.0, 0.0), robot, speed=0.1, cruise=True)
    assert float(fast.segments[0].twist.linear) == pytest.approx(0.175)  # 5 rad/s x 0.035 m
    assert float(slow.segments[0].twist.linear) == pytest.approx(0.1)
    assert slow.duration == pytest.approx(20.0)


def test_a_fastest_goal_plan_keeps_within_the_body_limits() -> None:
    from diffbot.body_limits import BodyLimits

    robot = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, max_wheel_speed=5.0)
    body = BodyLimits((-0.12, 0.12), (-0.4, 0.4))
    p = plan_to((1.0, 1.0, math.pi / 2), robot, body=body)
    for s in p.segments:
        assert abs(float(s.twist.linear)) <= 0.12 * (1 + 1e-12)
        assert abs(float(s.twist.angular)) <= 0.4 * (1 + 1e-12)
    assert p.final_pose.x == pytest.approx(1.0, abs=1e-9)
