"""The arrival phase of a :class:`diffbot.follow.Follower`: past the plan's end, the final pose
held (the equations are in :mod:`diffbot.follow`'s notes)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Final

if TYPE_CHECKING:
    from diffbot.follow import Gains

__all__ = ["Arrival"]

_TWO_PI = 2.0 * math.pi
#: Bearing error (rad) under which the arrival drives toward the goal point.
DRIVE_BEARING: Final = 0.3


class Arrival:
    """Stabilises a robot at a goal pose: call :meth:`command` at every control step.

    Args:
        x, y, heading: the goal pose (m, m, rad).
        gains: the follower's gains (``kx``, ``kspin``).
        tolerance: the follower's ``xy_tolerance`` (m).
    """

    def __init__(self, x: float, y: float, heading: float, gains: Gains, tolerance: float) -> None:
        self.goal = (x, y, heading)
        self.gains = gains
        self.tolerance = tolerance
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
        if not self.approach:
            return g.kx * ex, g.kspin * math.sin(eh)
        way = 1.0 if ex >= 0.0 else -1.0
        bearing = math.atan2(way * ey, way * ex)
        v = way * g.kx * distance * math.cos(bearing) if abs(bearing) < DRIVE_BEARING else 0.0
        return v, g.kspin * bearing
