"""Reading a recording from a path: a CSV file or a rosbag2 recording, by what the path is."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from diffbot.errors import RecordingError
from diffbot.io.bag import DEFAULT_TOPIC, is_bag, read_bag
from diffbot.io.csvfile import read_csv
from diffbot.io.outputs import BAG_FILES
from diffbot.io.textfile import check_regular
from diffbot.kinematics import DiffDriveParams
from diffbot.samples import SKIP_POSITION_RANGE, Recording, beyond_range

__all__ = ["read_recording"]


def read_recording(
    path: str | os.PathLike[str], params: DiffDriveParams, topic: str = DEFAULT_TOPIC
) -> Recording:
    """Read wheel joint samples from a CSV file or a rosbag2 recording.

    Args:
        path: a CSV file, a rosbag2 directory, or one of its ``.db3`` or ``.mcap`` files.
        params: the robot, whose wheel joint names select the CSV columns.
        topic: the JointState topic of a bag.

    Returns:
        The samples.

    Raises:
        RecordingError: missing, empty or unreadable input; missing columns or topic.
    """
    p = Path(path)
    if not p.exists():
        raise RecordingError(f"{p}: no such file or directory")
    # Only regular files are read: a FIFO or device would block or feed endless data.
    parts = [p] if not p.is_dir() else sorted(p.iterdir())
    for part in parts:
        if part is p or part.name == "metadata.yaml" or part.suffix.lower() in BAG_FILES:
            check_regular(part, RecordingError, "a recording")
    if is_bag(p):
        wheels = {params.left_joint, params.right_joint, *params.left_joints, *params.right_joints}
        return _within_range(read_bag(p, topic), wheels)
    return read_csv(p, params.left_joint, params.right_joint)


def _within_range(recording: Recording, wheels: set[str]) -> Recording:
    """The recording without the samples whose wheel positions are too large to compute with
    (counted as skipped, as a CSV reader counts them)."""
    kept = [
        sample
        for sample in recording.samples
        if not any(
            name in wheels and beyond_range(value)
            for name, value in zip(sample.names, sample.positions, strict=False)
        )
    ]
    dropped = len(recording.samples) - len(kept)
    if not dropped:
        return recording
    skipped = dict(recording.skipped)
    skipped[SKIP_POSITION_RANGE] = skipped.get(SKIP_POSITION_RANGE, 0) + dropped
    return dataclasses.replace(recording, samples=kept, skipped=skipped)
