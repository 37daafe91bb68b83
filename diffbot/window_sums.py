"""The sums of the last few steps of a stream, in constant time per step.

Odometry's velocity over a rolling window (``velocity_rolling_window_size``) is the sum of the
window's displacements over the sum of its times. Summing the window again at each step costs
its size per step (a window of a million steps made each joint state cost a million additions);
a running total from which the oldest step is subtracted is fast but keeps the rounding of every
step it ever held, so a robot at rest may report a velocity of 1e-17. :class:`WindowSums` keeps
the window as two stacks: the newer steps with their running sum, the older ones with the sums
of each and every newer step among them, built when the older stack runs empty. Each step is
added a bounded number of times, and every sum holds only steps still in the window: a window
of zero steps sums to exactly zero.
"""

from __future__ import annotations

__all__ = ["RollingVelocity", "WindowSums"]

Step = tuple[float, float, float]
_ZERO: Step = (0.0, 0.0, 0.0)


def _add(a: Step, b: Step) -> Step:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


class WindowSums:
    """The component sums of the last ``size`` steps of three numbers each.

    Args:
        size: how many steps the window holds (at least 1).
    """

    def __init__(self, size: int) -> None:
        self.size = size
        #: The older steps, oldest last: each the sum of itself and every newer older step.
        self._older: list[Step] = []
        #: The newer steps, newest last, and their sum.
        self._newer: list[Step] = []
        self._newer_sum = _ZERO

    def __len__(self) -> int:
        return len(self._older) + len(self._newer)

    def push(self, step: Step) -> Step:
        """Add ``step``, drop the oldest when the window is full; the window's sums."""
        self._newer.append(step)
        self._newer_sum = _add(self._newer_sum, step)
        if len(self) > self.size:
            if not self._older:
                total = _ZERO
                for newer in reversed(self._newer):
                    total = _add(newer, total)
                    self._older.append(total)
                self._newer.clear()
                self._newer_sum = _ZERO
            self._older.pop()
        return self.sums()

    def sums(self) -> Step:
        """The sums of the steps in the window (zeros when it is empty)."""
        if not self._older:
            return self._newer_sum
        return _add(self._older[-1], self._newer_sum)

    def clear(self) -> None:
        """Forget every step."""
        self._older.clear()
        self._newer.clear()
        self._newer_sum = _ZERO


class RollingVelocity:
    """The velocity over the last ``size`` steps of a stream of poses, each given with its
    stamp and the velocity over the step that ends at it: the window's displacement over the
    window's time, as :class:`diffbot.Odometry` with ``velocity_rolling_window_size=size``
    (and so ``node odom``) gives it.

    Args:
        size: how many steps the window holds (at least 1).
    """

    def __init__(self, size: int) -> None:
        self._sums = WindowSums(size)
        self._last_ns: int | None = None

    def restart(self) -> None:
        """Forget every step: the next pose is a baseline again."""
        self._sums.clear()
        self._last_ns = None

    def __call__(
        self, stamps_ns: list[int], linear: list[float], angular: list[float]
    ) -> tuple[list[float], list[float]]:
        """The windowed linear and angular velocities of the next poses (a baseline, the first
        pose after a start or restart, keeps its own: it ends no step)."""
        out_linear: list[float] = []
        out_angular: list[float] = []
        for stamp, v, w in zip(stamps_ns, linear, angular, strict=True):
            last, self._last_ns = self._last_ns, stamp
            if last is None:
                out_linear.append(v)
                out_angular.append(w)
                continue
            dt = (stamp - last) / 1e9
            distance, turn, time = self._sums.push((v * dt, w * dt, dt))
            out_linear.append(distance / time)
            out_angular.append(turn / time)
        return out_linear, out_angular
