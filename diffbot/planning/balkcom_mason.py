"""Time-optimal paths of a differential drive whose two wheels have the same speed bound.

Balkcom and Mason (2002), "Time optimal trajectories for bounded velocity differential drive
vehicles", Int. J. Robotics Research 21(3): with each wheel's ground speed bounded by ``v_max``,
the set of body velocities is the diamond ``|v| / v_max + |w| b / v_max <= 1`` (``b`` half the
wheel separation), whose corners are the straight line (forwards or backwards) at ``v_max`` and
the turn in place at ``w_max = v_max / b``. Pontryagin's principle makes every time-optimal
trajectory a sequence of those corners, turns in place (T) and straights (G), of at most five
actions; this module takes the best sequence of at most four (the tests hold it against a
numerical search over all four-action sequences).

In units where a straight of length ``b`` and a turn of one radian take the same time, the time
is ``sum |d| / b + sum |phi|``. Here the best of the families TGT, GTG, TGTG and GTGT is found in
closed form: TGT and GTG are fixed by the goal; TGTG has one free parameter, the length ``d`` of
its last straight, and the time is smooth in ``d`` except where a piece vanishes (TGT, GTG), so
its minimum is either there or where the derivative vanishes. With the goal ``(a, c)`` in the
frame of the goal heading and ``(u, c) = (a - d, c)`` the point before the last straight, at
polar angle ``alpha`` and distance ``rho``, the derivative of the time in ``u`` is
``cos(alpha) - 2 s sin(alpha) / rho - sigma`` (``s`` the direction of the first turn, the second
turning the other way, as it must for the derivative to vanish; ``sigma`` the sign of ``d``),
zero at

    cos(alpha) = -sigma - s c / 2,   rho = 2 s sin(alpha) / (cos(alpha) - sigma)

(this module's derivation; eq. (1) below). GTGT is TGTG for the path driven back from the goal.
Among equally fast paths the one with fewest actions wins, then the one that does not back up.
"""

from __future__ import annotations

import math

from diffbot.planning import ROUNDING, Piece

__all__ = ["candidates", "distance", "path"]

#: Relative difference of two times taken as a tie.
TIE = 1e-9


_PI = math.pi
_TWO_PI = 2.0 * math.pi

#: A candidate: its time, its pattern of kinds ("TST", ...) and the signed length of each.
_Candidate = tuple[float, str, tuple[float, ...]]


def _tgt(x: float, y: float, theta: float, signs: tuple[int, ...]) -> list[_Candidate]:
    """Turn to face (or back onto) the goal, drive, turn to the goal heading."""
    rho = math.hypot(x, y)
    if rho == 0.0:
        turn = math.remainder(theta, _TWO_PI)
        return [(abs(turn), "T", (turn,))]
    alpha = math.atan2(y, x)
    out: list[_Candidate] = []
    for sign in signs:
        first = math.remainder(alpha if sign > 0 else alpha + _PI, _TWO_PI)
        second = math.remainder(theta - first, _TWO_PI)
        out.append((abs(first) + rho + abs(second), "TST", (first, sign * rho, second)))
    return out


def _gtg(x: float, y: float, theta: float, signs: tuple[int, ...]) -> list[_Candidate]:
    """Drive along the start heading, turn to the goal heading, drive."""
    s = math.sin(theta)
    if abs(s) < 1e-12:
        return []
    second = y / s
    first = x - second * math.cos(theta)
    if all(d == 0.0 or math.copysign(1, d) in signs for d in (first, second)):
        turn = math.remainder(theta, _TWO_PI)
        return [(abs(first) + abs(turn) + abs(second), "STS", (first, turn, second))]
    return []


def _tgtg(x: float, y: float, theta: float, signs: tuple[int, ...]) -> list[_Candidate]:
    """TGTG paths whose last straight makes the time stationary, eq. (1)."""
    ct, st = math.cos(theta), math.sin(theta)
    a, c = x * ct + y * st, -x * st + y * ct
    remainder, hypot, atan2 = math.remainder, math.hypot, math.atan2
    out: list[_Candidate] = []
    for sigma in signs:
        for s in (1, -1):
            cos_alpha = -sigma - s * c / 2.0
            if not -1.0 < cos_alpha < 1.0:
                continue
            # rho = 2 s sin(alpha) / (cos(alpha) - sigma) > 0 fixes the sign of sin(alpha).
            sin_alpha = math.sqrt(1.0 - cos_alpha * cos_alpha) * (s if sigma < 0 else -s)
            rho = 2.0 * s * sin_alpha / (cos_alpha - sigma)
            last = a - rho * cos_alpha
            if last == 0.0 or (last > 0.0) != (sigma > 0):
                continue
            # Turn, drive, turn to the point before the last straight (both ways, as in _tgt).
            px, py = x - last * ct, y - last * st
            distance = hypot(px, py)
            if distance == 0.0:
                continue
            bearing = atan2(py, px)
            for sign in signs:
                first = remainder(bearing if sign > 0 else bearing + _PI, _TWO_PI)
                second = remainder(theta - first, _TWO_PI)
                t = abs(first) + distance + abs(second) + abs(last)
                out.append((t, "TSTS", (first, sign * distance, second, last)))
    return out


def _reversed(candidate: _Candidate) -> _Candidate:
    """The path driven back: pieces in reverse order, each negated."""
    t, kinds, lengths = candidate
    return t, kinds[::-1], tuple(-v for v in reversed(lengths))


def _pieces(candidate: _Candidate) -> list[Piece]:
    """The candidate's pieces without empty ones, neighbours of one kind joined."""
    out: list[Piece] = []
    for kind, length in zip(candidate[1], candidate[2], strict=True):
        if length == 0.0 or (kind == "T" and abs(length) <= ROUNDING):
            continue
        if out and out[-1].kind == kind:
            out[-1] = Piece(kind, out[-1].length + length)
        else:
            out.append(Piece(kind, length))
    return out


def time(pieces: list[Piece]) -> float:
    """The time of a path in units of ``b / v_max``: straights' lengths (in ``b``) plus turns'
    angles (rad)."""
    return math.fsum(abs(p.length) for p in pieces)


def _candidates(
    x: float, y: float, theta: float, forward_only: bool
) -> tuple[list[_Candidate], list[_Candidate]]:
    """The candidates, and those to be driven back (GTGT: the TGTG path from the goal back to
    the start, driven the other way; reversing keeps the time)."""
    signs = (1,) if forward_only else (1, -1)
    found = _tgt(x, y, theta, signs) + _gtg(x, y, theta, signs) + _tgtg(x, y, theta, signs)
    ct, st = math.cos(theta), math.sin(theta)
    back = (-1,) if forward_only else signs
    return found, _tgtg(-x * ct - y * st, x * st - y * ct, -theta, back)


def candidates(x: float, y: float, theta: float, forward_only: bool = False) -> list[list[Piece]]:
    """Every candidate path to ``(x, y, theta)`` (x, y in half wheel separations, theta in rad):
    TGT, GTG, stationary TGTG and GTGT, without empty pieces."""
    found, driven_back = _candidates(x, y, theta, forward_only)
    return [_pieces(c) for c in found] + [_pieces(_reversed(c)) for c in driven_back]


def path(x: float, y: float, theta: float, forward_only: bool = False) -> list[Piece]:
    """The time-optimal path from the origin heading along x to ``(x, y, theta)``.

    Args:
        x, y: the goal position in half wheel separations (start frame).
        theta: the goal heading (rad).
        forward_only: never drive backwards.

    Returns:
        Turns in place (``"T"``, rad, positive counter-clockwise) and straights (``"S"``, in half
        wheel separations, negative backwards); empty for the start itself and for a goal that
        is not finite.
    """
    isfinite = math.isfinite
    if not (isfinite(x) and isfinite(y) and isfinite(theta)):
        return []
    found, driven_back = _candidates(x, y, theta, forward_only)
    fastest = min(c[0] for c in (*found, *driven_back))
    bound = fastest * (1.0 + TIE)
    best: list[Piece] = []
    best_key = (0, 0)
    tied = [c for c in found if c[0] <= bound] + [
        _reversed(c) for c in driven_back if c[0] <= bound
    ]
    for candidate in tied:
        pieces = _pieces(candidate)
        key = (len(pieces), int(any(p.kind == "S" and p.length < 0.0 for p in pieces)))
        if not best_key[0] or key < best_key:
            best, best_key = pieces, key
    return best


def distance(x: float, y: float, theta: float, forward_only: bool = False) -> float:
    """The least time to ``(x, y, theta)`` in units of ``b / v_max`` (see :func:`path`)."""
    return time(path(x, y, theta, forward_only))
