"""diff_drive_controller's speed limiter: the upstream test cases, and the laws it keeps.

Known values are ported from ros-controls/control_toolbox, file
control_toolbox/test/rate_limiter.cpp (the RateLimiter that diff_drive_controller's SpeedLimiter
wraps), and from ros-controls/ros2_controllers, file
diff_drive_controller/test/test_diff_drive_controller.cpp (test_speed_limiter). Upstream passes NaN
for an unset limit; here that is NaN or None.
"""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffbot.controller_config import AxisLimits
from diffbot.errors import ParameterError
from diffbot.limiter import LimiterError, checked, execute, limit

NAN = math.nan
NO_LIMITS = AxisLimits()
UPSTREAM_ORDER = (
    "min_velocity",
    "max_velocity",
    "max_acceleration_reverse",
    "max_acceleration",
    "max_deceleration",
    "max_deceleration_reverse",
    "min_jerk",
    "max_jerk",
)


def rate_limiter(*args: float) -> AxisLimits:
    """control_toolbox's RateLimiter constructor: its arguments in its order, NaN for unset."""
    return checked(AxisLimits(**dict(zip(UPSTREAM_ORDER, args, strict=True))))


def only(limits: AxisLimits, group: str) -> AxisLimits:
    """One stage of the limiter: the limits whose names contain ``group``, the others unset."""
    return AxisLimits(
        **{f.name: getattr(limits, f.name) for f in fields(limits) if group in f.name}
    )


def assert_double_eq(actual: float, expected: float) -> None:
    """gtest's EXPECT_DOUBLE_EQ: equal to within 4 units in the last place."""
    assert actual == pytest.approx(expected, rel=4 * np.finfo(np.float64).eps, abs=0.0)


# control_toolbox/test/rate_limiter.cpp, testWrongParams: arguments in upstream order.
ACCEPTED = [
    (-1.0, NAN, -1.0, 1.0, NAN, NAN, -1.0, 1.0),
    (NAN, NAN, -1.0, 1.0, NAN, NAN, -1.0, 1.0),
    (NAN, 1.0, -1.0, 1.0, NAN, NAN, -1.0, 1.0),
    (-1.0, 1.0, -1.0, NAN, NAN, NAN, -1.0, 1.0),
    (-1.0, 1.0, NAN, NAN, NAN, NAN, -1.0, 1.0),
    (-1.0, 1.0, NAN, 1.0, NAN, NAN, -1.0, 1.0),
    (-1.0, 1.0, -1.0, 1.0, -10.0, NAN, -1.0, 1.0),
    (-1.0, 1.0, -1.0, 1.0, NAN, 10.0, -1.0, 1.0),
    (-1.0, 1.0, -1.0, 1.0, NAN, NAN, -1.0, NAN),
    (-1.0, 1.0, -1.0, 1.0, NAN, NAN, NAN, NAN),
    (-1.0, 1.0, -1.0, 1.0, NAN, NAN, NAN, 1.0),
]
REFUSED = [
    ((1.0, -1.0, -1.0, 1.0, NAN, NAN, -1.0, 1.0), "max_velocity must be >= 0"),
    ((-1.0, 1.0, 1.0, -1.0, NAN, NAN, -1.0, 1.0), "max_acceleration must be >= 0"),
    ((-1.0, 1.0, 1.0, -1.0, 10.0, -10.0, -1.0, 1.0), "max_acceleration must be >= 0"),
    ((-1.0, 1.0, -1.0, 1.0, NAN, NAN, 1.0, -1.0), "max_jerk must be >= 0"),
]


@pytest.mark.parametrize("args", ACCEPTED)
def test_limits_upstream_accepts_are_accepted(args: tuple[float, ...]) -> None:
    limiter = rate_limiter(*args)
    assert limit(limiter, 0.0, 0.0, 0.0, 0.1) == 0.0


@pytest.mark.parametrize(("args", "message"), REFUSED)
def test_limits_upstream_refuses_are_refused_naming_the_limit(
    args: tuple[float, ...], message: str
) -> None:
    with pytest.raises(LimiterError, match=message):
        rate_limiter(*args)


def test_limiter_errors_are_parameter_errors() -> None:
    with pytest.raises(ParameterError, match="max_deceleration must be <= 0"):
        checked(AxisLimits(max_deceleration=1.0))
    with pytest.raises(ParameterError, match="max_jerk must be a finite number"):
        AxisLimits(max_jerk="fast")  # type: ignore[arg-type]


def test_nan_and_none_both_mean_unset() -> None:
    assert rate_limiter(NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN) == NO_LIMITS


def test_no_limits_leave_commands_as_they_are() -> None:
    # rate_limiter.cpp, testNoLimits.
    assert_double_eq(limit(NO_LIMITS, 10.0, 0.0, 0.0, 0.5), 10.0)
    assert_double_eq(limit(NO_LIMITS, -10.0, 0.0, 0.0, 0.5), -10.0)


def test_value_limits_clamp_and_first_derivative_limits_first() -> None:
    # rate_limiter.cpp, testValueLimits.
    limiter = rate_limiter(-0.5, 1.0, -0.5, 1.0, NAN, NAN, -2.0, 5.0)
    assert_double_eq(limit(only(limiter, "velocity"), 10.0, 0.0, 0.0, 0.5), 1.0)
    assert_double_eq(limit(only(limiter, "velocity"), -10.0, 0.0, 0.0, 0.5), -0.5)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 0.5)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -0.25)


def test_no_value_limits_leave_the_derivative_limits_working() -> None:
    # rate_limiter.cpp, testValueNoLimits, its four blocks.
    limiter = rate_limiter(NAN, NAN, -0.5, 1.0, NAN, NAN, -0.5, 5.0)
    assert_double_eq(limit(only(limiter, "velocity"), 10.0, 0.0, 0.0, 0.5), 10.0)
    assert_double_eq(limit(only(limiter, "velocity"), -10.0, 0.0, 0.0, 0.5), -10.0)
    limiter = rate_limiter(NAN, NAN, -0.5, 1.0, NAN, NAN, -2.0, 2.0)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 0.5)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -0.25)
    limiter = rate_limiter(NAN, NAN, NAN, NAN, NAN, NAN, -0.5, 5.0)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 1.25)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -0.125)
    limiter = rate_limiter(NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 10.0)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -10.0)


def test_first_derivative_limits_bound_the_change_per_period() -> None:
    # rate_limiter.cpp, testFirstDerivativeLimits.
    limiter = rate_limiter(-0.5, 1.0, -0.5, 1.0, NAN, NAN, -2.0, 5.0)
    assert_double_eq(limit(only(limiter, "cel"), 10.0, 0.0, 0.0, 0.5), 0.5)
    assert_double_eq(limit(only(limiter, "cel"), -10.0, 0.0, 0.0, 0.5), -0.25)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 0.5)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -0.25)


def test_asymmetric_first_derivative_limits_follow_the_sign_of_the_last_command() -> None:
    # rate_limiter.cpp, testFirstDerivativeLimitsAsymmetric.
    limiter = rate_limiter(-0.5, 1.0, -0.5, 1.0, -5.0, 10.0, -0.5, 5.0)
    assert_double_eq(limit(only(limiter, "cel"), 10.0, 5.0, 5.0, 0.5), 5.5)
    assert_double_eq(limit(only(limiter, "cel"), -10.0, 5.0, 5.0, 0.5), 2.5)
    assert limit(only(limiter, "cel"), 10.0, -5.0, -5.0, 0.5) == 0.0
    assert_double_eq(limit(only(limiter, "cel"), -10.0, -5.0, -5.0, 0.5), -5.25)


def test_second_derivative_limits_bound_the_change_of_the_change() -> None:
    # rate_limiter.cpp, testSecondDerivativeLimits.
    limiter = rate_limiter(-0.5, 1.0, -0.5, 1.0, NAN, NAN, -1.0, 1.0)
    assert_double_eq(limit(only(limiter, "jerk"), 10.0, 0.0, 0.0, 0.5), 0.25)
    assert_double_eq(limit(only(limiter, "jerk"), -10.0, 0.0, 0.0, 0.5), -0.25)
    assert_double_eq(limit(limiter, 10.0, 0.0, 0.0, 0.5), 0.25)
    assert_double_eq(limit(limiter, -10.0, 0.0, 0.0, 0.5), -0.25)


def test_easing_off_is_not_jerk_limited() -> None:
    # The rule of control_toolbox issue #240: only jerk that grows the acceleration is limited.
    limiter = AxisLimits(max_jerk=1.0)
    assert limit(limiter, 0.5, 0.5, 0.25, 0.1) == 0.5
    assert limit(limiter, 1.0, 0.5, 0.25, 0.1) == pytest.approx(0.76, abs=1e-15)


def test_controller_reaches_each_step_after_its_own_acceleration_limit() -> None:
    # test_diff_drive_controller.cpp, test_speed_limiter: 1 kHz, steps 1, 0, -1, 0 m/s, wheel
    # radius 0.1 m and a 1e-3 rad/s tolerance on the wheel, so 1e-4 m/s here.
    linear = AxisLimits(
        max_acceleration=2.0,
        max_deceleration=-4.0,
        max_acceleration_reverse=-8.0,
        max_deceleration_reverse=10.0,
    )
    steps = [(1.0, 1.0 / 2.0), (0.0, -1.0 / -4.0), (-1.0, -1.0 / -8.0), (0.0, 1.0 / 10.0)]
    times = [0.0, 1.0, 2.0, 3.0]
    t, v, w = execute(
        times,
        [s for s, _ in steps],
        [0.0] * 4,
        linear_limits=linear,
        angular_limits=NO_LIMITS,
        rate_hz=1000.0,
        end=3.5,
    )
    assert not w.any()
    for start, (target, time_acc) in zip(times, steps, strict=True):
        first = int(np.searchsorted(t, start - 1e-12))
        short = math.floor(time_acc / 0.001) - 1
        assert (np.abs(v[first : first + short] - target) > 1e-12).all()
        assert v[first + short] == pytest.approx(target, abs=1e-4)
        assert v[first + short + 1 : first + short + 4] == pytest.approx([target] * 3, abs=1e-4)


def test_execute_ends_when_the_commands_have_settled_after_the_last() -> None:
    limits = AxisLimits(max_acceleration=1.0)
    t, v, _ = execute(
        [0.0, 2.0],
        [0.5, 0.0],
        [0.0, 0.0],
        linear_limits=limits,
        angular_limits=NO_LIMITS,
        rate_hz=10.0,
    )
    assert v[-1] == 0.0
    assert v[-2] != 0.0 or v[-3] != 0.0
    assert t[1] - t[0] == pytest.approx(0.1, rel=1e-15)


def test_execute_runs_to_the_given_end_update() -> None:
    t, v, w = execute(
        [0.0],
        [0.2],
        [0.1],
        linear_limits=NO_LIMITS,
        angular_limits=NO_LIMITS,
        rate_hz=50.0,
        end=1.0,
    )
    assert len(t) == 51
    assert t[-1] == pytest.approx(1.0, rel=1e-15)
    assert (v == 0.2).all()
    assert (w == 0.1).all()


def test_execute_ignores_a_command_with_nan_and_holds_the_previous_one() -> None:
    t, v, w = execute(
        [0.0, 0.1, 0.2],
        [0.3, NAN, 0.1],
        [0.0, 1.0, 0.0],
        linear_limits=NO_LIMITS,
        angular_limits=NO_LIMITS,
        rate_hz=100.0,
    )
    held = (t >= 0.1 - 1e-9) & (t < 0.2 - 1e-9)
    assert (v[held] == 0.3).all()
    assert (w[held] == 0.0).all()
    assert v[-1] == 0.1


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"times": [0.0, 1.0], "linear": [0.1], "angular": [0.0, 0.0]}, "the same length"),
        ({"times": [1.0, 0.0], "linear": [0.1, 0.1], "angular": [0.0, 0.0]}, "non-decreasing"),
        ({"times": [], "linear": [], "angular": []}, "times must be a non-empty"),
        ({"rate_hz": 0.0}, "rate_hz must be a positive finite number"),
        ({"end": -1.0}, "end must be finite and >= times"),
    ],
)
def test_execute_refuses_bad_input_naming_the_argument(
    kwargs: dict[str, object], message: str
) -> None:
    call: dict[str, object] = {
        "times": [0.0],
        "linear": [0.1],
        "angular": [0.0],
        "linear_limits": NO_LIMITS,
        "angular_limits": NO_LIMITS,
        "rate_hz": 10.0,
    }
    call.update(kwargs)
    with pytest.raises(LimiterError, match=message):
        execute(**call)  # type: ignore[arg-type]


limit_values = st.one_of(st.none(), st.floats(0.1, 5.0))


@st.composite
def limiters(draw: st.DrawFn) -> AxisLimits:
    """Any valid limiter, asymmetric limits included."""

    def negative() -> float | None:
        value = draw(limit_values)
        return None if value is None else -value

    return AxisLimits(
        min_velocity=negative(),
        max_velocity=draw(limit_values),
        max_acceleration_reverse=negative(),
        max_acceleration=draw(limit_values),
        max_deceleration=negative(),
        max_deceleration_reverse=draw(limit_values),
        min_jerk=negative(),
        max_jerk=draw(limit_values),
    )


commands = st.lists(st.floats(-5.0, 5.0), min_size=1, max_size=40)


@settings(max_examples=50, deadline=None)
@given(limiters(), commands, st.floats(5.0, 200.0))
def test_executed_commands_keep_velocity_acceleration_and_growing_jerk_limits(
    limiter: AxisLimits, stream: list[float], rate: float
) -> None:
    times = np.arange(len(stream)) * 0.05
    _, v, _ = execute(
        times,
        stream,
        [0.0] * len(stream),
        linear_limits=limiter,
        angular_limits=NO_LIMITS,
        rate_hz=rate,
        end=float(times[-1]) + 0.5,
    )
    dt = 1.0 / rate
    history = np.concatenate([[0.0, 0.0], v])
    tol = 1e-9
    bounds = limiter.velocity_range
    if bounds is not None:
        assert v.min() >= bounds[0] - tol
        assert v.max() <= bounds[1] + tol
    jerk_bounds = limiter.jerk_range
    for k in range(2, len(history)):
        dv = history[k] - history[k - 1]
        dv0 = history[k - 1] - history[k - 2]
        acc = limiter.acceleration_range(history[k - 1])
        if acc is not None:
            assert acc[0] * dt - tol <= dv <= acc[1] * dt + tol
        if jerk_bounds is not None and (dv - dv0) * dv > 0.0:
            assert jerk_bounds[0] * dt * dt - tol <= dv - dv0 <= jerk_bounds[1] * dt * dt + tol


@st.composite
def smooth_streams(draw: st.DrawFn) -> tuple[list[float], float, float, float]:
    """Per-update commands from rest within half of acceleration A and jerk J, and speed V."""
    a_max, j_max = draw(st.floats(0.5, 3.0)), draw(st.floats(5.0, 50.0))
    dt = 0.01
    steps = draw(st.lists(st.floats(-1.0, 1.0), min_size=1, max_size=200))
    v = a = 0.0
    out = []
    for step in steps:
        a = float(np.clip(a + step * j_max / 2 * dt, -a_max / 2, a_max / 2))
        v = v + a * dt
        out.append(v)
    # Twice the highest speed the accelerations can reach: set, never reached.
    return out, a_max * len(steps) * dt + 0.1, a_max, j_max


@settings(max_examples=40, deadline=None)
@given(smooth_streams())
def test_commands_within_every_limit_come_out_unchanged(
    case: tuple[list[float], float, float, float],
) -> None:
    stream, v_max, a_max, j_max = case
    limiter = AxisLimits(max_velocity=v_max, max_acceleration=a_max, max_jerk=j_max)
    times = np.arange(len(stream)) * 0.01
    _, v, w = execute(
        times,
        stream,
        stream,
        linear_limits=limiter,
        angular_limits=limiter,
        rate_hz=100.0,
        end=float(times[-1]),
    )
    np.testing.assert_allclose(v, stream, rtol=0, atol=1e-12)
    np.testing.assert_allclose(w, stream, rtol=0, atol=1e-12)
