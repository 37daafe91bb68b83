"""Reeds-Shepp paths: they reach the goal, and they are as short as OMPL's, word for word."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest
from extras import need
from hypothesis import given
from hypothesis import strategies as st
from path_pieces import (
    COORDINATES,
    GRID_GOALS,
    HEADINGS,
    NOT_FINITE_GOALS,
    PAIRS,
    assert_agrees_with_ompl,
    assert_ends_at,
    random_pairs,
)
from path_pieces import first_shortest as shortest_candidate

from diffbot.planning import Piece, reeds_shepp


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
    ob = need("ompl.base")
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
    assert [(p.kind, p.length) for p in reeds_shepp.path(x, y, phi)] == first_shortest(x, y, phi)


SPECIAL_HEADINGS = st.sampled_from([0.0, math.pi, -math.pi, 0.5 * math.pi, -0.5 * math.pi, 1e-17])
#: Goal coordinates from the tiny to the huge, in radii.
SPREAD = st.one_of(COORDINATES, st.floats(-1e-6, 1e-6), st.floats(-1e6, 1e6))


#: Goals on whole radii with headings in quarter turns: full of equally short words.
WHOLE_RADII = np.stack(
    np.meshgrid(np.arange(-4.0, 5.0), np.arange(-4.0, 5.0), np.arange(-4, 5) * 0.25 * math.pi),
    axis=-1,
).reshape(-1, 3)


def assert_paths_agree(goals: np.ndarray) -> None:
    """:func:`reeds_shepp.paths` gives each goal the word of :func:`reeds_shepp.path` and its
    lengths to 1e-12 of the goal's size, NaN after the word's last piece."""
    words, lengths = reeds_shepp.paths(goals[:, 0], goals[:, 1], goals[:, 2])
    assert words.shape == (len(goals),)
    assert lengths.shape == (len(goals), 5)
    for (x, y, phi), index, row in zip(goals.tolist(), words.tolist(), lengths, strict=True):
        pieces = reeds_shepp.path(x, y, phi)
        assert reeds_shepp.WORDS[index] == "".join(p.kind for p in pieces), (x, y, phi)
        tol = 1e-12 * max(1.0, abs(x), abs(y))
        np.testing.assert_allclose(row[: len(pieces)], [p.length for p in pieces], 0, tol)
        assert np.isnan(row[len(pieces) :]).all()


@given(st.lists(st.tuples(SPREAD, SPREAD, st.one_of(HEADINGS, SPECIAL_HEADINGS)), min_size=1))
def test_paths_of_many_goals_at_once_are_path_goal_by_goal(goals: list[tuple[float, ...]]) -> None:
    assert_paths_agree(np.array(goals, dtype=np.float64).reshape(-1, 3))


def test_paths_agree_with_path_on_random_goals_and_on_the_grid() -> None:
    # The grid (whole radii, headings in quarter turns) is full of equally short words, where
    # the first in OMPL's order must win however the last bit rounds.
    assert_paths_agree(np.concatenate((random_pairs(PAIRS), WHOLE_RADII)))


def test_paths_keeps_path_s_word_where_numpy_rounds_otherwise(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # NumPy's functions may differ from math's in the last bit on other machines; here a backend
    # one ulp off in every hypot and atan2 stands for that. On the grid's equally short words
    # the rounding alone then picks other words (47 goals): the goals within 1e-9 of a tie are
    # planned again with path(), so every word is still path()'s.
    exact = reeds_shepp._numpy_backend

    def one_ulp_off() -> Any:
        class OneUlpOff(exact()):  # type: ignore[misc]
            @staticmethod
            def hypot(a: Any, b: Any) -> Any:
                return np.nextafter(np.hypot(a, b), np.inf)

            @staticmethod
            def atan2(a: Any, b: Any) -> Any:
                return np.nextafter(np.arctan2(a, b), -np.inf)

        return OneUlpOff

    monkeypatch.setattr(reeds_shepp, "_numpy_backend", one_ulp_off)
    words, _ = reeds_shepp.paths(*WHOLE_RADII.T)
    for goal, index in zip(WHOLE_RADII.tolist(), words.tolist(), strict=True):
        kinds = "".join(p.kind for p in reeds_shepp.path(*goal))
        assert reeds_shepp.WORDS[index] == kinds, goal


def test_paths_plans_again_only_the_goals_within_rounding_of_a_tie(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A goal planned again one by one costs what path() costs: only goals whose two shortest
    # words are within 1e-9 relative of each other are, as the candidates' lengths tell.
    again: list[tuple[float, float, float]] = []
    one_by_one = reeds_shepp.shortest

    def counted(x: float, y: float, phi: float) -> tuple[int, tuple[float, ...]]:
        again.append((x, y, phi))
        return one_by_one(x, y, phi)

    monkeypatch.setattr(reeds_shepp, "shortest", counted)
    goals = np.concatenate((random_pairs(PAIRS), WHOLE_RADII))
    reeds_shepp.paths(*goals.T)
    tied = []
    for goal in goals.tolist():
        totals = sorted(
            sum(abs(v) for v in lengths) for _, lengths in reeds_shepp.candidates(*goal)
        )
        if totals[1] - totals[0] <= 1e-9 * (1.0 + totals[0]):
            tied.append(tuple(goal))
    assert again == tied
    assert 0 < len(tied) < len(goals) // 4  # the grid is full of ties; random goals have few


def test_paths_broadcast_and_unreachable_goals() -> None:
    words, lengths = reeds_shepp.paths([[3.0, -3.0]], 0.0, [0.0, math.nan])
    assert words.shape == (1, 2)
    assert lengths.shape == (1, 2, 5)
    # Straight ahead three radii: a straight between two empty arcs.
    assert reeds_shepp.WORDS[words[0, 0]][1] == "S"
    np.testing.assert_allclose(lengths[0, 0, :3], [0.0, 3.0, 0.0], atol=1e-15)
    assert np.isnan(lengths[0, 0, 3:]).all()
    # No word reaches a NaN heading, as path() finds none.
    assert reeds_shepp.path(-3.0, 0.0, math.nan) == []
    assert words[0, 1] == -1
    assert np.isnan(lengths[0, 1]).all()


def test_goals_of_any_number_type_are_solved_in_double_precision() -> None:
    # Goals in single precision (as a float32 point cloud or a sensor gives them), integers or
    # lists are read as the float64 values they hold: the same answer, to the bit.
    rng = np.random.default_rng(32)
    goals = rng.uniform(-6.0, 6.0, (3, 200)).astype(np.float32)
    exact = goals.astype(np.float64)
    assert np.array_equal(reeds_shepp.distances(*goals), reeds_shepp.distances(*exact))
    words, lengths = reeds_shepp.paths(*goals)
    words64, lengths64 = reeds_shepp.paths(*exact)
    assert np.array_equal(words, words64)
    assert np.array_equal(lengths, lengths64, equal_nan=True)
    assert lengths.dtype == np.float64
    whole = [[3, -2, 0], [1, 4, -1], [0, 1, 3]]
    assert np.array_equal(
        reeds_shepp.distances(*np.array(whole)), reeds_shepp.distances(*np.array(whole, float))
    )


#: The tolerance of the formulas' sign conditions (OMPL's).
ZERO = 10.0 * 2.220446049250313e-16
#: Each word's signs, by where its straight is (none: "CCC", "CCCC"), before a timeflip negates
#: them all: "+" forwards, "-" backwards, "*" either (Reeds and Shepp, section 8).
SIGNS = {
    "CSC": ["+++"],
    "CCC": ["+-*", "*-+"],
    "CCCC": ["++--", "+--+"],
    "CCSC": ["+---"],
    "CSCC": ["---+"],
    "CCSCC": ["+---+"],
}


def signs_hold(pattern: str, lengths: tuple[float, ...], flip: float) -> bool:
    return all(
        p == "*" or (flip * v >= -ZERO if p == "+" else flip * v <= ZERO)
        for p, v in zip(pattern, lengths, strict=True)
    )


#: Goals a rounding off the axes.
NEAR_AXES = [
    (x, y, phi)
    for x in (1.0, -1.0, 0.5, 2.0, 0.0)
    for y in (ZERO, -ZERO, 1e-15, -1e-15, 0.0)
    for phi in (0.0, ZERO, -ZERO, 1e-15, math.pi, -math.pi, 0.5 * math.pi)
]


def test_every_candidate_reaches_the_goal_with_its_words_signs() -> None:
    goals = GRID_GOALS[::5] + NEAR_AXES + random_pairs(300).tolist()
    for x, y, phi in goals:
        for word, lengths in reeds_shepp.candidates(x, y, phi):
            pieces = [Piece(k, v) for k, v in zip(word, lengths, strict=True)]
            assert_ends_at(pieces, (x, y, phi), 5)
            shape = "".join("S" if k == "S" else "C" for k in word)
            assert any(signs_hold(p, lengths, f) for p in SIGNS[shape] for f in (1.0, -1.0)), (
                x,
                y,
                phi,
                word,
                lengths,
            )
            # The quarter turns of 8.9 to 8.11 beside their straight.
            if len(word) > 3 and "S" in word:
                s = word.index("S")
                quarters = [s - 1] if shape == "CCSC" else [s + 1] if shape == "CSCC" else [1, 3]
                assert all(abs(lengths[q]) == 0.5 * math.pi for q in quarters), (word, lengths)


def first_shortest(x: float, y: float, phi: float) -> list[tuple[str, float]]:
    """The first shortest word of every candidate, as pieces (kind, length)."""
    word, lengths = shortest_candidate(reeds_shepp.candidates(x, y, phi))
    return list(zip(word, lengths, strict=True))


def test_one_goal_is_the_first_shortest_candidate_on_a_grid_and_near_the_axes() -> None:
    # Whole and half radii, eighth turns and goals a rounding off the axes are full of equally
    # short words and of conditions met with nothing to spare.
    for x, y, phi in GRID_GOALS[::2] + NEAR_AXES:
        assert [(p.kind, p.length) for p in reeds_shepp.path(x, y, phi)] == first_shortest(
            x, y, phi
        ), (x, y, phi)


def test_words_of_the_symmetries() -> None:
    # Reflect swaps left and right, reading backwards reverses the word.
    assert reeds_shepp._word("LRSL", False, False) == "LRSL"
    assert reeds_shepp._word("LRSL", True, False) == "RLSR"
    assert reeds_shepp._word("LRSL", False, True) == "LSRL"
    assert reeds_shepp._word("LRSL", True, True) == "RSLR"
    # Eleven formulas under four symmetries each.
    assert len(reeds_shepp.WORDS) == 44
    assert reeds_shepp.WORDS[:4] == ("LSL", "LSL", "RSR", "RSR")
    assert reeds_shepp.WORDS[32:40] == ("LSRL",) * 2 + ("RSLR",) * 2 + ("RSRL",) * 2 + ("LSLR",) * 2


def test_many_goals_at_once_warn_of_nothing() -> None:
    # Formulas that do not hold compute NaN and infinities on the way (acos beyond 1, a goal
    # that is not finite): the caller sees no warning.
    goals = np.array([[math.nan, 0.0, 0.0], [math.inf, 1.0, 0.0], [0.0, 0.0, math.pi]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        words, _ = reeds_shepp.paths(goals[:, 0], goals[:, 1], goals[:, 2])
        lengths = reeds_shepp.distances(goals[:, 0], goals[:, 1], goals[:, 2])
    assert words[0] == -1
    assert lengths[2] == pytest.approx(math.pi, abs=1e-12)


#: Goals where conditions hold with nothing to spare (a first turn of exactly -ZERO, circles
#: exactly two or four radii apart, a cusp word's middle arcs of exactly a quarter turn) and the
#: words candidates() lists there: a condition is met up to its tolerance, inclusive.
EDGES = {
    (0.0, 0.0, 0.0): "LSL LSL RSR LSR LSR RSL RSL LRL LRL RLR RLR LRL LRL RLR RLR LRLR LRLR RLRL "
    "RLRL LRLR LRLR RLRL RLRL",
    (0.0, 0.0, math.pi): "LRL LRL RLR RLR LRL LRL RLR RLR LRLR RLRL",
    (0.0, 0.0, -math.pi): "LRL LRL RLR RLR LRL LRL RLR RLR LRLR RLRL",
    (0.0, 2.0, 0.0): "RLR RLR LRL LRL LRLR LRLR RLRL RLRL",
    (0.0, 2.0, math.pi): "LSL LSR LSR RSL LRL LRL RLR RLR LRL LRL RLR RLR LRLR RLRL LRLR RLRL RLSL "
    "RLSL LSLR LSLR",
    (0.5, 1e-15, 0.0): "LSL RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, ZERO, 0.0): "LSL RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, 0.0, ZERO): "LSL LSL RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, 0.0, -ZERO): "LSL RSR RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, ZERO, ZERO): "LSL RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, -ZERO, -ZERO): "LSL RSR LSR RSL LRL RLR LRL RLR LRLR RLRL",
    (1.0, 3.0, -0.5 * math.pi): "LSR LRL RLR RLR LRL LRL RLR LRLR LRLR RLRL LRSL RLSR LRSR LSRL "
    "LSRL LSLR RLSRL",
    (2.0, ZERO, math.pi): "LRL LRL RLR RLR LRL LRL RLR RLR LRLR RLRL LRSL RLSR LRSR LSRL RSLR LSLR",
    (2.0, 2.0, 0.0): "LSR LRL RLR RLR LRL LRL RLR LRLR RLRL RLRL RLSR RLSR LSRL LSRL RLSRL RLSRL",
}


@pytest.mark.parametrize("goal", list(EDGES))
def test_conditions_met_with_nothing_to_spare_hold(goal: tuple[float, float, float]) -> None:
    assert " ".join(word for word, _ in reeds_shepp.candidates(*goal)) == EDGES[goal]


@pytest.mark.parametrize("goal", NOT_FINITE_GOALS)
def test_a_goal_that_is_not_finite_has_no_path_and_no_error(
    goal: tuple[float, float, float],
) -> None:
    assert reeds_shepp.path(*goal) == []


@pytest.mark.parametrize("phi", [math.inf, -math.inf])
def test_an_infinite_heading_has_no_candidates(phi: float) -> None:
    assert reeds_shepp.candidates(1.0, 2.0, phi) == []
