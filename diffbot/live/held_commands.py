"""Open-loop odometry as it happens: each body velocity command held until the next one.

diff_drive_controller with ``open_loop: true`` integrates the command it holds at every update
instead of the wheels' feedback (``try_update_open_loop``), and holds a command until the next
comes or until it is ``cmd_vel_timeout`` old, when it stops; its speed limiter acts after the
odometry, on the wheels' commands only. :class:`HeldCommands` does the same
on a wall clock: each command moves the robot along the arc of its linear and angular velocity
until the next command or the timeout, whichever comes first, and not at all after. The arcs are
integrated in closed form by :class:`~diffbot.odometry.Odometry`, fed the wheel angles the
commands turn the wheels through (as :func:`diffbot.open_loop.command_angles` does for a
recording), so its twist and covariances are those of wheel odometry.
"""

from __future__ import annotations

from diffbot.kinematics import DiffDriveParams
from diffbot.odometry import Odometry
from diffbot.samples import NS_PER_S

__all__ = ["HeldCommands"]


class HeldCommands:
    """Commands (m/s, rad/s) held on a clock of integer nanoseconds, integrated into ``odometry``.

    Args:
        params: the robot (radii, separation, direction signs).
        odometry: the integrator the held commands move (its feedback ``position``).
        timeout: seconds after its arrival when a command stops holding (0: never).
    """

    def __init__(self, params: DiffDriveParams, odometry: Odometry, timeout: float) -> None:
        self.odometry = odometry
        left_radius, right_radius = params.radii
        left = 1.0 / (params.left_sign * left_radius)
        right = 1.0 / (params.right_sign * right_radius)
        half = 0.5 * params.wheel_separation
        # Wheel angle (rad) per metre of linear and per radian of angular motion, each side.
        self._left = (left, -half * left)
        self._right = (right, half * right)
        # A positive timeout stays positive (at least 1 ns): 0 alone means never.
        self._timeout_ns = max(round(timeout * NS_PER_S), 1) if timeout > 0.0 else 0
        self._angles = [0.0, 0.0]
        self._held = (0.0, 0.0)
        self._since: int | None = None
        self._until: int | None = None

    @property
    def held(self) -> tuple[float, float]:
        """The command held now: (linear (m/s), angular (rad/s)); zeros before any or after
        the timeout."""
        return self._held

    def command(self, linear: float, angular: float, now_ns: int) -> None:
        """Hold (``linear``, ``angular``) from ``now_ns`` on, after moving by the command held
        until then."""
        self.advance(now_ns)
        self._held = (linear, angular)
        if self._timeout_ns > 0:
            self._until = now_ns + self._timeout_ns

    def advance(self, now_ns: int) -> bool:
        """Move the odometry by the held command up to ``now_ns`` (a time not after the last is
        ignored). Returns whether the odometry took a sample."""
        since = self._since
        if since is None:
            self._since = now_ns
            return self.odometry.update(0.0, 0.0, stamp_ns=now_ns)
        if now_ns <= since:
            return False
        until = self._until
        if until is not None and until < now_ns:
            if until > since:
                self._move(until - since)
                self.odometry.update(*self._angles, stamp_ns=until)
                since = until
            self._held = (0.0, 0.0)
            self._until = None
        self._move(now_ns - since)
        self._since = now_ns
        return self.odometry.update(*self._angles, stamp_ns=now_ns)

    def _move(self, dt_ns: int) -> None:
        linear, angular = self._held
        dt = dt_ns / NS_PER_S
        self._angles[0] += (self._left[0] * linear + self._left[1] * angular) * dt
        self._angles[1] += (self._right[0] * linear + self._right[1] * angular) * dt
