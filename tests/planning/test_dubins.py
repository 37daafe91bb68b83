"""Dubins paths: they reach the goal, and they are as short as OMPL's, word for word."""

from __future__ import annotations

import math

import pytest
from extras import need
from hypothesis import given
from path_pieces import COORDINATES, HEADINGS, PAIRS, assert_agrees_with_ompl, assert_ends_at

from diffbot.planning import dubins


@given(COORDINATES, COORDINATES, HEADINGS)
def test_path_ends_at_the_goal(x: float, y: float, phi: float) -> None:
    pieces = dubins.path(x, y, phi)
    assert len(pieces) >= 3
    assert_ends_at(pieces, (x, y, phi), 5)


def test_known_values() -> None:
    # A straight line is itself; a goal two radii left, facing back, is a half turn (pi).
    assert dubins.distance(3.0, 0.0, 0.0) == pytest.approx(3.0, abs=1e-15)
    assert dubins.distance(0.0, 2.0, math.pi) == pytest.approx(math.pi, abs=1e-15)
    # Three radii behind, same heading: a half turn, four radii back as the outer tangent
    # LSL cannot beat, so the answer is no longer than that and longer than the distance.
    assert 3.0 < dubins.distance(-3.0, 0.0, 0.0) <= 2 * math.pi + 3.0


@given(COORDINATES, COORDINATES, HEADINGS)
def test_never_backwards_and_never_shorter_than_the_distance(
    x: float, y: float, phi: float
) -> None:
    pieces = dubins.path(x, y, phi)
    assert all(p.length >= 0.0 for p in pieces)
    assert dubins.distance(x, y, phi) >= math.hypot(x, y) - 1e-12 * max(1.0, abs(x), abs(y))


def test_lengths_and_words_equal_ompls() -> None:
    ob = need("ompl.base")
    assert_agrees_with_ompl(dubins, ob.DubinsStateSpace(1.0), PAIRS)
