"""Reverse motion: backward straights and arcs mirror forward ones, in plans and in plan text."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from robots import BOT, BOT_50_RPM

from diffbot.errors import PlanError
from diffbot.kinematics import Pose
from diffbot.planfile import format_plan, parse_plan, segments_from_data
from diffbot.trajectory import Arc, Segment, Straight, plan


def mirrored(pose: Pose) -> Pose:
    """The pose mirrored front to back: x and the heading change sign."""
    return Pose(-pose.x, pose.y, -pose.theta)


def assert_same_pose(actual: Pose, expected: Pose) -> None:
    assert actual.x == pytest.approx(expected.x, abs=1e-12)
    assert actual.y == pytest.approx(expected.y, abs=1e-12)
    turn = math.remainder(actual.theta - expected.theta, 2 * math.pi)
    assert turn == pytest.approx(0.0, abs=1e-12)


radii = st.floats(0.01, 10.0)
angles = st.floats(0.01, 6.0)
durations = st.one_of(st.none(), st.floats(0.1, 100.0))


@settings(max_examples=30, deadline=None)
@given(radii, angles, st.sampled_from(["ccw", "cw"]), durations)
def test_a_reverse_arc_is_the_other_forward_arc_mirrored_with_its_wheels_negated(
    radius: float, angle: float, direction: str, duration: float | None
) -> None:
    other = "cw" if direction == "ccw" else "ccw"
    back = plan([Arc(radius, angle, direction, duration, reverse=True)], BOT)  # type: ignore[arg-type]
    ahead = plan([Arc(radius, angle, other, duration)], BOT)  # type: ignore[arg-type]
    assert_same_pose(back.final_pose, mirrored(ahead.final_pose))
    b, a = back.segments[0], ahead.segments[0]
    assert b.duration == a.duration
    assert (b.wheels.left, b.wheels.right) == (-a.wheels.left, -a.wheels.right)
    # The heading turns the named way whichever way the robot drives.
    assert math.copysign(1.0, b.twist.angular) == (1.0 if direction == "ccw" else -1.0)
    assert b.twist.linear < 0.0


@settings(max_examples=40, deadline=None)
@given(st.floats(0.001, 100.0), durations)
def test_a_backward_straight_mirrors_the_forward_one(length: float, duration: float | None) -> None:
    back = plan([Straight(-length, duration)], BOT)
    ahead = plan([Straight(length, duration)], BOT)
    assert_same_pose(back.final_pose, mirrored(ahead.final_pose))
    assert back.segments[0].twist.linear == -ahead.segments[0].twist.linear
    assert back.duration == ahead.duration


def test_straight_minus_one_drives_one_metre_back_in_ten_seconds() -> None:
    p = plan(parse_plan("straight -1"), BOT_50_RPM)
    assert p.final_pose == Pose(-1.0, 0.0, 0.0)
    assert p.duration == pytest.approx(10.0, rel=1e-15)
    assert p.segments[0].twist.linear == pytest.approx(-0.1, rel=1e-15)


def test_reverse_ccw_quarter_circle_ends_behind_and_to_the_right() -> None:
    # Backwards at 0.25 m radius, heading +90 deg: the centre moves to (-r, -r).
    p = plan(parse_plan("reverse ccw 0.25 90"), BOT)
    assert_same_pose(p.final_pose, Pose(-0.25, -0.25, math.pi / 2))


@pytest.mark.parametrize(
    "text",
    ["straight -1", "reverse ccw 0.25 90 5s", "reverse cw 25cm 1.5rad", "straight -0.5 2s"],
)
def test_reverse_segments_read_back_from_their_text(text: str) -> None:
    segments = parse_plan(text)
    assert parse_plan(format_plan(segments)) == segments


def test_reverse_straight_is_a_negative_straight() -> None:
    assert parse_plan("reverse straight 50cm") == [Straight(-0.5)]


def test_yaml_entries_drive_backwards_with_a_negative_length_or_reverse_true() -> None:
    data = [
        {"straight": -1.0},
        {"arc": "CCW", "radius": 0.25, "angle": 90, "reverse": True},
        {"arc": "cw", "radius": 0.25, "angle": 90, "reverse": False},
    ]
    expected: list[Segment] = [
        Straight(-1.0),
        Arc(0.25, math.pi / 2, "ccw", reverse=True),
        Arc(0.25, math.pi / 2, "cw"),
    ]
    assert segments_from_data(data) == expected


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("reverse spin 90", r"reverse needs an arc or a straight.*negative angle"),
        ("reverse", r"reverse needs an arc or a straight after it, got nothing"),
        ("reverse ccw 0.25 -90", r"angle '-90' must be > 0 \(the direction is in the kind: cw\)"),
        ("ccw -0.25 90", r"radius '-0.25' must be > 0 \(to drive the arc backwards write reverse"),
        ("straight 0", r"length '0' must not be zero"),
    ],
)
def test_reverse_text_errors_point_at_the_token(text: str, message: str) -> None:
    with pytest.raises(PlanError, match=message):
        parse_plan(text)


def test_yaml_reverse_must_be_a_boolean() -> None:
    with pytest.raises(PlanError, match=r"entry 1: reverse 'yes': expected true or false"):
        segments_from_data([{"arc": "ccw", "radius": 1, "angle": 90, "reverse": "yes"}])
