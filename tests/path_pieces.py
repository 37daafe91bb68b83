"""Helpers for the closed-form path tests: where pieces lead, and OMPL's paths for comparison."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from diffbot.planning import Piece


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


def same_pose(a: tuple[float, ...], b: tuple[float, ...], tol: float) -> bool:
    return (
        abs(a[0] - b[0]) <= tol
        and abs(a[1] - b[1]) <= tol
        and abs(math.remainder(a[2] - b[2], 2 * math.pi)) <= tol
    )
