"""The shortest Reeds-Shepp word to one goal, on floats, with the words that cannot win skipped.

:mod:`diffbot.planning.reeds_shepp` lists every word (:func:`~diffbot.planning.reeds_shepp.\
candidates`) with formulas written once for floats and NumPy arrays. :func:`shortest` finds the
same first shortest word with the same operations in the same order, so the lengths are the same
numbers, but each formula gives up at its first unmet condition (as OMPL's do), the formulas of
one symmetry share what they have in common, and a formula is solved only when a lower bound of
its length does not already exceed the shortest so far:

- The formulas use two pairs of circle centres: (xi, eta) = (x - s, y - 1 + c), whose norm is
  the distance between the start's and the goal's left turning circles (8.1, 8.3/8.4, 8.9), and
  (x + s, y - 1 - c), from the start's left circle to the goal's right one (8.2, 8.7, 8.8, 8.10,
  8.11). A word's straight is at least what that distance fixes: rho (8.1), sqrt(rho^2 - 4)
  (8.2), sqrt(rho^2 - 4) - 2 (8.9), rho - 2 (8.10), sqrt(rho^2 - 4) - 4 (8.11). The symmetries
  only change signs, and a word read backwards joins the same two circles, so four distances
  serve every word.
- Its arcs turn the heading by phi modulo 2 pi with the signs the formula's conditions fix: at
  least phi mod 2 pi (8.1), |phi| wrapped (8.2, 8.8, and any word), pi/2 + |phi - pi/2| wrapped
  (8.9), pi/2 + (phi - pi/2) mod 2 pi (8.10), pi + |phi| wrapped (8.11).

A bound rules a word out only when it exceeds the shortest length by more than :data:`SLACK`
relative (far above rounding), and equally short words keep the order of the full search: the
word chosen is the one it chooses. The wraps to [-pi, pi] are written out where they are used:
a call of a Python function costs more than the arithmetic. Keeping the shortest word, a few
times a goal, is the one call.

Units: lengths in turning radii (a turn's length is the angle it turns, rad); a negative length
drives backwards.
"""

from __future__ import annotations

import math

from diffbot.planning import wrap_pi

__all__ = ["SLACK", "ZERO", "shortest"]

#: Tolerance of the formulas' sign conditions, as in OMPL (10 machine epsilons).
ZERO = 10.0 * 2.220446049250313e-16
#: A bound skips a word only when it exceeds the shortest length so far by more than this,
#: relative.
SLACK = 1e-9
HALF_PI = 0.5 * math.pi
TWO_PI = 2.0 * math.pi
_PI = math.pi


def _tau_omega(u: float, v: float, xi: float, eta: float, phi: float) -> tuple[float, float]:
    """The first and last arcs of 8.7 (``v = -u``, u in [0, pi/3]) and 8.8 (``v = u``).

    The full search wraps ``u - v`` and ``tau`` to [-pi, pi] after an fmod; here ``u - v`` lies
    in [0, 2 pi/3] and ``tau`` (an atan2) in [-pi, pi], where both leave a value as it is, so
    they are skipped with the same numbers as the result. OMPL's turn of ``tau`` by pi is left
    out as in the full search: its condition holds only by rounding.
    """
    delta = u - v
    a1 = math.sin(u) - math.sin(delta)
    b1 = math.cos(u) - math.cos(delta) - 1.0
    tau = math.atan2(eta * a1 - xi * b1, xi * a1 + eta * b1)
    omega = wrap_pi(tau - u + v - phi)
    return tau, omega


def _lrl(xi: float, eta: float, rho: float, phi: float) -> tuple[float, float, float] | None:
    """8.3/8.4 L+ R- L from (xi, eta) of norm ``rho`` <= 4."""
    fmod, pi, two_pi = math.fmod, _PI, TWO_PI
    u = -2.0 * math.asin(0.25 * rho)
    # atan2 + u/2 + pi lies in [-pi/2, 2 pi]: only the upper wrap can apply.
    t = fmod(math.atan2(eta, xi) + 0.5 * u + pi, two_pi)
    if t > pi:
        t -= two_pi
    if not (t >= -ZERO and u <= ZERO):
        return None
    v = wrap_pi(phi - t + u)
    return t, u, v


def _lrsl(xi: float, eta: float, rho: float, phi: float) -> tuple[float, ...] | None:
    """8.9 L+ R-(pi/2) S- L- from (xi, eta) of norm ``rho`` >= 2."""
    fmod, pi, two_pi = math.fmod, _PI, TWO_PI
    r = math.sqrt(max(rho * rho - 4.0, 0.0))
    u = 2.0 - r
    if not u <= ZERO:
        return None
    # atan2(r, -2) lies in [pi/2, pi] (r >= 0): the sum in [-pi/2, 2 pi] only wraps down.
    t = fmod(math.atan2(eta, xi) + math.atan2(r, -2.0), two_pi)
    if t > pi:
        t -= two_pi
    if not t >= -ZERO:
        return None
    v = wrap_pi(phi - HALF_PI - t)
    return (t, -HALF_PI, u, v) if v <= ZERO else None


def _lrsr(xi: float, eta: float, phi: float) -> tuple[float, ...] | None:
    """8.10 L+ R-(pi/2) S- R- from (xi, eta)."""
    rho = math.hypot(-eta, xi)
    if not rho >= 2.0:
        return None
    t = math.atan2(xi, -eta)
    u = 2.0 - rho
    if not (t >= -ZERO and u <= ZERO):
        return None
    v = wrap_pi(t + HALF_PI - phi)
    return (t, -HALF_PI, u, v) if v <= ZERO else None


def _turns_back(xi: float, eta: float) -> int:
    """Where the direction ``atan2(eta, xi)`` lies, clear of rounding: 2 beyond pi/2 (8.3/8.4
    and 8.9 then start with a turn that wraps below zero), 1 below -3 pi/4 (8.9's first turn,
    theta plus at most 3 pi/4, is below zero), else 0 (either may hold). Circles a rounding
    apart (xi near zero) give 0: 8.3's first turn, pi plus half its tiny middle arc, wraps to
    within :data:`ZERO` of zero and holds."""
    if xi > -1e-9:
        return 0
    if eta >= 0.0:
        return 2 if -xi > 1e-6 * eta else 0
    return 1 if -eta < 0.999 * -xi else 0


def _turned(angle: float) -> float:
    """``angle`` mod 2 pi, or 0 where rounding may carry a turn of almost 2 pi round to 0."""
    m = angle % TWO_PI
    return m if m < TWO_PI - SLACK else 0.0


def shortest(x: float, y: float, phi: float) -> tuple[int, tuple[float, ...]]:
    """The first shortest word to the goal ``(x, y, phi)`` (radii, rad) and its lengths.

    Returns:
        The index of the word among the formulas under the symmetries, in the order of
        :data:`diffbot.planning.reeds_shepp.WORDS`, and its lengths before the symmetry's sign
        (negated by a timeflip); -1 and none when no formula holds (a NaN or infinite
        goal).
    """
    atan2, hypot, sqrt = math.atan2, math.hypot, math.sqrt
    remainder = math.remainder
    pi, two_pi, half_pi, zero, slack, inf = _PI, TWO_PI, HALF_PI, ZERO, SLACK, math.inf
    try:
        s, c = math.sin(phi), math.cos(phi)
    except ValueError:  # an infinite heading: no formula holds
        return -1, ()
    # Heading bounds for phi and -phi (the symmetries' headings).
    w = abs(remainder(phi, two_pi))
    plus = (_turned(phi), abs(remainder(phi - half_pi, two_pi)), _turned(phi - half_pi))
    minus = (_turned(-phi), abs(remainder(-phi - half_pi, two_pi)), _turned(-phi - half_pi))
    best, found = inf, -1
    lengths: tuple[float, ...] = ()

    def offer(length: float, index: int, word: tuple[float, ...]) -> float:
        # Keeps the word if it is shorter, or as short and earlier in WORDS; returns the cut.
        nonlocal best, found, lengths
        if length < best or (length == best and index < found):
            best, found, lengths = length, index, word
        return best + SLACK * (1.0 + best)

    cut = inf  # the shortest so far plus the slack: bounds above it cannot win
    # Symmetry k: (x, y, phi), timeflip, reflect, both: the formulas' (xi, eta) = (x - s,
    # y - 1 + c) and (x + s, y - 1 - c) with the signs of x, y, s and phi changed, written as
    # the formulas write them (a - b and a + -b round alike, signed zeros included).
    lo, lo_cross, hi, hi_cross = y - 1.0 + c, y - 1.0 - c, -y - 1.0 + c, -y - 1.0 - c
    left_same, left_cross = hypot(x - s, lo), hypot(x + s, lo_cross)
    right_same, right_cross = hypot(x + s, hi), hypot(x - s, hi_cross)
    # What the circles' distances fix, shared by the symmetries: the straight of 8.2 (and
    # 8.11's), and the least straight and arcs of 8.9 and 8.10 (inf where they cannot hold).
    u1 = left_same * left_same
    left_lrsl = half_pi + sqrt(u1 - 4.0) - 2.0 if u1 >= 7.99 else inf
    u1 = right_same * right_same
    right_lrsl = half_pi + sqrt(u1 - 4.0) - 2.0 if u1 >= 7.99 else inf
    u1 = left_cross * left_cross
    left_lsr = sqrt(u1 - 4.0) if u1 >= 4.0 else -1.0
    left_lrsr = half_pi + left_cross - 2.0 if left_cross >= 2.0 - slack else inf
    u1 = right_cross * right_cross
    right_lsr = sqrt(u1 - 4.0) if u1 >= 4.0 else -1.0
    right_lrsr = half_pi + right_cross - 2.0 if right_cross >= 2.0 - slack else inf
    left = (left_same, left_cross, left_lrsl, left_lsr, left_lrsr)
    right = (right_same, right_cross, right_lrsl, right_lsr, right_lrsr)
    forward = (
        (0, phi, x - s, lo, x + s, lo_cross, left, plus),
        (1, -phi, -x + s, lo, -x - s, lo_cross, left, minus),
        (2, -phi, x + s, hi, x - s, hi_cross, right, minus),
        (3, phi, -x - s, hi, -x + s, hi_cross, right, plus),
    )
    for k, p, xi, eta, xj, ej, (da, _, _, u, _), (turned, _, _) in forward:
        # 8.1 LSL (t, rho, v): rho = da.
        if da + turned <= cut:
            theta = atan2(eta, xi)
            if theta >= -zero:
                v = wrap_pi(p - theta)
                if v >= -zero:
                    length = abs(theta) + da + abs(v)
                    cut = offer(length, k, (theta, da, v))
        # 8.2 LSR.
        if u >= 0.0 and u + w <= cut:
            t = wrap_pi(atan2(ej, xj) + atan2(2.0, u))
            if t >= -zero:
                v = wrap_pi(t - p)
                if v >= -zero:
                    length = abs(t) + u + abs(v)
                    cut = offer(length, 4 + k, (t, u, v))
    # The others, once the shortest of those two gives their bounds something to cut. Whole
    # families drop out at once where no symmetry's circles are near enough.
    near_same = min(left_same, right_same) <= 4.0 + slack and w <= cut
    near_cross = min(left_cross, right_cross) <= 4.5 and w <= cut
    for k, p, xi, eta, xj, ej, (da, db, lrsl_low, straight, lrsr_low), headings in forward:
        quarter, quarter_turned = headings[1], headings[2]
        # 8.3 LRL, forwards.
        if near_same and da <= 4.0 and _turns_back(xi, eta) < 2:
            lrl = _lrl(xi, eta, da, p)
            if lrl is not None:
                t, u, v = lrl
                length = abs(t) + abs(u) + abs(v)
                cut = offer(length, 8 + k, lrl)
        if near_cross:
            # 8.7 LR+L-R (rho <= 1) and 8.8 L-R+L-R (0 <= rho <= 1): at most one holds.
            if db <= 2.0 + slack and w <= cut:
                rho = 0.25 * (2.0 + db)
                if rho <= 1.0:
                    u = math.acos(rho)
                    t, v = _tau_omega(u, -u, xj, ej, p)
                    if t >= -zero and v <= zero:
                        length = abs(t) + abs(u) + abs(-u) + abs(v)
                        cut = offer(length, 16 + k, (t, u, -u, v))
            if 1.9 <= db <= 4.5 and w <= cut:
                rho = (20.0 - xj * xj - ej * ej) / 16.0
                if rho >= 0.0 and rho <= 1.0:
                    u = -math.acos(rho)
                    # Its arcs: 2 |u|, and t + v >= |phi| wrapped (t - v is phi).
                    if u >= -half_pi and w - 2.0 * u <= cut:
                        t, v = _tau_omega(u, u, xj, ej, p)
                        if t >= -zero and v >= -zero:
                            length = abs(t) + abs(u) + abs(u) + abs(v)
                            cut = offer(length, 20 + k, (t, u, u, v))
        # 8.9 LRSL, forwards.
        if lrsl_low + quarter <= cut and _turns_back(xi, eta) == 0:
            lrsl = _lrsl(xi, eta, da, p)
            if lrsl is not None:
                t, _, u, v = lrsl
                length = abs(t) + half_pi + abs(u) + abs(v)
                cut = offer(length, 24 + k, lrsl)
        # 8.10 LRSR, forwards.
        if lrsr_low + quarter_turned <= cut and (xj >= 0.0 or (ej < 0.0 and -xj <= 1e-9 * -ej)):
            lrsr = _lrsr(xj, ej, p)
            if lrsr is not None:
                t, _, u, v = lrsr
                length = abs(t) + half_pi + abs(u) + abs(v)
                cut = offer(length, 28 + k, lrsr)
        # 8.11 LRSLR: its straight is 4 - 8.2's.
        if db * db >= 20.0 - slack and straight >= 0.0 and pi + w + straight - 4.0 <= cut:
            u = 4.0 - straight
            if u <= zero and db >= 2.0:
                t = wrap_pi(atan2((4.0 - u) * xj - 2.0 * ej, -2.0 * xj + (u - 4.0) * ej))
                if t >= -zero:
                    v = wrap_pi(t - p)
                    if v >= -zero:
                        length = abs(t) + half_pi + abs(u) + half_pi + abs(v)
                        cut = offer(length, 40 + k, (t, -half_pi, u, -half_pi, v))
    # The formulas read backwards (8.4, 8.9 and 8.10 from the goal): the same four distances,
    # the cross ones swapped between the symmetries.
    xb, yb = x * c + y * s, x * s - y * c
    lo, lo_cross, hi, hi_cross = yb - 1.0 + c, yb - 1.0 - c, -yb - 1.0 + c, -yb - 1.0 - c
    backward = (
        (0, phi, xb - s, lo, xb + s, lo_cross, left_same, left_lrsl, right_lrsr, plus),
        (1, -phi, -xb + s, lo, -xb - s, lo_cross, left_same, left_lrsl, right_lrsr, minus),
        (2, -phi, xb + s, hi, xb - s, hi_cross, right_same, right_lrsl, left_lrsr, minus),
        (3, phi, -xb - s, hi, -xb + s, hi_cross, right_same, right_lrsl, left_lrsr, plus),
    )
    for k, p, xi, eta, xj, ej, da, lrsl_low, lrsr_low, headings in backward:
        try_lrl = near_same and da <= 4.0 + slack
        try_lrsl = lrsl_low + headings[1] <= cut
        if (try_lrl or try_lrsl) and (back := _turns_back(xi, eta)) < 2:
            rho = hypot(xi, eta)
            if try_lrl and rho <= 4.0:
                lrl = _lrl(xi, eta, rho, p)
                if lrl is not None:
                    t, u, v = lrl
                    length = abs(v) + abs(u) + abs(t)
                    cut = offer(length, 12 + k, (v, u, t))
            if try_lrsl and back == 0 and rho >= 2.0:
                lrsl = _lrsl(xi, eta, rho, p)
                if lrsl is not None:
                    t, _, u, v = lrsl
                    length = abs(v) + abs(u) + half_pi + abs(t)
                    cut = offer(length, 32 + k, (v, u, -half_pi, t))
        if lrsr_low + headings[2] <= cut and (xj >= 0.0 or (ej < 0.0 and -xj <= 1e-9 * -ej)):
            lrsr = _lrsr(xj, ej, p)
            if lrsr is not None:
                t, _, u, v = lrsr
                length = abs(v) + abs(u) + half_pi + abs(t)
                cut = offer(length, 36 + k, (v, u, -half_pi, t))
    return found, lengths
