"""Kinematics: laws (hypothesis), the seed's exercise 5 values, singular cases."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from robots import BOT

import diffbot
from diffbot import DiffDriveParams, WheelSpeeds

speeds = st.floats(-50.0, 50.0, allow_nan=False)
radii = st.floats(0.005, 2.0)
separations = st.floats(0.01, 5.0)


@st.composite
def robots(draw: st.DrawFn) -> DiffDriveParams:
    return DiffDriveParams(
        wheel_radius=draw(radii),
        wheel_separation=draw(separations),
        left_sign=draw(st.sampled_from([1, -1])),
        right_sign=draw(st.sampled_from([1, -1])),
        max_wheel_speed=draw(st.one_of(st.none(), st.floats(0.1, 100.0))),
    )


SEED = BOT


# --- known values (the seed's exercise 5) -------------------------------------------------


def test_straight_at_a_tenth_of_a_metre_per_second_turns_each_wheel_at_2_857_rad_s() -> None:
    left, right = diffbot.inverse(SEED, 0.1, 0.0)
    assert left == pytest.approx(2.857142857, abs=1e-9)
    assert right == pytest.approx(2.857142857, abs=1e-9)


def test_clockwise_half_metre_circle_in_20_s_gives_the_seed_wheel_speeds() -> None:
    angular = -2.0 * math.pi / 20.0
    linear = -angular * 0.5
    left, right = diffbot.inverse(SEED, linear, angular)
    # seed: ~5.09 and ~3.88 rad/s (computed there with w rounded to 0.314)
    assert left == pytest.approx(5.09, abs=0.005)
    assert right == pytest.approx(3.88, abs=0.005)
    assert left == pytest.approx((linear - angular * 0.0675) / 0.035, rel=1e-15)


def test_seed_arc_of_quarter_metre_gives_1_637_and_2_848_rad_s() -> None:
    left, right = diffbot.inverse(SEED, 0.0785, 0.314)
    assert left == pytest.approx(1.637, abs=5e-4)
    assert right == pytest.approx(2.848, abs=5e-4)


def test_fifty_rpm_is_5_23599_rad_s() -> None:
    assert diffbot.rad_s_from_rpm(50.0) == pytest.approx(5.23599, abs=1e-5)
    assert diffbot.rpm_from_rad_s(2.857142857) == pytest.approx(27.28, abs=0.01)


# --- laws -----------------------------------------------------------------------------------


@given(robots(), speeds, speeds)
def test_forward_of_inverse_is_the_identity(params: DiffDriveParams, v: float, w: float) -> None:
    left, right = diffbot.inverse(params, v, w)
    twist = diffbot.forward(params, left, right)
    assert twist.linear == pytest.approx(v, rel=1e-12, abs=1e-12)
    assert twist.angular == pytest.approx(w, rel=1e-12, abs=1e-11)


@given(
    robots(),
    arrays(np.float64, 32, elements=speeds),
    arrays(np.float64, 32, elements=speeds),
)
def test_inverse_of_forward_is_the_identity_on_arrays(
    params: DiffDriveParams, left: np.ndarray, right: np.ndarray
) -> None:
    twist = diffbot.forward(params, left, right)
    back = diffbot.inverse(params, twist.linear, twist.angular)
    np.testing.assert_allclose(back.left, left, rtol=1e-12, atol=1e-11)
    np.testing.assert_allclose(back.right, right, rtol=1e-12, atol=1e-11)


@given(robots(), speeds, speeds)
def test_mirroring_the_turn_swaps_the_wheels(params: DiffDriveParams, v: float, w: float) -> None:
    left, right = diffbot.inverse(params, v, w)
    m_left, m_right = diffbot.inverse(params, v, -w)
    assert m_left == pytest.approx(right, rel=1e-12, abs=1e-12)
    assert m_right == pytest.approx(left, rel=1e-12, abs=1e-12)


@given(robots(), speeds, speeds, st.floats(-10.0, 10.0))
def test_wheel_speeds_scale_linearly_with_the_twist(
    params: DiffDriveParams, v: float, w: float, k: float
) -> None:
    left, right = diffbot.inverse(params, v, w)
    k_left, k_right = diffbot.inverse(params, k * v, k * w)
    assert k_left == pytest.approx(k * left, rel=1e-12, abs=1e-9)
    assert k_right == pytest.approx(k * right, rel=1e-12, abs=1e-9)


@given(robots(), speeds, speeds)
def test_joint_commands_apply_and_undo_the_direction_signs(
    params: DiffDriveParams, left: float, right: float
) -> None:
    joints = diffbot.joint_from_wheel(params, WheelSpeeds(left, right))
    assert joints == (params.left_sign * left, params.right_sign * right)
    assert diffbot.wheel_from_joint(params, joints) == (left, right)


@given(robots(), speeds, speeds)
def test_saturation_keeps_the_turning_radius_and_respects_the_limit(
    params: DiffDriveParams, v: float, w: float
) -> None:
    wheels = diffbot.inverse(params, v, w)
    out = diffbot.saturate(params, wheels)
    assert diffbot.within_limit(params, out)
    # one common factor: the ratio of the wheels, hence the curvature, is unchanged
    assert out.left * wheels.right == pytest.approx(out.right * wheels.left, abs=1e-9)
    if params.max_wheel_speed is None or diffbot.within_limit(params, wheels):
        assert out == wheels
    else:
        peak = max(abs(out.left), abs(out.right))
        assert peak == pytest.approx(params.max_wheel_speed, rel=1e-12)


def test_saturation_on_arrays_scales_only_the_samples_over_the_limit() -> None:
    params = SEED.replace(max_wheel_speed=5.0)
    wheels = WheelSpeeds(np.array([1.0, 10.0, -20.0]), np.array([2.0, 5.0, 0.0]))
    out = diffbot.saturate(params, wheels)
    np.testing.assert_allclose(out.left, [1.0, 5.0, -5.0])
    np.testing.assert_allclose(out.right, [2.0, 2.5, 0.0])
    assert diffbot.within_limit(params, out)
    assert not diffbot.within_limit(params, wheels)


# --- singular cases -------------------------------------------------------------------------


def test_zero_angular_velocity_drives_both_wheels_alike() -> None:
    left, right = diffbot.inverse(SEED, -0.3, 0.0)
    assert left == right == pytest.approx(-0.3 / 0.035)


def test_spin_in_place_drives_the_wheels_in_opposite_directions() -> None:
    left, right = diffbot.inverse(SEED, 0.0, 1.0)
    assert left == pytest.approx(-right)
    assert right > 0
    twist = diffbot.forward(SEED, left, right)
    assert twist.linear == pytest.approx(0.0, abs=1e-15)
    assert twist.angular == pytest.approx(1.0, rel=1e-15)


def test_huge_and_tiny_speeds_keep_full_relative_precision() -> None:
    for scale in (1e-300, 1e-12, 1e12, 1e300):
        left, right = diffbot.inverse(SEED, scale, 0.0)
        assert left == pytest.approx(scale / 0.035, rel=1e-15)
        twist = diffbot.forward(SEED, left, right)
        assert twist.linear == pytest.approx(scale, rel=1e-15)


def test_limit_fraction_is_none_without_a_limit_and_the_faster_wheel_over_it() -> None:
    assert diffbot.limit_fraction(SEED, WheelSpeeds(1.0, 2.0)) is None
    limited = SEED.replace(max_wheel_speed=4.0)
    assert diffbot.limit_fraction(limited, WheelSpeeds(-3.0, 2.0)) == pytest.approx(0.75)
    assert diffbot.within_limit(limited, WheelSpeeds(4.0, -4.0))
    assert not diffbot.within_limit(limited, WheelSpeeds(4.0001, 0.0))


def test_a_zero_limit_allows_only_standing_still() -> None:
    stopped = SEED.replace(max_wheel_speed=0.0)
    assert diffbot.within_limit(stopped, WheelSpeeds(0.0, 0.0))
    assert diffbot.limit_fraction(stopped, WheelSpeeds(0.1, 0.0)) == math.inf
    assert diffbot.saturate(stopped, WheelSpeeds(1.0, -2.0)) == (0.0, -0.0)


@pytest.mark.parametrize(
    ("angle", "expected"),
    [
        (0.0, 0.0),
        (math.pi, math.pi),
        (-math.pi, math.pi),
        (3 * math.pi, math.pi),
        (7.0, 7.0 - 2 * math.pi),
    ],
)
def test_norm_angle_maps_into_minus_pi_exclusive_to_pi_inclusive(
    angle: float, expected: float
) -> None:
    assert diffbot.norm_angle(angle) == pytest.approx(expected, abs=1e-12)


@given(st.floats(-1e6, 1e6))
def test_norm_angle_is_in_range_and_equivalent(angle: float) -> None:
    wrapped = diffbot.norm_angle(angle)
    assert -math.pi < wrapped <= math.pi
    assert math.cos(wrapped) == pytest.approx(math.cos(angle), abs=1e-9)
    assert math.sin(wrapped) == pytest.approx(math.sin(angle), abs=1e-9)


# --- parameter validation -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("wheel_radius", 0.0, "wheel_radius must be a finite number >= 0.0001"),
        ("wheel_radius", -0.1, "wheel_radius must be a finite number >= 0.0001"),
        ("wheel_radius", math.nan, "wheel_radius must be a finite number >= 0.0001"),
        ("wheel_separation", math.inf, "wheel_separation must be a finite number >= 0.0001"),
        ("max_wheel_speed", -1.0, "max_wheel_speed must be 0 or a finite number"),
        ("max_wheel_speed", math.nan, "max_wheel_speed must be 0 or a finite number"),
        ("left_sign", 0, "left_sign must be"),
        ("right_joint", "front_left_wheel_joint", "left and right joints are the same"),
    ],
)
def test_params_reject_values_out_of_their_domain(field: str, value: object, match: str) -> None:
    with pytest.raises(diffbot.ParameterError, match=match):
        SEED.replace(**{field: value})


def test_params_are_immutable_and_report_rpm() -> None:
    params = SEED.replace(max_wheel_speed=diffbot.rad_s_from_rpm(50.0))
    assert params.max_wheel_rpm == pytest.approx(50.0, rel=1e-12)
    with pytest.raises(AttributeError, match="cannot assign"):
        params.wheel_radius = 1.0  # type: ignore[misc]


def test_a_nan_wheel_speed_is_never_within_a_limit() -> None:
    limited = SEED.replace(max_wheel_speed=5.0)
    for speeds in (WheelSpeeds(1.0, math.nan), WheelSpeeds(math.nan, 1.0)):
        assert not diffbot.within_limit(limited, speeds)
        assert not diffbot.within_limit(limited, speeds, limit=0.0)
    assert not diffbot.within_limit(limited, WheelSpeeds(np.array([1.0, np.nan]), np.zeros(2)))


def test_a_negative_limit_is_rejected() -> None:
    with pytest.raises(diffbot.ParameterError, match="limit must be a finite number >= 0"):
        diffbot.saturate(SEED, WheelSpeeds(1.0, 2.0), limit=-1.0)


def test_saturating_an_infinite_speed_is_rejected() -> None:
    with pytest.raises(diffbot.ParameterError, match="cannot saturate non-finite"):
        diffbot.saturate(SEED.replace(max_wheel_speed=1.0), WheelSpeeds(math.inf, 1.0))


def test_norm_angle_works_on_arrays_like_on_floats() -> None:
    angles = np.array([-7.0, -math.pi, 0.0, math.pi, 3 * math.pi, 7.0])
    expected = [diffbot.norm_angle(float(a)) for a in angles]
    np.testing.assert_allclose(diffbot.norm_angle(angles), expected, atol=1e-12)


@pytest.mark.parametrize("sign", [1.0, True])
def test_direction_signs_must_be_integers(sign: object) -> None:
    with pytest.raises(diffbot.ParameterError, match="left_sign must be"):
        SEED.replace(left_sign=sign)


def test_a_missing_radius_is_a_parameter_error() -> None:
    with pytest.raises(diffbot.ParameterError, match="wheel_radius must be"):
        DiffDriveParams(None, 0.1)  # type: ignore[arg-type]


#: Sizes and limits no robot has: the odometry of a 1e308 radius was NaN, a 1e-300 separation
#: lost the turn of every command, a 5e-324 limit put every moving wheel infinitely over it.
@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("wheel_radius", 1e308),
        ("wheel_radius", 1e-300),
        ("wheel_radius", 5e-324),
        ("wheel_radius", 10**400),
        ("wheel_radius", "abc"),
        ("wheel_radius", True),
        ("wheel_radius", 1001.0),
        ("wheel_separation", 1e-300),
        ("wheel_separation", 9.9e-5),
        ("wheel_separation", "1e308"),
        ("left_wheel_radius", 1e308),
        ("right_wheel_radius", 1e-5),
        ("max_wheel_speed", 5e-324),
        ("max_wheel_speed", 1e-310),
        ("max_wheel_speed", 1e6),
        ("max_wheel_speed", 10**400),
        ("max_wheel_speed", math.inf),
        ("max_wheel_speed", "fast"),
    ],
)
def test_sizes_and_limits_no_robot_has_are_refused_by_name(field: str, value: object) -> None:
    with pytest.raises(diffbot.ParameterError, match=rf"^{field} must be .*, got "):
        SEED.replace(**{field: value})


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("wheel_radius", 1e-4),
        ("wheel_radius", 1e3),
        ("wheel_separation", 1e-4),
        ("wheel_separation", 1e3),
        ("max_wheel_speed", 0.0),
        ("max_wheel_speed", sys.float_info.min),
        ("max_wheel_speed", 1e4),
    ],
)
def test_the_ends_of_the_ranges_are_robots(field: str, value: float) -> None:
    assert getattr(SEED.replace(**{field: value}), field) == value


def test_numeric_strings_give_the_robot_of_their_numbers() -> None:
    text = DiffDriveParams("0.035", "0.135", max_wheel_speed="5", left_wheel_radius="0.036")  # type: ignore[arg-type]
    number = DiffDriveParams(0.035, 0.135, max_wheel_speed=5.0, left_wheel_radius=0.036)
    assert text == number
    assert diffbot.inverse(text, 0.1, 1.0) == diffbot.inverse(number, 0.1, 1.0)
    assert diffbot.forward(text, 3.0, 2.0) == diffbot.forward(number, 3.0, 2.0)


# --- saturation with body velocity ranges, with and without keeping the turning radius -----

#: The robot of ros2_controllers' test_diff_drive_controller.cpp fixture: b = 1.0 m, r = 0.1 m.
RC_BOT = DiffDriveParams(wheel_radius=0.1, wheel_separation=1.0)
HALF = (-0.5, 0.5)
ranges = st.one_of(st.none(), st.tuples(st.floats(-3.0, 0.0), st.floats(0.0, 3.0)))


def test_clamping_apart_gives_the_controllers_clamped_command() -> None:
    """ros2_controllers test_diff_drive_controller.cpp, test_open_loop_odometry_with_clamped_input:
    linear and angular max_velocity 0.5 turn a command of 5.0 into 0.5 on each axis apart."""
    for (linear, angular), expected in (((5.0, 0.0), (0.5, 0.0)), ((0.0, 5.0), (0.0, 0.5))):
        out = diffbot.saturate(
            RC_BOT,
            diffbot.inverse(RC_BOT, linear, angular),
            preserve_turning_radius=False,
            linear_range=HALF,
            angular_range=HALF,
        )
        twist = diffbot.forward(RC_BOT, out.left, out.right)
        assert twist.linear == pytest.approx(expected[0], abs=1e-12)
        assert twist.angular == pytest.approx(expected[1], abs=1e-12)


def test_clamping_apart_bends_the_path_where_one_factor_keeps_it() -> None:
    # 5 m/s along a 5 m radius (1 rad/s), limits 0.5 each: apart 0.5 and 0.5 (radius 1 m),
    # together both scaled by 0.1 (0.5 m/s, 0.1 rad/s: radius still 5 m).
    wheels = diffbot.inverse(RC_BOT, 5.0, 1.0)
    apart = diffbot.saturate(
        RC_BOT, wheels, preserve_turning_radius=False, linear_range=HALF, angular_range=HALF
    )
    kept = diffbot.saturate(RC_BOT, wheels, linear_range=HALF, angular_range=HALF)
    assert apart.left == pytest.approx(2.5, abs=1e-12)
    assert apart.right == pytest.approx(7.5, abs=1e-12)
    assert kept.left == pytest.approx(4.5, abs=1e-12)
    assert kept.right == pytest.approx(5.5, abs=1e-12)


def test_clamping_apart_clamps_each_wheel_to_the_wheel_limit_on_its_own() -> None:
    limited = SEED.replace(max_wheel_speed=5.0)
    out = diffbot.saturate(limited, WheelSpeeds(10.0, 2.0), preserve_turning_radius=False)
    assert out == (5.0, 2.0)
    assert diffbot.saturate(limited, WheelSpeeds(10.0, 2.0)) == (5.0, 1.0)


@given(robots(), speeds, speeds, ranges, ranges)
def test_one_factor_keeps_the_radius_and_meets_every_limit(
    params: DiffDriveParams,
    v: float,
    w: float,
    linear_range: tuple[float, float] | None,
    angular_range: tuple[float, float] | None,
) -> None:
    wheels = diffbot.inverse(params, v, w)
    out = diffbot.saturate(params, wheels, linear_range=linear_range, angular_range=angular_range)
    assert diffbot.within_limit(params, out)
    # one common factor: the ratio of the wheels, hence the curvature, is unchanged
    ratio = pytest.approx(out.right * wheels.left, rel=1e-12, abs=1e-9)
    assert out.left * wheels.right == ratio
    twist = diffbot.forward(params, out.left, out.right)
    for value, bounds in ((twist.linear, linear_range), (twist.angular, angular_range)):
        if bounds is not None:
            assert bounds[0] - 1e-9 <= value <= bounds[1] + 1e-9


@given(robots(), speeds, speeds, ranges, ranges)
def test_clamping_apart_puts_each_axis_in_its_range_and_each_wheel_in_the_limit(
    params: DiffDriveParams,
    v: float,
    w: float,
    linear_range: tuple[float, float] | None,
    angular_range: tuple[float, float] | None,
) -> None:
    wheels = diffbot.inverse(params, v, w)
    out = diffbot.saturate(
        params,
        wheels,
        preserve_turning_radius=False,
        linear_range=linear_range,
        angular_range=angular_range,
    )
    assert diffbot.within_limit(params, out)
    if params.max_wheel_speed is None:  # no wheel clamp afterwards: each axis is exactly clamped
        twist = diffbot.forward(params, out.left, out.right)
        for value, before, bounds in (
            (twist.linear, v, linear_range),
            (twist.angular, w, angular_range),
        ):
            lo, hi = bounds if bounds is not None else (-math.inf, math.inf)
            assert value == pytest.approx(min(max(before, lo), hi), abs=1e-9)


@given(robots(), st.booleans(), ranges, ranges)
def test_saturating_arrays_equals_saturating_each_sample(
    params: DiffDriveParams,
    preserve: bool,
    linear_range: tuple[float, float] | None,
    angular_range: tuple[float, float] | None,
) -> None:
    left = np.array([0.0, 3.0, -40.0, 25.0, 7.5])
    right = np.array([0.0, -3.0, 10.0, 30.0, 7.5])
    options = {
        "preserve_turning_radius": preserve,
        "linear_range": linear_range,
        "angular_range": angular_range,
    }
    out = diffbot.saturate(params, WheelSpeeds(left, right), **options)  # type: ignore[arg-type]
    for k in range(left.size):
        one = diffbot.saturate(params, WheelSpeeds(float(left[k]), float(right[k])), **options)  # type: ignore[arg-type]
        assert out.left[k] == pytest.approx(one.left, abs=1e-12)
        assert out.right[k] == pytest.approx(one.right, abs=1e-12)


def test_saturating_arrays_apart_leaves_non_finite_samples_nan() -> None:
    out = diffbot.saturate(
        RC_BOT,
        WheelSpeeds(np.array([1.0, np.inf]), np.array([1.0, 0.0])),
        preserve_turning_radius=False,
        linear_range=HALF,
    )
    assert out.left[0] == pytest.approx(1.0, abs=1e-12)
    assert np.isnan(out.left[1])
    assert np.isnan(out.right[1])


@pytest.mark.parametrize(
    ("bounds", "match"),
    [
        ((0.1, 0.5), "must run from <= 0 to >= 0"),
        ((-0.5, -0.1), "must run from <= 0 to >= 0"),
        ((math.nan, 0.5), "must run from <= 0 to >= 0"),
        ((0.5,), "must be two numbers"),
        (("a", "b"), "must be two numbers"),
    ],
)
def test_a_range_without_zero_or_two_numbers_is_refused(bounds: object, match: str) -> None:
    with pytest.raises(diffbot.ParameterError, match=f"linear_range {match}"):
        diffbot.saturate(RC_BOT, WheelSpeeds(1.0, 1.0), linear_range=bounds)  # type: ignore[arg-type]


def test_speeds_within_the_limits_rounding_slack_are_not_scaled() -> None:
    # Found by hypothesis: the right wheel at 1 + 2e-11 of the limit is within_limit(), so
    # saturate() must leave both wheels alone rather than scale them by 1 - 2e-11.
    params = DiffDriveParams(wheel_radius=0.005, wheel_separation=0.01, max_wheel_speed=1.0)
    wheels = diffbot.inverse(params, 1e-13, 1.0)
    assert diffbot.within_limit(params, wheels)
    assert diffbot.saturate(params, wheels) == wheels
