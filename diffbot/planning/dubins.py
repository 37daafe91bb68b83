"""Dubins paths: the shortest forward path between two poses with a bounded turning radius.

Dubins (1957), "On curves of minimal length with a constraint on average curvature, and with
prescribed initial and terminal positions and tangents", Am. J. Math. 79(3): the shortest path is
one of six words, CSC (LSL, RSR, LSR, RSL) or CCC (RLR, LRL), each arc at the minimum radius.
The words are those of Shkel and Lumelsky (2001), "Classification of the Dubins set", Robotics
and Autonomous Systems 34, section 3 (eq. 4-9), built here from the turning circles' centres in
the start's frame with the radius 1 (the tangent construction of their section 2), which keeps
the path closing on the goal to rounding even where their ``p**2`` cancels.
"""

from __future__ import annotations

import math

from diffbot.planning import Piece, mod2pi

__all__ = ["WORDS", "candidates", "distance", "path"]

#: The six words, in the order they are tried (ties go to the first).
WORDS = ("LSL", "RSR", "RSL", "LSR", "RLR", "LRL")


def candidates(x: float, y: float, phi: float) -> list[tuple[str, tuple[float, float, float]]]:
    """Every feasible word to ``(x, y, phi)`` and its lengths (t, p, q) in radii, in the order
    they are tried, built from the turning circles' centres: the start's left circle at (0, 1),
    right at (0, -1), the goal's at its sides."""
    sp, cp = math.sin(phi), math.cos(phi)
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
    # RLR and LRL (eq. 8, 9): a third circle touching both, its centre two radii from each.
    for word, (cx, cy), (ex, ey) in (("RLR", (0.0, -1.0), right2), ("LRL", (0.0, 1.0), left2)):
        vx, vy = ex - cx, ey - cy
        d = math.hypot(vx, vy)
        if d > 4.0 or d == 0.0:
            continue
        base = math.atan2(vy, vx)
        gap = math.acos(0.25 * d)
        for side in (gap, -gap):
            # w: from the first centre to the touching point; w2: from the middle centre to the
            # second touching point.
            wx, wy = math.cos(base + side), math.sin(base + side)
            mx, my = cx + 2.0 * wx, cy + 2.0 * wy
            w2x, w2y = 0.5 * (ex - mx), 0.5 * (ey - my)
            if word == "RLR":
                h1, h2 = math.atan2(-wx, wy), math.atan2(w2x, -w2y)
                found.append((word, (mod2pi(-h1), mod2pi(h2 - h1), mod2pi(h2 - phi))))
            else:
                h1, h2 = math.atan2(wx, -wy), math.atan2(-w2x, w2y)
                found.append((word, (mod2pi(h1), mod2pi(h1 - h2), mod2pi(phi - h2))))
    return found


def path(x: float, y: float, phi: float) -> list[Piece]:
    """The shortest Dubins path from the origin heading along x to ``(x, y, phi)``.

    Args:
        x, y: the goal position in turning radii (start frame).
        phi: the goal heading (rad).

    Returns:
        Three pieces, lengths in radii (turns: the angle turned), every length >= 0.
    """
    best: list[Piece] = []
    best_length = math.inf
    for word, (t, p, q) in candidates(x, y, phi):
        length = t + p + q
        if length < best_length:
            best_length = length
            best = [Piece(word[0], t), Piece(word[1], p), Piece(word[2], q)]
    return best


def distance(x: float, y: float, phi: float) -> float:
    """The length of the shortest Dubins path to ``(x, y, phi)``, in turning radii."""
    return sum(piece.length for piece in path(x, y, phi))
