"""Reeds-Shepp paths: they reach the goal, and they are as short as OMPL's, word for word."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from path_pieces import (
    COORDINATES,
    HEADINGS,
    PAIRS,
    assert_agrees_with_ompl,
    assert_ends_at,
    random_pairs,
)

from diffbot.planning import reeds_shepp


@given(COORDINATES, COORDINATES, HEADINGS)
def test_path_ends_at_the_goal(x: float, y: float, phi: float) -> None:
    pieces = reeds_shepp.path(x, y, phi)
    assert len(pieces) >= 3
    assert_ends_at(pieces, (x, y, phi), 5)


def test_known_values() -> None:
    # A straight line is itself; a goal two radii left, facing back, is a half turn (pi).
    assert reeds_shepp.distance(3.0, 0.0, 0.0) == pytest.approx(3.0, abs=1e-15)
    assert reeds_shepp.distance(0.0, 2.0, math.pi) == pytest.approx(math.pi, abs=1e-15)
    # Backing up three radii is as short as driving forward three.
    pieces = [p for p in reeds_shepp.path(-3.0, 0.0, 0.0) if abs(p.length) > 1e-12]
    assert pieces == [("S", pytest.approx(-3.0, abs=1e-15))]
    assert reeds_shepp.distance(-3.0, 0.0, 0.0) == pytest.approx(3.0, abs=1e-15)


def test_lengths_and_words_equal_ompls() -> None:
    ob = pytest.importorskip("ompl.base", reason="the comparison needs OMPL (pip install ompl)")
    assert_agrees_with_ompl(reeds_shepp, ob.ReedsSheppStateSpace(1.0), PAIRS)


def test_distances_of_many_goals_at_once_equal_one_by_one() -> None:
    goals = random_pairs(PAIRS)
    at_once = reeds_shepp.distances(goals[:, 0], goals[:, 1], goals[:, 2])
    one_by_one = np.array([reeds_shepp.distance(*goal) for goal in goals])
    assert at_once.shape == (PAIRS,)
    np.testing.assert_allclose(at_once, one_by_one, rtol=1e-12, atol=1e-12)
    # Broadcasting: one goal heading for every position.
    assert reeds_shepp.distances(goals[:3, 0], goals[:3, 1], 0.5) == pytest.approx(
        [reeds_shepp.distance(x, y, 0.5) for x, y in goals[:3, :2]], rel=1e-12
    )


@given(
    st.floats(-1e3, 1e3),
    st.floats(-1e3, 1e3),
    st.one_of(HEADINGS, st.sampled_from([0.0, math.pi, -math.pi, 0.5 * math.pi, 1e-17])),
)
def test_one_goal_is_the_first_shortest_candidate_exactly(x: float, y: float, phi: float) -> None:
    # path() evaluates the formulas on floats with early outs; candidates() evaluates them all
    # through the backend shared with distances(): both must pick the same word, bit for bit.
    best: tuple[str, tuple[float, ...]] = ("", ())
    best_length = math.inf
    for word, lengths in reeds_shepp.candidates(x, y, phi):
        length = sum(abs(v) for v in lengths)
        if length < best_length:
            best, best_length = (word, lengths), length
    assert [(p.kind, p.length) for p in reeds_shepp.path(x, y, phi)] == list(
        zip(*best, strict=True)
    )
