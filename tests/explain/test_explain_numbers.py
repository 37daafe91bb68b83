"""Every number a rendered derivation shows is the library's own, at its printed precision.

The numbers are read back out of the rendered text (both formats, both languages) and compared
with values computed here from diffbot.kinematics, diffbot.trajectory and diffbot.odometry.
"""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st
from linear_time import assert_linear
from rendered import assert_numbers, degrees, equations, notes
from robots import BOT_50_RPM

from diffbot.explain import (
    Derivation,
    Step,
    explain_fk,
    explain_ik,
    explain_odom,
    explain_plan,
    render,
)
from diffbot.formats.text import ceil_text
from diffbot.kinematics import (
    DiffDriveParams,
    Pose,
    WheelSpeeds,
    forward,
    inverse,
    limit_fraction,
    rpm_from_rad_s,
)
from diffbot.odometry import Odometry
from diffbot.trajectory import Arc, Plan, Segment, Spin, Straight, plan

#: The numbers substituted into a step's formula, those of its result, and which of the latter
#: are angles (compared wrap-aware).
Expected = tuple[list[float], list[float], frozenset[int]]

FORMATS = st.sampled_from(["text", "md"])
LANGS = st.sampled_from(["en", "es"])


def _value(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


#: Robots with one wheel radius or (some of them) one per side.
ROBOTS = st.builds(
    DiffDriveParams,
    wheel_radius=_value(0.01, 0.5),
    wheel_separation=_value(0.05, 1.5),
    max_wheel_speed=st.one_of(st.none(), _value(0.5, 50.0)),
    left_wheel_radius=st.one_of(st.none(), st.none(), _value(0.01, 0.5)),
    right_wheel_radius=st.one_of(st.none(), st.none(), _value(0.01, 0.5)),
)
SEGMENTS: st.SearchStrategy[Segment] = st.one_of(
    st.builds(
        Straight,
        _value(0.01, 5.0) | _value(-5.0, -0.01),
        st.one_of(st.none(), _value(0.5, 30.0)),
    ),
    st.builds(
        Arc,
        _value(0.01, 3.0),
        _value(0.05, 6.0),
        st.sampled_from(["ccw", "cw"]),
        st.one_of(st.none(), _value(0.5, 30.0)),
        reverse=st.booleans(),
    ),
    st.builds(Spin, _value(-6.0, 6.0).filter(lambda a: a != 0.0), _value(0.5, 30.0)),
)


def _robot_values(params: DiffDriveParams, step: Step) -> list[float] | None:
    """The exact numbers of a given robot value, or None for other steps."""
    if step.formula is not None:
        return None
    if step.symbol in ("r", "rL"):
        return [params.radii[0]]
    if step.symbol == "rR":
        return [params.radii[1]]
    if step.symbol == "b":
        return [params.wheel_separation]
    if step.symbol == "wmax":
        assert params.max_wheel_speed is not None
        return [params.max_wheel_speed, rpm_from_rad_s(params.max_wheel_speed)]
    return None


def _wheels(
    params: DiffDriveParams, v: float, w: float, step: Step, limit: float | None
) -> tuple[list[float], list[float]] | None:
    """Substituted and result numbers of the wheel and limit steps, or None for other steps."""
    left, right = (float(s) for s in inverse(params, v, w))
    (r_left, r_right), b = params.radii, params.wheel_separation
    # one radius r for both wheels (ik_left), or each side's (ik_left_sides)
    assert (step.formula in ("ik_left", "ik_right")) <= (r_left == r_right)
    if step.formula in ("ik_left", "ik_left_sides"):
        return [v, w, b, 2, r_left], [left, rpm_from_rad_s(left)]
    if step.formula in ("ik_right", "ik_right_sides"):
        return [v, w, b, 2, r_right], [right, rpm_from_rad_s(right)]
    if step.formula == "limit":
        assert limit is not None
        share = limit_fraction(params, inverse(params, v, w), limit)
        assert share is not None
        return [left, right, limit], [float(share), 100 * float(share)]
    return None


def _check_notes(rendered: str, fmt: str, expected: list[list[float]]) -> None:
    found = notes(rendered, fmt)
    assert len(found) == len(expected)
    for printed, exact in zip(found, expected, strict=True):
        assert_numbers(printed, exact, "limit check")


def _check(
    derivation: Derivation,
    rendered: str,
    fmt: str,
    expect: list[Expected],
) -> None:
    lines = equations(rendered, fmt)
    assert len(lines) == len(derivation.steps) == len(expect)
    for line, (substituted, result, angles) in zip(lines, expect, strict=True):
        assert_numbers(line.substituted, substituted, line.line)
        assert_numbers(line.result, result, line.line, angles=angles)


NONE: frozenset[int] = frozenset()
FIRST: frozenset[int] = frozenset({0})


@settings(max_examples=60, deadline=None)
@given(ROBOTS, _value(-2.0, 2.0), _value(-6.0, 6.0), FORMATS, LANGS)
def test_ik_shows_the_wheel_speeds_inverse_computes(
    params: DiffDriveParams, v: float, w: float, fmt: str, lang: str
) -> None:
    derivation = explain_ik(params, v, w)
    rendered = render(derivation, fmt, lang)
    expect: list[Expected] = []
    for step in derivation.steps:
        given_robot = _robot_values(params, step)
        wheels = _wheels(params, v, w, step, params.max_wheel_speed)
        if given_robot is not None:
            expect.append(([], given_robot, NONE))
        elif wheels is not None:
            expect.append((*wheels, NONE))
        else:
            assert step.symbol in ("v", "w")
            expect.append(([], [v if step.symbol == "v" else w], NONE))
    _check(derivation, rendered, fmt, expect)
    if params.max_wheel_speed is not None:
        peak = max(abs(float(s)) for s in inverse(params, v, w))
        limit = params.max_wheel_speed
        _check_notes(rendered, fmt, [[rpm_from_rad_s(peak), rpm_from_rad_s(limit)]])


@settings(max_examples=60, deadline=None)
@given(ROBOTS, _value(-60.0, 60.0), _value(-60.0, 60.0), FORMATS, LANGS)
def test_fk_shows_the_body_velocity_forward_computes(
    params: DiffDriveParams, left: float, right: float, fmt: str, lang: str
) -> None:
    derivation = explain_fk(params, left, right)
    rendered = render(derivation, fmt, lang)
    twist = forward(params, left, right)
    (r_left, r_right), b = params.radii, params.wheel_separation
    expect: list[Expected] = []
    for step in derivation.steps:
        given_robot = _robot_values(params, step)
        if given_robot is not None:
            expect.append(([], given_robot, NONE))
        elif step.symbol in ("wL", "wR"):
            speed = left if step.symbol == "wL" else right
            expect.append(([], [speed, rpm_from_rad_s(speed)], NONE))
        elif step.formula == "fk_linear":
            assert r_left == r_right
            expect.append(([r_left, left, right, 2], [float(twist.linear)], NONE))
        elif step.formula == "fk_angular":
            expect.append(([r_left, right, left, b], [float(twist.angular)], NONE))
        elif step.formula == "fk_linear_sides":
            assert r_left != r_right
            expect.append(([r_left, left, r_right, right, 2], [float(twist.linear)], NONE))
        elif step.formula == "fk_angular_sides":
            expect.append(([r_right, right, r_left, left, b], [float(twist.angular)], NONE))
        else:
            assert step.formula == "limit"
            share = limit_fraction(params, WheelSpeeds(left, right))
            assert share is not None
            assert params.max_wheel_speed is not None
            expect.append(
                ([left, right, params.max_wheel_speed], [float(share), 100 * float(share)], NONE)
            )
    _check(derivation, rendered, fmt, expect)


def _geometry(segment: Segment) -> tuple[float, float, float]:
    """Path length s (m, negative backwards), heading change (rad) and radius signed as v/ω (m,
    0 if not an arc)."""
    if isinstance(segment, Straight):
        return segment.length, 0.0, 0.0
    if isinstance(segment, Arc):
        turn = (1.0 if segment.direction == "ccw" else -1.0) * segment.angle
        forward = -1.0 if segment.reverse else 1.0
        return (
            forward * segment.radius * segment.angle,
            turn,
            forward * segment.radius * (1.0 if turn > 0.0 else -1.0),
        )
    return 0.0, segment.angle, 0.0


def _plan_expectations(p: Plan, derivation: Derivation) -> list[Expected]:
    params = p.params
    limited = params.replace(max_wheel_speed=p.limit)
    expect: list[Expected] = [
        ([], _robot_values(limited, step) or [], NONE) for step in derivation.sections[0].steps
    ]
    for planned, section in zip(p.segments, derivation.sections[1:], strict=True):
        s, turn, radius = _geometry(planned.segment)
        v, w, t = float(planned.twist.linear), float(planned.twist.angular), planned.duration
        start, end = planned.start_pose, planned.end_pose
        for step in section.steps:
            wheels = _wheels(params, v, w, step, p.limit)
            key = (step.symbol, step.formula)
            if wheels is not None:
                expect.append((*wheels, NONE))
            elif key == ("R", None):
                expect.append(([], [radius], NONE))
            elif key == ("dtheta", None):
                expect.append(([], [turn, degrees(turn)], NONE))
            elif key == ("s", None):
                expect.append(([], [s], NONE))
            elif key == ("s", "arc_length"):
                expect.append(([radius, turn], [s], NONE))
            elif key == ("t", None):
                expect.append(([], [t], NONE))
            elif key == ("v", "speed"):
                expect.append(([s, t], [v], NONE))
            elif key == ("w", "turn_rate"):
                expect.append(([turn, t], [w], NONE))
            elif key == ("v", "arc_speed"):
                expect.append(([w, radius], [v], NONE))
            elif key == ("x1", "pose_x"):
                expect.append(([start.x, s, turn, 2, start.theta, turn, 2], [end.x], NONE))
            elif key == ("y1", "pose_y"):
                expect.append(([start.y, s, turn, 2, start.theta, turn, 2], [end.y], NONE))
            else:
                assert key == ("th1", "pose_theta"), key
                expect.append(([start.theta, turn], [end.theta, degrees(end.theta)], FIRST))
    return expect


@settings(max_examples=40, deadline=None)
@given(ROBOTS, st.lists(SEGMENTS, min_size=1, max_size=4), FORMATS, LANGS)
def test_plan_shows_the_planned_velocities_wheels_and_poses(
    params: DiffDriveParams, segments: list[Segment], fmt: str, lang: str
) -> None:
    p = plan(segments, params)
    derivation = explain_plan(p)
    rendered = render(derivation, fmt, lang)
    _check(derivation, rendered, fmt, _plan_expectations(p, derivation))
    if p.limit is not None:
        shortest = {found.index: found.shortest_duration for found in p.violations()}
        expected_notes = []
        for planned in p.segments:
            peak = max(abs(float(s)) for s in planned.wheels)
            numbers = [rpm_from_rad_s(peak), rpm_from_rad_s(p.limit)]
            if planned.index in shortest:
                # rounded up to the digits shown, so that the duration printed still fits
                fits = float(ceil_text(shortest[planned.index], 4))
                assert fits >= shortest[planned.index]
                numbers.append(fits)
            expected_notes.append(numbers)
        _check_notes(rendered, fmt, expected_notes)


@settings(max_examples=60, deadline=None)
@given(
    ROBOTS,
    st.lists(_value(-50.0, 50.0), min_size=4, max_size=4),
    _value(1e-3, 2.0),
    st.builds(Pose, _value(-10.0, 10.0), _value(-10.0, 10.0), _value(-math.pi, math.pi)),
    FORMATS,
    LANGS,
)
def test_odom_shows_the_step_the_odometry_class_integrates(
    params: DiffDriveParams, angles: list[float], dt: float, start: Pose, fmt: str, lang: str
) -> None:
    l0, r0, l1, r1 = angles
    derivation = explain_odom(params, l0, r0, l1, r1, dt, start=start)
    rendered = render(derivation, fmt, lang)
    odom = Odometry(params, start.x, start.y, start.theta)
    odom.update(l0, r0, stamp=0.0)
    odom.update(l1, r1, stamp=dt)
    (r_left, r_right), b = params.radii, params.wheel_separation
    d_left, d_right = r_left * (l1 - l0), r_right * (r1 - r0)
    ds, dth = (d_left + d_right) / 2, (d_right - d_left) / b
    chord = ds * (math.sin(dth / 2) / (dth / 2) if dth != 0 else 1.0)
    pose, twist = odom.pose, odom.twist
    by_symbol: dict[str, Expected] = {
        "r": ([], [r_left], NONE),
        "rL": ([], [r_left], NONE),
        "rR": ([], [r_right], NONE),
        "b": ([], [b], NONE),
        "phiL0": ([], [l0], NONE),
        "phiL1": ([], [l1], NONE),
        "phiR0": ([], [r0], NONE),
        "phiR1": ([], [r1], NONE),
        "dt": ([], [dt], NONE),
        "x0": ([], [start.x], NONE),
        "y0": ([], [start.y], NONE),
        "th0": ([], [start.theta, degrees(start.theta)], FIRST),
        "dL": ([r_left, l1, l0], [d_left], NONE),
        "dR": ([r_right, r1, r0], [d_right], NONE),
        "ds": ([d_left, d_right, 2], [ds], NONE),
        "dth": ([d_right, d_left, b], [dth, degrees(dth)], NONE),
        "c": ([ds, dth, 2], [chord], NONE),
        "x1": ([start.x, chord, start.theta, dth, 2], [pose.x], NONE),
        "y1": ([start.y, chord, start.theta, dth, 2], [pose.y], NONE),
        "th1": ([start.theta, dth], [pose.theta, degrees(pose.theta)], FIRST),
        "v": ([ds, dt], [float(twist.linear)], NONE),
        "w": ([dth, dt], [float(twist.angular)], NONE),
    }
    _check(derivation, rendered, fmt, [by_symbol[step.symbol] for step in derivation.steps])


def test_a_long_plan_is_explained_in_linear_time() -> None:
    # each straight over the limit: its section names the shortest duration that keeps it
    def read(data: bytes) -> object:
        return explain_plan(plan([Straight(1.0, 0.1)] * data.count(b";"), BOT_50_RPM))

    print(assert_linear(read, lambda n: b"straight 1 0.1;" * n, 250, accepts=True))
