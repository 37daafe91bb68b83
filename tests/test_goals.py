"""Plans to a goal pose: every shape ends exactly at the goal; fastest is the fastest."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
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
from diffbot.planning import Piece

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


def test_through_waypoints_from_a_start_pose_other_than_the_origin() -> None:
    # From (1, 2) facing +y: 1 m ahead to (1, 3), where the next leg faces -x (heading pi),
    # a quarter turn left, then 1 m to (0, 3). Seen from the start, the end is (1, 1), pi/2.
    start = (1.0, 2.0, math.pi / 2)
    p = plan_through(
        [(1.0, 3.0), (0.0, 3.0, math.pi)], ROBOT, start=start, shape="spin-straight-spin"
    )
    first, turn, second = (s.segment for s in p.segments)
    assert isinstance(first, Straight)
    assert isinstance(second, Straight)
    assert isinstance(turn, Spin)
    assert [first.length, turn.angle, second.length] == pytest.approx(
        [1.0, math.pi / 2, 1.0], abs=1e-15
    )
    assert_reaches(p.final_pose, Pose(1.0, 1.0, math.pi / 2))
    assert_reaches(p.final_pose, relative_pose(Pose(*start), Pose(0.0, 3.0, math.pi)))
    # Waypoints already reached from the start give no segment at all.
    assert plan_through([(1.0, 2.0, math.pi / 2)], ROBOT, start=start).segments == ()
    # The same route from the origin is another plan: the start is not ignored.
    assert plan_through([(1.0, 3.0), (0.0, 3.0, math.pi)], ROBOT).final_pose != p.final_pose


def test_waypoint_headings_from_a_start_pose() -> None:
    # A lone waypoint without a heading faces along the leg from the start that reaches it.
    (pose,) = waypoint_poses([(2.0, 3.0)], (1.0, 2.0, 0.0))
    assert pose == Pose(2.0, 3.0, math.pi / 4)
    # A waypoint on the start keeps the start's heading.
    (pose,) = waypoint_poses([(1.0, 2.0)], (1.0, 2.0, 0.7))
    assert pose == Pose(1.0, 2.0, 0.7)


FREE = DiffDriveParams(0.035, 0.135)  # no motor limit

OPTION_SETS: list[dict[str, object]] = [
    {"shape": "spin-straight-spin", "speed": 0.05, "spin_rate": 0.4},
    {"shape": "dubins", "min_radius": 0.3},
    {"shape": "reeds-shepp", "min_radius": 0.2, "fastest": True},
    {"shape": "fastest", "forward_only": True},
    {"shape": "spin-straight-spin", "limit": 2.0, "fastest": True},
    {"shape": "fastest", "start": (0.5, -0.5, 1.0), "speed": 0.3},
]


@pytest.mark.parametrize("options", OPTION_SETS)
@pytest.mark.parametrize("robot", [ROBOT, FREE])
def test_through_one_waypoint_is_the_plan_to_it_option_by_option(
    options: dict[str, object], robot: DiffDriveParams
) -> None:
    goal = (1.0, 0.7, -2.0)
    if robot is FREE and options.get("fastest") and "limit" not in options:
        options = {**options, "limit": 4.0}
    through = plan_through([goal], robot, **options)
    to = plan_to(goal, robot, **options)  # type: ignore[arg-type]
    assert through == to
    assert through.segments


def test_unknown_options_are_named() -> None:
    with pytest.raises(
        TypeError, match=r"^plan_through\(\) got unexpected keyword arguments: a, b$"
    ):
        plan_through([(1.0, 0.0)], ROBOT, b=1, a=2)
    with pytest.raises(TypeError, match=r"^shape_times\(\) got unexpected keyword arguments: c$"):
        shape_times([(1.0, 0.0)], ROBOT, c=1)
    with pytest.raises(PlanError, match="the start must be"):
        plan_through([(1.0, 0.0)], ROBOT, start=(math.inf, 0.0, 0.0))
    with pytest.raises(PlanError, match="the start must be"):
        waypoint_poses([(1.0, 0.0)], (0.0, math.nan, 0.0))


def test_waypoints_already_reached_give_an_empty_plan_at_the_limit_asked() -> None:
    p = plan_through([(0.0, 0.0, 0.0)], ROBOT)
    assert (p.segments, p.duration, p.final_pose) == ((), 0.0, Pose(0.0, 0.0, 0.0))
    assert p.within_limit
    assert p.limit == ROBOT.max_wheel_speed
    assert plan_through([(0.0, 0.0, 0.0)], ROBOT, limit=3.0).limit == 3.0
    assert plan_through([(0.0, 0.0, 0.0)], FREE).limit is None


@pytest.mark.parametrize("robot", [ROBOT, FREE])
def test_shape_times_are_the_plans_of_each_shape(robot: DiffDriveParams) -> None:
    route = [(0.5, 0.5), (1.0, 0.0, 0.0)]
    # Timed alike: at the limit (the robot's, or the one given) when there is one.
    options: dict[str, object] = {"min_radius": 0.25}
    if robot is FREE:
        options["limit"] = 3.0
    times = {t.shape: t for t in shape_times(route, robot, **options)}
    for shape in SHAPES:
        p = plan_through(route, robot, shape=shape, fastest=True, **options)
        assert times[shape].duration == p.duration
        assert times[shape].segments == len(p.segments)
    # Without a limit: at the cruise speeds.
    cruise = {t.shape: t for t in shape_times(route, FREE, min_radius=0.25, speed=0.2)}
    for shape in SHAPES:
        p = plan_through(route, FREE, shape=shape, min_radius=0.25, speed=0.2)
        assert cruise[shape].duration == p.duration
    # Shapes that cannot be planned say so, with no segment.
    ahead = {t.shape: t for t in shape_times(route, robot, forward_only=True, limit=3.0)}
    assert (ahead["reeds-shepp"].duration, ahead["reeds-shepp"].segments) == (None, 0)
    assert (ahead["dubins"].duration, ahead["dubins"].segments) == (None, 0)
    assert ahead["fastest"].duration is not None
    with_radius = {
        t.shape: t for t in shape_times(route, robot, forward_only=True, min_radius=0.25, limit=3.0)
    }
    assert with_radius["dubins"].duration is not None
    assert with_radius["reeds-shepp"].duration is None


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


def test_limits_that_never_reverse_give_forward_only_goal_plans() -> None:
    """A controller whose linear.x.min_velocity is 0 never backs up: a goal behind the robot is
    reached by turning round, not refused."""
    from diffbot.body_limits import BodyLimits

    robot = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, max_wheel_speed=5.0)
    body = BodyLimits((0.0, 0.15), (-1.0, 1.0))
    goal = (-0.5, 0.0, 0.0)
    p = plan_to(goal, robot, body=body)
    assert all(float(s.twist.linear) >= 0.0 for s in p.segments)
    assert any(float(s.twist.linear) > 0.0 for s in p.segments)
    assert p.final_pose.x == pytest.approx(-0.5, abs=1e-9)
    assert p.final_pose.y == pytest.approx(0.0, abs=1e-9)
    assert math.remainder(p.final_pose.theta, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    # The same as asking for it; with reverse allowed, the plan backs straight up instead.
    assert p.segments == plan_to(goal, robot, body=body, forward_only=True).segments
    back = plan_to(goal, robot, body=BodyLimits((-0.15, 0.15), (-1.0, 1.0)))
    assert [float(s.twist.linear) < 0.0 for s in back.segments] == [True]
    with pytest.raises(PlanError, match="allow no backward motion, and reeds-shepp drives both"):
        plan_to(goal, robot, body=body, shape="reeds-shepp", min_radius=0.2)


@pytest.mark.parametrize(
    ("goal", "facing", "drive"),
    [
        # At the robot's own scale (b = 0.135 m): face the goal, drive, turn to its heading...
        ((0.04, 0.12, 0.7), math.atan2(0.12, 0.04), math.hypot(0.04, 0.12)),
        # ... or face away from it and back up, when the last turn is shorter that way.
        ((0.0, 0.15, -0.7), -math.pi / 2, -0.15),
    ],
)
def test_fastest_at_the_robots_own_scale_known_values(
    goal: tuple[float, float, float], facing: float, drive: float
) -> None:
    p = plan_to(goal, ROBOT)
    first, straight, last = (s.segment for s in p.segments)
    assert isinstance(first, Spin)
    assert isinstance(straight, Straight)
    assert isinstance(last, Spin)
    assert [first.angle, straight.length, last.angle] == pytest.approx(
        [facing, drive, goal[2] - facing], abs=1e-12
    )
    turns = abs(facing) + abs(goal[2] - facing)
    assert p.duration == pytest.approx(turns / W_MAX + abs(drive) / V_MAX, rel=1e-12)


@pytest.mark.parametrize("shape", ["fastest", "spin-straight-spin", "dubins", "reeds-shepp"])
def test_a_goal_on_the_start_turned_by_a_radian_turns_by_it(shape: str) -> None:
    p = plan_to((0.0, 0.0, 1.0), ROBOT, shape=shape, min_radius=0.25)  # type: ignore[arg-type]
    assert p.segments
    assert_reaches(p.final_pose, Pose(0.0, 0.0, 1.0))
    if shape in ("fastest", "spin-straight-spin"):
        assert [s.segment for s in p.segments] == [Spin(1.0)]


def test_numbers_of_any_kind_are_coordinates_and_flags_or_text_are_not() -> None:
    as_floats = plan_to((2.0, 1.0, 0.0), ROBOT, start=(0.0, 0.0, 0.5))
    assert plan_to((2, 1, 0), ROBOT, start=(0, 0, 0.5)) == as_floats
    assert plan_to((2, 1, 0), ROBOT, start=(0, 0, np.float64(0.5))) == as_floats
    # The edge of the range, given as an integer, is within it.
    assert plan_to((10**9, 0, 0), ROBOT).final_pose.x == 1e9
    for goal, shown in (((True, 0.0, 0.0), "True"), (("one", 0.0, 0.0), "'one'")):
        with pytest.raises(PlanError) as caught:
            plan_to(goal, ROBOT)  # type: ignore[arg-type]
        assert str(caught.value) == f"the goal must be a finite number within ±1e+09, got {shown}"


def test_messages_show_what_was_given() -> None:
    with pytest.raises(PlanError) as caught:
        plan_to((1.0, 0.0), ROBOT)
    assert str(caught.value) == "the goal must be x, y and a heading, got (1.0, 0.0)"
    with pytest.raises(PlanError) as caught:
        plan_through([(1.0, 0.0, 0.5, 2.0)], ROBOT)
    assert str(caught.value) == (
        "waypoint 1 must be x, y and an optional heading, got (1.0, 0.0, 0.5, 2.0)"
    )
    with pytest.raises(PlanError) as caught:
        plan_through([(1.0, 0.0), (2.0, 0.0, math.inf)], ROBOT)
    assert str(caught.value) == "waypoint 2 must be a finite number within ±1e+09, got inf"
    with pytest.raises(PlanError) as caught:
        plan_to((1.0, 0.0, 0.0), ROBOT, shape="zigzag")  # type: ignore[arg-type]
    assert str(caught.value) == (
        "unknown shape 'zigzag': give one of fastest, spin-straight-spin, dubins, reeds-shepp"
    )
    with pytest.raises(PlanError) as caught:
        plan_to((1.0, 0.0, 0.0), ROBOT, shape="dubins", min_radius=-2.0)
    assert str(caught.value) == (
        "min_radius= (the minimum turning radius) must be a positive finite number from 0.0001 "
        "to 1e+09 (m), got -2.0"
    )
    for plan_it in (plan_to, plan_through):
        goal = (1.0, 0.0, 0.0) if plan_it is plan_to else [(1.0, 0.0, 0.0)]
        with pytest.raises(PlanError) as caught:
            plan_it(goal, ROBOT, shape="reeds-shepp", min_radius=1.0, forward_only=True)  # type: ignore[operator]
        assert str(caught.value) == (
            "reeds-shepp drives both ways: with forward_only=True, the shape is dubins"
        )
    with pytest.raises(PlanError) as caught:
        plan_through([], ROBOT)
    assert str(caught.value) == "no waypoints: give at least one"


def test_minimum_radii_at_the_edges_of_their_range_are_accepted() -> None:
    for radius in (1e-4, 1e9):
        p = plan_to((1.0, 0.0, 0.0), ROBOT, shape="dubins", min_radius=radius)
        assert p.final_pose == pytest.approx(Pose(1.0, 0.0, 0.0), abs=1e-12)
    p = plan_to((1.0, 1.0, 0.0), ROBOT, shape="dubins", min_radius=1e4)
    # Arcs of 1e4 m turn by about 1e-4 rad: their ends keep about 1e-12 m of rounding.
    assert p.final_pose == pytest.approx(Pose(1.0, 1.0, 0.0), abs=1e-9)
    # Sideways by 1 m on turns of 1e9 m is a loop of about 2·pi·1e9 m: longer than time stamps.
    with pytest.raises(PlanError, match=r"^the plan takes 6\.28\d*e\+10 s, more than "):
        plan_to((1.0, 1.0, 0.0), ROBOT, shape="dubins", min_radius=1e9)


def test_as_many_waypoints_as_a_plan_may_go_through_and_not_one_more() -> None:
    from diffbot.numbers import MAX_WAYPOINTS

    route = [(float(k), 0.0) for k in range(1, MAX_WAYPOINTS + 1)]
    assert len(waypoint_poses(route)) == MAX_WAYPOINTS
    with pytest.raises(PlanError) as caught:
        waypoint_poses([*route, (0.0, 0.0)])
    assert str(caught.value) == (
        f"{MAX_WAYPOINTS + 1} waypoints, more than the {MAX_WAYPOINTS} a plan may go through: "
        "split the route into several plans"
    )


@pytest.mark.parametrize(
    ("pieces", "radius", "expected"),
    [
        # A piece of exactly the rounding (1e-15) is left out, in metres for straights.
        ([Piece("L", 1e-15), Piece("R", -1e-15), Piece("S", 1e-15)], 1.0, []),
        # A straight of 5e-12 radii of 0.0001 m is 5e-16 m: left out.
        ([Piece("S", 5e-12)], 1e-4, []),
    ],
)
def test_arcs_of_rounding_size_are_left_out(
    pieces: list[Piece], radius: float, expected: list[object]
) -> None:
    from diffbot.goals import _arcs

    assert _arcs(pieces, radius) == expected


def test_turns_of_rounding_size_are_left_out() -> None:
    from diffbot.goals import _turns

    assert _turns([Piece("T", 1e-15), Piece("S", 1e-15), Piece("T", -1e-15)], 1.0) == []


def test_an_empty_plan_is_of_the_robot() -> None:
    p = plan_to((0.0, 0.0, 0.0), ROBOT)
    assert p.params == ROBOT
    assert p.segments == ()


def test_a_limit_given_for_a_robot_without_one_times_the_fastest_shape_at_it() -> None:
    p = plan_to((1.0, 0.0, 0.0), FREE, limit=4.0)
    assert float(p.segments[0].twist.linear) == pytest.approx(4.0 * 0.035, rel=1e-12)
    assert p.duration == pytest.approx(1.0 / (4.0 * 0.035), rel=1e-12)


def test_cruise_speeds_time_every_segment() -> None:
    p = plan_to((0.0, 1.0, 0.0), FREE, shape="spin-straight-spin", speed=0.05, spin_rate=0.25)
    # Two quarter turns at 0.25 rad/s and 1 m at 0.05 m/s.
    assert p.duration == pytest.approx(math.pi / 0.25 + 20.0, rel=1e-12)


def test_through_waypoints_every_option_is_used() -> None:
    from diffbot.body_limits import BodyLimits

    route = [(1.0, 1.0, math.pi / 2)]
    robot = DiffDriveParams(wheel_radius=0.035, wheel_separation=0.135, max_wheel_speed=5.0)
    body = BodyLimits((-0.12, 0.12), (-0.4, 0.4))
    limited = plan_through(route, robot, body=body)
    assert limited == plan_to(route[0], robot, body=body)
    assert max(abs(float(s.twist.angular)) for s in limited.segments) <= 0.4 * (1 + 1e-12)
    slow = plan_through(route, robot, speed=0.05, cruise=True)
    assert slow == plan_to(route[0], robot, speed=0.05, cruise=True)
    assert slow.duration > limited.duration
    # A lone waypoint without a heading faces along the leg from the start.
    p = plan_through([(2.0, 3.0)], ROBOT, start=(1.0, 2.0, 0.0))
    assert_reaches(p.final_pose, Pose(1.0, 1.0, math.pi / 4))


def test_shape_times_take_fastest_and_cruise_as_plan_through_does() -> None:
    route = [(0.5, 0.5), (1.0, 0.0, 0.0)]
    for options in ({"fastest": True, "cruise": True}, {"cruise": True, "speed": 0.2}):
        times = {t.shape: t for t in shape_times(route, ROBOT, min_radius=0.25, **options)}
        for shape in SHAPES:
            p = plan_through(route, ROBOT, shape=shape, min_radius=0.25, **options)
            assert times[shape].duration == p.duration


@pytest.mark.parametrize(
    ("shape", "radius"),
    [("fastest", None), ("spin-straight-spin", None), ("dubins", 0.2), ("reeds-shepp", 0.2)],
)
@pytest.mark.parametrize("goal", [(0.0, 1e-18, 0.0), (1e-18, -1e-18, 0.0), (-1e-17, 0.0, 0.0)])
def test_a_goal_a_sliver_from_the_start_is_no_turn_and_back(
    shape: str, radius: float | None, goal: tuple[float, float, float]
) -> None:
    # the straight to it is shorter than a float's rounding: turning to face it and back
    # again is no motion, and took a second and more
    made = plan_through([goal], ROBOT, shape=shape, min_radius=radius)
    assert made.segments == ()


def test_turns_that_a_sliver_parts_are_joined_into_one() -> None:
    # a quarter turn off the start: the heading change alone, in one spin
    made = plan_through([(0.0, 1e-18, math.pi / 2)], ROBOT)
    assert [s.segment for s in made.segments] == [Spin(math.pi / 2)]


def test_slivers_are_measured_in_metres_and_radians_and_joined_neighbours_cancel() -> None:
    from diffbot.goals import _joined
    from diffbot.planning import ROUNDING, Piece

    # a straight is measured in metres (its length times the unit), a turn in radians
    assert _joined([Piece("S", 1e-14)], 0.05) == []  # 5e-16 m
    assert _joined([Piece("S", 1e-14)], 1.0) == [Piece("S", 1e-14)]
    assert _joined([Piece("T", 2e-15)], 0.1) == [Piece("T", 2e-15)]  # 2e-15 rad, kept
    assert _joined([Piece("T", 6e-16)], 0.1) == []
    # up to the rounding itself, inclusive
    assert _joined([Piece("S", ROUNDING)], 1.0) == []
    assert _joined([Piece("L", ROUNDING)], 1.0) == []
    # neighbours joined: to nothing within the rounding, in metres for straights
    parted = [Piece("S", 4e-15), Piece("T", 1e-300), Piece("S", -3 * 1e-15)]
    assert parted[0].length + parted[2].length == ROUNDING
    assert _joined(parted, 1.0) == []
    # 3e-15 m forward and 2.5e-15 m back, in units of 0.01 m: 5e-16 m in all
    there_and_back = [Piece("S", 3e-13), Piece("T", 0.0), Piece("S", -2.5e-13)]
    assert _joined(there_and_back, 0.01) == []
    assert _joined(there_and_back, 1.0) == [Piece("S", 3e-13 - 2.5e-13)]
    # a turn and the turn back cancel, and what follows is kept
    back = [Piece("T", 0.5), Piece("S", 1e-17), Piece("T", -0.5), Piece("S", 1.0)]
    assert _joined(back, 1.0) == [Piece("S", 1.0)]


def test_waypoints_as_a_numpy_array_plan_as_the_same_list() -> None:
    """A NumPy array of rows was an ambiguous-truth ValueError."""
    rows = [[0.5, 0.0, 0.0], [0.5, 0.5, math.pi / 2]]
    assert plan_through(np.array(rows), ROBOT) == plan_through(rows, ROBOT)


@pytest.mark.parametrize(
    ("call", "said"),
    [
        (lambda: plan_to(None, ROBOT), "the goal must be x, y and a heading, got None"),
        (lambda: plan_to((1.0, 0.0, 0.0), ROBOT, start=3.0), "the start must be x, y and a"),
        (lambda: plan_through(None, ROBOT), "waypoints must be a sequence of (x, y[, heading])"),
        (lambda: plan_through([None], ROBOT), "waypoint 1 must be x, y and an optional heading"),
    ],
)
def test_a_pose_or_waypoint_that_is_no_sequence_is_a_plan_error(
    call: Callable[[], object], said: str
) -> None:
    """None or a number where a pose is due was a bare TypeError (no len())."""
    with pytest.raises(PlanError) as caught:
        call()
    assert str(caught.value).startswith(said)
