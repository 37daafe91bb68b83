"""Helpers for the path tests: where closed-form pieces lead, OMPL's paths for comparison, and
plans' segments drawn for property tests."""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any

import numpy as np
from hypothesis import strategies as st

from diffbot.planning import Piece
from diffbot.trajectory import Arc, Segment, Spin, Straight

#: Goal coordinates (in radii, or half tracks) and headings (rad) of the property tests.
COORDINATES = st.floats(-50.0, 50.0)
HEADINGS = st.floats(-math.pi, math.pi)
#: Random start/goal pairs compared with OMPL.
PAIRS = 1000


def plan_segments(
    length: tuple[float, float],
    radius: tuple[float, float],
    angle: tuple[float, float],
    spin: tuple[float, float],
) -> st.SearchStrategy[Segment]:
    """A segment of a plan, each way it can go: a straight of ``length`` (m) forwards or back,
    an arc of ``radius`` (m) and ``angle`` (rad) either way round and driven either way, or a
    spin of ``spin`` (rad) either way; each a (least, most) pair of magnitudes."""

    def signed(bounds: tuple[float, float]) -> st.SearchStrategy[float]:
        return st.sampled_from([-1.0, 1.0]).flatmap(lambda s: st.floats(*bounds).map(s.__mul__))

    return st.one_of(
        st.builds(Straight, signed(length)),
        st.builds(
            Arc,
            st.floats(*radius),
            st.floats(*angle),
            st.sampled_from(["cw", "ccw"]),
            reverse=st.booleans(),
        ),
        st.builds(Spin, signed(spin)),
    )


def walk(pieces: list[Piece], radius: float = 1.0) -> Iterator[tuple[float, float, float]]:
    """The pose after each piece, from the origin heading x: turns ("L", "R") of ``radius``,
    straights ("S"), turns in place ("T", rad); lengths in radii, negative backwards."""
    x = y = heading = 0.0
    for kind, s in pieces:
        if kind == "S":
            x += radius * s * math.cos(heading)
            y += radius * s * math.sin(heading)
        elif kind == "T":
            heading += s
        else:
            turn = s if kind == "L" else -s
            chord = 2.0 * radius * math.sin(0.5 * turn) * (1 if kind == "L" else -1)
            x += chord * math.cos(heading + 0.5 * turn)
            y += chord * math.sin(heading + 0.5 * turn)
            heading += turn
        yield x, y, heading


def end(pieces: list[Piece], radius: float = 1.0) -> tuple[float, float, float]:
    """The pose at the end of the pieces (the origin for none)."""
    poses = list(walk(pieces, radius))
    return poses[-1] if poses else (0.0, 0.0, 0.0)


class Ompl:
    """One of OMPL's SE(2) curve spaces of unit radius: its distance and interpolated poses."""

    def __init__(self, space: Any) -> None:
        self.space = space
        self.a, self.b, self.s = space.allocState(), space.allocState(), space.allocState()

    def _set(self, x: float, y: float, phi: float) -> None:
        self.a.setX(0.0)
        self.a.setY(0.0)
        self.a.setYaw(0.0)
        self.b.setX(x)
        self.b.setY(y)
        self.b.setYaw(phi)

    def distance(self, x: float, y: float, phi: float) -> float:
        self._set(x, y, phi)
        return float(self.space.distance(self.a, self.b))

    def pose_at(self, x: float, y: float, phi: float, fraction: float) -> tuple[float, ...]:
        """OMPL's pose at ``fraction`` of its path to (x, y, phi)."""
        self._set(x, y, phi)
        self.space.interpolate(self.a, self.b, fraction, self.s)
        return self.s.getX(), self.s.getY(), self.s.getYaw()


def assert_ends_at(pieces: list[Piece], goal: tuple[float, float, float], most: int) -> None:
    """At most ``most`` pieces that end at ``goal`` (x, y, heading), to 1e-12 of its size."""
    x, y, _ = goal
    assert len(pieces) <= most
    assert same_pose(end(pieces), goal, 1e-12 * max(1.0, abs(x), abs(y)))


def same_pose(a: tuple[float, ...], b: tuple[float, ...], tol: float) -> bool:
    return (
        abs(a[0] - b[0]) <= tol
        and abs(a[1] - b[1]) <= tol
        and abs(math.remainder(a[2] - b[2], 2 * math.pi)) <= tol
    )


def random_pairs(count: int) -> Any:
    """``count`` random start/goal pairs (positions in [-5, 5], headings in [-pi, pi]), as each
    goal seen from its start: rows of (x, y, phi)."""
    rng = np.random.default_rng(20020)
    starts = np.column_stack((rng.uniform(-5, 5, (count, 2)), rng.uniform(-np.pi, np.pi, count)))
    goals = np.column_stack((rng.uniform(-5, 5, (count, 2)), rng.uniform(-np.pi, np.pi, count)))
    rel = np.empty_like(goals)
    c, s = np.cos(starts[:, 2]), np.sin(starts[:, 2])
    dx, dy = goals[:, 0] - starts[:, 0], goals[:, 1] - starts[:, 1]
    rel[:, 0], rel[:, 1] = c * dx + s * dy, -s * dx + c * dy
    rel[:, 2] = goals[:, 2] - starts[:, 2]
    return rel


def assert_agrees_with_ompl(module: Any, space: Any, count: int) -> None:
    """The shortest paths of a planning ``module`` (``path``, ``distance``, ``candidates``) have
    the lengths of OMPL's ``space`` (unit radius) on ``count`` random pairs to 1e-9, and where
    the shortest word is unique, OMPL's path passes through each piece's middle and end."""
    ompl = Ompl(space)
    unique = 0
    for x, y, phi in random_pairs(count):
        ours = module.distance(x, y, phi)
        theirs = ompl.distance(x, y, phi)
        assert abs(ours - theirs) <= 1e-9 * theirs + 1e-12, (x, y, phi, ours, theirs)
        best = [
            (word, lengths)
            for word, lengths in module.candidates(x, y, phi)
            if sum(abs(s) for s in lengths) <= ours * (1 + 1e-6)
        ]
        if any(
            word != best[0][0]
            or max(abs(a - b) for a, b in zip(lengths, best[0][1], strict=True)) > 1e-6
            for word, lengths in best
        ):
            continue
        unique += 1
        pieces = module.path(x, y, phi)
        done = 0.0
        for k, (piece, pose) in enumerate(zip(pieces, walk(pieces), strict=True)):
            middle = end([*pieces[:k], piece._replace(length=piece.length / 2)])
            at = (done + abs(piece.length) / 2) / ours
            assert same_pose(ompl.pose_at(x, y, phi, at), middle, 1e-7), (x, y, phi, pieces)
            done += abs(piece.length)
            assert same_pose(ompl.pose_at(x, y, phi, min(done / ours, 1.0)), pose, 1e-7)
    assert unique > count * 0.9


def first_shortest(
    candidates: Iterable[tuple[str, Sequence[float]]],
) -> tuple[str, Sequence[float]]:
    """The first of the shortest candidates ``(word, lengths)``, the length of one the sum of
    its pieces' magnitudes: ties go to the first listed; ``("", ())`` with none."""
    best: tuple[str, Sequence[float]] = ("", ())
    best_length = math.inf
    for word, lengths in candidates:
        length = sum(abs(v) for v in lengths)
        if length < best_length:
            best, best_length = (word, lengths), length
    return best


#: The math module's functions: the formulas' work is counted in their calls.
_MATH = frozenset(f for f in vars(math).values() if callable(f))


def math_calls(solve: Callable[..., object], goals: Iterable[Sequence[float]]) -> int:
    """How many calls of ``math`` functions solving each goal takes: the work a planner's
    bounds leave it (a bound that prunes less solves more formulas, and each costs calls).

    Counted by a profile hook on C calls, so wrappers around the planner (a tracer, a
    decorator) do not change the count."""
    calls = 0

    def hook(_frame: object, event: str, arg: object) -> None:
        nonlocal calls
        if event == "c_call" and arg in _MATH:
            calls += 1

    previous = sys.getprofile()
    sys.setprofile(hook)
    try:
        for goal in goals:
            solve(*goal)
    finally:
        sys.setprofile(previous)
    return calls


#: Goals that are not finite, one coordinate at a time: no planner has a path to them.
NOT_FINITE_GOALS = [
    (math.inf, 0.0, 0.0),
    (0.0, -math.inf, 0.0),
    (0.0, 0.0, math.inf),
    (0.0, 0.0, -math.inf),
    (math.nan, 1.0, 0.0),
    (1.0, 1.0, math.nan),
]

#: Goals on a grid of half radii and eighth turns: on the turning circles and their tangents,
#: where words tie and bounds meet lengths exactly.
GRID_GOALS = [
    (0.5 * i, 0.5 * j, 0.25 * math.pi * k)
    for i in range(-8, 9)
    for j in range(-8, 9)
    for k in range(-8, 9)
]

#: Calls a platform's math library may add to a measured figure by rounding a branch the other
#: way on a goal or two: far below what dropping a bound's term or widening a guard adds.
WORK_SLACK = 25


def seeded_goals(count: int, seed: int, reach: float = 6.0) -> list[list[float]]:
    """``count`` goals drawn with ``seed``: x and y in [-reach, reach], headings in [-pi, pi]."""
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-reach, reach, (count, 2))
    phi = rng.uniform(-math.pi, math.pi, count)
    goals: list[list[float]] = np.column_stack((xy, phi)).tolist()
    return goals
