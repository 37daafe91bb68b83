"""Time-optimal turn-and-drive paths: they reach the goal, and no four-action path is faster."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from path_pieces import end, same_pose

from diffbot.planning import ROUNDING, balkcom_mason

#: Goals of the numerical search.
GOALS = 1000
coordinate = st.floats(-50.0, 50.0)
heading = st.floats(-math.pi, math.pi)


@given(coordinate, coordinate, heading, st.booleans())
def test_path_ends_at_the_goal(x: float, y: float, theta: float, forward_only: bool) -> None:
    pieces = balkcom_mason.path(x, y, theta, forward_only)
    assert len(pieces) <= 4
    assert same_pose(end(pieces), (x, y, theta), 1e-12 * max(1.0, abs(x), abs(y)))
    if forward_only:
        assert all(p.length > 0.0 for p in pieces if p.kind == "S")


def test_known_values() -> None:
    # Straight ahead or behind: one straight; in place: one turn.
    assert balkcom_mason.path(2.0, 0.0, 0.0) == [("S", 2.0)]
    assert balkcom_mason.path(-2.0, 0.0, 0.0) == [("S", -2.0)]
    assert balkcom_mason.path(0.0, 0.0, 1.0) == [("T", 1.0)]
    # Five half tracks to the side: a quarter turn each way around the straight (pi + 5).
    assert balkcom_mason.distance(0.0, 5.0, 0.0) == pytest.approx(math.pi + 5.0, abs=1e-14)
    # Forwards only, two behind: half turn, two, half turn back would be 2 pi + 2; turning
    # around through a sideways step is faster, and still never backs up.
    assert balkcom_mason.distance(-2.0, 0.0, 0.0, forward_only=True) <= 2 * math.pi + 2.0
    # A small step sideways (eps half tracks): turn by phi, drive, turn back, back up costs
    # 2 phi + d (1 + cos phi) with d sin phi = eps, about 4 sqrt(eps) at phi = sqrt(eps), far
    # less than the pi + eps of turning to face the goal.
    eps = 1e-4
    best = min(
        2 * phi + eps / math.sin(phi) * (1 + math.cos(phi)) for phi in np.linspace(1e-3, 0.1, 20001)
    )
    assert balkcom_mason.distance(0.0, eps, 0.0) == pytest.approx(best, rel=1e-6)
    assert best == pytest.approx(4 * math.sqrt(eps), rel=1e-3)


def _tgt(x: np.ndarray, y: np.ndarray, theta: np.ndarray, signs: tuple[int, ...]) -> np.ndarray:
    """Time of turn, drive, turn to (x, y, theta), elementwise (the best of the signs given)."""
    rho = np.hypot(x, y)
    alpha = np.arctan2(y, x)
    best = np.full(np.broadcast(x, y, theta).shape, np.inf)
    for sign in signs:
        h = alpha if sign > 0 else alpha + np.pi
        turns = np.abs(np.remainder(h + np.pi, 2 * np.pi) - np.pi)
        turns += np.abs(np.remainder(theta - h + np.pi, 2 * np.pi) - np.pi)
        best = np.minimum(best, rho + turns)
    return best


def _search(
    x: float, y: float, theta: float, forward_only: bool, rng: np.random.Generator
) -> float:
    """The fastest four-action path found by search: TGTG over its last straight's length and
    GTGT over its first (the other three actions follow from the goal), from random restarts,
    each of the three best refined by zooming in (four rounds of 64 samples, 8x closer each)."""
    signs = (1,) if forward_only else (1, -1)
    ct, st_ = math.cos(theta), math.sin(theta)
    span = 4.0 + 2.0 * math.hypot(x, y)
    lo = 0.0 if forward_only else -span

    def tgtg(d: np.ndarray) -> np.ndarray:
        return np.abs(d) + _tgt(x - d * ct, y - d * st_, np.full_like(d, theta), signs)

    def gtgt(d: np.ndarray) -> np.ndarray:
        return np.abs(d) + _tgt(x - d, np.full_like(d, y), np.full_like(d, theta), signs)

    best = math.inf
    for family in (tgtg, gtgt):
        samples = rng.uniform(lo, span, 256)
        values = family(samples)
        for start in samples[np.argsort(values)[:3]]:
            centre, width = float(start), (span - lo) / 64.0
            for _ in range(4):
                grid = np.clip(np.linspace(centre - width, centre + width, 64), lo, span)
                found = family(grid)
                centre, width = float(grid[np.argmin(found)]), width / 8.0
                best = min(best, float(found.min()))
    return best


@pytest.mark.parametrize("forward_only", [False, True])
def test_no_four_action_path_found_by_search_is_faster(forward_only: bool) -> None:
    rng = np.random.default_rng(2002)
    goals = np.column_stack(
        (rng.uniform(-4, 4, (GOALS // 2, 2)), rng.uniform(-np.pi, np.pi, GOALS // 2))
    )
    for x, y, theta in goals:
        ours = balkcom_mason.distance(x, y, theta, forward_only)
        assert ours <= _search(x, y, theta, forward_only, rng) + 1e-9, (x, y, theta)
        assert ours <= float(_tgt(np.array(x), np.array(y), np.array(theta), (1,))) + 1e-12


#: Goals on a grid of half tracks and eighth turns: the axes, the start itself, turns in
#: place, goals straight ahead or behind, where candidates tie or lose pieces, and goals four
#: half tracks across the goal heading, where the stationary four-action paths degenerate.
SPOTS = [0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0, -4.0]
GRID = [(x, y, 0.25 * math.pi * k) for x in SPOTS for y in SPOTS for k in range(-8, 9)]


@pytest.mark.parametrize("forward_only", [False, True])
def test_every_candidate_ends_at_the_goal_and_the_path_is_the_fastest(forward_only: bool) -> None:
    for x, y, theta in GRID:
        found = balkcom_mason.candidates(x, y, theta, forward_only)
        assert found, (x, y, theta)
        for pieces in found:
            assert same_pose(end(pieces), (x, y, theta), 1e-9), (x, y, theta, pieces)
            # Without empty pieces, neighbours of one kind joined.
            assert all(p.length != 0.0 for p in pieces)
            assert all(a.kind != b.kind for a, b in itertools.pairwise(pieces))
            if forward_only:
                assert all(p.length > 0.0 for p in pieces if p.kind == "S"), pieces
        pieces = balkcom_mason.path(x, y, theta, forward_only)
        fastest = min(balkcom_mason.time(c) for c in found)
        assert balkcom_mason.time(pieces) == pytest.approx(fastest, rel=1e-9, abs=1e-12)
        assert balkcom_mason.distance(x, y, theta, forward_only) == balkcom_mason.time(pieces)
        if forward_only:
            assert all(p.length > 0.0 for p in pieces if p.kind == "S"), pieces


def test_candidates_of_a_known_goal() -> None:
    # Half a track to the left: turn, drive, turn back either way round (forwards or
    # backwards), and the stationary four-action paths; forwards only, the backwards ones go.
    both = balkcom_mason.candidates(0.0, 0.5, 0.0)
    forward = balkcom_mason.candidates(0.0, 0.5, 0.0, forward_only=True)
    assert [p.kind for p in both[0]] == ["T", "S", "T"]
    assert both[0] == [("T", pytest.approx(0.5 * math.pi)), ("S", 0.5), ("T", -0.5 * math.pi)]
    assert both[1] == [("T", pytest.approx(-0.5 * math.pi)), ("S", -0.5), ("T", 0.5 * math.pi)]
    assert forward[0] == both[0]
    assert len(forward) < len(both)
    assert all(p.length > 0.0 for c in forward for p in c if p.kind == "S")
    assert any(p.length < 0.0 for c in both for p in c if p.kind == "S")


def test_forward_only_is_never_faster_and_sometimes_slower() -> None:
    # Two half tracks behind: backing up takes 2; forwards only, more.
    assert balkcom_mason.distance(-2.0, 0.0, 0.0) == pytest.approx(2.0, abs=1e-15)
    assert balkcom_mason.distance(-2.0, 0.0, 0.0, forward_only=True) > 2.0 + 1.0
    assert balkcom_mason.distance(-2.0, 0.0, 0.0, True) == balkcom_mason.time(
        balkcom_mason.path(-2.0, 0.0, 0.0, True)
    )
    for x, y, theta in GRID[::7]:
        assert balkcom_mason.distance(x, y, theta, True) >= balkcom_mason.distance(
            x, y, theta
        ) - 1e-12 * (1.0 + abs(x) + abs(y))


def test_turns_of_rounding_size_are_left_out_and_ties_resolved() -> None:
    # A turn in place of a rounding (at most ROUNDING rad) is no motion.
    assert balkcom_mason.path(0.0, 0.0, 1e-17) == []
    assert balkcom_mason.path(0.0, 0.0, -1e-17) == []
    assert balkcom_mason.path(0.0, 0.0, ROUNDING) == []
    assert balkcom_mason.distance(0.0, 0.0, ROUNDING) == 0.0
    assert balkcom_mason.candidates(0.0, 0.0, ROUNDING) == [[]]
    # ... but one just above it is.
    assert balkcom_mason.path(0.0, 0.0, 4e-15) == [("T", 4e-15)]
    # Among equally fast paths the one of fewest actions wins: a quarter turn left then half a
    # track ahead, two actions, rather than an empty straight first.
    assert balkcom_mason.path(0.0, 0.5, 0.5 * math.pi) == [
        ("T", pytest.approx(0.5 * math.pi)),
        ("S", 0.5),
    ]
    # Then the one that does not back up: half a track to the right, facing back, is a
    # quarter turn right, half a track forwards and a quarter turn right, not the same turns
    # left around a straight backwards.
    pieces = balkcom_mason.path(0.0, -0.5, math.pi)
    assert [p.kind for p in pieces] == ["T", "S", "T"]
    assert pieces[1].length == pytest.approx(0.5)
    assert all(p.length == pytest.approx(-0.5 * math.pi) for p in (pieces[0], pieces[2]))
    # Then the first tried: half a track to the left, same heading, is turn, back up, turn,
    # drive (TGTG) rather than the GTGT path as fast.
    assert [p.kind for p in balkcom_mason.path(0.0, 0.5, 0.0)] == ["T", "S", "T", "S"]


def test_candidates_of_mirror_images_are_mirror_images() -> None:
    # Left for right: (x, y, theta) -> (x, -y, -theta) turns every turn the other way and keeps
    # every straight, candidate for candidate (a half turn either way is the same turn).
    for x, y, theta in GRID[::3]:
        for forward_only in (False, True):
            found = balkcom_mason.candidates(x, y, theta, forward_only)
            mirrored = balkcom_mason.candidates(x, -y, -theta, forward_only)
            assert len(found) == len(mirrored), (x, y, theta, forward_only)
            for a, b in zip(found, mirrored, strict=True):
                assert [p.kind for p in a] == [p.kind for p in b]
                for p, q in zip(a, b, strict=True):
                    if p.kind == "S":
                        assert p.length == pytest.approx(q.length, rel=1e-9, abs=1e-12)
                    else:
                        assert abs(math.remainder(p.length + q.length, 2 * math.pi)) < 1e-9


@pytest.mark.parametrize(
    "goal",
    [(math.nan, 0.0, 0.0), (math.inf, 0.0, 0.0), (0.0, -math.inf, 1.0), (1.0, 1.0, math.nan)],
)
@pytest.mark.parametrize("forward_only", [False, True])
def test_a_goal_that_is_not_finite_has_no_path(
    goal: tuple[float, float, float], forward_only: bool
) -> None:
    assert balkcom_mason.path(*goal, forward_only=forward_only) == []


def test_goals_at_the_edge_of_floating_point_still_have_paths() -> None:
    # Coordinates whose sum overflows are still finite goals: a straight of 1e308.
    (piece,) = balkcom_mason.path(1e308, 0.0, 0.0)
    assert piece == ("S", 1e308)
    assert len(balkcom_mason.path(1e308, 1e308, 0.0)) == 3
