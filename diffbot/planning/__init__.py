"""Closed-form shortest and fastest paths between two poses, one module per family.

Each module works in the frame of the start pose (start at the origin heading along x) and
returns its path as a list of :class:`Piece`: ``("L", s)`` a left turn, ``("R", s)`` a right turn,
``("S", s)`` a straight line (``s`` signed: negative drives backwards; turns in units of the
turning radius, straights likewise), or, for the time-optimal family, ``("T", angle)`` a turn in
place (rad) and ``("S", length)`` (m). :mod:`diffbot.goals` turns them into plan segments.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["ROUNDING", "Piece", "mod2pi", "wrap_pi"]

TWO_PI = 2.0 * math.pi
#: Turns smaller than this (rad) and straights shorter (m) are rounding, not motion (a few ulps
#: of an angle near pi): plans leave them out.
ROUNDING = 1e-15


class Piece(NamedTuple):
    """One piece of a path: its kind (``"L"``, ``"R"``, ``"S"`` or ``"T"``) and signed length."""

    kind: str
    length: float


def wrap_pi(angle: float) -> float:
    """``angle`` (rad) as OMPL's Reeds-Shepp search wraps it: ``fmod`` by 2 pi, then into
    [-pi, pi] by one turn."""
    turned = math.fmod(angle, TWO_PI)
    if turned < -math.pi:
        return turned + TWO_PI
    if turned > math.pi:
        return turned - TWO_PI
    return turned


def mod2pi(angle: float) -> float:
    """``angle`` wrapped to [0, 2 pi) (rad)."""
    wrapped = math.fmod(angle, TWO_PI)
    if wrapped < 0.0:
        wrapped += TWO_PI
    return 0.0 if wrapped >= TWO_PI else wrapped
