"""The planners' two angle wraps: mod2pi (Dubins, into [0, 2 pi)) and wrap_pi (Reeds-Shepp, OMPL's
fmod then one turn into [-pi, pi])."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from diffbot.planning import mod2pi, wrap_pi

ANGLES = st.floats(-1e6, 1e6, allow_nan=False)


@given(ANGLES)
def test_wrap_pi_lands_in_minus_pi_to_pi_a_whole_number_of_turns_away(angle: float) -> None:
    wrapped = wrap_pi(angle)
    assert -math.pi <= wrapped <= math.pi
    turns = (angle - wrapped) / (2.0 * math.pi)
    assert abs(turns - round(turns)) <= 1e-9 * max(1.0, abs(turns))


@given(st.floats(-math.pi, math.pi))
def test_wrap_pi_leaves_an_angle_within_pi_as_it_is(angle: float) -> None:
    assert wrap_pi(angle) == angle


@pytest.mark.parametrize(
    ("angle", "wrapped"),
    [
        (1.5 * math.pi, math.fmod(1.5 * math.pi, 2.0 * math.pi) - 2.0 * math.pi),
        (-1.5 * math.pi, math.fmod(-1.5 * math.pi, 2.0 * math.pi) + 2.0 * math.pi),
        (7.0, 7.0 - 2.0 * math.pi),
        (-7.0, -7.0 + 2.0 * math.pi),
        (4.0, 4.0 - 2.0 * math.pi),
        (-4.0, -4.0 + 2.0 * math.pi),
        (math.pi, math.pi),
        (-math.pi, -math.pi),
        (3.0 * math.pi, math.fmod(3.0 * math.pi, 2.0 * math.pi)),
    ],
)
def test_wrap_pi_is_fmod_then_one_turn_to_the_bit(angle: float, wrapped: float) -> None:
    assert wrap_pi(angle) == wrapped


@given(ANGLES)
def test_mod2pi_lands_in_zero_to_two_pi_a_whole_number_of_turns_away(angle: float) -> None:
    wrapped = mod2pi(angle)
    assert 0.0 <= wrapped < 2.0 * math.pi
    turns = (angle - wrapped) / (2.0 * math.pi)
    assert abs(turns - round(turns)) <= 1e-9 * max(1.0, abs(turns))


def test_mod2pi_of_a_rounding_below_zero_is_zero_not_two_pi() -> None:
    assert mod2pi(-1e-300) == 0.0
    assert mod2pi(-0.0) == 0.0
    assert mod2pi(2.0 * math.pi) == 0.0
