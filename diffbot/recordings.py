"""Recordings read whole, their positions conditioned: :func:`read_recording`, the library's
entry, which reads with :mod:`diffbot.io` and then conditions with :mod:`diffbot.conditioning`
(the readers never call the conditioning themselves).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence

import numpy as np

from diffbot.conditioning import Conditioning
from diffbot.errors import ParameterError
from diffbot.io.bag import is_bag, read_bag
from diffbot.io.csv_chunks import open_csv_chunks
from diffbot.io.recordings import csv_layout, existing_recording
from diffbot.kinematics import DiffDriveParams
from diffbot.reading import Reading
from diffbot.samples import (
    ColumnSamples,
    JointSample,
    Recording,
    beyond_range,
    range_reason,
)

__all__ = ["read_recording"]


def read_recording(
    path: str | os.PathLike[str],
    params: DiffDriveParams,
    topic: str | None = None,
    *,
    conditioning: Conditioning | None = None,
    counts_per_rev: float | None = None,
    wrap: float | None = None,
    time_column: str | None = None,
    left_column: str | Sequence[str] | None = None,
    right_column: str | Sequence[str] | None = None,
    delimiter: str | None = None,
    time_unit: str | None = None,
    feedback: str = "position",
) -> Recording:
    """Read wheel joint samples whole from a CSV file or a rosbag2 recording.

    With ``feedback="velocity"`` the wheels' velocities are read (a bag's JointState
    ``velocity`` fields, a CSV's ``/<joint>/velocity`` columns or the columns named) and the
    samples hold the wheel angles they integrate to, each sample's velocity held over the
    interval that ends at it, as diff_drive_controller does with ``position_feedback: false``
    (see :mod:`diffbot.velocity_feedback`): the odometry of the result is that of the
    velocities.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joint names select the CSV columns.
        topic: the JointState topic of a bag.
        conditioning: the positions' units and wrap (default: radians, wraps detected); the
            samples hold the wheel angles, and ``conditioning`` of the result says what was
            done.
        counts_per_rev: the positions are encoder counts, this many per wheel revolution
            (``--counts-per-rev``; instead of ``conditioning``).
        wrap: the modulus of a counter that wraps, in the recorded units; 0 for none and no
            detection (``--wrap``; instead of ``conditioning``).
        time_column: a CSV's time column (default: ``time``, ``stamp``, ``t`` or ``__time``).
        left_column: a CSV's left wheel position column(s) (default: named by the joints).
        right_column: a CSV's right wheel position column(s).
        delimiter: a CSV's delimiter (default: a comma, or what splits the header).
        time_unit: a CSV's time unit, ``s``, ``ms``, ``us`` or ``ns`` (default: seconds, or as
            the first stamp's size says; the result's ``notes`` say so).
        feedback: ``"position"`` or ``"velocity"``: the field read.

    Returns:
        The samples.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic.
        ParameterError: an unknown ``feedback``; ``counts_per_rev`` or ``wrap`` beside
            ``conditioning``, or out of range.
    """
    if counts_per_rev is not None or wrap is not None:
        if conditioning is not None:
            raise ParameterError("give counts_per_rev and wrap, or conditioning=, not both")
        conditioning = Conditioning(counts_per_rev=counts_per_rev, wrap=wrap)
    reading = Reading(conditioning=conditioning, feedback=feedback)
    p = existing_recording(path)
    if is_bag(p):
        joints = {params.left_joint, params.right_joint, *params.left_joints, *params.right_joints}
        read = read_bag(p, topic, feedback, (params.left_joints, params.right_joints))
        recording = _within_range(read, joints, feedback, reading.wheel_limit())
        return _conditioned(recording, params, reading)

    layout = csv_layout(time_column, left_column, right_column, delimiter, time_unit)
    reading = dataclasses.replace(reading, layout=layout)
    sides = (params.left_joints, params.right_joints)
    skipped: dict[str, int] = {}
    with open_csv_chunks(p, sides, layout=reading.csv_layout()) as chunks:
        samples = ColumnSamples(params.left_joints[0], params.right_joints[0])
        wheels = reading.wheel_angles(params, chunks.joints, chunks.left_count)
        for chunk in chunks:
            for reason, count in chunk.skipped.items():
                skipped[reason] = skipped.get(reason, 0) + count
            positions = wheels.feed(chunk.stamp_ns, chunk.positions, chunk.present)
            samples.add_chunk(chunk.stamp_ns, positions, chunk.present, chunks.left_count)
        report = wheels.report()
        return Recording(
            chunks.source, "csv", samples, skipped, conditioning=report, notes=chunks.notes()
        )


def _conditioned(recording: Recording, params: DiffDriveParams, reading: Reading) -> Recording:
    """A bag's samples with their wheel joints' values made wheel angles as ``reading`` says
    (other joints as read)."""
    joints = [*params.left_joints, *params.right_joints]
    wheels = reading.wheel_angles(params, joints, len(params.left_joints))
    samples = recording.samples
    n = len(samples)
    positions = np.zeros((n, len(joints)))
    present = np.zeros((n, len(joints)), dtype=np.bool_)
    stamps = np.empty(n, dtype=np.int64)
    column = {joint: j for j, joint in enumerate(joints)}
    for k, (stamp_ns, names, values) in enumerate(samples):
        stamps[k] = stamp_ns
        for name, value in zip(names, values, strict=False):
            j = column.get(name)
            if j is not None and not present[k, j]:  # a joint named twice: the first, as odometry
                positions[k, j] = value
                present[k, j] = True
    conditioned = wheels.feed(stamps, positions, present)
    report = wheels.report()
    if conditioned is positions:
        return dataclasses.replace(recording, conditioning=report)
    kept = []
    for k, sample in enumerate(samples):
        values = list(sample.positions)
        for i, name in enumerate(sample.names[: len(values)]):
            j = column.get(name)
            if j is not None:
                values[i] = float(conditioned[k, j])
        kept.append(JointSample(sample.stamp_ns, sample.names, values))
    return dataclasses.replace(recording, samples=kept, conditioning=report)


def _within_range(recording: Recording, wheels: set[str], field: str, limit: float) -> Recording:
    """The recording without the samples whose wheel positions (or velocities: ``field``) are
    beyond ``limit`` in their own unit, too large to compute with (counted as skipped, as a CSV
    reader counts them)."""
    kept = [
        sample
        for sample in recording.samples
        if not any(
            name in wheels and beyond_range(value, limit)
            for name, value in zip(sample.names, sample.positions, strict=False)
        )
    ]
    dropped = len(recording.samples) - len(kept)
    if not dropped:
        return recording
    skipped = dict(recording.skipped)
    reason = range_reason(field)
    skipped[reason] = skipped.get(reason, 0) + dropped
    return dataclasses.replace(recording, samples=kept, skipped=skipped)
