"""Each side's wheel angle from the angles of its several wheels, when a sample may lack some.

A skid steer's wheels of one side turn together, but their encoders do not read alike: each
started from its own zero. diff_drive_controller averages a side's wheel positions, which its
hardware always gives all of. A recorded or published JointState may not: two motor drivers
each publishing their own wheels, or a message that names one wheel of a side without a
position. The mean of the absolute angles of the wheels present would then jump by their
encoders' offsets whenever the set of wheels changes.

So a side's angle is the mean over its wheels present of each wheel's angle less its offset,
the offset learned where the wheel is first seen: against the mean of the first sample's wheels
for the wheels present there (their offsets sum to zero, so while every wheel is present the
side's angle is the mean of their angles, as the controller's), against the side's angle then
for a wheel that comes later. A wheel missing from a sample then moves the side by the motion
of the others only.

Angles in rad. Velocities need no offsets: they average as they are.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["MessageSides", "SideAngles", "SideOffsets"]


class SideOffsets:
    """The offsets of one side's wheels (rad), learned sample by sample or chunk by chunk.

    Args:
        wheels: how many wheels the side has.
    """

    __slots__ = ("_last", "offsets")

    def __init__(self, wheels: int) -> None:
        #: Each wheel's angle less the side's, once the wheel has been seen (else None).
        self.offsets: list[float | None] = [None] * wheels
        self._last: float | None = None

    def angle(self, values: Sequence[float | None]) -> float | None:
        """The side's angle in one sample: ``values`` holds each wheel's angle (rad), None for
        a wheel the sample lacks. None when it lacks them all; NaN when a wheel present is not
        finite (the sample is then skipped, and nothing is learned from it)."""
        total: float | None = None
        count = 0
        new = False
        for value, offset in zip(values, self.offsets, strict=True):
            if value is None:
                continue
            if value - value != 0.0:  # NaN or infinite
                return math.nan
            if offset is None:
                new = True
            elif total is None:  # the first term starts the sum: -0.0 stays -0.0
                total, count = value - offset, 1
            else:
                total += value - offset
                count += 1
        if new:
            return self._learn(values, total, count)
        if total is None:
            return None
        side = total / count
        if side - side == 0.0:  # a sum past the float range is no angle to hold on to
            self._last = side
        return side

    def _learn(self, values: Sequence[float | None], total: float | None, count: int) -> float:
        """angle() of a sample with a wheel seen for the first time: its offset set against
        the side's angle (that of the wheels known, else the last, else the new wheels' mean)."""
        if total is not None:
            side = total / count
        elif self._last is not None:
            side = self._last
        else:
            side = _mean([v for v in values if v is not None])
        learned = [
            (j, value - side)
            for j, value in enumerate(values)
            if value is not None and self.offsets[j] is None
        ]
        if not all(offset - offset == 0.0 for _, offset in learned):
            return math.nan  # past the float range: nothing learned, the sample skipped
        for j, offset in learned:
            self.offsets[j] = offset
        self._last = side
        return side

    def chunk(self, values: NDArray[np.float64], present: NDArray[np.bool_]) -> NDArray[np.float64]:
        """The side's angle in each row of a chunk, in order (rad): ``values`` shape (n,
        wheels), ``present`` whether each row has each wheel. 0.0 where a row has none; NaN
        where a wheel present is not finite."""
        import numpy as np  # here: a chunk is NumPy's, a message is not

        n = values.shape[0]
        out = np.zeros(n)
        with np.errstate(invalid="ignore"):
            usable = present & np.isfinite(values)
        start = 0
        while start < n:
            firsts = [
                start + int(np.argmax(usable[start:, j]))
                for j, offset in enumerate(self.offsets)
                if offset is None and usable[start:, j].any()
            ]
            stop = min(firsts, default=n)
            out[start:stop] = self._rows(values[start:stop], present[start:stop])
            if stop == n:
                break
            row = [
                float(v) if p else None for v, p in zip(values[stop], present[stop], strict=True)
            ]
            side = self.angle(row)
            out[stop] = 0.0 if side is None else side
            start = stop + 1
        return out

    def _rows(self, values: NDArray[np.float64], present: NDArray[np.bool_]) -> NDArray[np.float64]:
        """The angles of rows in which every wheel present and finite has an offset."""
        import numpy as np

        with np.errstate(invalid="ignore"):
            usable = present & np.isfinite(values)
        total = np.zeros(values.shape[0])
        count = np.zeros(values.shape[0])
        for j, offset in enumerate(self.offsets):
            if offset is None:
                continue
            # The first term starts the sum (not 0.0 + it: -0.0 stays -0.0), as angle() does.
            with np.errstate(all="ignore"):
                term = values[:, j] - offset
                added = np.where(count > 0, total + term, term)
            total = np.where(usable[:, j], added, total)
            count += usable[:, j]
        known = count > 0
        with np.errstate(invalid="ignore", divide="ignore"):
            angles: NDArray[np.float64] = np.where(known, total / np.where(known, count, 1.0), 0.0)
        spoiled = (present & ~usable).any(axis=1)
        angles[spoiled] = math.nan
        taken = np.flatnonzero(known & ~spoiled & np.isfinite(angles))
        if taken.size:
            self._last = float(angles[taken[-1]])
        return angles


class SideAngles:
    """Both sides' angles from the joints' angles of a stream of chunks (see the module).

    Args:
        left_count: how many of the joints are left wheels (the first columns).
        right_count: how many are right wheels (the columns after them).
    """

    def __init__(self, left_count: int, right_count: int) -> None:
        self.left_count = left_count
        self.sides = (SideOffsets(left_count), SideOffsets(right_count))

    def chunk(
        self, positions: NDArray[np.float64], present: NDArray[np.bool_]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
        """The left and right angles (rad) of each row, and whether the row has a wheel of
        each side (see :func:`diffbot.samples.side_means`)."""
        import numpy as np

        angles = []
        for side, columns in zip(
            self.sides, (slice(0, self.left_count), slice(self.left_count, None)), strict=True
        ):
            values, mask = positions[:, columns], present[:, columns]
            if values.shape[1] == 1:  # one wheel: its angle as it is
                angles.append(np.where(mask[:, 0], values[:, 0], 0.0))
            else:
                angles.append(side.chunk(values, mask))
        both: NDArray[np.bool_] = np.logical_and(
            np.any(present[:, : self.left_count], axis=1),
            np.any(present[:, self.left_count :], axis=1),
        )
        return angles[0], angles[1], both


class MessageSides:
    """Both sides' values from JointState messages, for sides of several wheels: where the
    last names looked up put each side's joints, and each side's offsets.

    Args:
        left_joints: the left wheel joints, in order.
        right_joints: the right wheel joints.
    """

    __slots__ = ("joints", "names", "offsets", "places")

    def __init__(self, left_joints: Sequence[str], right_joints: Sequence[str]) -> None:
        self.joints = (tuple(left_joints), tuple(right_joints))
        self.names: list[str] | tuple[str, ...] | None = None
        #: Where each side's joints are in ``names`` (their first occurrence), None if absent.
        self.places: tuple[tuple[int | None, ...], ...] = ((), ())
        self.offsets = (SideOffsets(len(left_joints)), SideOffsets(len(right_joints)))

    def values(
        self, names: Sequence[str], values: Sequence[float], *, angles: bool
    ) -> tuple[float, float] | None:
        """The left and right values of a message: with ``angles`` (positions, rad) each
        side's angle (see the module), else (velocities) the mean of its wheels present. None
        when a side has no joint holding a value (a joint named beyond ``values`` holds none);
        NaN when a wheel present is not finite."""
        if names != self.names:
            self.names = names if type(names) is tuple else list(names)
            self.places = tuple(
                tuple(names.index(j) if j in names else None for j in side) for side in self.joints
            )
        size = len(values)
        found: list[float | None] = []
        # Both sides are taken before either is found missing: a side learns its offsets from
        # a sample the other side leaves unusable, as a chunk's rows do.
        for places, offsets in zip(self.places, self.offsets, strict=True):
            side = [float(values[i]) if i is not None and i < size else None for i in places]
            present = [v for v in side if v is not None]
            if angles:
                found.append(offsets.angle(side))
            else:
                found.append(_mean(present) if present else None)
        left, right = found
        if left is None or right is None:
            return None
        return left, right


def _mean(values: Sequence[float]) -> float:
    """Summed in order, the first starting the sum, then divided by the count."""
    total = values[0]
    for value in values[1:]:
        total += value
    return total / len(values)
