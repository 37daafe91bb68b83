"""Regulated pure pursuit along a plan's path, without its timing (the ``pure-pursuit`` law of
:class:`diffbot.follow.Follower`; the equations are in that module's notes).

The plan's straights and arcs are sampled into legs, each driven in one direction; a spin or a
change of direction ends a leg, and the next one starts with a turn in place to its heading.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Final

if TYPE_CHECKING:
    from diffbot.follow import Gains
    from diffbot.trajectory import Plan

__all__ = ["Leg", "Pursuit", "legs"]

_TWO_PI = 2.0 * math.pi
#: Angle (rad) between the way the robot drives and the lookahead point beyond which it turns
#: in place first (Nav2's rotate_to_heading_min_angle).
ROTATE_MIN_ANGLE: Final = math.pi / 4.0
#: Heading error (rad) at which a turn in place between legs ends.
TURN_DONE: Final = math.radians(2.0)
#: Path lengths below this (m) are no leg: rounding, not motion.
_NO_LENGTH = 1e-9


class Leg:
    """Points along a piece of path driven in one direction.

    Attributes:
        xs, ys: the points (m), the first the leg's start, the last its end.
        lengths: path length from the leg's start to each point (m).
        speeds: the plan's speed along the path at each point (m/s, > 0).
        direction: +1 driving forward, -1 backwards.
        start_heading: the robot's heading at the start (rad, not wrapped).
    """

    __slots__ = ("direction", "lengths", "speeds", "start_heading", "xs", "ys")

    def __init__(self, direction: float, x: float, y: float, heading: float) -> None:
        self.direction = direction
        self.xs, self.ys = [x], [y]
        self.lengths = [0.0]
        self.speeds = [0.0]
        self.start_heading = heading


def legs(plan: Plan, spacing: float) -> list[Leg]:
    """The plan's path as legs with points at most ``spacing`` (m) apart."""
    from diffbot.trajectory import advance, geometry

    found: list[Leg] = []
    current: Leg | None = None
    heading = 0.0
    for planned in plan.segments:
        ds, turn = geometry(planned.segment)
        start = planned.start_pose
        if abs(ds) <= _NO_LENGTH:
            current = None  # a spin (or nothing): the next motion starts a new leg
            heading += turn
            continue
        direction = 1.0 if ds > 0.0 else -1.0
        if current is None or current.direction != direction:
            current = Leg(direction, start.x, start.y, heading)
            found.append(current)
        speed = abs(ds) / planned.duration
        current.speeds[-1] = speed
        count = max(1, math.ceil(abs(ds) / spacing))
        base = current.lengths[-1]
        for k in range(1, count + 1):
            share = k / count
            pose = advance(start.x, start.y, heading, ds * share, turn * share)
            current.xs.append(pose.x)
            current.ys.append(pose.y)
            current.lengths.append(base + abs(ds) * share)
            current.speeds.append(speed)
        heading += turn
    return found


class Pursuit:
    """The state of a regulated pure pursuit along a plan: which leg, where along it.

    Args:
        plan: the step plan whose path is followed.
        gains: the follower's gains (``kspin``, ``min_radius``, ``approach``, ``creep``).
        lookahead: the lookahead distance (m), > 0.
        tolerance: the distance (m) from a leg's end at which it counts as reached.
    """

    def __init__(self, plan: Plan, gains: Gains, lookahead: float, tolerance: float) -> None:
        self.gains = gains
        self.lookahead = lookahead
        self.tolerance = tolerance
        self.legs = legs(plan, min(0.01, 0.25 * lookahead))
        self.leg = 0
        self.index = 0
        self.ahead = 0
        self.turning = True
        #: True once the last leg is reached: the follower's arrival phase takes over.
        self.finished = not self.legs

    def update(self, x: float, y: float, theta: float) -> bool:
        """Advance along the path for the robot at ``(x, y, theta)``; return :attr:`finished`."""
        while not self.finished:
            leg = self.legs[self.leg]
            if self.turning:
                if abs(math.remainder(leg.start_heading - theta, _TWO_PI)) > TURN_DONE:
                    return False
                self.turning = False
            self._closest(leg, x, y)
            if not self._leg_done(leg, x, y, theta):
                return False
            self.leg += 1
            self.index = self.ahead = 0
            self.turning = True
            if self.leg == len(self.legs):
                self.finished = True
        return True

    def _closest(self, leg: Leg, x: float, y: float) -> None:
        """Move :attr:`index` forward to the point nearest the robot (a local search: the
        path may come back near itself)."""
        xs, ys, i = leg.xs, leg.ys, self.index
        last = len(xs) - 1
        best = (xs[i] - x) ** 2 + (ys[i] - y) ** 2
        while i < last:
            distance = (xs[i + 1] - x) ** 2 + (ys[i + 1] - y) ** 2
            if distance > best:
                break
            best, i = distance, i + 1
        self.index = i

    def _leg_done(self, leg: Leg, x: float, y: float, theta: float) -> bool:
        """Whether the robot has reached the leg's end: within the tolerance of it, or past it
        (behind it in the direction of travel) with the end within the lookahead."""
        dx, dy = leg.xs[-1] - x, leg.ys[-1] - y
        distance_squared = dx * dx + dy * dy
        if distance_squared <= self.tolerance * self.tolerance:
            return True
        ahead = leg.direction * (math.cos(theta) * dx + math.sin(theta) * dy)
        remaining = leg.lengths[-1] - leg.lengths[self.index]
        return ahead <= 0.0 and remaining < self.lookahead

    def command(self, x: float, y: float, theta: float) -> tuple[float, float]:
        """The command (m/s, rad/s) for the robot at ``(x, y, theta)`` after :meth:`update`."""
        leg = self.legs[self.leg]
        g = self.gains
        if self.turning:
            return 0.0, g.kspin * math.remainder(leg.start_heading - theta, _TWO_PI)
        xs, ys, i = leg.xs, leg.ys, self.index
        last = len(xs) - 1
        reach = self.lookahead * self.lookahead
        # The first point from the nearest on that lies outside the lookahead circle, searched
        # from where it was last time (it moves little between calls).
        k = min(max(self.ahead, i + 1), last)
        while k > i + 1 and (xs[k - 1] - x) ** 2 + (ys[k - 1] - y) ** 2 >= reach:
            k -= 1
        outside = (xs[k] - x) ** 2 + (ys[k] - y) ** 2
        while outside < reach and k < last:
            k += 1
            outside = (xs[k] - x) ** 2 + (ys[k] - y) ** 2
        self.ahead = k
        if outside >= reach:
            # Between point k - 1 (inside the circle) and k (outside), by squared distance.
            inside = (xs[k - 1] - x) ** 2 + (ys[k - 1] - y) ** 2
            share = (reach - inside) / (outside - inside) if outside > inside else 1.0
            share = min(max(share, 0.0), 1.0)
            px = xs[k - 1] + share * (xs[k] - xs[k - 1])
            py = ys[k - 1] + share * (ys[k] - ys[k - 1])
        else:
            px, py = xs[last], ys[last]
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        dx, dy = px - x, py - y
        lx = cos_t * dx + sin_t * dy
        ly = cos_t * dy - sin_t * dx
        square = lx * lx + ly * ly
        direction = leg.direction
        angle = math.atan2(direction * ly, direction * lx)
        if abs(angle) > ROTATE_MIN_ANGLE:
            return 0.0, g.kspin * angle
        kappa = 2.0 * ly / square if square > 0.0 else 0.0
        speed = leg.speeds[i]
        if abs(kappa) * g.min_radius > 1.0:
            speed /= abs(kappa) * g.min_radius
        remaining = leg.lengths[-1] - leg.lengths[i]
        if remaining < g.approach:
            speed = max(speed * remaining / g.approach, min(g.creep, leg.speeds[i]))
        v = direction * speed
        return v, v * kappa
