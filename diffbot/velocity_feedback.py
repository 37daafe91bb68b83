"""Wheel angles from recorded wheel velocities, for robots that report velocities only.

ros2_controllers' diff_drive_controller with ``position_feedback: false`` reads each wheel's
velocity feedback at every update and moves the odometry by that velocity times the wheel
radius times the update's period, the time since the previous update (``update_from_vel`` in its
``odometry.cpp``; ``updateFromVelocity(left_feedback_mean * left_wheel_radius *
period.seconds(), ...)`` in the releases before). The velocity read at a sample thus holds over
the interval that *ends* at that sample.

:class:`VelocityAngles` does the same to recorded samples: each wheel's angle advances by its
velocity at sample k times ``t_k - t_(k-1)``, the time since that wheel's previous usable
sample. The angles then go to the exact integrator as recorded positions would: with velocities
constant between samples (piecewise constant, each sample's own velocity over the interval
before it) the integration is exact. The first usable sample of each wheel sets its angle to 0
(it only starts the clock, as the first position sample sets the encoder baseline).

A wheel's sample is usable when it is present, finite and stamped after that wheel's previous
usable sample; a NaN velocity is passed on as NaN (the integrator skips the sample as not
finite) and the next usable velocity holds over the whole gap, as the controller's next update
spans the missed one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from diffbot.errors import ParameterError
from diffbot.samples import NS_PER_S

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

__all__ = ["FEEDBACKS", "VelocityAngles", "check_feedback"]

#: What odometry may be computed from: wheel positions, or wheel velocities.
FEEDBACKS: Final = ("position", "velocity")


def check_feedback(feedback: str) -> str:
    """``feedback`` when it is one of :data:`FEEDBACKS`.

    Raises:
        ParameterError: anything else (the message names ``feedback``).
    """
    if feedback not in FEEDBACKS:
        raise ParameterError(
            f"{{feedback}} {feedback!r}: expected {' or '.join(repr(f) for f in FEEDBACKS)}"
        )
    return feedback


class VelocityAngles:
    """Wheel velocities (rad/s) turned into wheel angles (rad), chunk by chunk.

    Args:
        joints: how many wheel columns a chunk has.
    """

    def __init__(self, joints: int) -> None:
        import numpy as np  # here: the streaming Odometry imports this module, not NumPy

        self._angle = np.zeros(joints)
        #: Each wheel's last usable stamp (ns); meaningful where ``_started``.
        self._last_ns = np.zeros(joints, dtype=np.int64)
        self._started = np.zeros(joints, dtype=np.bool_)

    def feed(
        self, stamps_ns: ArrayLike, velocities: ArrayLike, present: ArrayLike
    ) -> NDArray[np.float64]:
        """The wheel angles at the samples of the next chunk, in recording order.

        Args:
            stamps_ns: the samples' stamps (ns), int64, shape (n,).
            velocities: the wheels' velocities (rad/s), float64, shape (n, joints).
            present: whether each sample holds each wheel's velocity, bool, shape (n, joints).

        Returns:
            The angles (rad), float64, shape (n, joints): NaN where the velocity is NaN or
            infinite, the wheel's last angle where the stamp is not after its last usable one,
            0.0 where the wheel is absent.
        """
        import numpy as np

        stamps = np.asarray(stamps_ns, dtype=np.int64)
        values = np.asarray(velocities, dtype=np.float64)
        have = np.asarray(present, dtype=np.bool_)
        angles = np.zeros(values.shape)
        for j in range(values.shape[1]):
            angles[:, j] = self._column(j, stamps, values[:, j], have[:, j])
        return angles

    def _column(
        self,
        j: int,
        stamps: NDArray[np.int64],
        values: NDArray[np.float64],
        have: NDArray[np.bool_],
    ) -> NDArray[np.float64]:
        import numpy as np

        out = np.zeros(values.shape[0])
        finite = np.isfinite(values)
        out[have & ~finite] = np.nan
        candidates = np.flatnonzero(have & finite)
        if candidates.size == 0:
            return out
        t = stamps[candidates]
        # A sample is usable when it is after the latest stamp of the candidates before it (a
        # candidate that was not usable was no later than the usable one before it).
        before = np.empty_like(t)
        before[0] = self._last_ns[j] if self._started[j] else t[0]
        np.maximum.accumulate(t[:-1], out=before[1:])
        if self._started[j]:
            np.maximum(before, self._last_ns[j], out=before)
        usable = t > before
        if not self._started[j]:
            usable[0] = True  # the wheel's first sample: its angle is 0, it starts the clock
        rows = candidates[usable]
        if rows.size == 0:
            # Every sample of the chunk is late (stamps gone back past the wheel's last usable
            # one): the wheel stays where it was.
            out[candidates] = self._angle[j]
            return out
        dt = (t[usable] - before[usable]).astype(np.float64) / NS_PER_S
        steps = values[rows] * dt
        reached = self._angle[j] + np.cumsum(steps)
        out[rows] = reached
        late = candidates[~usable]
        if late.size:
            # Not after the last usable stamp: the angle where the wheel was (the integrator
            # skips such a sample for its stamp).
            where = np.searchsorted(rows, late) - 1
            out[late] = np.where(where >= 0, reached[np.maximum(where, 0)], self._angle[j])
        self._angle[j] = float(reached[-1])
        self._last_ns[j] = int(t[usable][-1])
        self._started[j] = True
        return out
