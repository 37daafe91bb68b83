"""Reeds-Shepp paths: the shortest path between two poses for a car that drives both ways with a
bounded turning radius.

Reeds and Shepp (1990), "Optimal paths for a car that goes both forwards and backwards", Pacific
J. Math. 145(2): the shortest path is one of 48 words of at most five pieces (arcs at the minimum
radius and straights, with at most two cusps). Section 8 gives the closed forms of nine base
formulas (8.1 LSL, 8.2 LSR, 8.3/8.4 L|R|L or LR|L, 8.7 LR+|L-R, 8.8 L|R+L-|R, 8.9 L|R(pi/2)SL,
8.10 L|R(pi/2)SR, 8.11 L|R(pi/2)SL(pi/2)|R); the other words follow from them by the paper's
symmetries (section 7): *timeflip* (drive the path backwards: (x, y, phi) -> (-x, y, -phi)),
*reflect* (left for right: (x, y, phi) -> (x, -y, -phi)) and *backwards* (the path read from the
end: (x, y, phi) -> (x cos phi + y sin phi, x sin phi - y cos phi, phi)). The formulas are tried
in the order OMPL's ``ReedsSheppStateSpace`` tries them, with 8.3's typo corrected as there, so
equally short words resolve alike.

Units: lengths in turning radii (a turn's length is the angle it turns, rad); a negative length
drives backwards.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator

from diffbot.planning import Piece, wrap

__all__ = ["candidates", "distance", "path"]

#: Tolerance of the formulas' sign conditions, as in OMPL (10 machine epsilons).
ZERO = 10.0 * 2.220446049250313e-16
HALF_PI = 0.5 * math.pi

_Lengths = tuple[float, ...]
_Formula = Callable[[float, float, float], "_Lengths | None"]


def _polar(x: float, y: float) -> tuple[float, float]:
    return math.hypot(x, y), math.atan2(y, x)


def _tau_omega(u: float, v: float, xi: float, eta: float, phi: float) -> tuple[float, float]:
    delta = wrap(u - v)
    a = math.sin(u) - math.sin(delta)
    b = math.cos(u) - math.cos(delta) - 1.0
    t1 = math.atan2(eta * a - xi * b, xi * a + eta * b)
    t2 = 2.0 * (math.cos(delta) - math.cos(v) - math.cos(u)) + 3.0
    tau = wrap(t1 + math.pi) if t2 < 0.0 else wrap(t1)
    return tau, wrap(tau - u + v - phi)


def _lsl(x: float, y: float, phi: float) -> _Lengths | None:
    """8.1: L+ S+ L+."""
    u, t = _polar(x - math.sin(phi), y - 1.0 + math.cos(phi))
    if t >= -ZERO:
        v = wrap(phi - t)
        if v >= -ZERO:
            return t, u, v
    return None


def _lsr(x: float, y: float, phi: float) -> _Lengths | None:
    """8.2: L+ S+ R+."""
    u1, t1 = _polar(x + math.sin(phi), y - 1.0 - math.cos(phi))
    u1 *= u1
    if u1 < 4.0:
        return None
    u = math.sqrt(u1 - 4.0)
    t = wrap(t1 + math.atan2(2.0, u))
    v = wrap(t - phi)
    return (t, u, v) if t >= -ZERO and v >= -ZERO else None


def _lrl(x: float, y: float, phi: float) -> _Lengths | None:
    """8.3/8.4: L+ R- L."""
    u1, theta = _polar(x - math.sin(phi), y - 1.0 + math.cos(phi))
    if u1 > 4.0:
        return None
    u = -2.0 * math.asin(0.25 * u1)
    t = wrap(theta + 0.5 * u + math.pi)
    v = wrap(phi - t + u)
    return (t, u, v) if t >= -ZERO and u <= ZERO else None


def _lrlr_meet(x: float, y: float, phi: float) -> _Lengths | None:
    """8.7: L+ R+ L- R-."""
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = 0.25 * (2.0 + math.hypot(xi, eta))
    if rho > 1.0:
        return None
    u = math.acos(rho)
    t, v = _tau_omega(u, -u, xi, eta, phi)
    return (t, u, -u, v) if t >= -ZERO and v <= ZERO else None


def _lrlr_cusp(x: float, y: float, phi: float) -> _Lengths | None:
    """8.8: L+ R- L- R+."""
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho = (20.0 - xi * xi - eta * eta) / 16.0
    if not 0.0 <= rho <= 1.0:
        return None
    u = -math.acos(rho)
    if u < -HALF_PI:
        return None
    t, v = _tau_omega(u, u, xi, eta, phi)
    return (t, u, u, v) if t >= -ZERO and v >= -ZERO else None


def _lrsl(x: float, y: float, phi: float) -> _Lengths | None:
    """8.9: L+ R-(pi/2) S- L-."""
    rho, theta = _polar(x - math.sin(phi), y - 1.0 + math.cos(phi))
    if rho < 2.0:
        return None
    r = math.sqrt(rho * rho - 4.0)
    u = 2.0 - r
    t = wrap(theta + math.atan2(r, -2.0))
    v = wrap(phi - HALF_PI - t)
    return (t, -HALF_PI, u, v) if t >= -ZERO and u <= ZERO and v <= ZERO else None


def _lrsr(x: float, y: float, phi: float) -> _Lengths | None:
    """8.10: L+ R-(pi/2) S- R-."""
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho, theta = _polar(-eta, xi)
    if rho < 2.0:
        return None
    t = theta
    u = 2.0 - rho
    v = wrap(t + HALF_PI - phi)
    return (t, -HALF_PI, u, v) if t >= -ZERO and u <= ZERO and v <= ZERO else None


def _lrslr(x: float, y: float, phi: float) -> _Lengths | None:
    """8.11: L+ R-(pi/2) S- L-(pi/2) R+."""
    xi, eta = x + math.sin(phi), y - 1.0 - math.cos(phi)
    rho, _ = _polar(xi, eta)
    if rho < 2.0:
        return None
    u = 4.0 - math.sqrt(rho * rho - 4.0)
    if u > ZERO:
        return None
    t = wrap(math.atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
    v = wrap(t - phi)
    return (t, -HALF_PI, u, -HALF_PI, v) if t >= -ZERO and v >= -ZERO else None


#: (formula, its word, read backwards), in OMPL's order.
_FAMILIES: tuple[tuple[_Formula, str, bool], ...] = (
    (_lsl, "LSL", False),
    (_lsr, "LSR", False),
    (_lrl, "LRL", False),
    (_lrl, "LRL", True),
    (_lrlr_meet, "LRLR", False),
    (_lrlr_cusp, "LRLR", False),
    (_lrsl, "LRSL", False),
    (_lrsr, "LRSR", False),
    (_lrsl, "LRSL", True),
    (_lrsr, "LRSR", True),
    (_lrslr, "LRSLR", False),
)
_REFLECT = str.maketrans("LR", "RL")


def _transforms(
    formula: _Formula, word: str, x: float, y: float, phi: float
) -> Iterator[tuple[str, _Lengths]]:
    """The formula under the identity, timeflip, reflect and both (paper, section 7)."""
    for sx, sy, sphi, flip in (
        (1, 1, 1, False),
        (-1, 1, -1, False),
        (1, -1, -1, True),
        (-1, -1, 1, True),
    ):
        found = formula(sx * x, sy * y, sphi * phi)
        if found is None:
            continue
        lengths = tuple(-s for s in found) if sx < 0 else found
        yield (word.translate(_REFLECT) if flip else word), lengths


def candidates(x: float, y: float, phi: float) -> list[tuple[str, _Lengths]]:
    """Every feasible word and its piece lengths for the goal ``(x, y, phi)`` (radii, rad), in
    the order they are tried."""
    found: list[tuple[str, _Lengths]] = []
    c, s = math.cos(phi), math.sin(phi)
    xb, yb = x * c + y * s, x * s - y * c
    for formula, word, backwards in _FAMILIES:
        if not backwards:
            found.extend(_transforms(formula, word, x, y, phi))
            continue
        for w, lengths in _transforms(formula, word, xb, yb, phi):
            found.append((w[::-1], lengths[::-1]))
    return found


def path(x: float, y: float, phi: float) -> list[Piece]:
    """The shortest Reeds-Shepp path from the origin heading along x to ``(x, y, phi)``.

    Args:
        x, y: the goal position in turning radii (start frame).
        phi: the goal heading (rad).

    Returns:
        Three to five pieces (lengths in radii, negative backwards); the first of equally short
        words in OMPL's order.
    """
    best: tuple[str, _Lengths] = ("", ())
    best_length = math.inf
    for word, lengths in candidates(x, y, phi):
        length = sum(abs(s) for s in lengths)
        if length < best_length:
            best, best_length = (word, lengths), length
    return [Piece(kind, s) for kind, s in zip(best[0], best[1], strict=True)]


def distance(x: float, y: float, phi: float) -> float:
    """The length of the shortest Reeds-Shepp path to ``(x, y, phi)``, in turning radii."""
    return sum(abs(piece.length) for piece in path(x, y, phi))
