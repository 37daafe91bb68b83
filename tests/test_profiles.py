"""Speed profiles: known durations, the laws they obey, ruckig's answers, path bounds."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
from extras import need
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from robots import BOT

from diffbot.errors import PlanError
from diffbot.profiles import (
    Limits,
    PathLimits,
    Profile,
    ProfileError,
    path_limits,
    scurve,
    segment_limits,
    time_optimal,
    trapezoid,
)
from diffbot.trajectory import Arc, Spin, Straight

REL = 1e-12
EPS = float(np.finfo(np.float64).eps)

lengths = st.floats(1e-4, 100.0)
speeds = st.floats(1e-2, 10.0)
accels = st.floats(1e-2, 50.0)
jerks = st.floats(1e-1, 500.0)


def samples(profile: Profile, count: int = 200) -> np.ndarray:
    """Sample times: a uniform grid plus every phase boundary and both sides of it."""
    grid = np.linspace(0.0, profile.duration, count)
    edges = np.array([p.start for p in profile.phases] + [profile.duration])
    tiny = 1e-9 * max(profile.duration, 1.0)
    return np.sort(np.concatenate([grid, edges, edges - tiny, edges + tiny]))


def assert_within(profile: Profile, v_max: float, a_max: float, j_max: float | None) -> None:
    """Velocity, acceleration and jerk never exceed their limits (float slack 1e-9 relative)."""
    t = samples(profile)
    v = profile.velocity(t)
    a = profile.acceleration(t)
    assert v.min() >= -1e-9 * v_max
    assert v.max() <= v_max * (1 + 1e-9)
    assert np.abs(a).max() <= a_max * (1 + 1e-9)
    if j_max is not None:
        assert max(abs(p.jerk) for p in profile.phases) <= j_max * (1 + 1e-12)


def test_trapezoid_that_reaches_cruise_takes_length_over_speed_plus_speed_over_accel() -> None:
    profile = trapezoid(1.0, 0.5, 1.0)
    assert profile.duration == pytest.approx(1.0 / 0.5 + 0.5 / 1.0, rel=1e-15)
    assert [p.acceleration for p in profile.phases] == [1.0, 0.0, -1.0]


def test_trapezoid_too_short_to_cruise_takes_twice_root_of_length_over_accel() -> None:
    profile = trapezoid(0.1, 0.5, 1.0)
    assert profile.duration == pytest.approx(2.0 * math.sqrt(0.1 / 1.0), rel=1e-15)
    assert profile.velocity(profile.duration / 2) == pytest.approx(math.sqrt(0.1), rel=1e-15)
    assert len(profile.phases) == 2


def test_trapezoid_at_the_cruise_threshold_has_no_cruise_and_both_formulas_agree() -> None:
    profile = trapezoid(0.25, 0.5, 1.0)
    assert len(profile.phases) == 2
    assert profile.duration == pytest.approx(0.25 / 0.5 + 0.5 / 1.0, rel=1e-15)
    assert profile.duration == pytest.approx(2.0 * math.sqrt(0.25), rel=1e-15)


def test_trapezoid_between_boundary_speeds_starts_and_ends_at_them() -> None:
    profile = trapezoid(2.0, 1.0, 0.5, v_start=0.4, v_end=0.2)
    assert profile.velocity(0.0) == pytest.approx(0.4, abs=1e-15)
    assert profile.velocity(profile.duration) == pytest.approx(0.2, abs=1e-14)
    # (1 - 0.4)/0.5 up, (1 - 0.2)/0.5 down, the rest at 1 m/s: 2 - (0.84 + 0.96)/1 m.
    assert profile.duration == pytest.approx(1.2 + 1.6 + (2.0 - 0.84 - 0.96), rel=1e-14)


def test_trapezoid_without_acceleration_limit_holds_the_speed_throughout() -> None:
    profile = trapezoid(3.0, 1.5, None)
    assert profile.duration == pytest.approx(2.0, rel=1e-15)
    assert profile.velocity(np.array([0.0, 1.0, 2.0])).tolist() == [1.5, 1.5, 1.5]


def test_scurve_reaching_every_limit_has_seven_phases_and_the_hand_computed_duration() -> None:
    # Ramp: tj = a/j = 0.25 s, ta = v/a - a/j = 0.25 s, 0.1875 m; cruise 0.625 m at 0.5 m/s.
    profile = scurve(1.0, 0.5, 1.0, 4.0)
    assert len(profile.phases) == 7
    assert profile.duration == pytest.approx(2.75, rel=1e-15)
    assert [p.jerk for p in profile.phases] == [4.0, 0.0, -4.0, 0.0, -4.0, 0.0, 4.0]


def test_scurve_that_never_reaches_the_acceleration_limit_has_no_constant_acceleration() -> None:
    # v_max = 0.1 < a²/j = 0.25: tj = sqrt(v/j), duration 2·tj + L/v.
    profile = scurve(1.0, 0.1, 1.0, 4.0)
    assert [p.jerk for p in profile.phases] == [4.0, -4.0, 0.0, -4.0, 4.0]
    assert profile.duration == pytest.approx(2 * math.sqrt(0.1 / 4.0) + 1.0 / 0.1, rel=1e-14)
    assert np.abs(profile.acceleration(samples(profile))).max() < 1.0


def test_scurve_that_never_reaches_the_speed_limit_has_no_cruise() -> None:
    # L = 0.2 >= 2a³/j² = 0.125: peak speed solves v² + (a²/j)·v = a·L.
    profile = scurve(0.2, 0.5, 1.0, 4.0)
    peak = (math.sqrt(0.25**2 + 4 * 0.2) - 0.25) / 2
    assert [p.jerk for p in profile.phases] == [4.0, 0.0, -4.0, -4.0, 0.0, 4.0]
    assert profile.velocity(profile.duration / 2) == pytest.approx(peak, rel=1e-14)
    assert profile.duration == pytest.approx(2 * (peak / 1.0 + 1.0 / 4.0), rel=1e-14)


def test_scurve_that_reaches_neither_speed_nor_acceleration_is_four_jerk_phases() -> None:
    # L = 0.1 < 2a³/j² = 0.125: tj = (L/(2j))^(1/3), duration 4·tj.
    profile = scurve(0.1, 0.5, 1.0, 4.0)
    assert [p.jerk for p in profile.phases] == [4.0, -4.0, -4.0, 4.0]
    assert profile.duration == pytest.approx(4 * (0.1 / 8.0) ** (1 / 3), rel=1e-14)
    assert profile.position(profile.duration) == pytest.approx(0.1, rel=REL)


def test_scurve_exactly_at_both_thresholds_drops_the_vanishing_phases() -> None:
    # v_max = a²/j: no constant acceleration; L = 2·ramp (v·tj each way): no cruise.
    profile = scurve(2 * 0.25 * 0.5 / 2, 0.25, 1.0, 4.0)
    assert [p.jerk for p in profile.phases] == [4.0, -4.0, -4.0, 4.0]
    assert profile.duration == pytest.approx(4 * 0.25, rel=1e-15)


def test_scurve_without_acceleration_limit_is_limited_by_jerk_alone() -> None:
    profile = scurve(0.1, 10.0, None, 4.0)
    assert profile.duration == pytest.approx(4 * (0.1 / 8.0) ** (1 / 3), rel=1e-14)


def test_zero_length_gives_an_empty_profile_at_rest() -> None:
    for profile in (trapezoid(0.0, 1.0, 1.0), scurve(0.0, 1.0, 1.0, 1.0)):
        assert profile.duration == 0.0
        assert profile.position(1.0) == 0.0
        assert profile.velocity(np.array([0.0, 1.0])).tolist() == [0.0, 0.0]


def test_profile_functions_accept_arrays_and_match_scalars() -> None:
    profile = scurve(1.0, 0.5, 1.0, 4.0)
    t = np.linspace(-1.0, 4.0, 23)
    for fn in (profile.position, profile.velocity, profile.acceleration):
        values = fn(t)
        assert values.shape == t.shape
        np.testing.assert_allclose(values, [fn(float(x)) for x in t], rtol=0, atol=0)


def test_profile_is_clamped_outside_its_duration() -> None:
    profile = trapezoid(1.0, 0.5, 1.0)
    assert profile.position(-5.0) == 0.0
    assert profile.velocity(-5.0) == 0.0
    assert profile.position(99.0) == pytest.approx(1.0, rel=REL)
    assert profile.velocity(99.0) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: trapezoid(-1.0, 1.0, 1.0), "length must be a finite number >= 0"),
        (lambda: trapezoid(math.inf, 1.0, 1.0), "length must be a finite number >= 0"),
        (lambda: trapezoid(1.0, 0.0, 1.0), "v_max must be positive"),
        (lambda: trapezoid(1.0, 1.0, 0.0), "a_max must be positive"),
        (lambda: trapezoid(1.0, math.nan, 1.0), "v_max must be a number"),
        (lambda: trapezoid(1.0, 1.0, 1.0, v_start=2.0), r"v_start must be within \[0, v_max"),
        (lambda: trapezoid(0.1, 1.0, 1.0, v_end=1.0), "too short to go from v_start"),
        (lambda: scurve(1.0, 1.0, 1.0, 0.0), "j_max must be positive"),
        (lambda: scurve(1.0, math.inf, 1.0, 1.0), "v_max must be finite"),
        (lambda: time_optimal(1.0, PathLimits(None, 1.0, None)), "path speed is unbounded"),
        (
            lambda: Limits(wheel=PathLimits(acceleration=0.0)),
            r"wheel\.acceleration must be positive",
        ),
        (lambda: path_limits(BOT, Limits(), math.inf), "curvature must be finite"),
        (lambda: path_limits(BOT, Limits(), 1.0, left_wheel_radius=0.0), "left_wheel_radius"),
    ],
)
def test_bad_profile_input_raises_a_plan_error_naming_the_parameter(
    call: object, message: str
) -> None:
    with pytest.raises(ProfileError, match=message):
        call()  # type: ignore[operator]
    assert issubclass(ProfileError, PlanError)


@settings(max_examples=60, deadline=None)
@given(lengths, speeds, accels, st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_trapezoid_travels_the_length_within_its_limits(
    length: float, v_max: float, a_max: float, start: float, end: float
) -> None:
    v_start, v_end = start * v_max, end * v_max
    assume(length >= abs(v_end**2 - v_start**2) / (2 * a_max))
    profile = trapezoid(length, v_max, a_max, v_start=v_start, v_end=v_end)
    assert profile.position(profile.duration) == pytest.approx(length, rel=REL, abs=1e-15)
    # Times carry ~eps·duration rounding, which the slope a_max turns into speed.
    slack = 1e-9 * v_max + 4 * EPS * profile.duration * a_max
    assert profile.velocity(profile.duration) == pytest.approx(v_end, abs=slack)
    assert_within(profile, v_max, a_max, None)


@settings(max_examples=60, deadline=None)
@given(lengths, speeds, accels, jerks)
def test_scurve_travels_the_length_within_its_limits(
    length: float, v_max: float, a_max: float, j_max: float
) -> None:
    profile = scurve(length, v_max, a_max, j_max)
    assert profile.position(profile.duration) == pytest.approx(length, rel=REL)
    slack = 4 * EPS * profile.duration
    assert profile.velocity(profile.duration) == pytest.approx(0.0, abs=slack * a_max)
    assert profile.acceleration(profile.duration) == pytest.approx(0.0, abs=slack * j_max)
    assert_within(profile, v_max, a_max, j_max)


@settings(max_examples=50, deadline=None)
@given(lengths, speeds, accels, jerks)
def test_scurve_position_velocity_and_acceleration_are_continuous(
    length: float, v_max: float, a_max: float, j_max: float
) -> None:
    profile = scurve(length, v_max, a_max, j_max)
    for before, after in zip(profile.phases, profile.phases[1:], strict=False):
        tau = before.duration
        assert before.position + tau * (
            before.velocity + tau * (before.acceleration / 2 + tau * before.jerk / 6)
        ) == pytest.approx(after.position, rel=1e-12, abs=1e-12 * length)
        assert before.velocity + tau * (before.acceleration + tau * before.jerk / 2) == (
            pytest.approx(after.velocity, rel=1e-12, abs=1e-12 * v_max)
        )
        assert before.acceleration + tau * before.jerk == pytest.approx(
            after.acceleration, rel=1e-9, abs=1e-9 * a_max
        )


@settings(max_examples=50, deadline=None)
@given(lengths, speeds, accels, st.one_of(st.none(), jerks), st.floats(0.001, 0.999))
def test_rest_to_rest_profiles_are_symmetric_under_time_reversal(
    length: float, v_max: float, a_max: float, j_max: float | None, fraction: float
) -> None:
    profile = time_optimal(length, PathLimits(v_max, a_max, j_max))
    t = fraction * profile.duration
    mirror = profile.duration - t
    assert profile.position(mirror) == pytest.approx(
        length - profile.position(t), rel=1e-9, abs=1e-12 * length
    )
    slack = 4 * EPS * profile.duration
    assert profile.velocity(mirror) == pytest.approx(
        profile.velocity(t), abs=1e-9 * v_max + slack * a_max
    )
    if j_max is not None:
        assert profile.acceleration(mirror) == pytest.approx(
            -profile.acceleration(t), abs=1e-9 * a_max + slack * j_max
        )


@settings(max_examples=50, deadline=None)
@given(lengths, speeds, accels, st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_trapezoid_reversed_in_time_is_the_trapezoid_with_swapped_boundary_speeds(
    length: float, v_max: float, a_max: float, start: float, end: float, fraction: float
) -> None:
    v_start, v_end = start * v_max, end * v_max
    assume(length >= abs(v_end**2 - v_start**2) / (2 * a_max))
    forward = trapezoid(length, v_max, a_max, v_start=v_start, v_end=v_end)
    backward = trapezoid(length, v_max, a_max, v_start=v_end, v_end=v_start)
    assert backward.duration == pytest.approx(forward.duration, rel=1e-12)
    t = fraction * forward.duration
    slack = 1e-9 * v_max + 4 * EPS * forward.duration * a_max
    assert backward.velocity(forward.duration - t) == pytest.approx(forward.velocity(t), abs=slack)


@settings(max_examples=50, deadline=None)
@given(lengths, speeds, accels, st.one_of(st.none(), jerks))
def test_time_optimal_profile_touches_a_limit(
    length: float, v_max: float, a_max: float, j_max: float | None
) -> None:
    profile = time_optimal(length, PathLimits(v_max, a_max, j_max))
    t = samples(profile)
    touches_speed = profile.velocity(t).max() >= v_max * (1 - 1e-12)
    touches_accel = np.abs(profile.acceleration(t)).max() >= a_max * (1 - 1e-12)
    touches_jerk = j_max is not None and any(abs(p.jerk) == j_max for p in profile.phases)
    assert touches_speed or touches_accel or touches_jerk


@settings(max_examples=50, deadline=None)
@given(lengths, speeds, accels, jerks)
def test_jerk_limit_only_lengthens_a_profile(
    length: float, v_max: float, a_max: float, j_max: float
) -> None:
    smooth = scurve(length, v_max, a_max, j_max)
    sharp = trapezoid(length, v_max, a_max)
    assert smooth.duration >= sharp.duration * (1 - 1e-12)
    assert sharp.duration >= length / v_max * (1 - 1e-12)
    # The difference is bounded by one jerk ramp each way: at most 2·a/j seconds... or less.
    assert smooth.duration <= sharp.duration + 2 * a_max / j_max + 1e-9 * sharp.duration


def ruckig_profile(length: float, v_max: float, a_max: float, j_max: float) -> object:
    ruckig = need("ruckig")
    otg = ruckig.Ruckig(1)
    inp = ruckig.InputParameter(1)
    inp.current_position = [0.0]
    inp.target_position = [length]
    inp.max_velocity = [v_max]
    inp.max_acceleration = [a_max]
    inp.max_jerk = [j_max]
    trajectory = ruckig.Trajectory(1)
    result = otg.calculate(inp, trajectory)
    assert result in (ruckig.Result.Working, ruckig.Result.Finished)
    return trajectory


@pytest.mark.parametrize(
    ("length", "v_max", "a_max", "j_max"),
    [
        (1.0, 0.5, 1.0, 4.0),  # every limit reached
        (1.0, 0.1, 1.0, 4.0),  # acceleration never reached
        (0.2, 0.5, 1.0, 4.0),  # speed never reached
        (0.1, 0.5, 1.0, 4.0),  # neither
        (0.125, 0.25, 1.0, 4.0),  # exactly at both thresholds
        (3.14159, 0.1047, 0.3, 2.0),  # the bundled robot's spin rate, a half turn
    ],
)
def test_scurve_matches_ruckig_in_duration_and_position(
    length: float, v_max: float, a_max: float, j_max: float
) -> None:
    trajectory = ruckig_profile(length, v_max, a_max, j_max)
    profile = scurve(length, v_max, a_max, j_max)
    assert profile.duration == pytest.approx(trajectory.duration, rel=1e-9)  # type: ignore[attr-defined]
    for t in np.linspace(0.0, profile.duration, 41):
        position, velocity, _ = trajectory.at_time(float(t))  # type: ignore[attr-defined]
        assert profile.position(float(t)) == pytest.approx(position[0], rel=1e-9, abs=1e-9)
        assert profile.velocity(float(t)) == pytest.approx(velocity[0], rel=1e-9, abs=1e-9)


@settings(max_examples=40, deadline=None)
@given(lengths, speeds, accels, jerks)
def test_scurve_duration_equals_ruckigs_for_any_limits(
    length: float, v_max: float, a_max: float, j_max: float
) -> None:
    trajectory = ruckig_profile(length, v_max, a_max, j_max)
    profile = scurve(length, v_max, a_max, j_max)
    assert profile.duration == pytest.approx(trajectory.duration, rel=1e-9)  # type: ignore[attr-defined]
    t = profile.duration * 0.37
    position = trajectory.at_time(t)[0][0]  # type: ignore[attr-defined]
    assert profile.position(t) == pytest.approx(position, rel=1e-8, abs=1e-9 * length)


def test_straight_bounds_are_the_tightest_of_linear_and_wheel_limits() -> None:
    limits = Limits(
        linear=PathLimits(velocity=0.5, acceleration=2.0),
        wheel=PathLimits(velocity=5.0, acceleration=10.0),
    )
    bounds = path_limits(BOT, limits, 0.0)
    assert bounds.velocity == pytest.approx(5.0 * 0.035, rel=1e-15)
    assert bounds.acceleration == pytest.approx(10.0 * 0.035, rel=1e-15)
    assert bounds.jerk is None


def test_arc_bounds_follow_the_outer_wheel_and_the_turn_rate() -> None:
    # R = 0.25 m ccw: the right (outer) wheel runs at v·(1 + 0.135/0.5)/r.
    limits = Limits(
        linear=PathLimits(jerk=0.2),
        angular=PathLimits(velocity=0.3, jerk=1.0),
        wheel=PathLimits(velocity=5.23599),
    )
    bounds = path_limits(BOT, limits, 1 / 0.25)
    outer = 5.23599 * 0.035 / (1 + 0.135 / 2 / 0.25)
    assert bounds.velocity == pytest.approx(min(outer, 0.3 * 0.25), rel=1e-15)
    assert bounds.acceleration is None
    assert bounds.jerk == pytest.approx(min(0.2, 1.0 * 0.25), rel=1e-15)


def test_spin_bounds_are_in_heading_space_from_the_wheel_limits() -> None:
    limits = Limits(
        linear=PathLimits(velocity=0.1),
        angular=PathLimits(acceleration=4.0),
        wheel=PathLimits(velocity=5.0, acceleration=20.0),
    )
    bounds = path_limits(BOT, limits, spin=True)
    assert bounds.velocity == pytest.approx(5.0 * 0.035 / (0.135 / 2), rel=1e-15)
    assert bounds.acceleration == pytest.approx(min(4.0, 20.0 * 0.035 / (0.135 / 2)), rel=1e-15)
    assert bounds == path_limits(BOT, limits, 7.0, spin=True)


def test_the_smaller_wheel_sets_the_spin_bound_when_radii_differ() -> None:
    bounds = path_limits(
        BOT,
        Limits(wheel=PathLimits(velocity=5.0)),
        spin=True,
        left_wheel_radius=0.03,
        right_wheel_radius=0.04,
    )
    assert bounds.velocity == pytest.approx(5.0 * 0.03 / (0.135 / 2), rel=1e-15)


@pytest.mark.parametrize("spin", [False, True])
def test_path_limits_take_each_sides_radius_from_the_robot_when_not_given(spin: bool) -> None:
    robot = BOT.replace(left_wheel_radius=0.03, right_wheel_radius=0.04)
    limits = Limits(wheel=PathLimits(velocity=5.0, acceleration=20.0))
    given = path_limits(
        BOT, limits, 2.0, spin=spin, left_wheel_radius=0.03, right_wheel_radius=0.04
    )
    assert path_limits(robot, limits, 2.0, spin=spin) == given
    assert segment_limits(Spin(1.0) if spin else Arc(0.5, 1.0, "ccw"), robot, limits)[1] == given


def test_no_limits_give_unbounded_path_limits() -> None:
    assert path_limits(BOT, Limits(), 2.0) == PathLimits(None, None, None)


def test_segment_bounds_match_their_geometry() -> None:
    limits = Limits(wheel=PathLimits(velocity=5.0, acceleration=10.0))
    assert segment_limits(Straight(1.0), BOT, limits) == (1.0, path_limits(BOT, limits))
    length, bounds = segment_limits(Arc(0.25, math.pi, "cw"), BOT, limits)
    assert length == pytest.approx(0.25 * math.pi, rel=1e-15)
    assert bounds == path_limits(BOT, limits, -4.0)
    assert segment_limits(Spin(-math.pi / 2), BOT, limits) == (
        math.pi / 2,
        path_limits(BOT, limits, spin=True),
    )


@settings(max_examples=30, deadline=None)
@given(st.floats(0.05, 2.0), st.sampled_from(["cw", "ccw"]))
def test_cw_and_ccw_arcs_of_equal_wheels_have_equal_bounds(radius: float, direction: str) -> None:
    limits = Limits(
        angular=PathLimits(velocity=1.0),
        wheel=PathLimits(velocity=5.0, acceleration=10.0, jerk=40.0),
    )
    assert path_limits(BOT, limits, 1 / radius) == path_limits(BOT, limits, -1 / radius)


@settings(max_examples=50, deadline=None)
@given(
    st.floats(-20.0, 20.0),
    st.floats(0.01, 5.0),
    st.one_of(st.none(), st.floats(0.05, 2.0)),
    st.one_of(st.none(), st.floats(0.1, 5.0)),
    st.floats(1.0, 10.0),
    st.one_of(st.none(), st.floats(0.1, 5.0)),
    st.one_of(st.none(), st.floats(1.0, 40.0)),
    st.one_of(st.none(), st.floats(5.0, 400.0)),
    st.booleans(),
)
def test_time_optimal_motion_keeps_every_robot_limit_and_touches_one(
    curvature: float,
    length: float,
    linear_speed: float | None,
    angular_speed: float | None,
    wheel_speed: float,
    linear_accel: float | None,
    wheel_accel: float | None,
    linear_jerk: float | None,
    spin: bool,
) -> None:
    limits = Limits(
        linear=PathLimits(linear_speed, linear_accel, linear_jerk),
        angular=PathLimits(
            angular_speed,
            None if wheel_accel is None else wheel_accel / 3,
            None if linear_jerk is None else linear_jerk * 2,
        ),
        wheel=PathLimits(
            wheel_speed, wheel_accel, None if linear_jerk is None else linear_jerk * 50
        ),
    )
    bounds = path_limits(BOT, limits, curvature, spin=spin)
    profile = time_optimal(length, bounds)
    t = samples(profile)
    s_dot, s_ddot = profile.velocity(t), profile.acceleration(t)
    s_dddot = np.array([p.jerk for p in profile.phases])
    half = BOT.wheel_separation / 2
    if spin:
        linear: tuple[np.ndarray, ...] = (np.zeros_like(t),) * 2 + (np.zeros(len(s_dddot)),)
        angular: tuple[np.ndarray, ...] = (s_dot, s_ddot, s_dddot)
        wheel = tuple(q * half / BOT.wheel_radius for q in angular)
    else:
        linear = (s_dot, s_ddot, s_dddot)
        angular = tuple(curvature * q for q in linear)
        gain = max(abs(1 - curvature * half), abs(1 + curvature * half)) / BOT.wheel_radius
        wheel = tuple(gain * q for q in linear)
    checks = [
        (linear, (linear_speed, linear_accel, linear_jerk)),
        (angular, (angular_speed, limits.angular.acceleration, limits.angular.jerk)),
        (wheel, (wheel_speed, wheel_accel, limits.wheel.jerk)),
    ]
    touched = False
    for quantities, caps in checks:
        for quantity, cap in zip(quantities, caps, strict=True):
            if cap is None:
                continue
            peak = float(np.abs(quantity).max())
            assert peak <= cap * (1 + 1e-9)
            touched = touched or peak >= cap * (1 - 1e-9)
    assert touched


def test_arc_bounds_use_each_wheels_own_radius() -> None:
    # R = 0.5 m cw: the left wheel is outer, (1 + b/(2R)) = 1.135; the right is inner, 0.865.
    limits = Limits(wheel=PathLimits(velocity=5.0, acceleration=20.0))
    bounds = path_limits(BOT, limits, -2.0, left_wheel_radius=0.03, right_wheel_radius=0.04)
    outer, inner = 1 + 0.135 / 2 * 2.0, 1 - 0.135 / 2 * 2.0
    assert bounds.velocity == pytest.approx(min(5.0 * 0.03 / outer, 5.0 * 0.04 / inner), rel=1e-15)
    assert bounds.acceleration == pytest.approx(20.0 * 0.03 / outer, rel=1e-15)


def test_negative_robot_limits_are_refused() -> None:
    with pytest.raises(ProfileError, match=r"linear\.velocity must be positive"):
        Limits(linear=PathLimits(velocity=-1.0))


# --- limits that no plan can keep ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("build", "fragment"),
    [
        (lambda: scurve(1.0, 0.1, None, 1e-300), "jerk limit of 1e-300"),
        (lambda: scurve(1.0, 0.1, 1e-300, 1.0), "acceleration limit of 1e-300"),
        (lambda: trapezoid(1.0, 0.1, 1e-300), "acceleration limit of 1e-300"),
        (lambda: trapezoid(1.0, 1e-12, None), "speed limit of 1e-12"),
        (lambda: scurve(1e9, 1e-3, 1.0, 1.0), "speed limit of 0.001"),
    ],
)
def test_limits_that_take_more_than_a_million_seconds_are_refused_before_any_maths(
    build: Callable[[], Profile], fragment: str
) -> None:
    with pytest.raises(ProfileError, match=f"{fragment}.*more than 1e\\+06 s"):
        build()


def test_a_run_just_within_a_million_seconds_is_planned() -> None:
    # 1e5 m at 0.1 m/s: 1e6 s exactly, the longest accepted.
    assert trapezoid(1e5, 0.1, None).duration == pytest.approx(1e6, rel=1e-12)


@given(st.floats(1e3, 1e300), st.floats(1e-6, 1e3))
def test_an_acceleration_the_speed_limit_never_lets_the_ramp_reach_changes_nothing(
    huge: float, jerk: float
) -> None:
    # Above sqrt(v·j) the acceleration limit never binds: the profile is that of sqrt(v·j),
    # and no power of the huge value may overflow on the way.
    v = 0.1
    reached = math.sqrt(v * jerk)
    assume(huge > reached)
    assert scurve(1.0, v, huge, jerk).duration == pytest.approx(
        scurve(1.0, v, reached, jerk).duration, rel=1e-9
    )
