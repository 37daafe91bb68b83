"""Dubins paths: they reach the goal, and they are as short as OMPL's, word for word."""

from __future__ import annotations

import math

import numpy as np
import pytest
from extras import need
from hypothesis import given, settings
from hypothesis import strategies as st
from path_pieces import (
    COORDINATES,
    GRID_GOALS,
    HEADINGS,
    NOT_FINITE_GOALS,
    PAIRS,
    WORK_SLACK,
    assert_agrees_with_ompl,
    assert_ends_at,
    math_calls,
    seeded_goals,
)
from path_pieces import first_shortest as shortest_candidate

from diffbot.planning import Piece, dubins


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


#: Goals where words tie or degenerate: the start itself, turns in place, goals on the start's
#: line or its circles, whole radii and quarter turns, mirror images, the tiny and the huge.
SINGULAR_HEADINGS = st.sampled_from(
    [0.0, math.pi, -math.pi, 0.5 * math.pi, -0.5 * math.pi, 2.0 * math.pi, 1e-17, -1e-17]
)
GRID = st.integers(-4, 4).map(float)
SPREAD = st.one_of(COORDINATES, GRID, st.floats(-1e-6, 1e-6), st.floats(-1e4, 1e4))
GOALS = st.one_of(
    st.tuples(SPREAD, SPREAD, st.one_of(HEADINGS, SINGULAR_HEADINGS)),
    st.tuples(st.just(0.0), st.just(0.0), st.one_of(HEADINGS, SINGULAR_HEADINGS)),
    st.tuples(SPREAD, st.just(0.0), SINGULAR_HEADINGS),
    st.tuples(st.just(0.0), st.sampled_from([2.0, -2.0, 4.0, -4.0]), SINGULAR_HEADINGS),
)


def first_shortest(x: float, y: float, phi: float) -> list[tuple[str, float]]:
    """The first shortest of all feasible words, every one solved (no bound skips any)."""
    word, lengths = shortest_candidate(dubins.candidates(x, y, phi))
    return list(zip(word, lengths, strict=True))


@settings(max_examples=1000, deadline=None)
@given(GOALS, st.booleans())
def test_path_is_the_first_shortest_of_every_word_exactly(
    goal: tuple[float, float, float], mirrored: bool
) -> None:
    # path() skips the words whose lower bound exceeds the shortest so far: it must still find
    # the word and the lengths that solving every word finds, bit for bit, mirror images too.
    x, y, phi = goal
    if mirrored:
        y, phi = -y, -phi
    assert [(p.kind, p.length) for p in dubins.path(x, y, phi)] == first_shortest(x, y, phi)


def test_singular_goals() -> None:
    # The start itself is no motion.
    assert dubins.distance(0.0, 0.0, 0.0) == 0.0
    assert dubins.distance(0.0, 0.0, 2.0 * math.pi) == 0.0
    # A quarter turn in place, forward only: LRL, its middle arc 2 pi less the angle
    # 2 asin(sqrt(2) / 4) that the two left circles (sqrt(2) apart) subtend at its centre, its
    # outer arcs the pi/2 - 2 asin(sqrt(2) / 4) left: 5 pi / 2 - 4 asin(sqrt(2) / 4) in all.
    pieces = dubins.path(0.0, 0.0, 0.5 * math.pi)
    assert "".join(p.kind for p in pieces) == "LRL"
    expected = 2.5 * math.pi - 4.0 * math.asin(math.sqrt(2.0) / 4.0)
    assert dubins.distance(0.0, 0.0, 0.5 * math.pi) == pytest.approx(expected, rel=1e-12)
    # Its mirror image is the same length, turning the other way.
    assert "".join(p.kind for p in dubins.path(0.0, 0.0, -0.5 * math.pi)) == "RLR"
    assert dubins.distance(0.0, 0.0, -0.5 * math.pi) == pytest.approx(expected, rel=1e-12)
    # No word reaches a goal that is not finite.
    assert dubins.path(1.0, 2.0, math.nan) == []
    assert dubins.path(math.inf, 0.0, 0.0) == []
    assert dubins.distance(1.0, 2.0, math.nan) == 0.0


#: Goals on a grid of half radii and eighth turns (headings beyond a full turn too): goals on
#: the turning circles, on their tangents and four radii apart, where words tie.
HALVES = [0.5 * i for i in range(-8, 9)] + [-0.0, 1e-15, -1e-15]
TURNS = [0.25 * math.pi * k for k in range(-8, 9)] + [1e-15, -1e-15, 2.5 * math.pi]


def test_path_is_the_first_shortest_of_every_word_on_a_grid() -> None:
    for x in HALVES:
        for y in HALVES:
            for phi in TURNS:
                assert [(p.kind, p.length) for p in dubins.path(x, y, phi)] == first_shortest(
                    x, y, phi
                ), (x, y, phi)


def test_path_is_the_first_shortest_of_every_word_on_random_goals() -> None:
    rng = np.random.default_rng(1957)
    goals = np.column_stack(
        (rng.uniform(-6.0, 6.0, (4000, 2)), rng.uniform(-math.pi, math.pi, 4000))
    ).tolist()
    # RLR by a margin its bound must not rule out: its outer arcs turn the heading by the
    # middle arc less phi, not plus.
    goals.append([1.3635258577067209, 1.631609659321521, 2.709111957525808])
    for x, y, phi in goals:
        assert [(p.kind, p.length) for p in dubins.path(x, y, phi)] == first_shortest(x, y, phi), (
            x,
            y,
            phi,
        )


def test_every_candidate_ends_at_the_goal() -> None:
    for x in HALVES[::2]:
        for y in HALVES[::2]:
            for phi in TURNS[::2]:
                for word, lengths in dubins.candidates(x, y, phi):
                    pieces = [Piece(k, v) for k, v in zip(word, lengths, strict=True)]
                    assert all(v >= 0.0 for v in lengths)
                    assert_ends_at(pieces, (x, y, phi), 3)


def test_candidates_four_radii_apart() -> None:
    # Two radii left facing back: the goal's right circle is four radii from the start's, so
    # RLR has one middle circle touching both (its two solutions coincide: a half turn left
    # between empty arcs); at the start itself the circles of one side coincide and no CCC
    # word is listed.
    found = dubins.candidates(0.0, 2.0, math.pi)
    assert [word for word, _ in found] == ["LSL", "RSR", "RSL", "LSR", "RLR", "RLR", "LRL", "LRL"]
    for _, lengths in found[4:6]:
        assert lengths == pytest.approx((0.0, math.pi, 0.0), abs=1e-15)
    assert [word for word, _ in dubins.candidates(0.0, 0.0, 0.0)] == ["LSL", "RSR", "RSL", "LSR"]


#: The math calls :func:`dubins.path` makes on the 4,000 goals below, as measured: its bounds
#: skip RSL, LSR, RLR and LRL where they cannot win. Solving all six takes 129,417.
DUBINS_WORK = 76_797
#: And on the grid of half radii and eighth turns, where bounds meet lengths exactly.
DUBINS_GRID_WORK = 125_498


def test_the_bounds_skip_as_many_words_as_they_did() -> None:
    # A weaker bound finds the same path, only slower: the work is where that shows. A tighter
    # bound may lower the figure; none may raise it.
    goals = seeded_goals(4000, 26)
    assert math_calls(dubins.path, goals) <= DUBINS_WORK + WORK_SLACK
    assert math_calls(dubins.path, GRID_GOALS) <= DUBINS_GRID_WORK + WORK_SLACK
    assert math_calls(dubins.candidates, goals) > DUBINS_WORK


@pytest.mark.parametrize("goal", NOT_FINITE_GOALS)
def test_a_goal_that_is_not_finite_has_no_path_and_no_error(
    goal: tuple[float, float, float],
) -> None:
    assert dubins.path(*goal) == []


@pytest.mark.parametrize("phi", [math.inf, -math.inf])
def test_an_infinite_heading_has_no_candidates(phi: float) -> None:
    assert dubins.candidates(1.0, 2.0, phi) == []
