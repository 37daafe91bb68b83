"""The arrival phase of a :class:`diffbot.follow.Follower`: past the plan's end, the final pose
held (the equations are in :mod:`diffbot.follow`'s notes), and the speed from which the
follower's acceleration and jerk limits still stop the robot within a distance.

A proportional law toward a goal that does not move (the arrival, pure pursuit's turns in place
and its approach to a leg's end) asks a speed that the limits may not be able to take back in
time: through an acceleration limit ``A`` the robot coasts ``v²/(2A)`` before it stops, and
through a jerk limit ``J`` the braking itself only builds up at ``J``. Such a law overshoots,
comes back faster, and swings ever wider. :func:`stopping_speed` bounds it: the fastest speed
from which braking at half the limits stops within the distance left, so that each approach
brakes in time and ends at rest on the goal."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Final

if TYPE_CHECKING:
    from diffbot.follow import Gains

__all__ = ["Arrival", "AxisBrake", "stopping_speed"]

_TWO_PI = 2.0 * math.pi
#: Bearing error (rad) under which the arrival drives toward the goal point.
DRIVE_BEARING: Final = 0.3
#: The share of the acceleration and jerk limits a braking speed counts on: the rest is left
#: for the command's hold between control steps and for the feedback.
BRAKE_SHARE: Final = 0.5

#: The (acceleration, jerk) limits of one axis (unit/s², unit/s³; None: unlimited).
AxisBrake = tuple[float | None, float | None]


def stopping_speed(distance: float, brake: AxisBrake) -> float:
    """The fastest speed (unit/s) from which braking within ``BRAKE_SHARE`` of the axis limits
    ``brake`` = (acceleration unit/s², jerk unit/s³) stops within ``distance`` (unit, >= 0);
    infinite without limits.

    The diff_drive_controller's limiter eases an acceleration off at once and builds one up at
    the jerk limit ``J``, to at most ``A``: from ``u`` it brakes with a deceleration growing at
    ``J`` for ``t1 = A/J`` (while ``u > A²/(2J)``), then at ``A``. So it stops within
    ``(2/3) u sqrt(2u/J)`` when ``u <= c = A²/(2J)``, else ``u A/J - A³/(6J²) + (u - c)²/(2A)``;
    inverted, ``u = (1.5 d sqrt(J/2))^(2/3)``, else ``u = sqrt(4c²/3 + 2 A d) - c``
    (``sqrt(2 A d)`` without a jerk limit)."""
    accel, jerk = brake
    if accel is None and jerk is None:
        return math.inf
    if distance <= 0.0:
        return 0.0
    if jerk is None:
        return math.sqrt(2.0 * BRAKE_SHARE * (accel or 0.0) * distance)
    jerk *= BRAKE_SHARE
    ramp_only = float((1.5 * distance * math.sqrt(0.5 * jerk)) ** (2.0 / 3.0))
    if accel is None:
        return ramp_only
    accel *= BRAKE_SHARE
    corner = accel * accel / (2.0 * jerk)
    if ramp_only <= corner:
        return ramp_only
    return float(math.sqrt(4.0 * corner * corner / 3.0 + 2.0 * accel * distance) - corner)


def _capped(value: float, distance: float, brake: AxisBrake) -> float:
    """``value`` (unit/s) with its magnitude at most :func:`stopping_speed` of ``distance``."""
    top = stopping_speed(abs(distance), brake)
    return min(max(value, -top), top)


class Arrival:
    """Stabilises a robot at a goal pose: call :meth:`command` at every control step.

    Args:
        x, y, heading: the goal pose (m, m, rad).
        gains: the follower's gains (``kx``, ``kspin``).
        tolerance: the follower's ``xy_tolerance`` (m).
        brakes: the (linear, angular) :data:`AxisBrake` limits its commands go through: each
            command is at most the speed that stops within the error left (m, rad).
    """

    def __init__(
        self,
        x: float,
        y: float,
        heading: float,
        gains: Gains,
        tolerance: float,
        brakes: tuple[AxisBrake, AxisBrake] = ((None, None), (None, None)),
    ) -> None:
        self.goal = (x, y, heading)
        self.gains = gains
        self.tolerance = tolerance
        self.brakes = brakes
        #: Whether it is driving toward the goal point (else aligning on the spot).
        self.approach = False

    def command(self, x: float, y: float, theta: float) -> tuple[float, float]:
        """The command (m/s, rad/s) for the robot at ``(x, y, theta)`` (m, m, rad)."""
        gx, gy, gh = self.goal
        g, tol = self.gains, self.tolerance
        dx, dy = gx - x, gy - y
        cos_t, sin_t = math.cos(theta), math.sin(theta)
        ex = cos_t * dx + sin_t * dy
        ey = cos_t * dy - sin_t * dx
        eh = math.remainder(gh - theta, _TWO_PI)
        distance = math.hypot(dx, dy)
        # Wide hysteresis: a noisy pose source (a millimetre) must not toggle the phases.
        if self.approach:
            self.approach = distance > 0.4 * tol
        else:
            self.approach = abs(ey) > 0.6 * tol and distance > tol
        linear, angular = self.brakes
        if not self.approach:
            return _capped(g.kx * ex, ex, linear), _capped(g.kspin * math.sin(eh), eh, angular)
        way = 1.0 if ex >= 0.0 else -1.0
        bearing = math.atan2(way * ey, way * ex)
        v = way * g.kx * distance * math.cos(bearing) if abs(bearing) < DRIVE_BEARING else 0.0
        return _capped(v, distance, linear), _capped(g.kspin * bearing, bearing, angular)
