"""Dubins paths: the shortest forward path between two poses with a bounded turning radius.

Dubins (1957), "On curves of minimal length with a constraint on average curvature, and with
prescribed initial and terminal positions and tangents", Am. J. Math. 79(3): the shortest path is
one of six words, CSC (LSL, RSR, LSR, RSL) or CCC (RLR, LRL), each arc at the minimum radius.
The words are those of Shkel and Lumelsky (2001), "Classification of the Dubins set", Robotics
and Autonomous Systems 34, section 3 (eq. 4-9), built here from the turning circles' centres in
the start's frame with the radius 1 (the tangent construction of their section 2), which keeps
the path closing on the goal to rounding even where their ``p**2`` cancels.

:func:`candidates` lists every feasible word; :func:`path` finds the same shortest one with the
same operations, but solves a word only when a lower bound of its length, known before solving
it, does not already exceed the shortest so far (see :func:`path`).
"""

from __future__ import annotations

import math

from diffbot.planning import Piece, mod2pi

__all__ = ["WORDS", "candidates", "distance", "path"]

#: The six words, in the order they are tried (ties go to the first).
WORDS = ("LSL", "RSR", "RSL", "LSR", "RLR", "LRL")
TWO_PI = 2.0 * math.pi
#: A bound is trusted to rule a word out only when it exceeds the shortest length so far by
#: more than this, relative (far above the rounding of either).
_SLACK = 1e-9


def _ccc(
    word: str, cx: float, cy: float, ex: float, ey: float, d: float, phi: float
) -> list[tuple[float, float, float]]:
    """RLR (``word`` "RLR", first centre (0, -1)) or LRL (first centre (0, 1)) to the goal's
    circle centred at (ex, ey), ``d`` (0 < d <= 4) from the first: a third circle touching
    both, its centre two radii from each, on either side (eq. 8, 9)."""
    vx, vy = ex - cx, ey - cy
    base = math.atan2(vy, vx)
    gap = math.acos(0.25 * d)
    found = []
    for side in (gap, -gap):
        # w: from the first centre to the touching point; w2: from the middle centre to the
        # second touching point.
        wx, wy = math.cos(base + side), math.sin(base + side)
        mx, my = cx + 2.0 * wx, cy + 2.0 * wy
        w2x, w2y = 0.5 * (ex - mx), 0.5 * (ey - my)
        if word == "RLR":
            h1, h2 = math.atan2(-wx, wy), math.atan2(w2x, -w2y)
            found.append((mod2pi(-h1), mod2pi(h2 - h1), mod2pi(h2 - phi)))
        else:
            h1, h2 = math.atan2(wx, -wy), math.atan2(-w2x, w2y)
            found.append((mod2pi(h1), mod2pi(h1 - h2), mod2pi(phi - h2)))
    return found


def candidates(x: float, y: float, phi: float) -> list[tuple[str, tuple[float, float, float]]]:
    """Every feasible word to ``(x, y, phi)`` and its lengths (t, p, q) in radii, in the order
    they are tried, built from the turning circles' centres: the start's left circle at (0, 1),
    right at (0, -1), the goal's at its sides."""
    try:
        sp, cp = math.sin(phi), math.cos(phi)
    except ValueError:  # an infinite heading: no goal to reach
        return []
    left2, right2 = (x - sp, y + cp), (x + sp, y - cp)
    found: list[tuple[str, tuple[float, float, float]]] = []
    # LSL and RSR (eq. 4, 5): the outer tangent joins circles of one side; the straight is
    # parallel to the line of centres.
    vx, vy = left2[0], left2[1] - 1.0
    h = math.atan2(vy, vx)
    found.append(("LSL", (mod2pi(h), math.hypot(vx, vy), mod2pi(phi - h))))
    vx, vy = right2[0], right2[1] + 1.0
    h = math.atan2(vy, vx)
    found.append(("RSR", (mod2pi(-h), math.hypot(vx, vy), mod2pi(h - phi))))
    # RSL and LSR (eq. 7, 6): the inner tangent, between centres at least two radii apart.
    vx, vy = left2[0], left2[1] + 1.0
    d2 = vx * vx + vy * vy
    if d2 >= 4.0:
        p = math.sqrt(d2 - 4.0)
        h = math.atan2(vy, vx) - math.atan2(2.0, p)
        found.append(("RSL", (mod2pi(-h), p, mod2pi(phi - h))))
    vx, vy = right2[0], right2[1] - 1.0
    d2 = vx * vx + vy * vy
    if d2 >= 4.0:
        p = math.sqrt(d2 - 4.0)
        h = math.atan2(vy, vx) + math.atan2(2.0, p)
        found.append(("LSR", (mod2pi(h), p, mod2pi(h - phi))))
    # RLR and LRL (eq. 8, 9): the centres of one side at most four radii apart.
    for word, (cx, cy), (ex, ey) in (("RLR", (0.0, -1.0), right2), ("LRL", (0.0, 1.0), left2)):
        d = math.hypot(ex - cx, ey - cy)
        if 0.0 < d <= 4.0:
            found += [(word, lengths) for lengths in _ccc(word, cx, cy, ex, ey, d, phi)]
    return found


def path(x: float, y: float, phi: float) -> list[Piece]:
    """The shortest Dubins path from the origin heading along x to ``(x, y, phi)``.

    The first shortest word of :func:`candidates`, with its lengths to the bit, found with fewer
    words solved: LSL and RSR always (they always exist), then a word only where a lower bound
    of its length does not exceed the shortest so far. RSL and LSR: their straight, fixed by the
    distance ``d`` between their circles, plus their arcs, which turn the heading by ``phi`` and
    so at least by ``|phi|`` wrapped to [-pi, pi]. RLR and LRL (circles at most four radii
    apart): the middle arc is ``a`` or ``2 pi - a`` for the angle ``a = 2 asin(d / 4)`` the
    neighbours' centres subtend at its centre, and the outer arcs add what the middle one leaves
    of the turn ``phi`` (mod 2 pi); and no word is shorter than the straight line to the goal.

    Args:
        x, y: the goal position in turning radii (start frame).
        phi: the goal heading (rad).

    Returns:
        Three pieces, lengths in radii (turns: the angle turned), every length >= 0; none for a
        goal that is not finite.
    """
    atan2, sqrt, two_pi = math.atan2, math.sqrt, TWO_PI
    try:
        sp, cp = math.sin(phi), math.cos(phi)
    except ValueError:  # an infinite heading: no goal to reach
        return []
    lx, ly, rx, ry = x - sp, y + cp, x + sp, y - cp
    # LSL. a % 2 pi % 2 pi is mod2pi(a), a zero aside (+0.0): Python's % is fmod with the same
    # correction, and the second % turns a result rounded up to 2 pi into 0, mod2pi's last step.
    vy = ly - 1.0
    h = atan2(vy, lx)
    t, q = h % two_pi % two_pi, (phi - h) % two_pi % two_pi
    same_left = math.hypot(lx, vy)
    best = t + same_left + q
    word, a, b, c = "LSL", t, same_left, q
    # RSR.
    vy = ry + 1.0
    h = atan2(vy, rx)
    t, q = -h % two_pi % two_pi, (h - phi) % two_pi % two_pi
    same_right = math.hypot(rx, vy)
    length = t + same_right + q
    if length < best:
        best, word, a, b, c = length, "RSR", t, same_right, q
    cut = best + _SLACK * (1.0 + best)
    turn = abs(math.remainder(phi, two_pi))
    # RSL, then LSR: each the other's mirror (sign -1 for RSL, +1 for LSR; a negation is exact).
    for ccs, sign, ex, vy in (("RSL", -1.0, lx, ly + 1.0), ("LSR", 1.0, rx, ry - 1.0)):
        d2 = ex * ex + vy * vy
        if d2 >= 4.0:
            p = sqrt(d2 - 4.0)
            if p + turn <= cut:
                h = atan2(vy, ex) + sign * atan2(2.0, p)
                t, q = sign * h % two_pi % two_pi, sign * (h - phi) % two_pi % two_pi
                length = t + p + q
                if length < best:
                    best, word, a, b, c = length, ccs, t, p, q
                    cut = best + _SLACK * (1.0 + best)
    # RLR and LRL: the middle arc a or 2 pi - a; RLR's outer arcs turn by (middle - phi) mod 2 pi
    # (at least), LRL's by (phi + middle).
    if (same_right <= 4.0 or same_left <= 4.0) and math.hypot(x, y) <= cut:
        for ccc, sign, cy, ex, ey, d in (
            ("RLR", -1.0, -1.0, rx, ry, same_right),
            ("LRL", 1.0, 1.0, lx, ly, same_left),
        ):
            if not 0.0 < d <= 4.0:
                continue
            arc = math.pi - 2.0 * math.acos(0.25 * d)
            low = min(arc + (sign * phi + arc) % two_pi, two_pi - arc + (sign * phi - arc) % two_pi)
            if low <= cut:
                for t, p, q in _ccc(ccc, 0.0, cy, ex, ey, d, phi):
                    length = t + p + q
                    if length < best:
                        best, word, a, b, c = length, ccc, t, p, q
                        cut = best + _SLACK * (1.0 + best)
    if not best < math.inf:  # no word reaches a goal that is not finite
        return []
    new = tuple.__new__
    return [new(Piece, (word[0], a)), new(Piece, (word[1], b)), new(Piece, (word[2], c))]


def distance(x: float, y: float, phi: float) -> float:
    """The length of the shortest Dubins path to ``(x, y, phi)``, in turning radii."""
    pieces = path(x, y, phi)
    return pieces[0].length + pieces[1].length + pieces[2].length if pieces else 0.0
