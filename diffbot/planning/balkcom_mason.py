"""Time-optimal paths of a differential drive whose two wheels have the same speed bound.

Balkcom and Mason (2002), "Time optimal trajectories for bounded velocity differential drive
vehicles", Int. J. Robotics Research 21(3): with each wheel's ground speed bounded by ``v_max``,
the set of body velocities is the diamond ``|v| / v_max + |w| b / v_max <= 1`` (``b`` half the
wheel separation), whose corners are the straight line (forwards or backwards) at ``v_max`` and
the turn in place at ``w_max = v_max / b``. Pontryagin's principle (their section 3) makes every
time-optimal trajectory a sequence of those corners, turns in place (T) and straights (G), of at
most five actions, and a sequence of at most four always does as well (their section 6, table 1).

In units where a straight of length ``b`` and a turn of one radian take the same time, the time
is ``sum |d| / b + sum |phi|``. Here the best of the families TGT, GTG, TGTG and GTGT is found in
closed form: TGT and GTG are fixed by the goal; TGTG has one free parameter, the length ``d`` of
its last straight, and the time is smooth in ``d`` except where a piece vanishes (TGT, GTG), so
its minimum is either there or where the derivative vanishes. With the goal ``(a, c)`` in the
frame of the goal heading and ``(u, c) = (a - d, c)`` the point before the last straight, at
polar angle ``alpha``, that derivative is ``cos(alpha) - 2 s sin(alpha) / rho - sigma`` (``s``
the turning direction of the two turns, which must differ, ``sigma`` the sign of ``d``), zero at

    cos(alpha) = -sigma - s c / 2,   rho = 2 s sin(alpha) / (cos(alpha) - sigma)

(this module's derivation; eq. (1) below). GTGT is TGTG for the path driven back from the goal.
Among equally fast paths the one with fewest actions wins, then the one that does not back up.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from diffbot.planning import Piece, wrap

__all__ = ["candidates", "distance", "path"]

#: Relative difference of two times taken as a tie.
TIE = 1e-9


def _tgt(x: float, y: float, theta: float, signs: tuple[int, ...]) -> Iterator[list[Piece]]:
    """Turn to face (or back onto) the goal, drive, turn to the goal heading."""
    rho = math.hypot(x, y)
    if rho == 0.0:
        yield [Piece("T", wrap(theta))]
        return
    alpha = math.atan2(y, x)
    for sign in signs:
        heading = alpha if sign > 0 else alpha + math.pi
        first = wrap(heading)
        yield [Piece("T", first), Piece("S", sign * rho), Piece("T", wrap(theta - first))]


def _gtg(x: float, y: float, theta: float, signs: tuple[int, ...]) -> Iterator[list[Piece]]:
    """Drive along the start heading, turn to the goal heading, drive."""
    s = math.sin(theta)
    if abs(s) < 1e-12:
        return
    second = y / s
    first = x - second * math.cos(theta)
    if all(d == 0.0 or math.copysign(1, d) in signs for d in (first, second)):
        yield [Piece("S", first), Piece("T", wrap(theta)), Piece("S", second)]


def _tgtg(x: float, y: float, theta: float, signs: tuple[int, ...]) -> Iterator[list[Piece]]:
    """TGTG paths whose last straight makes the time stationary, eq. (1)."""
    ct, st = math.cos(theta), math.sin(theta)
    a, c = x * ct + y * st, -x * st + y * ct
    for sigma in signs:
        for s in (1, -1):
            cos_alpha = -sigma - s * c / 2.0
            if not -1.0 <= cos_alpha <= 1.0:
                continue
            sin_abs = math.sqrt(max(0.0, 1.0 - cos_alpha * cos_alpha))
            for sin_alpha in (sin_abs, -sin_abs):
                denominator = cos_alpha - sigma
                if denominator == 0.0:
                    continue
                rho = 2.0 * s * sin_alpha / denominator
                if not rho > 0.0:
                    continue
                last = a - rho * cos_alpha
                if last == 0.0 or math.copysign(1, last) not in signs:
                    continue
                px, py = x - last * ct, y - last * st
                for head in _tgt(px, py, theta, signs):
                    yield [*head, Piece("S", last)]


def _reversed(pieces: list[Piece]) -> list[Piece]:
    """The path driven back: pieces in reverse order, each negated."""
    return [Piece(p.kind, -p.length) for p in reversed(pieces)]


def _normal(pieces: list[Piece]) -> list[Piece]:
    """Without empty pieces, neighbours of one kind joined."""
    out: list[Piece] = []
    for piece in pieces:
        if piece.length == 0.0:
            continue
        if out and out[-1].kind == piece.kind:
            out[-1] = Piece(piece.kind, out[-1].length + piece.length)
        else:
            out.append(piece)
    return [p for p in out if p.length != 0.0]


def time(pieces: list[Piece]) -> float:
    """The time of a path in units of ``b / v_max``: straights' lengths (in ``b``) plus turns'
    angles (rad)."""
    return math.fsum(abs(p.length) for p in pieces)


def candidates(x: float, y: float, theta: float, forward_only: bool = False) -> list[list[Piece]]:
    """Every candidate path to ``(x, y, theta)`` (x, y in half wheel separations, theta in rad):
    TGT, GTG, stationary TGTG and GTGT, without empty pieces."""
    signs = (1,) if forward_only else (1, -1)
    back = (-1,) if forward_only else (1, -1)
    found = [*_tgt(x, y, theta, signs), *_gtg(x, y, theta, signs), *_tgtg(x, y, theta, signs)]
    # GTGT: the TGTG path from the goal back to the start, driven the other way.
    ct, st = math.cos(theta), math.sin(theta)
    bx, by = -x * ct - y * st, x * st - y * ct
    found.extend(_reversed(p) for p in _tgtg(bx, by, -theta, back))
    return [_normal(p) for p in found]


def path(x: float, y: float, theta: float, forward_only: bool = False) -> list[Piece]:
    """The time-optimal path from the origin heading along x to ``(x, y, theta)``.

    Args:
        x, y: the goal position in half wheel separations (start frame).
        theta: the goal heading (rad).
        forward_only: never drive backwards.

    Returns:
        Turns in place (``"T"``, rad, positive counter-clockwise) and straights (``"S"``, in half
        wheel separations, negative backwards); empty for the start itself.
    """
    best: list[Piece] = []
    best_key = (math.inf, 0, 0)
    for pieces in candidates(x, y, theta, forward_only):
        t = time(pieces)
        backs = any(p.kind == "S" and p.length < 0.0 for p in pieces)
        key = (t, len(pieces), int(backs))
        if t < best_key[0] * (1.0 - TIE):
            best, best_key = pieces, key
        elif t <= best_key[0] * (1.0 + TIE) and key[1:] < best_key[1:]:
            best, best_key = pieces, (min(t, best_key[0]), *key[1:])
    return best


def distance(x: float, y: float, theta: float, forward_only: bool = False) -> float:
    """The least time to ``(x, y, theta)`` in units of ``b / v_max`` (see :func:`path`)."""
    return time(path(x, y, theta, forward_only))
