"""How a recording is read and where what is read goes: :class:`Reading`, the options that
:func:`~diffbot.replay.recording_odometry` takes once and hands to the step that reads its kind
of input (:func:`~diffbot.replay.bag_odometry`, :func:`~diffbot.replay.csv_odometry`,
:func:`~diffbot.open_loop.open_loop_odometry`), and by which
:func:`~diffbot.recordings.read_recording` reads a recording whole.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from diffbot.chunk_odometry import ChunkPoses
    from diffbot.conditioning import Conditioner, Conditioning, ConditioningReport
    from diffbot.io.csv_layout import CsvLayout
    from diffbot.kinematics import DiffDriveParams
    from diffbot.velocity_feedback import VelocityAngles

__all__ = ["PoseSink", "Progress", "ReadAgain", "Reading", "WheelAngles"]


#: Called with how much of the input a chunk used (messages of a bag, characters of a CSV).
Progress = Callable[[int], None]


class PoseSink(Protocol):
    """Where the poses of a run go as they come."""

    def write(self, poses: ChunkPoses) -> None:
        """Take the poses after the used samples of one chunk, in order."""

    def restart(self) -> None:
        """Drop every pose written so far: the run starts again from the first sample."""


@dataclass(frozen=True, kw_only=True)
class Reading:
    """How a recording is read, and where the poses and the progress go while it is.

    Attributes:
        sink: where the poses go as they come, if anywhere.
        progress: called after each chunk with how much of the input it used: messages of a
            bag, characters of a CSV (:func:`~diffbot.io.recordings.recording_size` says how
            much in all), or once the number of commands integrated open loop.
        conditioning: the recorded wheel positions' units and wrap (default: radians, wraps
            detected); a reader's result says what was done.
        layout: a CSV's columns, delimiter and time unit, where not the defaults.
        feedback: ``"position"`` (the wheel joints' positions) or ``"velocity"`` (their
            velocities, integrated as diff_drive_controller does with
            ``position_feedback: false``; see :mod:`diffbot.velocity_feedback`).

    Raises:
        ParameterError: an unknown ``feedback``.
    """

    sink: PoseSink | None = None
    progress: Progress | None = None
    conditioning: Conditioning | None = None
    layout: CsvLayout | None = None
    feedback: str = "position"

    def __post_init__(self) -> None:
        from diffbot.velocity_feedback import check_feedback

        check_feedback(self.feedback)

    @property
    def counts_per_rev(self) -> float | None:
        """Encoder counts per wheel revolution when the positions are counts; None for
        radians."""
        return None if self.conditioning is None else self.conditioning.counts_per_rev

    def wheel_limit(self) -> float:
        """The largest magnitude a recorded wheel value is taken with, in its own unit (see
        :func:`~diffbot.samples.wheel_limit`)."""
        from diffbot.samples import wheel_limit

        return wheel_limit(self.feedback, self.counts_per_rev)

    def csv_layout(self) -> CsvLayout:
        """``layout`` (or the default one) reading the wheel columns of ``feedback``, in the
        units of ``conditioning``."""
        from diffbot.io.csv_layout import CsvLayout

        layout = self.layout or CsvLayout()
        return dataclasses.replace(layout, field=self.feedback, counts_per_rev=self.counts_per_rev)

    def wheel_angles(
        self, params: DiffDriveParams, joints: Sequence[str], left_count: int
    ) -> WheelAngles:
        """The wheel angles of the values recorded for ``joints`` (the left ones first,
        ``left_count`` of them), as ``feedback`` and ``conditioning`` say."""
        from diffbot.conditioning import Conditioner
        from diffbot.velocity_feedback import VelocityAngles

        conditioner = Conditioner.for_robot(params, joints, left_count, self.conditioning)
        velocity = self.feedback == "velocity"
        return WheelAngles(conditioner, VelocityAngles(len(joints)) if velocity else None)

    def deliver(self, poses: ChunkPoses, used: int) -> None:
        """Hand one chunk's poses to ``sink``, and how much of the input it used to
        ``progress``."""
        if self.sink is not None:
            self.sink.write(poses)
        if self.progress is not None:
            self.progress(used)

    def restart(self) -> None:
        """Tell ``sink`` that the run starts again from the first sample."""
        if self.sink is not None:
            self.sink.restart()


class ReadAgain:
    """A progress callback for an input that may be read a second time from its start: each
    part of it is reported once, so a total of the input's size is reached once and never
    passed (a bag topic whose zero header stamp turns up late is read twice)."""

    def __init__(self, progress: Progress) -> None:
        self.progress = progress
        self.seen = 0
        self.told = 0

    def __call__(self, used: int) -> None:
        """Count ``used`` more of the input; report what goes past what was reported."""
        self.seen += used
        if self.seen > self.told:
            self.progress(self.seen - self.told)
            self.told = self.seen

    def again(self) -> None:
        """The input is read again from its start."""
        self.seen = 0


class WheelAngles:
    """Recorded wheel values made wheel angles, chunk by chunk in recording order: velocities
    integrated first (:class:`~diffbot.velocity_feedback.VelocityAngles`), then every value
    conditioned (:class:`~diffbot.conditioning.Conditioner`: units, wraps, implausible steps).
    """

    def __init__(self, conditioner: Conditioner, velocities: VelocityAngles | None) -> None:
        self.conditioner = conditioner
        self.velocities = velocities

    def feed(
        self, stamps_ns: ArrayLike, values: NDArray[np.float64], present: ArrayLike
    ) -> NDArray[np.float64]:
        """The wheel angles (rad) of the next chunk's values (rad or counts; per second for
        velocities), shape (n, joints); ``present`` marks the values recorded."""
        if self.velocities is not None:
            values = self.velocities.feed(stamps_ns, values, present)
        return self.conditioner.feed(stamps_ns, values, present)

    def report(self) -> ConditioningReport:
        """What conditioning did so far."""
        return self.conditioner.report()
