"""Regulated pure pursuit along a plan's path, without its timing (the ``pure-pursuit`` law of
:class:`diffbot.follow.Follower`; the equations are in that module's notes).

The plan's straights and arcs are sampled into legs, each driven in one direction; a spin or a
change of direction ends a leg, and the next one starts with a turn in place to its heading. A
spin is a leg of its own, a turn in place by its signed angle. The legs are taken in the plan's
order, and the progress along a leg only moves forward: a leg is done once its end is near
along the path, not merely near in space, as a loop's end is at its start. Turns compare the
robot's heading counted in whole turns (from the pose's changes between calls) with the heading
the plan accumulates, so a spin of 360 or 270 degrees turns that far, the plan's way.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Final

from diffbot.arrival import AxisBrake, stopping_speed

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
    """Points along a piece of path driven in one direction, or a turn in place.

    Attributes:
        xs, ys: the points (m), the first the leg's start, the last its end; a turn in place
            has its start point only.
        lengths: path length from the leg's start to each point (m).
        speeds: the plan's speed along the path at each point (m/s, > 0).
        direction: +1 driving forward, -1 backwards (+1 for a turn in place).
        from_heading: the plan's heading where the leg starts (rad, not wrapped).
        start_heading: the heading to turn to before driving (rad, not wrapped): a spin's
            end heading for a turn in place, else ``from_heading``.
    """

    __slots__ = ("direction", "from_heading", "lengths", "speeds", "start_heading", "xs", "ys")

    def __init__(
        self, direction: float, x: float, y: float, heading: float, turn: float = 0.0
    ) -> None:
        self.direction = direction
        self.xs, self.ys = [x], [y]
        self.lengths = [0.0]
        self.speeds = [0.0]
        self.from_heading = heading
        self.start_heading = heading + turn

    @property
    def moves(self) -> bool:
        """Whether the leg drives (else it is a turn in place)."""
        return len(self.xs) > 1


def legs(plan: Plan, spacing: float) -> list[Leg]:
    """The plan's path as legs with points at most ``spacing`` (m) apart, and a turn in place
    for each spin, in the plan's order."""
    from diffbot.trajectory import advance, geometry

    found: list[Leg] = []
    current: Leg | None = None
    heading = 0.0
    for planned in plan.segments:
        ds, turn = geometry(planned.segment)
        start = planned.start_pose
        if abs(ds) <= _NO_LENGTH:
            current = None  # a spin (or nothing): the next motion starts a new leg
            if turn:
                found.append(Leg(1.0, start.x, start.y, heading, turn))
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
    """The state of a regulated pure pursuit along a plan: which leg, where along it, and the
    robot's heading counted in whole turns.

    Args:
        plan: the step plan whose path is followed.
        gains: the follower's gains (``kspin``, ``min_radius``, ``approach``, ``creep``).
        lookahead: the lookahead distance (m), > 0.
        tolerance: the distance (m) from a leg's end at which it counts as reached.
        brakes: the (linear, angular) acceleration and jerk limits the commands go through: a
            turn in place and the approach to a leg's end go no faster than they can stop
            (:func:`diffbot.arrival.stopping_speed`).
    """

    def __init__(
        self,
        plan: Plan,
        gains: Gains,
        lookahead: float,
        tolerance: float,
        brakes: tuple[AxisBrake, AxisBrake] = ((None, None), (None, None)),
    ) -> None:
        self.gains = gains
        self.brakes = brakes
        self.lookahead = lookahead
        self.tolerance = tolerance
        self.legs = legs(plan, min(0.01, 0.25 * lookahead))
        self.leg = 0
        self.index = 0
        self.ahead = 0
        self.turning = True
        #: The robot's heading (rad, not wrapped), from the headings given to :meth:`update`.
        self.heading = 0.0
        self._theta: float | None = None
        #: True once every leg is driven and turned: the follower's arrival phase takes over.
        self.finished = not self.legs

    def update(self, x: float, y: float, theta: float) -> bool:
        """Advance along the path for the robot at ``(x, y, theta)`` (m, m, rad, wrapped or
        not); return :attr:`finished`. Call it at every control step: the heading is counted
        from its change since the last call, which must be under half a turn."""
        self._count_turns(theta)
        while not self.finished:
            leg = self.legs[self.leg]
            if self.turning:
                if abs(leg.start_heading - self.heading) > TURN_DONE:
                    return False
                self.turning = False
            if leg.moves:
                self._closest(leg, x, y)
                if not self._leg_done(leg, x, y, theta):
                    return False
            self.leg += 1
            self.index = self.ahead = 0
            self.turning = True
            if self.leg == len(self.legs):
                self.finished = True
            else:
                self._anchor(self.legs[self.leg].from_heading)
        return True

    def _count_turns(self, theta: float) -> None:
        """Move :attr:`heading` by the change of ``theta`` (rad) since the last call."""
        last = self._theta
        self._theta = theta
        if last is None:
            self.heading = theta
            self._anchor(self.legs[self.leg].from_heading if self.legs else 0.0)
        else:
            self.heading += math.remainder(theta - last, _TWO_PI)

    def _anchor(self, planned: float) -> None:
        """Take as :attr:`heading` the robot's heading nearest ``planned`` (rad), the plan's
        heading where a leg starts: a whole turn the robot made that the plan did not is not
        turned back, and from there every turn of the plan is made in full."""
        self.heading = planned + math.remainder(self.heading - planned, _TWO_PI)

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
        """Whether the robot has driven the leg: its progress along the path has come within
        the lookahead of the end (a leg that ends where it starts is not done at its start),
        and it is within the tolerance of the end or past it (behind it in the direction of
        travel)."""
        if leg.lengths[-1] - leg.lengths[self.index] >= self.lookahead:
            return False
        dx, dy = leg.xs[-1] - x, leg.ys[-1] - y
        if dx * dx + dy * dy <= self.tolerance * self.tolerance:
            return True
        return leg.direction * (math.cos(theta) * dx + math.sin(theta) * dy) <= 0.0

    def command(self, x: float, y: float, theta: float) -> tuple[float, float]:
        """The command (m/s, rad/s) for the robot at ``(x, y, theta)`` after :meth:`update`."""
        leg = self.legs[self.leg]
        g = self.gains
        if self.turning:
            return 0.0, self._turn(leg.start_heading - self.heading)
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
            return 0.0, self._turn(angle)
        kappa = 2.0 * ly / square if square > 0.0 else 0.0
        speed = leg.speeds[i]
        if abs(kappa) * g.min_radius > 1.0:
            speed /= abs(kappa) * g.min_radius
        remaining = leg.lengths[-1] - leg.lengths[i]
        if remaining < g.approach:
            speed = max(speed * remaining / g.approach, min(g.creep, leg.speeds[i]))
        # Slow enough to stop at the leg's end, the path length left.
        speed = min(speed, stopping_speed(remaining, self.brakes[0]))
        if kappa:
            # The turn rate v kappa stops too, within the turn the leg has left.
            turn_left = abs(kappa) * max(remaining, 0.0)
            speed = min(speed, stopping_speed(turn_left, self.brakes[1]) / abs(kappa))
        v = direction * speed
        return v, v * kappa

    def _turn(self, angle: float) -> float:
        """The turn rate (rad/s) toward a heading ``angle`` (rad) away, that can stop there."""
        top = stopping_speed(abs(angle), self.brakes[1])
        return min(max(self.gains.kspin * angle, -top), top)
