"""Known values: the class's exercises 5 and 6 and the limit check, worked out by the library."""

from __future__ import annotations

from math import nan, pi

import pytest
from rendered import equations, numbers
from robots import BOT_50_RPM

from diffbot.errors import ParameterError
from diffbot.explain import (
    ExplainError,
    explain_fk,
    explain_ik,
    explain_odom,
    explain_plan,
    format_number,
    render,
)
from diffbot.kinematics import norm_angle
from diffbot.planfile import parse_plan
from diffbot.trajectory import EXAMPLES, plan


def _results(rendered: str, fmt: str, prefix: str) -> list[float]:
    """The first result number of every step line starting with ``prefix``."""
    return [e.result[0].value for e in equations(rendered, fmt) if e.line.startswith(prefix)]


def test_spanish_ik_of_the_bundled_robot_shows_2_857_rad_s_and_27_3_rpm() -> None:
    text = render(explain_ik(BOT_50_RPM, 0.1, 0.0), "text", "es")
    minus = "\N{MINUS SIGN}"
    lines = text.splitlines()
    label = lines.index("  Velocidad angular de la rueda izquierda")
    assert lines[label + 1] == (
        f"    ω_L = (v {minus} ω·b/2) / r = (0.1 {minus} 0·0.135/2) / 0.035"
        " = 2.857 rad/s (27.3 rpm)"
    )
    assert "ω_R = (v + ω·b/2) / r = (0.1 + 0·0.135/2) / 0.035 = 2.857 rad/s (27.3 rpm)" in text
    assert "27.3 rpm ≤ 50 rpm: dentro del límite del motor" in text


def test_markdown_ik_writes_the_wheel_speed_as_a_latex_fraction() -> None:
    md = render(explain_ik(BOT_50_RPM, 0.1, 0.0), "md", "en")
    assert (
        r"$$\omega_L = \frac{v - \omega \cdot b/2}{r} = \frac{0.1 - 0 \cdot 0.135/2}{0.035}"
        r" = 2.857\ \mathrm{rad/s}\ (27.3\ \mathrm{rpm})$$"
    ) in md
    assert "**Angular velocity of the left wheel**" in md


def test_ik_over_the_limit_says_so() -> None:
    text = render(explain_ik(BOT_50_RPM, 0.5, 0.0), "text", "en")
    # 0.5 / 0.035 = 14.29 rad/s = 136.4 rpm
    assert "136 rpm > 50 rpm: over the motor limit" in text


def test_fk_of_equal_wheel_speeds_drives_straight_at_0_1_m_s() -> None:
    text = render(explain_fk(BOT_50_RPM, 0.1 / 0.035, 0.1 / 0.035), "text", "en")
    assert _results(text, "text", "v = ") == pytest.approx([0.1], abs=5e-5)
    assert _results(text, "text", "ω = ") == pytest.approx([0.0], abs=1e-12)


def test_plan_of_trajectory_a_gives_the_class_exercise_6_commands() -> None:
    # Exercise 6 rounds ω to 0.314 before using it, hence its 1.637 and 2.848 rad/s; the exact
    # values are 1.638 and 2.850.
    text = render(explain_plan(plan(parse_plan(EXAMPLES["A"]), BOT_50_RPM)), "text", "es")
    assert _results(text, "text", "v = s / t") == pytest.approx(
        [0.0785, 0.1, 0.0785, 0.1], abs=5e-4
    )
    assert _results(text, "text", "ω = Δθ / t") == pytest.approx(
        [0.314, 0.0, -0.314, 0.0], abs=5e-4
    )
    assert _results(text, "text", "ω_L = ") == pytest.approx([1.638, 2.857, 2.850, 2.857], abs=2e-3)
    assert _results(text, "text", "ω_R = ") == pytest.approx([2.850, 2.857, 1.638, 2.857], abs=2e-3)
    assert "v = ω·R = (-0.3142)·(-0.25) = 0.07854 m/s" in text


def test_plan_of_trajectory_a_ends_each_segment_at_the_closed_form_pose() -> None:
    text = render(explain_plan(plan(parse_plan(EXAMPLES["A"]), BOT_50_RPM)), "text", "en")
    xs = _results(text, "text", "x₁ = ")
    ys = _results(text, "text", "y₁ = ")
    headings = _results(text, "text", "θ₁ = ")
    assert xs == pytest.approx([0.0, -1.0, -1.0, 0.0], abs=5e-4)
    assert ys == pytest.approx([0.5, 0.5, 1.0, 1.0], abs=5e-4)
    for heading, expected in zip(headings, [pi, pi, 0.0, 0.0], strict=True):
        assert abs(norm_angle(heading - expected)) < 5e-4


def test_plan_over_the_limit_names_the_shortest_duration() -> None:
    # 1 m in 1 s turns both wheels at 28.57 rad/s = 272.8 rpm; at 50 rpm it needs 5.457 s.
    text = render(explain_plan(plan(parse_plan("straight 1 1s"), BOT_50_RPM)), "text", "es")
    assert (
        "273 rpm > 50 rpm: supera el límite del motor; el segmento necesita al menos 5.457 s"
        in text
    )


def test_the_shortest_duration_is_rounded_up_so_that_it_fits() -> None:
    # 0.3 m at 50 rpm needs 0.3 / (5.236 rad/s · 0.035 m) = 1.63702 s: 1.637 s would not fit.
    text = render(explain_plan(plan(parse_plan("straight 0.3 1s"), BOT_50_RPM)), "text", "en")
    assert "the segment needs at least 1.638 s" in text


def test_odometry_of_a_spin_in_place_turns_without_moving() -> None:
    # wheels turned by -1 and +1 rad: d = 0.035 m each way, dθ = 0.07 / 0.135 = 0.5185 rad
    text = render(explain_odom(BOT_50_RPM, 0.0, 0.0, -1.0, 1.0, 0.5), "text", "en")
    assert _results(text, "text", "ds = ") == [0.0]
    assert _results(text, "text", "dθ = ") == pytest.approx([0.5185], abs=5e-5)
    assert _results(text, "text", "x₁ = ") == [0.0]
    assert _results(text, "text", "ω = ") == pytest.approx([1.037], abs=5e-4)


@pytest.mark.parametrize(
    ("value", "digits", "latex", "expected"),
    [
        (2.857142857, 4, False, "2.857"),
        (27.28370, 3, False, "27.3"),
        (0.1, 4, False, "0.1"),
        (-0.0, 4, False, "0"),
        (1234567.0, 4, False, "1234567"),
        (1.5e-7, 4, False, "1.5e-07"),
        (1.5e-7, 4, True, r"1.5 \times 10^{-7}"),
        (-2.5e12, 3, False, "-2.5e+12"),
    ],
)
def test_numbers_keep_their_significant_digits(
    value: float, digits: int, latex: bool, expected: str
) -> None:
    assert format_number(value, digits, latex=latex) == expected


def test_numbers_read_back_from_text_include_powers_of_ten() -> None:
    assert [n.value for n in numbers(r"1.5e-07 and 2.5 \times 10^{3} and -4")] == [
        1.5e-07,
        2500.0,
        -4.0,
    ]


def test_an_unknown_format_is_refused() -> None:
    with pytest.raises(ExplainError, match=r"unknown format 'html': expected one of text, md"):
        render(explain_ik(BOT_50_RPM, 0.1, 0.0), "html")


def test_a_nan_velocity_is_refused_by_name() -> None:
    with pytest.raises(ParameterError, match="linear must be a finite number"):
        explain_ik(BOT_50_RPM, nan, 0.0)


def test_an_odometry_step_without_time_is_refused() -> None:
    with pytest.raises(ParameterError, match=r"dt must be > 0 \(s\)"):
        explain_odom(BOT_50_RPM, 0.0, 0.0, 1.0, 1.0, 0.0)


def test_wheels_of_different_radii_are_shown_side_by_side() -> None:
    # a right wheel 1 mm larger: at 0.1 m/s it turns at 0.1 / 0.036 = 2.778 rad/s (26.5 rpm)
    robot = BOT_50_RPM.replace(left_wheel_radius=0.035, right_wheel_radius=0.036)
    text = render(explain_ik(robot, 0.1, 0.0), "text", "es")
    assert "Radio de las ruedas izquierdas\n    r_L = 0.035 m\n" in text
    assert "Radio de las ruedas derechas\n    r_R = 0.036 m\n" in text
    assert "/ r_R = (0.1 + 0·0.135/2) / 0.036 = 2.778 rad/s (26.5 rpm)" in text
    assert "\n    r = " not in text
    fk = render(explain_fk(robot, 1.0, 1.0), "text", "en")
    # v = (0.035·1 + 0.036·1) / 2 = 0.0355 m/s; ω = (0.036·1 - 0.035·1) / 0.135 = 0.007407 rad/s
    assert "v = (r_L·ω_L + r_R·ω_R) / 2 = (0.035·1 + 0.036·1) / 2 = 0.0355 m/s" in fk
    assert "= (0.036·1 \N{MINUS SIGN} 0.035·1) / 0.135 = 0.007407 rad/s" in fk


@pytest.mark.parametrize("angle", [1e308, -1.0000001e12])
def test_odom_wheel_angles_beyond_a_recordings_range_are_refused(angle: float) -> None:
    # Angles of 1e308 failed in sin(inf); 1e307 printed a heading change of inf degrees.
    with pytest.raises(ParameterError, match=r"right1 must be a finite number >= -1e\+12"):
        explain_odom(BOT_50_RPM, 0.0, 0.0, 0.0, angle, 1.0)


def test_odom_of_the_largest_angles_prints_finite_degrees() -> None:
    derivation = explain_odom(BOT_50_RPM, 0.0, 0.0, -1e12, 1e12, 1.0)
    text = render(derivation, "text", "en")
    assert "inf" not in text
    assert "nan" not in text
