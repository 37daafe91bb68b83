"""Odometry over a recording read in chunks, equal bit for bit to the sample-by-sample run.

The odometry of a recording feeds every sample to :class:`diffbot.odometry.Odometry` with its
stamp in seconds since the first sample, ``(stamp_ns - first_stamp_ns) / 10**9``. This module
does the same over NumPy chunks: it applies the integrator's skip rules (a wheel joint missing,
a NaN or infinite position, a stamp not after the previous used one) to a whole chunk at once,
then integrates the used samples with :func:`diffbot.batch_odometry.advance`, the one
vectorised integrator, continuing from the state the previous chunk left. The pose, twist and
distance after the last sample are then those of the sample-by-sample run, to the last bit,
wherever NumPy's sin and cos equal libm's (they do on the platforms measured; see the tests).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Final, NamedTuple

import numpy as np

from diffbot.batch_odometry import advance, initial_pose
from diffbot.errors import RecordingError
from diffbot.kinematics import DiffDriveParams, Pose, Twist, norm_angle
from diffbot.odometry import SKIP_MISSING_JOINT, SKIP_NOT_FINITE, SKIP_STAMP_NOT_AFTER
from diffbot.samples import NS_PER_S, later_than_before, side_means

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

__all__ = [
    "ChunkOdometry",
    "ChunkPoses",
    "OdometrySummary",
    "seconds_since",
    "side_means",
]

#: Integers up to 2**53 convert to float64 exactly, so below it ``a / b`` in Python is one
#: rounding of float(a) / float(b), which NumPy reproduces.
_EXACT: Final = 2**53
_INT64_MIN: Final = -(2**63)
_INT64_MAX: Final = 2**63 - 1


class ChunkPoses(NamedTuple):
    """The state after each used sample of one chunk (float64 unless said otherwise, shape (k,)).

    Attributes:
        stamp_ns: the samples' stamps (ns), int64.
        x: x (m).
        y: y (m).
        heading: the unwrapped heading (rad).
        linear: linear velocity over the step that ends at the sample (m/s); 0 for the baseline.
        angular: angular velocity over that step (rad/s); 0 for the baseline.
    """

    stamp_ns: NDArray[np.int64]
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    heading: NDArray[np.float64]
    linear: NDArray[np.float64]
    angular: NDArray[np.float64]


class OdometrySummary(NamedTuple):
    """The end of a run over a whole recording.

    Attributes:
        final_pose: the pose after the last used sample, theta in (-pi, pi].
        heading: the unwrapped heading (rad) after the last used sample.
        twist: the velocity over the last step.
        samples: how many samples were used, the baseline included.
        skipped: how many samples were skipped, by reason.
        distance: path length travelled (m), the sum of |ds|.
        duration: time (s) from the first to the last used sample.
        first_repeat_ns: the stamp (ns) of the first sample skipped for a stamp not after the
            previous used one (a second publisher on the topic, or a clock that went back);
            None when there was none.
    """

    final_pose: Pose
    heading: float
    twist: Twist
    samples: int
    skipped: Mapping[str, int]
    distance: float
    duration: float
    first_repeat_ns: int | None = None


def seconds_since(stamps_ns: ArrayLike, origin_ns: int) -> NDArray[np.float64]:
    """``(stamp_ns - origin_ns) / 10**9`` for each stamp, rounded exactly as Python rounds it.

    Args:
        stamps_ns: stamps (ns), int64, shape (n,).
        origin_ns: the stamp (ns) that is time zero.

    Returns:
        Seconds since ``origin_ns``, float64, shape (n,).
    """
    stamps = np.asarray(stamps_ns, dtype=np.int64)
    lo = max(origin_ns - _EXACT, _INT64_MIN)
    hi = min(origin_ns + _EXACT, _INT64_MAX)
    far = (stamps < lo) | (stamps > hi)
    near = np.where(far, origin_ns, stamps)
    seconds: NDArray[np.float64] = (near - np.int64(origin_ns)).astype(np.float64) / NS_PER_S
    if far.any():
        # Python divides big integers exactly, then rounds once; float64 would round twice.
        for k in np.flatnonzero(far).tolist():
            seconds[k] = (int(stamps[k]) - origin_ns) / NS_PER_S
    return seconds


class ChunkOdometry:
    """The odometry of a recording fed chunk by chunk, in constant memory.

    Args:
        params: the robot.
        x: initial x (m).
        y: initial y (m).
        theta: initial heading (rad).

    Raises:
        ParameterError: an initial pose that is no number, not finite or out of its range (as
            :class:`~diffbot.odometry.Odometry`'s).
    """

    def __init__(
        self, params: DiffDriveParams, x: float = 0.0, y: float = 0.0, theta: float = 0.0
    ) -> None:
        self._params = params
        x, y, theta = initial_pose(x, y, theta, ("x", "y", "theta"))
        self._x = x
        self._y = y
        self._heading = self._heading0 = theta
        self._linear = 0.0
        self._angular = 0.0
        self._distance = 0.0
        self._origin_ns: int | None = None
        self._baseline: tuple[float, float] | None = None
        self._last: tuple[float, float, float] = (0.0, 0.0, -math.inf)
        self._first_used_ns: int | None = None
        self._last_used_ns: int | None = None
        self._samples = 0
        self._skipped: dict[str, int] = {}
        self._first_repeat_ns: int | None = None

    def _skip(self, reason: str, count: int) -> None:
        if count:
            self._skipped[reason] = self._skipped.get(reason, 0) + count

    def feed(
        self,
        stamps_ns: ArrayLike,
        left: ArrayLike,
        right: ArrayLike,
        present: ArrayLike | None = None,
    ) -> ChunkPoses:
        """Integrate the next chunk of samples, in recording order.

        Args:
            stamps_ns: the samples' stamps (ns), int64, shape (n,). The first sample ever fed
                is time zero, whether or not it is used.
            left: the left wheel joint's angle (rad), shape (n,).
            right: the right wheel joint's angle (rad), shape (n,).
            present: whether the sample has both wheel joints, bool, shape (n,); all if None.

        Returns:
            The state after each used sample of the chunk.
        """
        stamps = np.asarray(stamps_ns, dtype=np.int64)
        lefts = np.asarray(left, dtype=np.float64)
        rights = np.asarray(right, dtype=np.float64)
        n = stamps.shape[0]
        have = np.ones(n, dtype=np.bool_) if present is None else np.asarray(present, bool)
        if n == 0:
            empty = np.empty(0)
            return ChunkPoses(stamps, empty, empty, empty, empty, empty)
        if self._origin_ns is None:
            self._origin_ns = int(stamps[0])
        seconds = seconds_since(stamps, self._origin_ns)
        with np.errstate(invalid="ignore"):
            finite = (lefts - lefts) + (rights - rights) == 0.0
        valid = have & finite
        self._skip(SKIP_MISSING_JOINT, int(n - np.count_nonzero(have)))
        self._skip(SKIP_NOT_FINITE, int(np.count_nonzero(have & ~finite)))
        index = np.flatnonzero(valid)
        t = seconds[index]
        # A sample is used when it is after the latest stamp of all valid samples before it:
        # each valid sample that was skipped was no later than the used one before it.
        used = later_than_before(t, self._last[2])
        self._skip(SKIP_STAMP_NOT_AFTER, int(t.size - np.count_nonzero(used)))
        if self._first_repeat_ns is None and not used.all():
            self._first_repeat_ns = int(stamps[index[int(np.argmin(used))]])
        index = index[used]
        return self._integrate(stamps[index], lefts[index], rights[index], seconds[index])

    def _integrate(
        self,
        stamps: NDArray[np.int64],
        left: NDArray[np.float64],
        right: NDArray[np.float64],
        t: NDArray[np.float64],
    ) -> ChunkPoses:
        k = stamps.shape[0]
        xs = np.empty(k)
        ys = np.empty(k)
        heading = np.empty(k)
        linear = np.zeros(k)
        angular = np.zeros(k)
        if k == 0:
            return ChunkPoses(stamps, xs, ys, heading, linear, angular)
        start = 0
        if self._baseline is None:
            # The first used sample sets the encoder baseline and does not move the robot.
            self._baseline = (float(left[0]), float(right[0]))
            self._first_used_ns = int(stamps[0])
            xs[0], ys[0], heading[0] = self._x, self._y, self._heading
            self._last = (float(left[0]), float(right[0]), float(t[0]))
            start = 1
        # The steps after this chunk's baseline (if any), from the state the last used sample
        # left: index 0 of each work array is that state, as advance() takes it.
        steps = k - start
        if steps:
            wl = np.empty(steps + 1)
            wr = np.empty(steps + 1)
            wx = np.empty(steps + 1)
            wy = np.empty(steps + 1)
            wh = np.empty(steps + 1)
            wl[0], wr[0], _ = self._last
            wl[1:], wr[1:] = left[start:], right[start:]
            wx[0], wy[0], wh[0] = self._x, self._y, self._heading
            ds = np.empty(steps)
            half = np.empty(steps)
            advance(
                self._params,
                wx,
                wy,
                wh,
                wl,
                wr,
                (*self._baseline, self._heading0),
                ds=ds,
                half=half,
            )
            xs[start:], ys[start:], heading[start:] = wx[1:], wy[1:], wh[1:]
            prev_t = np.empty(steps)
            prev_t[0] = self._last[2]
            prev_t[1:] = t[start:-1]
            with np.errstate(all="ignore"):
                dt = t[start:] - prev_t
                linear[start:] = ds / dt
                angular[start:] = 2.0 * half / dt
            self._distance = float(np.cumsum(np.concatenate(([self._distance], np.abs(ds))))[-1])
        self._x, self._y, self._heading = float(xs[-1]), float(ys[-1]), float(heading[-1])
        if k > start:
            self._linear, self._angular = float(linear[-1]), float(angular[-1])
        self._last = (float(left[-1]), float(right[-1]), float(t[-1]))
        self._last_used_ns = int(stamps[-1])
        self._samples += k
        return ChunkPoses(stamps, xs, ys, heading, linear, angular)

    def skip(self, reason: str, count: int = 1) -> None:
        """Count samples the reader could not turn into samples (unreadable, no stamp)."""
        self._skip(reason, count)

    @property
    def used(self) -> int:
        """How many samples were used so far."""
        return self._samples

    @property
    def skipped(self) -> Mapping[str, int]:
        """How many samples were skipped so far, by reason."""
        return dict(self._skipped)

    def summary(self, source: str, hint: str = "") -> OdometrySummary:
        """The run so far.

        Args:
            source: the recording's name, for the error message.
            hint: added to the error message (what the recording holds, say).

        Raises:
            RecordingError: no sample could be used.
        """
        skipped = dict(self._skipped)
        if self._first_used_ns is None or self._last_used_ns is None:
            reasons = ", ".join(f"{reason}: {n}" for reason, n in sorted(skipped.items()))
            raise RecordingError(
                f"{source}: no usable sample"
                + (f" (skipped: {reasons})" if reasons else " (the recording holds no samples)")
                + hint
            )
        return OdometrySummary(
            final_pose=Pose(self._x, self._y, norm_angle(self._heading)),
            heading=self._heading,
            twist=Twist(self._linear, self._angular),
            samples=self._samples,
            skipped=skipped,
            distance=self._distance,
            duration=(self._last_used_ns - self._first_used_ns) / NS_PER_S,
            first_repeat_ns=self._first_repeat_ns,
        )
