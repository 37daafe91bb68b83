"""Dubins paths: they reach the goal, and they are as short as OMPL's, word for word."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from path_pieces import Ompl, end, same_pose, walk

from diffbot.planning import dubins

#: Random start/goal pairs compared with OMPL.
PAIRS = 1000
coordinate = st.floats(-50.0, 50.0)
heading = st.floats(-math.pi, math.pi)


@given(coordinate, coordinate, heading)
def test_path_ends_at_the_goal(x: float, y: float, phi: float) -> None:
    pieces = dubins.path(x, y, phi)
    assert 3 <= len(pieces) <= 5
    assert same_pose(end(pieces), (x, y, phi), 1e-12 * max(1.0, abs(x), abs(y)))


def test_known_values() -> None:
    # A straight line is itself; a goal two radii left, facing back, is a half turn (pi).
    assert dubins.distance(3.0, 0.0, 0.0) == pytest.approx(3.0, abs=1e-15)
    assert dubins.distance(0.0, 2.0, math.pi) == pytest.approx(math.pi, abs=1e-15)
    # Three radii behind, same heading: a half turn, four radii back as the outer tangent
    # LSL cannot beat, so the answer is no longer than that and longer than the distance.
    assert 3.0 < dubins.distance(-3.0, 0.0, 0.0) <= 2 * math.pi + 3.0


@given(coordinate, coordinate, heading)
def test_never_backwards_and_never_shorter_than_the_distance(
    x: float, y: float, phi: float
) -> None:
    pieces = dubins.path(x, y, phi)
    assert all(p.length >= 0.0 for p in pieces)
    assert dubins.distance(x, y, phi) >= math.hypot(x, y) - 1e-12 * max(1.0, abs(x), abs(y))


def _pairs() -> np.ndarray:
    rng = np.random.default_rng(20020)
    starts = np.column_stack((rng.uniform(-5, 5, (PAIRS, 2)), rng.uniform(-np.pi, np.pi, PAIRS)))
    goals = np.column_stack((rng.uniform(-5, 5, (PAIRS, 2)), rng.uniform(-np.pi, np.pi, PAIRS)))
    rel = np.empty_like(goals)
    c, s = np.cos(starts[:, 2]), np.sin(starts[:, 2])
    dx, dy = goals[:, 0] - starts[:, 0], goals[:, 1] - starts[:, 1]
    rel[:, 0], rel[:, 1] = c * dx + s * dy, -s * dx + c * dy
    rel[:, 2] = goals[:, 2] - starts[:, 2]
    return rel


def test_lengths_and_words_equal_ompls() -> None:
    ob = pytest.importorskip("ompl.base", reason="the comparison needs OMPL (pip install ompl)")
    ompl = Ompl(ob.DubinsStateSpace(1.0))
    unique = 0
    for x, y, phi in _pairs():
        ours = dubins.distance(x, y, phi)
        theirs = ompl.distance(x, y, phi)
        assert ours == pytest.approx(theirs, rel=1e-9, abs=1e-12), (x, y, phi)
        best = [
            (word, lengths)
            for word, lengths in dubins.candidates(x, y, phi)
            if sum(abs(s) for s in lengths) <= ours * (1 + 1e-6)
        ]
        if any(
            word != best[0][0] or lengths != pytest.approx(best[0][1], abs=1e-6)
            for word, lengths in best
        ):
            continue
        # Unique optimum: OMPL's path passes through each of our piece ends and middles.
        unique += 1
        pieces = dubins.path(x, y, phi)
        done = 0.0
        for piece, pose in zip(pieces, walk(pieces), strict=True):
            middle = end([*pieces[: pieces.index(piece)], piece._replace(length=piece.length / 2)])
            assert same_pose(
                ompl.pose_at(x, y, phi, (done + abs(piece.length) / 2) / ours), middle, 1e-7
            ), (x, y, phi, pieces)
            done += abs(piece.length)
            assert same_pose(ompl.pose_at(x, y, phi, min(done / ours, 1.0)), pose, 1e-7)
    assert unique > PAIRS * 0.9
