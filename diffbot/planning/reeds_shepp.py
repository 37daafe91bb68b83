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

The formulas are written once for both numbers and NumPy arrays (a *backend* gives the
functions): :func:`candidates` lists one goal's words with :mod:`math`, :func:`distances` measures
many goals at once with NumPy, and :func:`paths` plans them. :func:`path` plans one goal with the
same formulas on floats (:mod:`diffbot.planning.reeds_shepp_search`), each giving up at its first
unmet condition, and skips the words a lower bound of their length rules out: the same words and
lengths, several times faster.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from diffbot.planning import Piece, wrap_pi
from diffbot.planning.reeds_shepp_search import SLACK, ZERO, shortest

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["WORDS", "candidates", "distance", "distances", "path", "paths"]

HALF_PI = 0.5 * math.pi
TWO_PI = 2.0 * math.pi

# A value is a float or an array of them, a condition a bool or an array of them: the formulas
# combine conditions with &.
_Lengths = tuple[Any, ...]
_Formula = Callable[[Any, Any, Any, Any, Any, Any], tuple[Any, _Lengths]]


class _Math:
    """The scalar backend: :mod:`math`."""

    sin, cos, atan2, hypot, sqrt = math.sin, math.cos, math.atan2, math.hypot, math.sqrt
    asin, acos, fmod = math.asin, math.acos, math.fmod

    wrap = staticmethod(wrap_pi)

    @staticmethod
    def clip(value: float, low: float, high: float) -> float:
        return min(max(value, low), high)


def _numpy_backend() -> Any:
    import numpy as np

    class _NumPy:
        sin, cos, atan2, hypot, sqrt = np.sin, np.cos, np.arctan2, np.hypot, np.sqrt
        asin, acos, fmod, clip = np.arcsin, np.arccos, np.fmod, np.clip

        @staticmethod
        def wrap(angle: Any) -> Any:
            v = np.fmod(angle, TWO_PI)
            return np.where(v < -math.pi, v + TWO_PI, np.where(v > math.pi, v - TWO_PI, v))

    return _NumPy


def _tau_omega(b: Any, u: Any, v: Any, xi: Any, eta: Any, phi: Any) -> tuple[Any, Any]:
    """The first and last arcs of 8.7 (``v = -u``) and 8.8 (``v = u``).

    OMPL's ``tauOmega`` also turns ``tau`` by pi where ``t2 = 2 (cos(u - v) - cos v - cos u) + 3``
    is negative. Here ``t2`` is ``(2 cos u - 1)^2`` (8.7), negative only by a rounding, or
    ``5 - 4 cos u >= 1`` (8.8), so the turn is left out: a rounding cannot flip the path.
    """
    delta = b.wrap(u - v)
    a1 = b.sin(u) - b.sin(delta)
    b1 = b.cos(u) - b.cos(delta) - 1.0
    tau = b.wrap(b.atan2(eta * a1 - xi * b1, xi * a1 + eta * b1))
    return tau, b.wrap(tau - u + v - phi)


def _lsl(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.1: L+ S+ L+."""
    xi, eta = x - s, y - 1.0 + c
    u, t = b.hypot(xi, eta), b.atan2(eta, xi)
    v = b.wrap(phi - t)
    return (t >= -ZERO) & (v >= -ZERO), (t, u, v)


def _lsr(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.2: L+ S+ R+."""
    xi, eta = x + s, y - 1.0 - c
    u1 = b.hypot(xi, eta)
    u1 = u1 * u1
    u = b.sqrt(b.clip(u1 - 4.0, 0.0, math.inf))
    t = b.wrap(b.atan2(eta, xi) + b.atan2(2.0, u))
    v = b.wrap(t - phi)
    return (u1 >= 4.0) & (t >= -ZERO) & (v >= -ZERO), (t, u, v)


def _lrl(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.3/8.4: L+ R- L."""
    xi, eta = x - s, y - 1.0 + c
    u1, theta = b.hypot(xi, eta), b.atan2(eta, xi)
    u = -2.0 * b.asin(b.clip(0.25 * u1, -1.0, 1.0))
    t = b.wrap(theta + 0.5 * u + math.pi)
    v = b.wrap(phi - t + u)
    return (u1 <= 4.0) & (t >= -ZERO) & (u <= ZERO), (t, u, v)


def _lrlr_meet(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.7: L+ R+ L- R-."""
    xi, eta = x + s, y - 1.0 - c
    rho = 0.25 * (2.0 + b.hypot(xi, eta))
    u = b.acos(b.clip(rho, -1.0, 1.0))
    t, v = _tau_omega(b, u, -u, xi, eta, phi)
    return (rho <= 1.0) & (t >= -ZERO) & (v <= ZERO), (t, u, -u, v)


def _lrlr_cusp(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.8: L+ R- L- R+."""
    xi, eta = x + s, y - 1.0 - c
    rho = (20.0 - xi * xi - eta * eta) / 16.0
    u = -b.acos(b.clip(rho, -1.0, 1.0))
    t, v = _tau_omega(b, u, u, xi, eta, phi)
    ok = (rho >= 0.0) & (rho <= 1.0) & (u >= -HALF_PI)
    return ok & (t >= -ZERO) & (v >= -ZERO), (t, u, u, v)


def _lrsl(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.9: L+ R-(pi/2) S- L-."""
    xi, eta = x - s, y - 1.0 + c
    rho, theta = b.hypot(xi, eta), b.atan2(eta, xi)
    r = b.sqrt(b.clip(rho * rho - 4.0, 0.0, math.inf))
    u = 2.0 - r
    t = b.wrap(theta + b.atan2(r, -2.0))
    v = b.wrap(phi - HALF_PI - t)
    ok = (rho >= 2.0) & (t >= -ZERO) & (u <= ZERO) & (v <= ZERO)
    return ok, (t, -HALF_PI + 0.0 * u, u, v)


def _lrsr(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.10: L+ R-(pi/2) S- R-."""
    xi, eta = x + s, y - 1.0 - c
    rho, t = b.hypot(-eta, xi), b.atan2(xi, -eta)
    u = 2.0 - rho
    v = b.wrap(t + HALF_PI - phi)
    ok = (rho >= 2.0) & (t >= -ZERO) & (u <= ZERO) & (v <= ZERO)
    return ok, (t, -HALF_PI + 0.0 * u, u, v)


def _lrslr(b: Any, x: Any, y: Any, s: Any, c: Any, phi: Any) -> tuple[Any, _Lengths]:
    """8.11: L+ R-(pi/2) S- L-(pi/2) R+."""
    xi, eta = x + s, y - 1.0 - c
    rho = b.hypot(xi, eta)
    u = 4.0 - b.sqrt(b.clip(rho * rho - 4.0, 0.0, math.inf))
    t = b.wrap(b.atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
    v = b.wrap(t - phi)
    ok = (rho >= 2.0) & (u <= ZERO) & (t >= -ZERO) & (v >= -ZERO)
    quarter = -HALF_PI + 0.0 * u
    return ok, (t, quarter, u, quarter, v)


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
#: The symmetries of section 7 as sign changes of (x, y, phi), and whether they swap L and R:
#: identity, timeflip, reflect, both.
_SYMMETRIES = (
    (1.0, 1.0, 1.0, False),
    (-1.0, 1.0, -1.0, False),
    (1.0, -1.0, -1.0, True),
    (-1.0, -1.0, 1.0, True),
)
_REFLECT = str.maketrans("LR", "RL")


def _word(word: str, flip: bool, backwards: bool) -> str:
    flipped = word.translate(_REFLECT) if flip else word
    return flipped[::-1] if backwards else flipped


#: Every formula under every symmetry: (formula, read backwards, sign of x, of y, of phi, the
#: word its lengths spell), in the order tried.
_EVALUATIONS = tuple(
    (formula, backwards, sx, sy, sphi, _word(word, flip, backwards))
    for formula, word, backwards in _FAMILIES
    for sx, sy, sphi, flip in _SYMMETRIES
)


def _evaluations(b: Any, x: Any, y: Any, phi: Any) -> list[tuple[str, Any, _Lengths]]:
    """Every formula under every symmetry: (word, condition, lengths), in the order tried; with
    the scalar backend only those whose condition holds."""
    scalar = b is _Math
    try:
        s, c = b.sin(phi), b.cos(phi)
    except ValueError:  # math's, for an infinite heading: no formula holds
        return []
    xb, yb = x * c + y * s, x * s - y * c
    found: list[tuple[str, Any, _Lengths]] = []
    for formula, backwards, sx, sy, sphi, word in _EVALUATIONS:
        px, py = (xb, yb) if backwards else (x, y)
        # sin is odd and cos even: the symmetries only change signs.
        ok, lengths = formula(b, sx * px, sy * py, sphi * s, c, sphi * phi)
        if scalar and not ok:
            continue
        if sx < 0:
            lengths = tuple([-v for v in lengths])
        found.append((word, ok, lengths[::-1] if backwards else lengths))
    return found


def candidates(x: float, y: float, phi: float) -> list[tuple[str, _Lengths]]:
    """Every feasible word and its piece lengths for the goal ``(x, y, phi)`` (radii, rad), in
    the order they are tried."""
    return [(w, lengths) for w, _, lengths in _evaluations(_Math, x, y, phi)]


#: The word of every formula under every symmetry, in the order tried: :func:`paths` gives
#: each goal's word as an index into it.
WORDS: tuple[str, ...] = tuple(word for *_, word in _EVALUATIONS)
_WORDS = WORDS
#: The sign of x of each evaluation's symmetry (timeflip drives it backwards).
_SIGNS = tuple(sx for _, _, sx, *_ in _EVALUATIONS)


def path(x: float, y: float, phi: float) -> list[Piece]:
    """The shortest Reeds-Shepp path from the origin heading along x to ``(x, y, phi)``.

    Args:
        x, y: the goal position in turning radii (start frame).
        phi: the goal heading (rad).

    Returns:
        Three to five pieces (lengths in radii, negative backwards); the first of equally short
        words in OMPL's order; none for a goal that is not finite.
    """
    found, lengths = shortest(x, y, phi)
    if found < 0:
        return []
    if _SIGNS[found] < 0:
        lengths = tuple([-v for v in lengths])
    new = tuple.__new__
    return [new(Piece, piece) for piece in zip(_WORDS[found], lengths, strict=True)]


def distance(x: float, y: float, phi: float) -> float:
    """The length of the shortest Reeds-Shepp path to ``(x, y, phi)``, in turning radii (0 where
    no word reaches it, as for NaN)."""
    # The sum path()'s pieces give, without making them.
    return sum([abs(v) for v in shortest(x, y, phi)[1]])


def distances(x: ArrayLike, y: ArrayLike, phi: ArrayLike) -> NDArray[np.float64]:
    """The lengths of the shortest Reeds-Shepp paths to many goals at once (NumPy arrays of
    ``x``, ``y`` in turning radii and ``phi`` in rad, broadcast together), in turning radii."""
    import numpy as np

    b = _numpy_backend()
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (x, y, phi)))
    best = np.full(arrays[0].shape, np.inf)
    with np.errstate(all="ignore"):
        for _, ok, lengths in _evaluations(b, *arrays):
            total = sum(np.abs(v) for v in lengths)
            np.minimum(best, np.where(ok, total, np.inf), out=best)
    return best


def paths(
    x: ArrayLike, y: ArrayLike, phi: ArrayLike
) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
    """The shortest Reeds-Shepp paths to many goals at once: the words and lengths :func:`path`
    gives, goal by goal, found with NumPy.

    Every word of :data:`WORDS` is measured for all goals at once and each goal takes the first
    shortest. The NumPy functions may round differently from :mod:`math` in the last bit, so a
    goal whose runner-up word is within 1e-9 relative of its shortest (equally short words, as
    on the axes or at a heading of pi) is planned again with :func:`path`: the word chosen is
    always :func:`path`'s, and the lengths equal its lengths to rounding.

    Args:
        x, y: the goals' positions in turning radii (start frame), broadcast with ``phi``.
        phi: the goals' headings (rad).

    Returns:
        ``(words, lengths)``: for each goal the index of its word in :data:`WORDS` (-1 where no
        word reaches it, as for NaN), and its piece lengths in radii (negative backwards),
        shape ``(*goals, 5)``, padded with NaN after the word's last piece.
    """
    import numpy as np

    b = _numpy_backend()
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (x, y, phi)))
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    n = flat[0].size
    evaluations = []
    best, runner_up = np.full(n, np.inf), np.full(n, np.inf)
    words = np.full(n, -1, dtype=np.intp)
    with np.errstate(all="ignore"):
        for k, (_, ok, lengths) in enumerate(_evaluations(b, *flat)):
            # Summed in the order path() sums them; only a strictly shorter word replaces the
            # shortest so far, so the first of equally short words stays.
            total = np.where(ok, sum(np.abs(v) for v in lengths), np.inf)
            np.minimum(runner_up, np.maximum(total, best), out=runner_up)
            np.putmask(words, total < best, k)
            np.minimum(best, total, out=best)
            evaluations.append(lengths)
    out = np.full((n, 5), np.nan)
    for k, lengths in enumerate(evaluations):
        chosen = np.flatnonzero(words == k)
        if chosen.size:
            for j, v in enumerate(lengths):
                out[chosen, j] = np.broadcast_to(v, (n,))[chosen]
    with np.errstate(invalid="ignore"):  # no word: inf - inf
        near = ~(runner_up - best > SLACK * (1.0 + best))
    doubtful = np.flatnonzero(near & np.isfinite(best))
    for i in doubtful.tolist():
        found, exact = shortest(*(float(a[i]) for a in flat))
        words[i] = found
        out[i] = np.nan
        if found >= 0:
            out[i, : len(exact)] = [-v for v in exact] if _SIGNS[found] < 0 else exact
    return words.reshape(shape), out.reshape((*shape, 5))
