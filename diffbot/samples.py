"""Recorded wheel joint samples: the data that file readers produce and the odometry replay
consumes (kept apart from both, so that neither imports the other).

Stamps are kept as integer nanoseconds, like ROS time, so outputs carry the inputs' stamps
unchanged.
"""

from __future__ import annotations

import array
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from decimal import ROUND_HALF_EVEN, Decimal, InvalidOperation
from typing import TYPE_CHECKING, Any, Final, Generic, NamedTuple, TypeVar, overload

from diffbot.kinematics import Pose, Twist, norm_angle
from diffbot.numbers import MAX_RECORDED_ANGLE, MAX_WHEEL_SPEED, written_form

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from diffbot.conditioning import ConditioningReport
    from diffbot.odometry import Odometry
    from diffbot.side_angles import SideAngles

__all__ = [
    "CLOCK_HEADER",
    "CLOCK_RECEIVE",
    "INT64",
    "NS_PER_S",
    "SKIP_MISSING_STAMP",
    "SKIP_NOT_FINITE",
    "SKIP_POSITION_RANGE",
    "SKIP_STAMP_RANGE",
    "SKIP_UNREADABLE",
    "SKIP_VELOCITY_RANGE",
    "ColumnSamples",
    "ColumnView",
    "JointSample",
    "OdometryRow",
    "OdometryRows",
    "Recording",
    "beyond_range",
    "beyond_ranges",
    "each_side",
    "later_than_before",
    "ns_from_seconds",
    "range_reason",
    "seconds_text",
    "side_means",
    "wheel_limit",
]

#: :attr:`Recording.clock` of a bag stamped by the messages' header stamps.
CLOCK_HEADER: Final = "header"
#: :attr:`Recording.clock` of a bag stamped by the times the bag received the messages.
CLOCK_RECEIVE: Final = "receive"
#: Why a sample was skipped: a wheel position or its stamp is NaN or infinite.
SKIP_NOT_FINITE: Final = "not finite"
#: Why a CSV row was skipped: its time cell is empty.
SKIP_MISSING_STAMP: Final = "missing stamp"
#: Why a CSV row or bag message was skipped: a value (or the message) cannot be read.
SKIP_UNREADABLE: Final = "unreadable value"
#: Why a CSV row was skipped: its time is outside ROS time in int64 ns (about ±292 years).
SKIP_STAMP_RANGE: Final = "stamp out of range"
#: Why a CSV row was skipped: a wheel position beyond :data:`~diffbot.numbers.MAX_RECORDED_ANGLE`.
SKIP_POSITION_RANGE: Final = "position out of range"
#: Why a sample of wheel velocities was skipped: one beyond
#: :data:`~diffbot.numbers.MAX_WHEEL_SPEED` (rad/s).
SKIP_VELOCITY_RANGE: Final = "velocity out of range"


#: Nanoseconds per second.
NS_PER_S: Final = 1_000_000_000
#: Stamps in ns are ROS times: they fit in a signed 64-bit integer.
INT64: Final = 2**63


class JointSample(NamedTuple):
    """One JointState: stamp (ns), joint names and positions (rad), parallel sequences."""

    stamp_ns: int
    names: Sequence[str]
    positions: Sequence[float]


@dataclass(frozen=True)
class Recording:
    """Joint samples read from a file, in file order.

    Attributes:
        source: the path read, for messages.
        kind: ``"csv"`` or ``"rosbag2"``.
        samples: the samples, stamps in ns.
        skipped: rows or messages that could not be turned into a sample, by reason.
        clock: for a bag, what stamps the samples: :data:`CLOCK_HEADER` (the header stamps) or
            :data:`CLOCK_RECEIVE` (the bag's receive times); None for a CSV file (its time
            column).
        conditioning: what was done to the recorded positions (units, wraps) and the steps
            found implausible; None when they were read as they are.
        topic: for a bag, the topic read; None for a CSV.
        notes: what the reader judged by itself (a CSV's delimiter, its time unit), for people.
    """

    source: str
    kind: str
    samples: Sequence[JointSample]
    skipped: Mapping[str, int] = field(default_factory=dict)
    clock: str | None = None
    conditioning: ConditioningReport | None = None
    topic: str | None = None
    notes: tuple[str, ...] = ()


def range_reason(field: str) -> str:
    """Why a sample of ``field`` (``"position"`` or ``"velocity"``) beyond its
    :func:`wheel_limit` was skipped."""
    return SKIP_VELOCITY_RANGE if field == "velocity" else SKIP_POSITION_RANGE


def wheel_limit(field: str, counts_per_rev: float | None = None) -> float:
    """The largest magnitude a wheel's ``field`` (``"position"``, rad, or ``"velocity"``, rad/s)
    is taken with, from a file or a message alike.

    Args:
        field: ``"position"`` or ``"velocity"``.
        counts_per_rev: encoder counts per revolution when the values are counts (counts/s),
            None when they are radians (rad/s).

    Returns:
        The bound in the values' own unit: with ``counts_per_rev``, the bound in radians (rad/s)
        as counts (counts/s), ``bound * counts_per_rev / (2 pi)``, so that the bound holds for
        the values once converted, not for the counts.
    """
    limit = MAX_WHEEL_SPEED if field == "velocity" else MAX_RECORDED_ANGLE
    return limit if counts_per_rev is None else limit * counts_per_rev / (2.0 * math.pi)


def beyond_range(value: float, limit: float) -> bool:
    """A finite wheel value beyond ``limit`` (a :func:`wheel_limit`; infinities and NaN are the
    replay's to skip)."""
    return (value > limit or value < -limit) and math.isfinite(value)


def beyond_ranges(values: NDArray[np.float64], limit: float) -> NDArray[np.bool_]:
    """:func:`beyond_range` of each of ``values`` (an array of any shape)."""
    magnitude = abs(values)
    return (magnitude > limit) & (magnitude < math.inf)


def seconds_text(stamp_ns: int) -> str:
    """A stamp (ns) as exact decimal seconds without trailing zeros (1500000000 -> ``"1.5"``)."""
    sign = "-" if stamp_ns < 0 else ""
    whole, frac = divmod(abs(stamp_ns), NS_PER_S)
    if frac == 0:
        return f"{sign}{whole}"
    return f"{sign}{whole}.{frac:09d}".rstrip("0")


def ns_from_seconds(text: str, decimals: int = 9) -> int | None:
    """Decimal seconds -> ns, exactly rounded (ties to even); None if NaN or infinite;
    ValueError if not a plain decimal number (Python's digit grouping, ``1_0``, included).

    ``decimals`` reads the text in another unit: 9 for seconds, 6 for milliseconds, 3 for
    microseconds, 0 for nanoseconds (the power of ten that makes the unit nanoseconds).

    Beyond 1e30 s (far outside ROS time) the result is ±10**39 rather than the exact value, so
    that ``1e100000000`` costs nothing.
    """
    if not written_form(text):
        raise ValueError(text)
    try:
        seconds = Decimal(text.strip())
    except InvalidOperation:
        raise ValueError(text) from None
    if not seconds.is_finite():
        return None
    if seconds.adjusted() > 30:
        return -(10**39) if seconds.is_signed() else 10**39
    if seconds.adjusted() < -30:
        return 0
    sign, digits, exponent = seconds.as_tuple()
    assert isinstance(exponent, int)  # finite
    nanoseconds = Decimal((sign, digits, exponent + decimals))  # exact: no context rounding
    return int(nanoseconds.to_integral_value(rounding=ROUND_HALF_EVEN))


_Row = TypeVar("_Row")


class ColumnView(Sequence[_Row], Generic[_Row]):
    """A sequence of records kept as compact columns: a record is made only when one is read."""

    def __len__(self) -> int:
        raise NotImplementedError

    def row(self, index: int) -> _Row:
        """The record at ``index`` (negative counts from the end)."""
        raise NotImplementedError

    @overload
    def __getitem__(self, index: int) -> _Row: ...
    @overload
    def __getitem__(self, index: slice) -> list[_Row]: ...
    def __getitem__(self, index: int | slice) -> _Row | list[_Row]:
        if isinstance(index, slice):
            return [self.row(i) for i in range(*index.indices(len(self)))]
        return self.row(index)


class ColumnSamples(ColumnView[JointSample]):
    """The samples of a two-wheel recording as compact columns rather than one object per row.

    Stamps are int64 ns and wheel positions float64 (8 bytes each); a byte per row says which
    wheels the row has. :class:`JointSample` records are made only when asked for.
    """

    def __init__(self, left_joint: str, right_joint: str) -> None:
        self.stamps_ns = array.array("q")
        self.left = array.array("d")
        self.right = array.array("d")
        #: Per row: 1 if the left wheel's cell is set, 2 if the right's, 3 if both.
        self.present = bytearray()
        self._sides: SideAngles | None = None
        self._names: tuple[tuple[str, ...], ...] = (
            (),
            (left_joint,),
            (right_joint,),
            (left_joint, right_joint),
        )

    def __len__(self) -> int:
        return len(self.stamps_ns)

    def add_chunk(
        self,
        stamps_ns: NDArray[np.int64],
        positions: NDArray[np.float64],
        present: NDArray[np.bool_],
        left_count: int,
    ) -> None:
        """Append a chunk of rows: each side's angle (:func:`side_means`), the wheels' offsets
        kept from one chunk to the next.

        Args:
            stamps_ns: the rows' stamps (ns), shape (n,).
            positions: the joints' angles (rad), shape (n, joints): the left joints first.
            present: whether each row has each joint, same shape.
            left_count: how many of the joints are on the left.
        """
        if self._sides is None:
            from diffbot.side_angles import SideAngles

            self._sides = SideAngles(left_count, positions.shape[1] - left_count)
        left, right, _ = self._sides.chunk(positions, present)
        have_left = present[:, :left_count].any(axis=1)
        have_right = present[:, left_count:].any(axis=1)
        _extend(self.stamps_ns, stamps_ns, "<i8")
        _extend(self.left, left, "<f8")
        _extend(self.right, right, "<f8")
        self.present += (have_left + 2 * have_right.astype("u1")).tobytes()

    def row(self, index: int) -> JointSample:
        return self._sample(self.stamps_ns[index], self.left[index], self.right[index], index)

    def __iter__(self) -> Iterator[JointSample]:
        for k, (stamp_ns, left, right) in enumerate(
            zip(self.stamps_ns, self.left, self.right, strict=True)
        ):
            yield self._sample(stamp_ns, left, right, k)

    def _sample(self, stamp_ns: int, left: float, right: float, index: int) -> JointSample:
        present = self.present[index]
        values = (left, right) if present == 3 else (right,) if present == 2 else (left,)
        return JointSample(stamp_ns, self._names[present], values[: bin(present).count("1")])


def _extend(column: array.array[Any], values: NDArray[Any], dtype: str) -> None:
    """Append an array's values to a typed column as raw bytes: no Python number per cell,
    whose freed memory would stay with the process."""
    import numpy as np

    column.frombytes(np.ascontiguousarray(values, dtype=dtype).view(np.uint8).data)


def each_side(present: NDArray[np.bool_], left_count: int) -> NDArray[np.bool_]:
    """Whether each sample holds a joint of each side: a sample the odometry can use.

    Args:
        present: whether each sample has each joint, bool, shape (n, joints): the left joints
            first, then the right.
        left_count: how many of the columns are left joints.
    """
    import numpy as np

    both: NDArray[np.bool_] = np.logical_and(
        np.any(present[:, :left_count], axis=1), np.any(present[:, left_count:], axis=1)
    )
    return both


def later_than_before(values: NDArray[Any], prior: float) -> NDArray[np.bool_]:
    """Whether each value is greater than ``prior`` and than every value before it: the
    samples whose stamp is after every stamp before theirs, those the odometry uses.

    Args:
        values: stamps (any unit, int or float), shape (n,).
        prior: the latest stamp before them (``-inf``, or the type's least, when none).
    """
    import numpy as np

    before = np.empty_like(values)
    if values.size:
        before[0] = prior
        np.maximum.accumulate(values[:-1], out=before[1:])
        np.maximum(before, prior, out=before)
    later: NDArray[np.bool_] = values > before
    return later


def side_means(
    positions: NDArray[np.float64], present: NDArray[np.bool_], left_count: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """Each side's wheel angle per sample, for a whole recording at once.

    A side of one wheel is that wheel's angle, unchanged. A side of several is the mean over
    its wheels present of each one's angle less its offset (:mod:`diffbot.side_angles`): while
    every wheel is present, the mean of their angles, as diff_drive_controller averages them;
    a wheel missing from a sample moves the side by the others' motion, not by the encoders'
    offsets. A stream of chunks keeps one :class:`~diffbot.side_angles.SideAngles` instead.

    Args:
        positions: joint angles (rad), shape (n, joints): the left joints first, then the right.
        present: whether each sample has each joint, bool, same shape.
        left_count: how many of the columns are left joints.

    Returns:
        The left and right angles (rad), shape (n,) each, and whether the sample has at least
        one joint of each side.
    """
    from diffbot.side_angles import SideAngles

    sides = SideAngles(left_count, positions.shape[1] - left_count)
    return sides.chunk(positions, present)


class OdometryRow(NamedTuple):
    """The odometry after one used sample: its stamp (ns), the pose and the twist."""

    stamp_ns: int
    pose: Pose
    twist: Twist


class OdometryRows(ColumnView[OdometryRow]):
    """Odometry rows as compact columns: stamps int64 ns, the rest float64 (48 bytes a row).

    ``theta`` holds the unwrapped heading; rows report it in (-pi, pi].
    """

    def __init__(self) -> None:
        self.stamps_ns = array.array("q")
        self.x = array.array("d")
        self.y = array.array("d")
        self.heading = array.array("d")
        self.linear = array.array("d")
        self.angular = array.array("d")

    def add(self, stamp_ns: int, odom: Odometry) -> None:
        """Append the integrator's state after a used sample."""
        # One read of the whole state: odom.pose and odom.twist would wrap the heading and build
        # two records per row only to be taken apart here.
        x, y, heading, linear, angular = odom.state
        self.stamps_ns.append(stamp_ns)
        self.x.append(x)
        self.y.append(y)
        self.heading.append(heading)
        self.linear.append(linear)
        self.angular.append(angular)

    def __len__(self) -> int:
        return len(self.stamps_ns)

    def row(self, index: int) -> OdometryRow:
        return OdometryRow(
            self.stamps_ns[index],
            Pose(self.x[index], self.y[index], norm_angle(self.heading[index])),
            Twist(self.linear[index], self.angular[index]),
        )

    def __iter__(self) -> Iterator[OdometryRow]:
        columns = (self.stamps_ns, self.x, self.y, self.heading, self.linear, self.angular)
        for stamp_ns, x, y, heading, linear, angular in zip(*columns, strict=True):
            yield OdometryRow(stamp_ns, Pose(x, y, norm_angle(heading)), Twist(linear, angular))
