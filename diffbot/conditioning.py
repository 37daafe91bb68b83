"""Recorded wheel positions made usable before they are integrated: encoder units, counters that
wrap around, and steps no wheel can make.

A robot's driver may publish raw encoder counts instead of radians, on a counter of a fixed width
that wraps around (a 16-bit counter jumps from 65535 back to 0). Integrated as they are, such
positions give kilometres for a metre's run. :class:`Conditioner` turns them into radians chunk by
chunk, in recording order, continuing from the state the previous chunk left, so that a bag read
in chunks, a whole CSV and a live stream of one message at a time get the same angles:

- unwrapping: with a modulus ``N`` (in the recorded units) a step beyond ``±N/2`` is a wrap and is
  undone; without one, a wrap is detected by itself: whole-number positions held within a
  power-of-two range (``[0, 2**k)`` or ``[-2**(k-1), 2**(k-1))``, 8 <= k <= 32) that jump by at
  least three quarters of its width, the jump undone no longer than four ordinary steps;
- units: counts times ``2*pi / counts_per_rev`` radians;
- time offsets: :func:`estimate_time_offset` finds how late wheel stamps are against a pose
  track by aligning heading rates;
- plausibility: a step whose wheel turns faster than :data:`MOTOR_LIMIT_FACTOR` times the motor
  limit (or, with no limit, faster than its rim could move at :data:`RIM_SPEED_BOUND`) is counted
  and the first one kept for the report. Such steps are integrated all the same: the report says
  the pose is not to be trusted.

Pure: NumPy arrays in, arrays and a report out; no files.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Final

import numpy as np

from diffbot.errors import ParameterError
from diffbot.kinematics import DiffDriveParams
from diffbot.numbers import as_number, finite_in_range, store_checked, store_number
from diffbot.samples import NS_PER_S, later_than_before

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MOTOR_LIMIT_FACTOR",
    "RIM_SPEED_BOUND",
    "Conditioner",
    "Conditioning",
    "ConditioningReport",
    "ImplausibleStep",
    "counter_range",
    "detect_wrap",
    "estimate_time_offset",
]

#: A step is implausible when its wheel speed is beyond this many times the motor limit.
MOTOR_LIMIT_FACTOR: Final = 4.0
#: Without a motor limit, a step is implausible when its wheel's rim moves faster than this
#: (m/s, 108 km/h: beyond any differential-drive robot).
RIM_SPEED_BOUND: Final = 30.0
#: Rim travel (m) allowed on top of the speed bound, for stamps that jitter.
RIM_SLACK: Final = 0.01
#: The smallest and largest counter widths (bits) recognised by themselves.
_WRAP_BITS: Final = (8, 32)
#: Counts per revolution and a counter's modulus an encoder may have (recorded units).
ENCODER_SIZE_RANGE: Final = (1e-9, 1e15)

#: A detected wrap jumps by at least this fraction of the counter's range.
_WRAP_JUMP: Final = 0.75
#: ... and, undone, is at most this many times the largest ordinary step.
_WRAP_TYPICAL: Final = 4.0
#: Relative rounding a given modulus may be short of the positions' spread (angles that wrap in
#: ``[-pi, pi]`` span the whole of ``2*pi``).
_WRAP_SLACK: Final = 1e-9


@dataclass(frozen=True)
class Conditioning:
    """How the recorded positions become wheel angles.

    Attributes:
        counts_per_rev: encoder counts per wheel revolution when the positions are counts;
            None when they are radians.
        wrap: the modulus of a counter that wraps, in the recorded units (counts, or radians
            without ``counts_per_rev``); None to detect one, 0 for none and no detection.
    """

    counts_per_rev: float | None = None
    wrap: float | None = None

    def __post_init__(self) -> None:
        # Sizes no encoder has are refused: 2*pi / 1e-320 is inf, and the positions NaN.
        low, high = ENCODER_SIZE_RANGE
        what = "{counts_per_rev} (encoder counts per revolution)"
        store_number(self, "counts_per_rev", low, high, what=what, optional=True)
        store_checked(self, "wrap", _modulus, optional=True)


def _modulus(value: object) -> float:
    """A counter's modulus as :class:`Conditioning` takes it: 0 (none), or a size within
    :data:`ENCODER_SIZE_RANGE`."""
    what = "{wrap} (0 for none)"
    if as_number(value, what) == 0.0:
        return 0.0
    return finite_in_range(value, what, *ENCODER_SIZE_RANGE)


@dataclass(frozen=True)
class ImplausibleStep:
    """A step no wheel can make.

    Attributes:
        sample: the index of the sample that ends the step, among the samples conditioned
            (the first is 0).
        seconds: its time since the first sample (s).
        joint: the wheel joint.
        speed: its speed over the step (rad/s).
    """

    sample: int
    seconds: float
    joint: str
    speed: float


@dataclass(frozen=True)
class ConditioningReport:
    """What conditioning did to a recording.

    Attributes:
        counts_per_rev: as asked (None: the positions were radians).
        wrap: the counter's modulus used (recorded units); None when none.
        wrap_detected: whether ``wrap`` was detected rather than given.
        wraps: how many wraps were undone, all joints together.
        speed_limit: the wheel speed (rad/s) beyond which a step is implausible, per side
            (left, right).
        limit_source: where the limit comes from, for people (``"4 x the motor limit"``, ``"a
            rim speed of 30 m/s"``).
        implausible_steps: how many samples end a step beyond the limit.
        first_implausible: the first of them, or None.
    """

    counts_per_rev: float | None
    wrap: float | None
    wrap_detected: bool
    wraps: int
    speed_limit: tuple[float, float]
    limit_source: str
    implausible_steps: int
    first_implausible: ImplausibleStep | None


def counter_range(lowest: float, highest: float, whole: bool) -> float | None:
    """The range of the counter that could have recorded these positions, or None.

    Args:
        lowest: the smallest position seen.
        highest: the largest position seen.
        whole: whether every position seen is a whole number.

    Returns:
        ``2**k`` when the positions fit ``[0, 2**k)`` (or ``[-2**(k-1), 2**(k-1))`` when any is
        negative), k the smallest in 8..32; None when they are not whole numbers or need more
        than 32 bits.
    """
    if not whole or not (math.isfinite(lowest) and math.isfinite(highest)):
        return None
    if lowest >= 0:
        bits = max(_WRAP_BITS[0], math.ceil(math.log2(highest + 1)))
    else:
        half = max(-lowest, highest + 1)
        bits = max(_WRAP_BITS[0], math.ceil(math.log2(half)) + 1)
    return float(2**bits) if bits <= _WRAP_BITS[1] else None


def detect_wrap(width: float | None, steps: NDArray[np.float64], typical: float) -> bool:
    """Whether a counter of range ``width`` wrapped in these steps.

    It did when a step covers at least three quarters of the range and, undone, is no longer
    than :data:`_WRAP_TYPICAL` times the ``typical`` step (the largest under a quarter of the
    range): a counter's wrap looks like its neighbours once undone, a jump in the data does not.

    Args:
        width: the counter's range (:func:`counter_range`), or None.
        steps: the steps between consecutive positions.
        typical: the largest step seen under a quarter of the range (0: none moved).
    """
    if width is None or typical <= 0:
        return False
    size = np.abs(steps)
    jumps = size[size >= _WRAP_JUMP * width]
    return bool(jumps.size) and float((width - jumps).max()) <= _WRAP_TYPICAL * typical


@dataclass
class _Column:
    """One joint's state between chunks."""

    limit: float
    slack: float
    last_raw: float | None = None
    last_value: float = 0.0
    last_stamp: int = 0
    turns: float = 0.0
    lowest: float = math.inf
    highest: float = -math.inf
    whole: bool = True
    typical: float = 0.0
    modulus: float | None = None
    started: bool = False


@dataclass
class Conditioner:
    """Recorded positions to wheel angles, chunk by chunk (see the module's docstring).

    Build one with :meth:`for_robot`.

    Args:
        joints: the wheel joints, in the columns' order.
        conditioning: the units and the wrap.
        limits: per joint, the largest plausible speed (rad/s) and the travel (rad) allowed on
            top of it.
        limit_source: what the limits come from, for the report.
    """

    joints: Sequence[str]
    conditioning: Conditioning
    limits: Sequence[tuple[float, float]]
    limit_source: str
    _columns: list[_Column] = field(init=False)
    _seen: int = field(init=False, default=0)
    _origin: int | None = field(init=False, default=None)
    _wraps: int = field(init=False, default=0)
    _detected: bool = field(init=False, default=False)
    _implausible: int = field(init=False, default=0)
    _first: ImplausibleStep | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        wrap = self.conditioning.wrap
        modulus = wrap if wrap else None
        self._columns = [_Column(limit, slack, modulus=modulus) for limit, slack in self.limits]

    @classmethod
    def for_robot(
        cls,
        params: DiffDriveParams,
        joints: Sequence[str],
        left_count: int,
        conditioning: Conditioning | None = None,
    ) -> Conditioner:
        """A conditioner for a robot's wheel joints, its limits from the robot.

        Args:
            params: the robot (motor limit, wheel radii).
            joints: the wheel joints of the columns, the left ones first.
            left_count: how many of them are on the left.
            conditioning: units and wrap; the default reads radians and detects wraps.
        """
        radii = params.radii
        limits = []
        for k in range(len(joints)):
            radius = radii[0] if k < left_count else radii[1]
            if params.max_wheel_speed:
                limit = MOTOR_LIMIT_FACTOR * params.max_wheel_speed
            else:
                limit = RIM_SPEED_BOUND / radius
            limits.append((limit, RIM_SLACK / radius))
        source = (
            f"{MOTOR_LIMIT_FACTOR:g} x the motor limit"
            if params.max_wheel_speed
            else f"a rim speed of {RIM_SPEED_BOUND:g} m/s"
        )
        return cls(list(joints), conditioning or Conditioning(), limits, source)

    def feed(
        self, stamps_ns: ArrayLike, positions: ArrayLike, present: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Condition the next chunk of samples, in recording order.

        Args:
            stamps_ns: the samples' stamps (ns), int64, shape (n,).
            positions: the joints' recorded positions, shape (n, joints).
            present: whether each sample has each joint, bool, same shape; all if None.

        Returns:
            The wheel angles (rad), shape (n, joints): the input array itself when nothing was
            to be changed.
        """
        stamps = np.asarray(stamps_ns, dtype=np.int64)
        values: NDArray[np.float64] = np.asarray(positions, dtype=np.float64)
        n = stamps.shape[0]
        have = (
            np.ones(values.shape, dtype=np.bool_)
            if present is None
            else np.asarray(present, dtype=np.bool_)
        )
        if n == 0:
            return values
        if self._origin is None:
            self._origin = int(stamps[0])
        out = values
        flagged = np.zeros(n, dtype=np.bool_)
        first_joint = np.full(n, -1, dtype=np.int64)
        speeds = np.zeros(n)
        for c, column in enumerate(self._columns):
            rows = np.flatnonzero(have[:, c] & np.isfinite(values[:, c]))
            if rows.size == 0:
                continue
            raw = values[rows, c]
            angles = self._unwrap(column, raw)
            if self.conditioning.counts_per_rev is not None:
                angles = angles * (2.0 * math.pi / self.conditioning.counts_per_rev)
            if angles is not raw:
                if out is values:
                    out = values.copy()
                out[rows, c] = angles
            speed, bad = self._steps(column, stamps[rows], angles)
            new = bad & ~flagged[rows]
            first_joint[rows[new]] = c
            speeds[rows[new]] = speed[new]
            flagged[rows[bad]] = True
        count = int(np.count_nonzero(flagged))
        if count:
            self._implausible += count
            if self._first is None:
                k = int(np.argmax(flagged))
                self._first = ImplausibleStep(
                    self._seen + k,
                    (int(stamps[k]) - self._origin) / NS_PER_S,
                    self.joints[int(first_joint[k])],
                    float(speeds[k]),
                )
        self._seen += n
        return out

    def _unwrap(self, column: _Column, raw: NDArray[np.float64]) -> NDArray[np.float64]:
        """A joint's positions with the wraps undone (``raw`` itself when none ever was)."""
        previous = raw[0] if column.last_raw is None else column.last_raw
        steps = np.diff(raw, prepend=previous)
        column.last_raw = float(raw[-1])
        if column.modulus is None and self.conditioning.wrap is None:
            column.lowest = min(column.lowest, float(raw.min()))
            column.highest = max(column.highest, float(raw.max()))
            column.whole = column.whole and bool(np.all(raw == np.floor(raw)))
            width = counter_range(column.lowest, column.highest, column.whole)
            if width is not None:
                size = np.abs(steps)
                small = size[size < width / 4]
                if small.size:
                    column.typical = max(column.typical, float(small.max()))
                if detect_wrap(width, steps, column.typical):
                    column.modulus = width
                    self._detected = True
        elif self.conditioning.wrap:
            self._check_given_wrap(column, raw)
        if column.modulus is None:
            return raw
        turns = np.rint(steps / column.modulus)
        wraps = int(np.count_nonzero(turns))
        if not wraps and not column.turns:
            return raw
        self._wraps += wraps
        total = np.cumsum(turns) + column.turns
        column.turns = float(total[-1])
        unwrapped: NDArray[np.float64] = raw - total * column.modulus
        return unwrapped

    def _check_given_wrap(self, column: _Column, raw: NDArray[np.float64]) -> None:
        """Refuse a given modulus the positions do not fit: a counter of modulus ``N`` holds its
        values within ``N`` of each other, and unwrapping with a smaller one turns every step
        beyond ``N/2`` into a false wrap (a wrong pose, said nowhere)."""
        column.lowest = min(column.lowest, float(raw.min()))
        column.highest = max(column.highest, float(raw.max()))
        modulus = float(self.conditioning.wrap or 0.0)
        spread = column.highest - column.lowest
        if spread > modulus * (1.0 + _WRAP_SLACK):
            joint = next(self.joints[k] for k, c in enumerate(self._columns) if c is column)
            raise ParameterError(
                f"the counter's modulus ({{wrap}}) of {modulus:g} is smaller than the range the "
                f"positions of {joint!r} cover ({column.lowest:g} to {column.highest:g}, "
                f"{spread:g} apart): a counter that wraps at {modulus:g} cannot hold them, and "
                "its steps would be taken for wraps; give the counter's real modulus, or 0 for "
                "none"
            )

    @staticmethod
    def _steps(
        column: _Column, stamps: NDArray[np.int64], angles: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Each sample's speed over the step that ends at it (rad/s) and whether the step is
        beyond the joint's limit; the first sample a joint ever has ends no step.

        The steps are those the odometry integrates: a sample whose stamp is not after every
        earlier one's is skipped there (a repeat, a second publisher), so it ends no step here
        and the next step is measured from the sample before it."""
        speed = np.zeros(stamps.shape[0])
        bad = np.zeros(stamps.shape[0], dtype=np.bool_)
        prior = column.last_stamp if column.started else np.iinfo(np.int64).min
        kept = np.flatnonzero(later_than_before(stamps, prior))
        if kept.size == 0:
            return speed, bad
        times, values = stamps[kept], angles[kept]
        d_angle = np.diff(values, prepend=column.last_value)
        # Each step is in (0, 2**64) ns: as unsigned 64-bit numbers the differences are exact
        # even across more than 2**63 ns (292 years), where signed ones wrap around.
        last = np.array([column.last_stamp], dtype=np.int64).view(np.uint64)
        steps_ns = np.diff(times.view(np.uint64), prepend=last)
        d_time = steps_ns.astype(np.float64) / NS_PER_S
        if not column.started:
            # no step ends at a joint's first sample: as if it came after all time, at rest
            d_time[0] = math.inf
            column.started = True
        column.last_value = float(values[-1])
        column.last_stamp = int(times[-1])
        # each kept stamp is after the one before it: every step takes time
        moved = np.abs(d_angle)
        speed[kept] = moved / d_time
        bad[kept] = moved > column.limit * d_time + column.slack
        return speed, bad

    def report(self) -> ConditioningReport:
        """What was done so far."""
        moduli = {c.modulus for c in self._columns if c.modulus is not None}
        limits = [limit for limit, _ in self.limits] or [math.inf]
        return ConditioningReport(
            counts_per_rev=self.conditioning.counts_per_rev,
            wrap=max(moduli) if moduli else None,
            wrap_detected=self._detected,
            wraps=self._wraps,
            speed_limit=(limits[0], limits[-1]),
            limit_source=self.limit_source,
            implausible_steps=self._implausible,
            first_implausible=self._first,
        )


def estimate_time_offset(
    wheel_seconds: ArrayLike,
    left: ArrayLike,
    right: ArrayLike,
    truth_seconds: ArrayLike,
    truth_theta: ArrayLike,
    params: DiffDriveParams,
    max_offset: float = 1.0,
) -> float:
    """How late the wheel stamps are against a pose track (s), found by aligning heading rates.

    The heading the wheels give (linear in their angles) and the track's heading (unwrapped) are
    differentiated on one even grid; the offset within ``±max_offset`` that best correlates the
    two rates is taken, to a tenth of the wheels' sample interval, then refined by a parabola
    through the best three. Subtract it from the wheel stamps.

    Args:
        wheel_seconds: the wheel samples' times (s), increasing, shape (n,).
        left: the left wheel's angles (rad), shape (n,).
        right: the right wheel's angles (rad), shape (n,).
        truth_seconds: the track's times (s), increasing, shape (m,).
        truth_theta: the track's heading (rad), shape (m,).
        params: the robot (radii, separation, signs).
        max_offset: the largest offset tried either way (s).

    Raises:
        ParameterError: too few samples, no overlap, or no turning to align by.
    """
    t = np.asarray(wheel_seconds, dtype=np.float64)
    tt = np.asarray(truth_seconds, dtype=np.float64)
    if t.size < 3 or tt.size < 3:
        raise ParameterError("aligning stamps needs at least three samples on each side")
    left_radius, right_radius = params.radii
    heading = (
        np.asarray(right, dtype=np.float64) * (params.right_sign * right_radius)
        - np.asarray(left, dtype=np.float64) * (params.left_sign * left_radius)
    ) / params.wheel_separation
    truth = np.unwrap(np.asarray(truth_theta, dtype=np.float64))
    step = float(np.median(np.diff(t))) / 10.0
    start = max(t[0], tt[0]) + max_offset
    end = min(t[-1], tt[-1]) - max_offset
    if not step > 0 or end - start < 10 * step:
        raise ParameterError(
            "the wheel samples and the pose track overlap too little to align their stamps"
        )
    grid = np.arange(start, end, step)
    truth_rate = np.gradient(np.interp(grid, tt, truth), step)
    truth_rate -= truth_rate.mean()
    if not np.any(truth_rate):
        raise ParameterError("the pose track does not turn: no heading rate to align by")
    reach = round(max_offset / step)
    lags = np.arange(-reach, reach + 1) * step
    scores = _lag_scores(
        np.interp(start + np.arange(-reach, grid.size + reach) * step, t, heading), truth_rate, step
    )
    best = int(np.argmax(scores))
    if best in (0, lags.size - 1):
        raise ParameterError(
            "the heading rates align best at the edge of the offsets tried "
            f"({max_offset:g} s either way): the wheel stamps may be further off; give the "
            "offset ({time_offset})"
        )
    offset = float(lags[best])
    if 0 < best < lags.size - 1:
        below, here, above = scores[best - 1], scores[best], scores[best + 1]
        curve = below - 2.0 * here + above
        if curve < 0:
            offset += 0.5 * step * (below - above) / curve
    return offset


def _lag_scores(
    heading: NDArray[np.float64], truth_rate: NDArray[np.float64], step: float
) -> NDArray[np.float64]:
    """The correlation of ``truth_rate`` (mean 0, n values) with the rate of each window of n
    values of ``heading`` (sampled every ``step`` s, n + 2 K values), window j starting at
    value j: as ``np.gradient`` of the window, its mean taken away, would give it, for all
    2 K + 1 windows at once (one FFT correlation and running sums: a loop over the windows
    would take time in proportion to the samples times the lags, that is to the square of the
    sample rate)."""
    n = truth_rate.size
    count = heading.size - n + 1
    rate = np.gradient(heading, step)  # central differences: a window's inner values
    # A window's first and last values are its own one-sided differences.
    first = (heading[1 : count + 1] - heading[:count]) / step
    last = (heading[n - 1 :] - heading[n - 2 : n - 2 + count]) / step
    size = 1 << (heading.size + n).bit_length()
    dot = np.fft.irfft(np.fft.rfft(rate, size) * np.conj(np.fft.rfft(truth_rate, size)), size)
    dot = dot[:count]
    dot += (first - rate[:count]) * truth_rate[0] + (last - rate[n - 1 :]) * truth_rate[-1]
    sums = np.concatenate(([0.0], np.cumsum(rate)))
    squares = np.concatenate(([0.0], np.cumsum(rate * rate)))
    total = sums[n:] - sums[:count] + (first - rate[:count]) + (last - rate[n - 1 :])
    square = (
        squares[n:]
        - squares[:count]
        + (first**2 - rate[:count] ** 2)
        + (last**2 - rate[n - 1 :] ** 2)
    )
    spread = np.maximum(square - total * total / n, 0.0)
    norm = np.sqrt(spread * float(np.dot(truth_rate, truth_rate)))
    scores = np.full(count, -math.inf)
    np.divide(dot, norm, out=scores, where=norm > 0.0)
    return scores
