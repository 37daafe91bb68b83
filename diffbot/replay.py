"""Odometry over a whole recording: every sample fed to an :class:`Odometry`, the poses kept as
compact columns."""

from __future__ import annotations

import array
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import NamedTuple

from diffbot.errors import RecordingError
from diffbot.formats.text import listing
from diffbot.kinematics import Pose, Twist, norm_angle
from diffbot.odometry import SKIP_MISSING_JOINT, Odometry
from diffbot.samples import NS_PER_S, ColumnSamples, ColumnView, Recording

__all__ = ["OdometryRow", "OdometryRows", "OdometryRun", "run_odometry"]


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


@dataclass(frozen=True)
class OdometryRun:
    """The odometry of a whole recording.

    Attributes:
        rows: one row per used sample (the baseline first), kept as compact columns and made
            into :class:`OdometryRow` records when read.
        samples: how many samples were used.
        skipped: how many were skipped, by reason (reading and odometry together).
        distance: path length travelled (m), the sum of |ds|.
        duration: time (s) from the first to the last used sample.
    """

    rows: Sequence[OdometryRow]
    samples: int
    skipped: Mapping[str, int]
    distance: float
    duration: float

    @property
    def final_pose(self) -> Pose:
        """The pose after the last used sample."""
        return self.rows[-1].pose


def run_odometry(recording: Recording, odom: Odometry) -> OdometryRun:
    """Feed every sample of a recording to an odometry integrator.

    The integrator sees stamps in seconds relative to the first sample, so the differences it
    divides by keep full precision even for stamps since 1970.

    Args:
        recording: the samples.
        odom: the integrator, at its start pose.

    Returns:
        The run.

    Raises:
        RecordingError: no sample could be used.
    """
    rows = OdometryRows()
    samples = recording.samples
    origin = samples[0].stamp_ns if samples else 0
    missing = 0
    if isinstance(samples, ColumnSamples):
        # The columns straight to update(): no JointSample per row.
        update = odom.update
        columns = (samples.stamps_ns, samples.left, samples.right, samples.present)
        for stamp_ns, left, right, present in zip(*columns, strict=True):
            if present != 3:
                missing += 1  # counted as the integrator would count it
            elif update(left, right, (stamp_ns - origin) / NS_PER_S):
                rows.add(stamp_ns, odom)
    else:
        update_joint_state = odom.update_joint_state
        for stamp_ns, names, positions in samples:
            if update_joint_state(names, positions, (stamp_ns - origin) / NS_PER_S):
                rows.add(stamp_ns, odom)
    skipped = dict(recording.skipped)
    for reason, count in odom.skipped.items():
        skipped[reason] = skipped.get(reason, 0) + count
    if missing:
        skipped[SKIP_MISSING_JOINT] = skipped.get(SKIP_MISSING_JOINT, 0) + missing
    if not rows:
        reasons = ", ".join(f"{reason}: {n}" for reason, n in sorted(skipped.items()))
        hint = ""
        if skipped.get(SKIP_MISSING_JOINT) and samples:
            wanted = listing([*odom.params.left_joints, *odom.params.right_joints])
            hint = f"; wheel joints wanted: {wanted}; joints found: {listing(samples[0].names)}"
        raise RecordingError(
            f"{recording.source}: no usable sample"
            + (f" (skipped: {reasons})" if reasons else " (the recording holds no samples)")
            + hint
        )
    duration = (rows.stamps_ns[-1] - rows.stamps_ns[0]) / NS_PER_S
    return OdometryRun(rows, odom.samples, skipped, odom.distance, duration)


# --------------------------------------------------------------------------------------------
# Outputs
